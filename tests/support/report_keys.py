"""Comparing two reports of the same surface (report.json, or rows of sweep.csv), timings aside.

TIMING_KEYS are the keys whose values depend on the machine, the clock or where a run was
interrupted and resumed, not on the surface computed: the report keys the library's table marks
as timings (schema/report_schema.cpp), read from `$CMCSURF_BIN schema --json`. The test scripts
that compare a resumed or decomposed run with an uninterrupted one import them from here
(PYTHONPATH=tests/support, CMCSURF_BIN=the cmcsurf under test); without CMCSURF_BIN, or when
the command fails, importing this module fails: an empty set would compare nothing.
undeclared_keys names the keys of a report.json or sweep.json that the schema lacks.
"""
import json
import math
import os
import subprocess


def schema():
    """The report schema of the cmcsurf in $CMCSURF_BIN, as `cmcsurf schema --json` prints it."""
    binary = os.environ.get("CMCSURF_BIN")
    if not binary:
        raise RuntimeError("report_keys: set CMCSURF_BIN to the cmcsurf under test (its "
                           "`schema --json` names the timing keys)")
    out = subprocess.run([binary, "schema", "--json"], check=True, capture_output=True,
                         text=True).stdout
    return json.loads(out)


SCHEMA = schema()
TIMING_KEYS = frozenset(k["key"] for k in SCHEMA["report_keys"] if k["timing"])
if not TIMING_KEYS:
    raise RuntimeError("report_keys: the schema marks no key as a timing")


def _same(a, b, rtol):
    if isinstance(a, bool) or isinstance(b, bool) or rtol == 0.0:
        return a == b
    if isinstance(a, (int, float)) and isinstance(b, (int, float)):
        if isinstance(a, int) and isinstance(b, int):
            return a == b
        return a == b or math.isclose(a, b, rel_tol=rtol, abs_tol=rtol * 1e-3)
    if isinstance(a, dict) and isinstance(b, dict):
        return a.keys() == b.keys() and all(_same(a[k], b[k], rtol) for k in a)
    if isinstance(a, list) and isinstance(b, list):
        return len(a) == len(b) and all(_same(x, y, rtol) for x, y in zip(a, b))
    return a == b


def differing_keys(a, b, ignore=(), rtol=0.0):
    """The keys of the dicts a and b, less TIMING_KEYS and ignore, whose values differ (a key
    present in one only differs, unless its value is null), sorted. rtol > 0: floating-point
    numbers (also inside nested dicts and lists) may differ by that relative amount; integers,
    strings and booleans not."""
    skip = TIMING_KEYS | set(ignore)
    return sorted(k for k in set(a) | set(b)
                  if k not in skip and not _same(a.get(k), b.get(k), rtol))


def undeclared_keys(doc, kind="report"):
    """The paths of the keys of `doc` that the schema does not declare, sorted: a run's
    report.json (kind "report": its top level in report_keys, its dictionaries in
    nested_report_keys) or sweep.json (kind "sweep_json": sweep_json_keys). A dictionary with no
    declared keys of its own (report.json's parameters, build) is declared as a whole; "[]" is a
    list's dictionaries; an entry's `like` lends it another dictionary's keys."""
    table = SCHEMA["nested_report_keys" if kind == "report" else "sweep_json_keys"]
    declared = {e["path"] for e in table}
    if kind == "report":
        declared |= {k["key"] for k in SCHEMA["report_keys"]}
    like = {e["path"]: e["like"] for e in table if e["like"]}
    found = []

    def lookups(path):  # the path, then what it is like, and so on
        while path:
            yield path
            path = like.get(path)

    def walk(value, path, lookup):
        if isinstance(value, list):
            if any(d.startswith(lookup + "[].") for d in declared):
                for item in value:
                    walk(item, path + "[]", lookup + "[]")
            return
        if not isinstance(value, dict):
            return
        names = list(lookups(lookup)) if lookup else [""]
        if lookup and not any(d.startswith(n + ".") for n in names for d in declared):
            return  # declared as a whole
        for key, item in value.items():
            full = f"{path}.{key}" if path else key
            match = next((f"{n}.{key}" if n else key for n in names
                          if (f"{n}.{key}" if n else key) in declared), None)
            if match is None:
                found.append(full)
            else:
                walk(item, full, match)

    walk(doc, "", "")
    return sorted(found)
