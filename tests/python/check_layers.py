#!/usr/bin/env python3
"""No include in src/vascsim/ runs back up the layers of docs/architecture.md, section 1, and none closes a cycle.

Usage: /usr/bin/python3 tests/python/check_layers.py [--root REPO]

The folders under src/vascsim/ are layers; "a file may include its own layer and the layers below it, never one
above". LEVELS and RENDER_INCLUDES below mirror that section (its figure and the "includes" column of its
table); a change of the layers is a change of both. Bottom to top:

    core -> geometry . constraints . mapping . interaction -> io -> model -> scene -> run -> experiments -> app

with render (GL) including only core, geometry and interaction, and viewer (GL) including everything. The four
layers of the second level are siblings: in the table each of them includes core only, so none may include
another. Only viewer may include render (the core library builds without any GL package).

Checked in every .hpp and .cpp under src/vascsim/:
  - every #include "vascsim/<layer>/...": the file's layer may include that layer;
  - a quoted #include that is not of that form (a relative path would hide the layer it reaches);
  - a folder or an included layer that the table does not name (a new layer needs its place here and in
    docs/architecture.md);
  - no cycle among the files' includes.
Exit code 0 when all holds, 1 otherwise, each problem on one line: file:line: what (for an include running
back up: "layer X includes layer Y above it").
"""
import argparse
import os
import re
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
DEFAULT_ROOT = os.path.normpath(os.path.join(HERE, "..", ".."))

# docs/architecture.md, section 1: the layers bottom to top; the layers of one entry are siblings.
LEVELS = [
    ("core",),
    ("geometry", "constraints", "mapping", "interaction"),
    ("io", "rod"),
    ("model",),
    ("scene",),
    ("run",),
    ("experiments",),
    ("app",),
]
# The two GL layers beside that order: render includes only these; viewer includes every layer.
RENDER_INCLUDES = ("core", "geometry", "interaction")
LEVEL = {layer: i for i, group in enumerate(LEVELS) for layer in group}
KNOWN = set(LEVEL) | {"render", "viewer"}

INCLUDE = re.compile(r'^\s*#\s*include\s*"([^"]*)"')
VASCSIM_INCLUDE = re.compile(r"^vascsim/([A-Za-z0-9_]+)/")


def problem(layer, target):
    """Why `layer` may not include `target` (None when it may)."""
    if target == layer or layer == "viewer":
        return None
    if layer == "render":
        if target in RENDER_INCLUDES:
            return None
        if target == "viewer" or (target in LEVEL and LEVEL[target] > LEVEL["interaction"]):
            return f"layer render includes layer {target} above it (render includes only {', '.join(RENDER_INCLUDES)})"
        return f"layer render includes layer {target} (render includes only {', '.join(RENDER_INCLUDES)})"
    if target in ("render", "viewer"):
        return f"layer {layer} includes layer {target} above it ({target} is GL; only viewer may include it)"
    if LEVEL[target] > LEVEL[layer]:
        return f"layer {layer} includes layer {target} above it"
    if LEVEL[target] == LEVEL[layer]:
        return (f"layer {layer} includes layer {target} beside it (the siblings "
                f"{', '.join(LEVELS[LEVEL[layer]])} include only the layers below them)")
    return None


def source_files(src):
    for folder, dirs, files in os.walk(src):
        dirs.sort()
        for name in sorted(files):
            if name.endswith((".hpp", ".cpp", ".h")):
                yield os.path.join(folder, name)


def find_cycle(graph):
    """One include cycle of `graph` (file -> files it includes) as a list of files, or None."""
    state = {}  # absent: not seen; 1: on the current path; 2: done
    for start in sorted(graph):
        if start in state:
            continue
        path, stack = [start], [iter(sorted(graph[start]))]
        state[start] = 1
        while stack:
            node = next(stack[-1], None)
            if node is None:
                state[path.pop()] = 2
                stack.pop()
            elif state.get(node) == 1:
                return path[path.index(node):] + [node]
            elif node not in state and node in graph:
                state[node] = 1
                path.append(node)
                stack.append(iter(sorted(graph[node])))
    return None


def check(root):
    src = os.path.join(root, "src", "vascsim")
    if not os.path.isdir(src):
        return [f"{src}: no such folder (--root is the repository)"]
    problems = []
    graph = {}
    for path in source_files(src):
        rel = os.path.relpath(path, root)
        parts = os.path.relpath(path, src).split(os.sep)
        layer = parts[0] if len(parts) > 1 else None
        if layer not in KNOWN:
            problems.append(f"{rel}:1: the folder is not a layer of docs/architecture.md section 1 "
                            f"(add it there and to check_layers.py)")
            continue
        key = os.path.relpath(path, src).replace(os.sep, "/")
        graph[key] = set()
        with open(path, encoding="utf-8", errors="replace") as f:
            for number, line in enumerate(f, start=1):
                m = INCLUDE.match(line)
                if not m:
                    continue
                included = m.group(1)
                target = VASCSIM_INCLUDE.match(included)
                if not target:
                    problems.append(f'{rel}:{number}: #include "{included}" is not "vascsim/<layer>/...", so its '
                                    f"layer cannot be checked")
                    continue
                graph[key].add(included[len("vascsim/"):])
                if target.group(1) not in KNOWN:
                    problems.append(f"{rel}:{number}: layer {layer} includes '{target.group(1)}', which is not a "
                                    f"layer of docs/architecture.md section 1")
                    continue
                why = problem(layer, target.group(1))
                if why:
                    problems.append(f"{rel}:{number}: {why}")
    cycle = find_cycle(graph)
    if cycle:
        problems.append(f"src/vascsim/{cycle[0]}:1: an include cycle: {' -> '.join(cycle)}")
    return problems


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--root", default=DEFAULT_ROOT, help="the repository (default: this script's)")
    args = parser.parse_args()
    problems = check(args.root)
    for p in problems:
        print(p)
    if problems:
        print(f"check_layers: {len(problems)} problem(s); the layers are in docs/architecture.md, section 1",
              file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
