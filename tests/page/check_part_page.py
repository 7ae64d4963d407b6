"""Opens a part's FILE.html (cmcsurf scaffold) in headless Chromium from a file URL with the
network cut off, as check_page.py does a run's page, and checks: the page's status is "ok"
and it shows the part, no "Uncaught" error, the 3D view in a screenshot is not blank, every
number cell (data-path, a JSON pointer into FILE.json, and data-value) equals FILE.json's
number and its text shows it, the slices and the wall and pore distributions are drawn, and
FILE.png is a picture that is not blank.

usage: check_part_page.py CHROMIUM FILE.html WORKDIR
"""
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from headless_page import (  # noqa: E402
    StatusAndPaths, check_path_cells, load_page, view_stats)
from png_check import read_png, region_stats  # noqa: E402

class Page(StatusAndPaths):
    """The status, the data-path cells and the svg charts."""

    def __init__(self):
        super().__init__()
        self.svgs = []

    def handle_starttag(self, tag, attrs):
        super().handle_starttag(tag, attrs)
        if tag == "svg":
            self.svgs.append(dict(attrs))


def main():
    exe, page, work = sys.argv[1:4]
    part = page[:-len(".html")]
    report = json.load(open(part + ".json"))
    parsed = load_page(exe, page, work, Page())
    assert parsed.status.get("data-shown") == "part", parsed.status
    numbers = check_path_cells(parsed.paths, report)
    assert numbers >= 8, f"only {numbers} numbers on the page"
    slices = [s for s in parsed.svgs if "data-segments" in s]
    assert len(slices) == 2 and all(int(s["data-segments"]) > 50 for s in slices), slices
    charts = [s.get("data-title", "") for s in parsed.svgs if "data-title" in s]
    assert any(t.startswith("wall") for t in charts), charts
    assert any(t.startswith("pore") for t in charts), charts
    var, coloured = view_stats(exe, page, work, parsed.status)
    w, h, rows = read_png(part + ".png")
    pvar, pcol = region_stats(rows, 0, 0, w, h)
    assert w >= 400 and h >= 400 and pvar > 50 and pcol > 0.03, (w, h, pvar, pcol)
    print(f"check_part_page: status ok, {numbers} numbers equal FILE.json, view variance "
          f"{var:.0f}, coloured {coloured:.2f}; preview {w}x{h}")


main()
