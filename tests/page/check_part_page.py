"""Opens a part's FILE.html (cmcsurf scaffold) in headless Chromium from a file URL with the
network cut off, as check_page.py does a run's page, and checks: the page's status is "ok"
and it shows the part, no "Uncaught" error, the 3D view in a screenshot is not blank, every
number cell (data-path, a JSON pointer into FILE.json, and data-value) equals FILE.json's
number and its text shows it, the slices and the wall and pore distributions are drawn, and
FILE.png is a picture that is not blank.

usage: check_part_page.py CHROMIUM FILE.html WORKDIR
"""
import html.parser
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from headless_page import chromium, pointer, shown_matches  # noqa: E402
from png_check import read_png, region_stats  # noqa: E402

class Page(html.parser.HTMLParser):
    def __init__(self):
        super().__init__()
        self.status, self.paths, self._path, self.svgs = None, [], None, []

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if a.get("id") == "status":
            self.status = a
        if tag == "td" and "data-path" in a:
            self._path = [a["data-path"], a.get("data-value"), ""]
        if tag == "svg":
            self.svgs.append(a)

    def handle_data(self, data):
        if self._path is not None:
            self._path[2] += data

    def handle_endtag(self, tag):
        if tag == "td" and self._path is not None:
            self.paths.append(tuple(self._path))
            self._path = None


def main():
    exe, page, work = sys.argv[1:4]
    part = page[:-len(".html")]
    report = json.load(open(part + ".json"))
    dom, log = chromium(exe, page, work, "--dump-dom")
    assert "Uncaught" not in log, [line for line in log.splitlines() if "Uncaught" in line]
    parsed = Page()
    parsed.feed(dom)
    assert parsed.status is not None, "no #status in the page"
    assert parsed.status.get("data-status") == "ok", f"page status: {parsed.status}"
    assert parsed.status.get("data-shown") == "part", parsed.status
    numbers = 0
    for path, value, text in parsed.paths:
        if value is None:
            continue
        want = pointer(report, path)
        assert float(value) == float(want), (path, value, want)
        assert shown_matches(text.replace("−", "-"), want), (path, text, want)
        numbers += 1
    assert numbers >= 8, f"only {numbers} numbers on the page"
    slices = [s for s in parsed.svgs if "data-segments" in s]
    assert len(slices) == 2 and all(int(s["data-segments"]) > 50 for s in slices), slices
    charts = [s.get("data-title", "") for s in parsed.svgs if "data-title" in s]
    assert any(t.startswith("wall") for t in charts), charts
    assert any(t.startswith("pore") for t in charts), charts
    shot = os.path.join(work, "shot.png")
    chromium(exe, page, work, f"--screenshot={shot}")
    x0, y0, x1, y1 = (int(v) for v in parsed.status["data-canvas"].split(","))
    w, h, rows = read_png(shot)
    x1, y1 = min(x1, w), min(y1, h)
    var, coloured = region_stats(rows, x0 + 2, y0 + 2, x1 - 2, y1 - 2)
    assert var > 50 and coloured > 0.05, \
        f"blank 3D view: variance {var:.1f}, coloured {coloured:.3f}"
    w, h, rows = read_png(part + ".png")
    pvar, pcol = region_stats(rows, 0, 0, w, h)
    assert w >= 400 and h >= 400 and pvar > 50 and pcol > 0.03, (w, h, pvar, pcol)
    print(f"check_part_page: status ok, {numbers} numbers equal FILE.json, view variance "
          f"{var:.0f}, coloured {coloured:.2f}; preview {w}x{h}")


main()
