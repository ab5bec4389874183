#!/usr/bin/env python3
"""The layering check: every #include "..." in the project's C++ sources against the table of
allowed dependencies in docs/DESIGN.md ("Layers"), the one place that table is written.

A file belongs to the longest folder of the table its path starts with; it may include its own
folder, the folders its row names, and what those may include in turn. An include resolves the
same way (or, failing that, relative to the including file, as "fuzz_support.h"); one that names
no project file (a third-party header in quotes) is not checked. Prints each include that goes
against the table as file:line and exits 1; a source file outside every folder of the table, or a
table with a cycle, is an error too. Python 3 standard library only.

Usage: check_layers.py [--root DIR] [--design FILE]  (DIR: the repository, by default this
script's parent's; FILE: the page with the table, by default DIR/docs/DESIGN.md)
"""
import argparse
import os
import re
import sys

SOURCE_SUFFIXES = (".h", ".hpp", ".cpp", ".cc")
# Build trees, dependencies and tool state: not the project's sources.
SKIPPED_DIRS = {".git", "node_modules", "dist"}
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"')
ROW = re.compile(r"^\|\s*`([^`]+)`\s*\|(.*)\|\s*$")


def read_table(design_path):
    """{folder: set of folders it may include directly} from the Layers table."""
    table = {}
    in_section = False
    with open(design_path, encoding="utf-8") as f:
        for line in f:
            if line.startswith("#"):
                in_section = line.strip().lstrip("#").strip() == "Layers"
                continue
            match = ROW.match(line.strip()) if in_section else None
            if match:
                table[match.group(1)] = set(re.findall(r"`([^`]+)`", match.group(2)))
    if not table:
        raise SystemExit(f"{design_path}: no Layers table (a '## Layers' section of | `folder` | ... | rows)")
    return table


def closure(table):
    """{folder: every folder it may include}, or exits naming a cycle or an unknown name."""
    def expand(name):
        # `core` in a row stands for every core/ folder of the table.
        if name in table:
            return {name}
        below = {f for f in table if f.startswith(name + "/")}
        if not below:
            raise SystemExit(f"Layers table: `{name}` is not a folder of the table")
        return below

    direct = {f: set().union(*(expand(n) for n in names)) if names else set() for f, names in table.items()}
    allowed, visiting = {}, []

    def visit(folder):
        if folder in allowed:
            return allowed[folder]
        if folder in visiting:
            cycle = visiting[visiting.index(folder):] + [folder]
            raise SystemExit("Layers table has a cycle: " + " -> ".join(cycle))
        visiting.append(folder)
        reach = set()
        for below in direct[folder]:
            reach |= {below} | visit(below)
        visiting.pop()
        allowed[folder] = reach
        return reach

    for folder in table:
        visit(folder)
    return allowed


def folder_of(path, folders):
    """The longest folder of the table that `path` (relative, with /) lies in, or None."""
    best = None
    for folder in folders:
        if path.startswith(folder + "/") and (best is None or len(folder) > len(best)):
            best = folder
    return best


def sources(root):
    for dirpath, dirnames, filenames in os.walk(root):
        rel_dir = os.path.relpath(dirpath, root)
        dirnames[:] = sorted(d for d in dirnames
                             if d not in SKIPPED_DIRS and not (rel_dir == "." and d.startswith("build")))
        for name in sorted(filenames):
            if name.endswith(SOURCE_SUFFIXES):
                yield os.path.normpath(os.path.join(rel_dir, name)).replace(os.sep, "/")


def check(root, design_path):
    table = read_table(design_path)
    allowed = closure(table)
    problems = []
    for path in sources(root):
        own = folder_of(path, table)
        if own is None:
            problems.append(f"{path}: in no folder of the Layers table (docs/DESIGN.md)")
            continue
        with open(os.path.join(root, path), encoding="utf-8", errors="replace") as f:
            for number, line in enumerate(f, 1):
                match = INCLUDE.match(line)
                if not match:
                    continue
                target = match.group(1)
                if not os.path.exists(os.path.join(root, target)):
                    beside = os.path.normpath(os.path.join(os.path.dirname(path), target))
                    if not os.path.exists(os.path.join(root, beside)):
                        continue  # not a project file
                    target = beside.replace(os.sep, "/")
                theirs = folder_of(target, table)
                if theirs is None or theirs == own or theirs in allowed[own]:
                    continue
                problems.append(f"{path}:{number}: includes {match.group(1)}: {own} may not include {theirs}")
    return problems


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--root", default=os.path.dirname(here))
    parser.add_argument("--design", help="the page holding the table (default ROOT/docs/DESIGN.md)")
    args = parser.parse_args()
    problems = check(args.root, args.design or os.path.join(args.root, "docs", "DESIGN.md"))
    for problem in problems:
        print(problem)
    if problems:
        print(f"{len(problems)} include(s) against the layers of docs/DESIGN.md", file=sys.stderr)
        return 1
    print("layers: every include follows docs/DESIGN.md")
    return 0


if __name__ == "__main__":
    sys.exit(main())
