#!/usr/bin/env bash
# A fixed run and sweep (32^3) against report_reference/ beside this script, written by the
# build before the report schema (schema/report_schema.cpp) existed: report.json (its keys
# and values), history.csv (header and rows: the stages with their "@N" grids), sweep.csv
# (header and rows), the run page's key numbers, the sweep page's members table,
# scripts/sweep_table.py's tables and the command line's summary and member lines, timings
# aside (tests/support/report_keys.py's one comparison). Numbers may differ by 1e-6
# relatively: the reference came from a Release build, and another compiler may contract or
# vectorise the solve's sums differently; counts, names and formatted text may not. A build
# of another type (the sanitizers' -O1) may move a stop rule by a step on such round-off: there
# only the names are compared (keys, headers, the pages' labels and keys, the tables' headings).
# Every key of the report and column of sweep.csv must be declared in the schema, and so must
# the keys inside the report's dictionaries (with a --properties run's) and sweep.json's.
set -u
bin="$1"
here=$(cd "$(dirname "$0")" && pwd)
support="$(cd "$here/../support" && pwd)"
export CMCSURF_BIN="$bin"  # report_keys.py reads the timing keys from its `schema --json`
command -v python3 >/dev/null || { echo "SKIP: python3 missing"; exit 77; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work" || exit 1
fail=0
# The commands that wrote the references (relative --out: the messages name the folders), with
# --anderson-depth 0 since the fast mode's Anderson mixing came after them (without it the fast
# mode was the same to the bit); report.json's parameters gained the options added since, at their
# defaults, by hand. The run's numbers (report.json, history.csv, run.err, run_numbers.html)
# were written again late on 2026-11-27 by the build whose coarser grids end on their own
# equilibrium rule (docs/method.md): 86 coarse steps instead of 89, area 3.0836526 ->
# 3.0836529; the sweep (32^3, no coarser grid) kept its references. --continued-dt-factor 0
# keeps the ramp the references had before the fast mode started continued grids at dt_max.
"$bin" run --surface G --volume-fraction 0.45 --grid 32 --epsilon 0.05 --coarse-levels 2 \
  --max-steps 12 --anderson-depth 0 --continued-dt-factor 0 --threads 1 --no-preview --out run \
  2>run.err ||
  { echo "FAIL: the run"; cat run.err; exit 1; }
"$bin" sweep --surface P,G --volume-fractions 0.45,0.5 --grid 32 --epsilon 0.05 --max-steps 6 \
  --anderson-depth 0 --threads 1 --no-preview --no-plot --out sweep 2>sweep.err ||
  { echo "FAIL: the sweep"; cat sweep.err; exit 1; }
# The properties dictionary's keys (a sheet with its nodal twins and the N/2 check: the most
# keys; 0.9 s of CPU), for the schema's nested keys; compared with no reference.
"$bin" run --surface G --volume-fraction 0.5 --grid 16 --epsilon 0.05 --max-steps 3 --threads 1 \
  --properties-solid sheet --properties-porosity 0.5 --properties-nodal --properties-grid-check \
  --no-preview --no-report --quiet --out properties 2>properties.err ||
  { echo "FAIL: the --properties run"; cat properties.err; exit 1; }
python3 "$here/../../scripts/sweep_table.py" --cmcsurf "$bin" sweep/sweep.csv >sweep_table.md ||
  fail=1
PYTHONPATH="$support" python3 - "$here/report_reference" "$work" <<'PY' || fail=1
import csv, io, json, math, re, sys
from report_keys import SCHEMA, TIMING_KEYS, differing_keys, undeclared_keys

ref, got = sys.argv[1], sys.argv[2]
RTOL = 1e-6
failed = []
release = json.load(open(f"{got}/run/report.json"))["build"]["build_type"] == "Release"
if not release:
    print("note: not a Release build: names and labels compared, not numbers")

def check(what, ok, detail=""):
    if not ok:
        failed.append(f"{what}: {detail}")

# report.json: the same keys; the same values but for the timings and the build's identity.
a = json.load(open(f"{ref}/report.json"))
b = json.load(open(f"{got}/run/report.json"))
check("report.json keys", list(a) == list(b), sorted(set(a) ^ set(b)))
if release:
    diff = differing_keys(a, b, ignore={"build", "version"}, rtol=RTOL)
    check("report.json values", not diff, diff)

# Every key of the run's report and every column of sweep.csv is declared in the schema.
declared = {k["key"] for k in SCHEMA["report_keys"]}
check("report.json keys not in the schema", set(b) <= declared, sorted(set(b) - declared))
columns = next(csv.reader(open(f"{got}/sweep/sweep.csv", newline="")))
check("sweep.csv columns not in the schema", set(columns) <= declared,
      sorted(set(columns) - declared))

# ... and every key inside their dictionaries, and sweep.json's (nested_report_keys,
# sweep_json_keys).
for name in ("run/report.json", "sweep/P_0.45/report.json", "properties/report.json"):
    undeclared = undeclared_keys(json.load(open(f"{got}/{name}")))
    check(f"{name} keys not in the schema", not undeclared, undeclared)
undeclared = undeclared_keys(json.load(open(f"{got}/sweep/sweep.json")), "sweep_json")
check("sweep.json keys not in the schema", not undeclared, undeclared)

def csv_rows(path):
    return list(csv.reader(open(path, newline="")))

def number(cell):
    try:
        return float(cell)
    except ValueError:
        return None

def same_cell(x, y):
    u, v = number(x), number(y)
    if u is None or v is None or ("." not in x and "e" not in x and "." not in y):
        return x == y  # text, and integers (steps, V-cycles)
    if math.isnan(u) or math.isnan(v):
        return math.isnan(u) and math.isnan(v)
    return u == v or abs(u - v) <= RTOL * max(abs(u), abs(v)) + 1e-12

def compare_csv(name, ours, timing):
    x, y = csv_rows(f"{ref}/{name}"), csv_rows(ours)
    check(f"{name} header", x[0] == y[0], f"{x[0]} != {y[0]}")
    if not release:
        return
    check(f"{name} rows", len(x) == len(y), f"{len(x)} != {len(y)}")
    for i, (r, s) in enumerate(zip(x[1:], y[1:])):
        for col, u, v in zip(x[0], r, s):
            if col not in timing and not same_cell(u, v):
                failed.append(f"{name} row {i + 1} {col}: {u} != {v}")

compare_csv("history.csv", f"{got}/run/history.csv", {"elapsed"})
compare_csv("sweep.csv", f"{got}/sweep/sweep.csv", TIMING_KEYS)

# The pages' tables: each row's heading, key and text, the values within RTOL; timings aside.
CELL = re.compile(r'<t([hd])( data-key="([^"]*)")?( data-value="([^"]*)")?>([^<]*)</t[hd]>')

def cells(html):
    return [(m.group(1), m.group(3), m.group(5), m.group(6)) for m in CELL.finditer(html)]

def table(path, pattern):
    return re.search(pattern, open(path).read(), re.S).group(0)

for name, ours, pattern in [
        ("run_numbers.html", f"{got}/run/report.html",
         r'<table class="numbers" id="numbers">.*?</table>\n'),
        ("sweep_members.html", f"{got}/sweep/report.html",
         r'<table class="members" id="members">.*?</table>\n')]:
    x, y = cells(open(f"{ref}/{name}").read()), cells(table(ours, pattern))
    check(f"{name} cells", len(x) == len(y), f"{len(x)} != {len(y)}")
    for (t, key, value, text), (t2, key2, value2, text2) in zip(x, y):
        if (t, key) != (t2, key2) or (t == "h" and text != text2):
            failed.append(f"{name}: {t} {key} {text} != {t2} {key2} {text2}")
        elif release and key not in TIMING_KEYS and (
                text != text2 or not same_cell(value or "", value2 or "")):
            failed.append(f"{name} {key}: '{text}' ({value}) != '{text2}' ({value2})")

# sweep_table.py's tables and the messages: times (a decimal before " s" or " ms") masked.
def masked(text):
    text = re.sub(r"\| [0-9.]+ \|\n", "| T |\n", text)  # the table's last column: seconds
    return re.sub(r"[0-9]+\.[0-9]+( m?s\b)", r"T\1", text)

for name, ours in [("sweep_table.md", f"{got}/sweep_table.md"), ("run.err", f"{got}/run.err"),
                   ("sweep.err", f"{got}/sweep.err")]:
    lines = [l for l in open(ours) if not re.match(r"(prerelax|relax|volume)\s+step", l)]
    x, y = masked(open(f"{ref}/{name}").read()), masked("".join(lines))
    if not release:  # the families tables' headings only
        if name != "sweep_table.md":
            continue
        x, y = (re.sub(r"(?m)^\| [-+0-9].*\n", "", t) for t in (x, y))
    check(name, x == y, "\n" + "".join(
        f"  want {u!r}\n  got  {v!r}\n" for u, v in zip(x.splitlines(), y.splitlines()) if u != v))

for f in failed:
    print("FAIL:", f)
sys.exit(1 if failed else 0)
PY
exit $fail
