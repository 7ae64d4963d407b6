#!/usr/bin/env python3
"""The layer gate (CTest lint.layers; docs/architecture.md, "Layers"): every #include "x/..." in
src/, apps/ and python/src names a layer at or below the including file's own, in the order of
src/layers.txt (lowest first), which CMakeLists.txt reads too.

Usage: scripts/check_layers.py [--edges]
  Prints each violation as path:line: what is wrong, and exits 1 on any. --edges prints instead
  which layers each layer includes (tests left out), one line per layer.

A test (*_test.cpp) is compiled into cmcsurf_tests, which links every layer, so it may build its
input with a higher layer (measure/'s tests make fields with surfaces/); it may include tests/
support/ too, and never apps/ or python/.
"""
import pathlib
import re
import sys

ROOT = pathlib.Path(__file__).resolve().parents[1]
ORDER_FILE = ROOT / "src" / "layers.txt"
INCLUDE = re.compile(r'^\s*#\s*include\s+"([A-Za-z0-9_]+)/[^"]*"')
SUFFIXES = {".h", ".hpp", ".cpp", ".in"}
TEST_ONLY = {"support"}  # tests/support: test helpers, in cmcsurf_test_support
ENTRY_POINTS = {"apps", "python"}  # never included by anything


def read_order():
    layers = []
    for line in ORDER_FILE.read_text(encoding="utf-8").splitlines():
        name = line.split("#", 1)[0].strip()
        if name:
            layers.append(name)
    return layers


def sources():
    """(path relative to ROOT, its layer) of every file the gate reads."""
    found = []
    for folder in sorted((ROOT / "src").iterdir()):
        if folder.is_dir():
            found += [(p, folder.name) for p in sorted(folder.rglob("*")) if p.suffix in SUFFIXES]
    for base, layer in (("apps", "apps"), ("python/src", "python")):
        found += [(p, layer) for p in sorted((ROOT / base).rglob("*")) if p.suffix in SUFFIXES]
    return [(p.relative_to(ROOT).as_posix(), layer) for p, layer in found]


def check(order):
    rank = {layer: i for i, layer in enumerate(order)}
    problems = []
    edges = {}
    for folder in sorted((ROOT / "src").iterdir()):
        if folder.is_dir() and folder.name not in rank:
            problems.append(f"src/{folder.name}/: a folder that src/layers.txt does not list "
                            "(add it where its includes put it)")
    for path, layer in sources():
        if layer not in rank:
            continue  # reported above
        test = path.endswith("_test.cpp")
        lines = (ROOT / path).read_text(encoding="utf-8", errors="replace").splitlines()
        for number, line in enumerate(lines, start=1):
            m = INCLUDE.match(line)
            if not m:
                continue
            target = m.group(1)
            where = f"{path}:{number}: includes \"{line.split(chr(34))[1]}\""
            if target in TEST_ONLY:
                if not test:
                    problems.append(f"{where}: {target}/ is for tests only")
                continue
            if target not in rank:
                problems.append(f"{where}: {target}/ is no layer of src/layers.txt")
                continue
            if test:
                if target in ENTRY_POINTS:
                    problems.append(f"{where}: a test includes no entry point ({target}/)")
                continue
            if target != layer:
                edges.setdefault(layer, set()).add(target)
            if rank[target] > rank[layer]:
                problems.append(f"{where}: {target}/ is above {layer}/ in src/layers.txt")
    return problems, edges


def main(argv):
    order = read_order()
    problems, edges = check(order)
    if "--edges" in argv:
        for layer in order:
            below = sorted(edges.get(layer, ()), key=order.index)
            print(f"{layer:14} -> {', '.join(below) if below else '(none)'}")
        return 0
    for p in problems:
        print(p)
    if problems:
        print(f"check_layers: {len(problems)} include(s) against the order of src/layers.txt")
        return 1
    print(f"check_layers: {len(sources())} files follow the {len(order)} layers of "
          "src/layers.txt")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
