#!/usr/bin/env python3
"""Markdown tables (one per surface) from a cmcsurf sweep.csv, as in docs/families.md.

usage: scripts/sweep_table.py [--cmcsurf BIN] DIR/sweep.csv

The columns, their headings and formats are the library's families table
(schema/report_schema.cpp), read from `BIN schema --json`; BIN: --cmcsurf, $CMCSURF_BIN,
`cmcsurf` on PATH, or build/cmcsurf beside this script's folder.
"""
import csv
import json
import os
import shutil
import subprocess
import sys


def find_cmcsurf(given):
    if given:
        return given
    here = os.path.dirname(os.path.abspath(__file__))
    for candidate in (os.environ.get("CMCSURF_BIN"), shutil.which("cmcsurf"),
                      os.path.join(here, "..", "build", "cmcsurf")):
        if candidate and os.access(candidate, os.X_OK):
            return candidate
    sys.exit("sweep_table.py: no cmcsurf found (pass --cmcsurf BIN): its `schema --json` "
             "names the columns")


def columns(binary):
    """(heading, sweep.csv column, format) of each column of the table."""
    out = subprocess.run([binary, "schema", "--json"], check=True, capture_output=True,
                         text=True).stdout
    return [(c["header"], c["key"], c["format"]) for c in json.loads(out)["families_table"]]


def main(path, binary):
    table = columns(binary)
    rows = list(csv.DictReader(open(path)))
    for surface in dict.fromkeys(r["surface"] for r in rows):
        print(f"**{surface}**\n")
        print("| " + " | ".join(h for h, _, _ in table) + " |")
        print("|" + "---|" * len(table))
        for r in rows:
            if r["surface"] != surface:
                continue
            cells = []
            for _, key, fmt in table:
                v = r.get(key, "")
                cells.append(fmt.format(float(v)) if v not in ("", None) else "")
            print("| " + " | ".join(cells) + " |")
        print()


if __name__ == "__main__":
    args = sys.argv[1:]
    given = None
    if len(args) == 3 and args[0] == "--cmcsurf":
        given = args[1]
        args = args[2:]
    if len(args) != 1:
        sys.exit(__doc__)
    main(args[0], find_cmcsurf(given))
