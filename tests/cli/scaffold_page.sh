#!/usr/bin/env bash
# A part's page (docs/scaffolds.md, "The part's page"): scaffold's FILE.html opened by headless
# Chromium from a file URL with no network (tests/page/check_part_page.py): no script error, a
# non-blank WebGL view of the part, the numbers (the part's, --compare-nodal's CMC and nodal,
# --properties') equal to FILE.json, both slices and the wall and pore distributions drawn, a
# FILE.png that is not blank. Skipped (exit 77) without Chromium or the page's bundled script
# (a build without npm or with -DCMCSURF_WEB_VIEWER=OFF).
set -eu
bin="$1"
here=$(cd "$(dirname "$0")" && pwd)
chromium=$(command -v chromium || command -v chromium-browser || true)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
export OMP_NUM_THREADS=1
"$bin" scaffold --surface G --porosity 0.7 --solid sheet --cell-size 2 --size 3x3x2 --grid 16 \
  --fast --epsilon 0.04 --compare-nodal --properties --cache "$work/cache" --quiet \
  --out "$work/part.3mf"
for f in part.3mf part.3mf.json part.3mf.html part.3mf.png; do
  [ -s "$work/$f" ] || { echo "FAIL: missing $f"; exit 1; }
done
if grep -Eqi '(src|href)="(https?:)?//' "$work/part.3mf.html"; then
  echo "FAIL: FILE.html loads something over the network"; exit 1
fi
if [ -z "$chromium" ]; then
  echo "scaffold_page: browser checks skipped (no chromium: apt-get install chromium)"
  exit 77
fi
if grep -q "built without npm" "$work/part.3mf.html"; then
  echo "scaffold_page: browser checks skipped (this cmcsurf was built without npm or with" \
       "-DCMCSURF_WEB_VIEWER=OFF: its pages have no 3D view)"
  exit 77
fi
/usr/bin/python3 "$here/../page/check_part_page.py" "$chromium" "$work/part.3mf.html" "$work"
echo "scaffold_page: all passed"
