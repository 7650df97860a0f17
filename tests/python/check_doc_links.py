#!/usr/bin/env python3
"""Every link and file reference in README.md and docs/**/*.md resolves inside the repository.

Usage: /usr/bin/python3 tests/python/check_doc_links.py [--root REPO] [--allow FILE]

Checked:
  - markdown links [text](target) and images ![alt](target) with a relative target: the file or folder
    exists, and a #anchor names a heading of the target markdown file (GitHub's heading slugs);
  - file references in inline code (`scenes/vein-indent.json`, `scripts/*.py`, `run/haptic_rig`) and in
    fenced code blocks (the paths a command names): a path under scenes/, scripts/, docs/, data/, tests/, src/,
    apps/ or bench/ must exist from the repository root (globs and {a,b} lists must match something); a path
    under a source folder (core/, model/, run/, ...) must exist under src/vascsim/ as a file, a folder or a
    file stem (run/haptic_rig -> run/haptic_rig.cpp);
  - references that leave the repository, anywhere in the text: a link or path going above the repository
    root (../ too many) or an absolute path outside the system folders (/usr, /proc, /dev, /tmp, ...).
Any problem fails the check unless its reference is listed in the allow-list file (one `DOC: REFERENCE` per
line; lines starting with '#' are comments), which holds only references that are being removed; allowed ones are still printed.

Outputs (out/, build/, vtk/...) and placeholders (<name>, NNNN) are not checked. Exit code 0 when everything
resolves, 1 otherwise (each problem on one line: file:line: what).
"""
import argparse
import glob
import os
import re
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
DEFAULT_ROOT = os.path.normpath(os.path.join(HERE, "..", ".."))
DEFAULT_ALLOW = os.path.join(HERE, "doc_links_allowlist.txt")

ROOT_DIRS = ("scenes/", "scripts/", "docs/", "data/", "tests/", "src/", "apps/", "bench/")
SOURCE_DIRS = ("core/", "geometry/", "constraints/", "mapping/", "interaction/", "io/", "model/", "scene/", "run/",
               "experiments/", "app/", "render/", "viewer/")
SYSTEM_PREFIXES = ("/usr/", "/proc/", "/dev/", "/sys/", "/tmp/", "/etc/", "/opt/", "/bin/", "/lib/", "/var/")
LINK = re.compile(r"!?\[(?:[^\[\]]|\[[^\]]*\])*\]\(([^)\s]+)(?:\s+\"[^\"]*\")?\)")
CODE = re.compile(r"`([^`\n]+)`")
FENCE = re.compile(r"^\s*(```|~~~)")


def slug(heading):
    """GitHub's anchor of a heading: lower case, punctuation dropped, spaces to hyphens."""
    text = re.sub(r"`|\*\*|__", "", heading.strip()).lower()
    text = re.sub(r"\[([^\]]*)\]\([^)]*\)", r"\1", text)  # a link in a heading keeps its text
    text = re.sub(r"[^\w\- ]", "", text, flags=re.UNICODE)
    return text.replace(" ", "-")


def anchors(path, cache={}):
    if path not in cache:
        found, seen = set(), {}
        in_fence = False
        with open(path, encoding="utf-8") as f:
            for line in f:
                if FENCE.match(line):
                    in_fence = not in_fence
                    continue
                m = re.match(r"^(#{1,6})\s+(.*?)\s*#*\s*$", line)
                if m and not in_fence:
                    s = slug(m.group(2))
                    n = seen.get(s, 0)
                    seen[s] = n + 1
                    found.add(s if n == 0 else f"{s}-{n}")
                for a in re.findall(r"<a\s+(?:name|id)=\"([^\"]+)\"", line):
                    found.add(a)
        cache[path] = found
    return cache[path]


def expand_braces(p):
    m = re.search(r"\{([^{}]*)\}", p)
    if not m:
        return [p]
    out = []
    for alt in m.group(1).split(","):
        out += expand_braces(p[: m.start()] + alt + p[m.end():])
    return out


def exists(root, rel):
    for p in expand_braces(rel):
        full = os.path.join(root, p)
        if any(c in p for c in "*?["):
            if not glob.glob(full):
                return False
        elif not os.path.exists(full):
            return False
    return True


def outside(root, doc_dir, target):
    """True when a relative target climbs above the repository root."""
    full = os.path.normpath(os.path.join(doc_dir, target))
    return os.path.relpath(full, root).startswith("..")


