#!/usr/bin/env bash
# report.html (docs/report.md) of a run and of a sweep, opened by headless Chromium from a file
# URL with no network: no script or console error, a non-blank WebGL view, the numbers equal to
# report.json (the --properties table too, with its nodal column, and youngs_modulus.png and the
# sweep's properties_chart.png on the pages); the sweep's gallery.png is a valid picture; the
# page `cmcsurf report` remakes from the folder is the run's own, byte for byte. The
# browser checks are skipped (exit 77) without Chromium (scripts/test.sh installs Debian's
# chromium) or the page's bundled script (a build without npm or with -DCMCSURF_WEB_VIEWER=OFF).
set -eu
bin="$1"
here=$(cd "$(dirname "$0")" && pwd)
chromium=$(command -v chromium || command -v chromium-browser || true)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$bin" run --paper --surface G --volume-fraction 0.4 --grid 16 --epsilon 0.04 --max-steps 40 \
  --quiet \
  --properties-nodal --out "$work/g"
"$bin" sweep --paper --surface P --volume-fractions 0.4,0.6 --grid 16 --epsilon 0.04 \
  --max-steps 20 \
  --quiet --properties --out "$work/sweep"
for f in g/report.html g/preview.png g/youngs_modulus.png sweep/report.html sweep/gallery.png \
         sweep/P_0.40/report.html sweep/P_0.60/preview.png sweep/P_0.60/youngs_modulus.png \
         sweep/properties_chart.png; do
  [ -s "$work/$f" ] || { echo "FAIL: missing $f"; exit 1; }
done
# Self-contained: nothing is fetched (no src= or href= leaving the file).
if grep -Eqi '(src|href)="(https?:)?//' "$work/g/report.html"; then
  echo "FAIL: report.html loads something over the network"; exit 1
fi
/usr/bin/python3 - "$work/sweep" "$here/../page" <<'PY'
import json, sys
sys.path.insert(0, sys.argv[2])
from png_check import read_png, region_stats
d = sys.argv[1]
w, h, rows = read_png(f"{d}/gallery.png")
assert w > 400 and h > 200, (w, h)
var, coloured = region_stats(rows, 0, 0, w, h)  # mostly the white families plot
assert var > 100 and coloured > 0.03, (var, coloured)
assert json.load(open(f"{d}/sweep.json"))["gallery_seconds"] > 0
print("report_page: gallery.png passed")
PY
# cmcsurf report rewrites the page from the folder alone, byte for byte the page the run made
# from its data in memory, but for the row of write_seconds, which report.json gains after the
# page is written.
mv "$work/g/report.html" "$work/run_page.html"
"$bin" report --quiet "$work/g"
[ -s "$work/g/report.html" ] || { echo "FAIL: report wrote no report.html"; exit 1; }
grep -v 'data-key="write_seconds"' "$work/g/report.html" > "$work/remade_page.html"
cmp "$work/run_page.html" "$work/remade_page.html" ||
  { echo "FAIL: the run's page differs from the one remade from its folder"; exit 1; }
if [ -z "$chromium" ]; then
  echo "report_page: browser checks skipped (no chromium: apt-get install chromium)"
  exit 77
fi
if grep -q "built without npm" "$work/g/report.html"; then
  echo "report_page: browser checks skipped (this cmcsurf was built without npm or with" \
       "-DCMCSURF_WEB_VIEWER=OFF: its pages have no 3D view)"
  exit 77
fi
/usr/bin/python3 "$here/../page/check_page.py" "$chromium" "$work/g/report.html" "$work"
/usr/bin/python3 "$here/../page/check_page.py" "$chromium" "$work/sweep/report.html" "$work"
echo "report_page: all passed"
