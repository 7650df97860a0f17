#!/usr/bin/env python3
"""Every C++ source is formatted as .clang-format says (clang-format 14, Debian's clang-format-14).

Usage: /usr/bin/python3 tests/python/check_format.py [--root REPO] [--clang-format PROGRAM]

Runs `clang-format --dry-run -Werror` on the repository's *.cpp and *.hpp files (git's list of them; every such
file under src/, tests/, python/, apps/, bench/, examples/ and fuzz/ when the tree is not a git checkout). Exit 0
when nothing would change, 1 otherwise (clang-format names each file, line and column), 2 when clang-format is
missing. `make format` formats the tree. The version is pinned because another clang-format may break lines
differently.
"""
import argparse
import os
import shutil
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
DEFAULT_ROOT = os.path.normpath(os.path.join(HERE, "..", ".."))
FOLDERS = ("src", "tests", "python", "apps", "bench", "examples", "fuzz")


def sources(root):
    try:
        out = subprocess.run(["git", "-C", root, "ls-files", "*.cpp", "*.hpp"], capture_output=True, text=True,
                             check=True).stdout.split()
        if out:
            return sorted(out)
    except (OSError, subprocess.CalledProcessError):
        pass
    found = []
    for folder in FOLDERS:
        for dirpath, _, files in os.walk(os.path.join(root, folder)):
            found += [os.path.relpath(os.path.join(dirpath, f), root) for f in files if f.endswith((".cpp", ".hpp"))]
    return sorted(found)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--root", default=DEFAULT_ROOT)
    ap.add_argument("--clang-format", default="clang-format-14")
    args = ap.parse_args()
    program = shutil.which(args.clang_format)
    if program is None:
        print(f"check_format: {args.clang_format} not found (Debian package clang-format-14; make deps installs it)",
              file=sys.stderr)
        return 2
    files = sources(args.root)
    if not files:
        print(f"check_format: no C++ sources under {args.root}", file=sys.stderr)
        return 2
    bad = 0
    for i in range(0, len(files), 100):
        p = subprocess.run([program, "--dry-run", "-Werror", "--style=file", *files[i:i + 100]], cwd=args.root,
                           capture_output=True, text=True)
        if p.returncode != 0:
            bad += 1
            sys.stdout.write(p.stderr)
    if bad:
        print("check_format: some sources are not formatted; run `make format` (clang-format-14 -i)", file=sys.stderr)
        return 1
    print(f"check_format: {len(files)} sources formatted as .clang-format says")
    return 0


if __name__ == "__main__":
    sys.exit(main())