class Checker:
    def __init__(self, root, allowed):
        self.root, self.allowed = root, allowed
        self.problems, self.allowed_seen = [], []

    def report(self, doc, line, what, reference):
        rel = os.path.relpath(doc, self.root)
        if (rel, reference) in self.allowed:
            self.allowed_seen.append(f"{rel}:{line}: {what} (allowed for now)")
        else:
            self.problems.append(f"{rel}:{line}: {what}")

    def link(self, doc, line, target):
        if re.match(r"^[a-z][a-z0-9+.-]*:", target, re.I):  # http:, https:, mailto:
            return
        path, _, anchor = target.partition("#")
        doc_dir = os.path.dirname(doc)
        if path.startswith("/") or outside(self.root, doc_dir, path):
            self.report(doc, line, f"link to '{target}' leaves the repository", target)
            return
        full = os.path.normpath(os.path.join(doc_dir, path)) if path else doc
        if not os.path.exists(full):
            self.report(doc, line, f"link to '{target}': {os.path.relpath(full, self.root)} does not exist", target)
            return
        if anchor and full.endswith(".md") and anchor not in anchors(full):
            self.report(doc, line, f"link to '{target}': no heading '#{anchor}' in {os.path.relpath(full, self.root)}",
                        target)

    def path(self, doc, line, token):
        token = token.strip().rstrip(".,;:)").strip("'\"")
        if not token or re.search(r"<|>|NNNN|\.\.\.|\$", token):
            return
        if token.startswith("../") and outside(self.root, os.path.dirname(doc), token):
            self.report(doc, line, f"reference to '{token}' leaves the repository", token)
            return
        if re.match(r"^/[\w.-]+/", token):
            if not token.startswith(SYSTEM_PREFIXES):
                self.report(doc, line, f"reference to '{token}', an absolute path outside the repository", token)
            return
        if token.startswith(ROOT_DIRS):
            if not exists(self.root, token):
                self.report(doc, line, f"'{token}' does not exist in the repository", token)
        elif token.startswith(SOURCE_DIRS) and re.fullmatch(r"[\w./*{},-]+", token):
            src = os.path.join("src", "vascsim", token)
            if not (exists(self.root, src) or glob.glob(os.path.join(self.root, src) + ".*")):
                self.report(doc, line, f"'{token}' is no file or folder under src/vascsim/", token)

    def document(self, doc):
        in_fence = False
        with open(doc, encoding="utf-8") as f:
            for n, line in enumerate(f, 1):
                if FENCE.match(line):
                    in_fence = not in_fence
                    continue
                if in_fence:
                    for token in line.split():
                        if token.startswith(ROOT_DIRS) or token.startswith(("../", "/")):
                            self.path(doc, n, token)
                    continue
                for target in LINK.findall(line):
                    self.link(doc, n, target)
                prose = LINK.sub("", line)
                for code in CODE.findall(prose):
                    for token in code.split():
                        self.path(doc, n, token)
                for token in CODE.sub("", prose).split():  # plain text: only what leaves the repository
                    if token.startswith(("../", "/")):
                        self.path(doc, n, token)


def read_allow(path):
    allowed = set()
    if not os.path.isfile(path):
        return allowed
    with open(path, encoding="utf-8") as f:
        for line in f:
            line = "" if line.lstrip().startswith("#") else line.strip()
            if line:
                doc, _, ref = line.partition(": ")
                allowed.add((doc.strip(), ref.strip()))
    return allowed


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--root", default=DEFAULT_ROOT, help="repository root (default: this checkout)")
    ap.add_argument("--allow", default=DEFAULT_ALLOW, help="allow-list of references outside the repository")
    args = ap.parse_args()
    root = os.path.abspath(args.root)
    docs = [os.path.join(root, "README.md")]
    docs += sorted(glob.glob(os.path.join(root, "docs", "**", "*.md"), recursive=True))  # docs/model/ too
    checker = Checker(root, read_allow(args.allow))
    for doc in docs:
        checker.document(doc)
    for a in checker.allowed_seen:
        print(a)
    for p in checker.problems:
        print(p)
    print(f"check_doc_links: {len(docs)} documents, {len(checker.problems)} problems, "
          f"{len(checker.allowed_seen)} allowed by the allow-list")
    return 1 if checker.problems else 0


if __name__ == "__main__":
    sys.exit(main())
