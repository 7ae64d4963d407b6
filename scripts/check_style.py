#!/usr/bin/env python3
"""The style gate of CI (docs/architecture.md, "Tests and the gate"): no line over 100 columns,
no tab and no trailing whitespace in the C++, CMake, Python and shell sources git tracks.

Usage: scripts/check_style.py [--summary] [FILE...]
  Prints each violation as path:line:column: rule, or with --summary one line per file with its
  counts; FILEs (paths from the repository root) limit the check to them. Exit 1 on a violation.

Files listed in scripts/style_pending.txt (owned by work in progress, to be reformatted after it
merges) are reported but do not fail the check; an entry whose file is clean fails it, so the
list only shrinks. (clang-format over the whole tree would change about 1,700 lines of hand-made
line breaks, which is why the gate checks these plain rules; .clang-format is for new code.)
"""
import pathlib
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parents[1]
MAX_COLUMNS = 100
SUFFIXES = {".h", ".hpp", ".cpp", ".cc", ".in", ".cmake", ".py", ".pyi", ".sh", ".bash"}
NAMES = {"CMakeLists.txt"}
PENDING = ROOT / "scripts" / "style_pending.txt"


def checked(path):
    p = pathlib.PurePosixPath(path)
    return p.name in NAMES or p.suffix in SUFFIXES


def tracked_files():
    try:
        out = subprocess.run(["git", "ls-files", "-z"], cwd=ROOT, capture_output=True,
                             check=True).stdout.decode()
        return [f for f in out.split("\0") if f]
    except (OSError, subprocess.CalledProcessError):
        # Not a git checkout (a source archive): every file but the build folders'.
        skip = ("build", "out", "node_modules", ".git")
        return [str(p.relative_to(ROOT)) for p in ROOT.rglob("*")
                if p.is_file() and not any(part.startswith(skip) for part in
                                           p.relative_to(ROOT).parts)]


def violations(path):
    """(line, column, rule) of each violation in the file at path (relative to ROOT)."""
    found = []
    text = (ROOT / path).read_bytes().decode("utf-8", errors="replace")
    for number, line in enumerate(text.split("\n"), start=1):
        if len(line) > MAX_COLUMNS:
            found.append((number, MAX_COLUMNS + 1, f"line of {len(line)} columns (limit "
                          f"{MAX_COLUMNS})"))
        tab = line.find("\t")
        if tab >= 0:
            found.append((number, tab + 1, "tab character (indent with spaces)"))
        stripped = line.rstrip(" \t\r\f\v")
        if stripped != line:
            found.append((number, len(stripped) + 1, "trailing whitespace"))
    return found


def read_pending():
    if not PENDING.exists():
        return set()
    lines = PENDING.read_text().splitlines()
    return {s.strip() for s in lines if s.strip() and not s.lstrip().startswith("#")}


def main(argv):
    summary = "--summary" in argv
    given = [a for a in argv if a != "--summary"]
    if any(a.startswith("-") for a in given):
        print(__doc__.strip().splitlines()[2], file=sys.stderr)
        return 2
    files = sorted(given) if given else sorted(f for f in tracked_files() if checked(f))
    pending = read_pending()
    failed = False
    pending_lines = 0
    for f in files:
        if not (ROOT / f).is_file():
            print(f"{f}: no such file under {ROOT}", file=sys.stderr)
            return 2
        found = violations(f)
        if f in pending:
            pending_lines += len(found)
        elif found:
            failed = True
        if summary and found:
            note = " (pending: scripts/style_pending.txt)" if f in pending else ""
            print(f"{f}: {len(found)}{note}")
        elif not summary:
            tag = " [pending]" if f in pending else ""
            for line, column, rule in found:
                print(f"{f}:{line}:{column}: {rule}{tag}")
    if not given:
        listed = set(files)
        for f in sorted(pending):
            if f not in listed:
                print(f"scripts/style_pending.txt: {f} is not a checked file; remove the entry")
                failed = True
            elif not violations(f):
                print(f"scripts/style_pending.txt: {f} is clean now; remove the entry")
                failed = True
    if pending_lines:
        print(f"check_style: {pending_lines} violations in files of scripts/style_pending.txt "
              "(not failing)")
    print("check_style: " + ("FAILED" if failed else f"{len(files)} files OK"))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
