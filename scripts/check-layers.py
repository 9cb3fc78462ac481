#!/usr/bin/env python3
"""The layer rule of docs/architecture.md, checked on every include.

Each folder of src/qdmeta/ (and python/src/, as the folder "python") may include its own files
and those of lower layers, never a folder of its own layer or of a higher one. The order is data:
the ```layers block of docs/architecture.md, lowest layer first, one line per layer, the folders
of one layer separated by spaces. So the documented order is the checked one.

Usage: check-layers.py [ROOT]     ROOT: the repository (default: the one holding this script)
Exit status: 0 when every include points down; 1 with one line per offending include or
unplaced folder; 2 when the layer block is missing or names a folder twice.
"""
import pathlib
import re
import sys

INCLUDE = re.compile(r'^\s*#\s*include\s*[<"]qdmeta/([A-Za-z0-9_]+)/([^>"]+)[>"]')


def refuse(message: str):
    print(message, file=sys.stderr)
    sys.exit(2)


def read_layers(architecture: pathlib.Path) -> dict:
    """Folder -> layer index, from the ```layers block."""
    text = architecture.read_text(encoding="utf-8")
    block = re.search(r"^```layers\n(.*?)^```", text, re.MULTILINE | re.DOTALL)
    if block is None:
        refuse(f"{architecture}: no ```layers block")
    layers = {}
    for index, line in enumerate(l for l in block.group(1).splitlines() if l.strip()):
        for folder in line.split():
            if folder in layers:
                refuse(f"{architecture}: folder {folder} is listed twice in the ```layers block")
            layers[folder] = index
    return layers


def sources(root: pathlib.Path):
    """(folder, path) of every C++ file the rule covers."""
    for path in sorted((root / "src" / "qdmeta").rglob("*")):
        if path.suffix in (".hpp", ".cpp") and path.is_file():
            yield path.relative_to(root / "src" / "qdmeta").parts[0], path
    for path in sorted((root / "python" / "src").rglob("*")):
        if path.suffix in (".hpp", ".cpp") and path.is_file():
            yield "python", path


def check(root: pathlib.Path) -> list:
    layers = read_layers(root / "docs" / "architecture.md")
    problems = []
    unplaced = set()
    for folder, path in sources(root):
        shown = path.relative_to(root)
        if folder not in layers:
            if folder not in unplaced:
                problems.append(f"{shown.parent}: folder {folder} is not in docs/architecture.md's layer order")
                unplaced.add(folder)
            continue
        for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), start=1):
            match = INCLUDE.match(line)
            if match is None or match.group(1) == folder:
                continue
            target = match.group(1)
            if target not in layers:
                problems.append(f"{shown}:{number}: includes qdmeta/{target}/{match.group(2)}, "
                                f"a folder not in docs/architecture.md's layer order")
            elif layers[target] >= layers[folder]:
                where = "the same layer" if layers[target] == layers[folder] else "a higher layer"
                problems.append(f"{shown}:{number}: {folder} includes qdmeta/{target}/{match.group(2)}, "
                                f"{where} (layer {layers[target]} >= {layers[folder]})")
    return problems


def main() -> int:
    root = pathlib.Path(sys.argv[1]) if len(sys.argv) > 1 else pathlib.Path(__file__).resolve().parent.parent
    problems = check(root)
    for p in problems:
        print(p)
    if problems:
        print(f"{len(problems)} include(s) against the layer order of docs/architecture.md")
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
