#!/usr/bin/env bash
# preview.png (docs/report.md): in every run folder, a valid PNG of the documented size (890 x 862
# with the nodal twin, 510 x 862 without), not blank, both columns drawn and coloured; its
# stage time in report.json; --no-preview writes none, and a later run removes an earlier one's;
# --no-report writes no page; a sweep with both writes no gallery, pages or member previews.
set -eu
bin="$1"
here=$(cd "$(dirname "$0")" && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$bin" run --paper --surface P --volume-fraction 0.4 --grid 16 --epsilon 0.04 --max-steps 40 \
  --quiet \
  --no-report --out "$work/p"
"$bin" run --paper --surface sphere --radius 0.3 --grid 16 --epsilon 0.04 --max-steps 5 --quiet \
  --no-report --out "$work/ball"
/usr/bin/python3 - "$work" "$here/../page" <<'PY'
import json, sys
sys.path.insert(0, sys.argv[2])
from png_check import read_png, region_stats
work = sys.argv[1]
for name, width in [("p", 890), ("ball", 510)]:
    w, h, rows = read_png(f"{work}/{name}/preview.png")
    assert (w, h) == (width, 862), (name, w, h)
    report = json.load(open(f"{work}/{name}/report.json"))
    assert report["preview_seconds"] > 0, report.get("preview_seconds")
    # Each column's two panels (380 px squares from y = 102) hold a lit, coloured surface.
    for col in range(1 if name == "ball" else 2):
        for row in range(2):
            x0, y0 = 380 * col, 102 + 380 * row
            var, coloured = region_stats(rows, x0 + 20, y0 + 20, x0 + 360, y0 + 360)
            assert var > 100 and coloured > 0.1, (name, col, row, var, coloured)
    # The colour bar runs from red (top) to blue (bottom).
    bar_x = 380 * (1 if name == "ball" else 2) + 16 + 13
    top, bottom = rows[200][bar_x], rows[h - 80][bar_x]
    assert top[0] > top[2] + 60 and bottom[2] > bottom[0] + 60, (top, bottom)
    # The title is drawn: dark pixels in the band above the panels.
    assert sum(min(p) < 100 for r in rows[10:40] for p in r) > 200
print("preview_png: sizes, panels, colour bar and title passed")
PY
"$bin" run --paper --surface P --volume-fraction 0.4 --grid 16 --epsilon 0.04 --max-steps 3 \
  --quiet \
  --no-preview --no-report --out "$work/p"
if [ -e "$work/p/preview.png" ]; then echo "FAIL: --no-preview left a preview.png"; exit 1; fi
if grep -q preview_seconds "$work/p/report.json"; then
  echo "FAIL: preview_seconds without a preview"
  exit 1
fi
if [ -e "$work/p/report.html" ]; then echo "FAIL: --no-report left a report.html"; exit 1; fi
"$bin" sweep --paper --surface G --volume-fractions 0.5 --grid 16 --epsilon 0.04 --max-steps 3 \
  --quiet \
  --no-plot --no-preview --no-report --out "$work/sweep"
for f in gallery.png report.html G_0.50/preview.png G_0.50/report.html; do
  if [ -e "$work/sweep/$f" ]; then echo "FAIL: sweep --no-preview --no-report wrote $f"; exit 1; fi
done
if grep -q gallery_seconds "$work/sweep/sweep.json"; then
  echo "FAIL: gallery_seconds without a gallery"
  exit 1
fi
echo "preview_png: --no-preview and --no-report passed"
