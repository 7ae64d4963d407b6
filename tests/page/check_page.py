"""Opens a report.html in headless Chromium from a file URL with the network cut off (every host
name resolves nowhere) and checks (docs/report.md): the page's status is "ok" (no script error,
no console.error, WebGL available), no "Uncaught" error in the browser's log, the 3D view in a
screenshot is not blank (grey-level variance and coloured fraction of the canvas's box), every
number cell (data-key, data-value) equals the report.json it came from, and the other views
(report.html#nodal&tiles=2, #member=NAME&tiles=3, ...) load with no error and show what they
name. A run page with report.json's `properties` has its table (id "properties"): every cell's
data-path is a JSON pointer into report.json and its data-value and text equal that number, with
a column per solid (CMC, nodal); every picture on the page (img with alt) is a PNG that is not
blank, and a folder's youngs_modulus.png / properties_chart.png is on its page.

usage: check_page.py CHROMIUM report.html WORKDIR [MEMBER_DIR_PARENT]
For a run page the numbers are compared with report.json beside report.html; for a sweep page
(rows data-member=NAME) with NAME/report.json.
"""
import base64
import html.parser
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from headless_page import chromium, pointer, shown_matches  # noqa: E402
from png_check import read_png, region_stats  # noqa: E402

class Cells(html.parser.HTMLParser):
    """The status div and every td with data-key (with its row's data-member, if any)."""

    def __init__(self):
        super().__init__()
        self.status, self.cells, self.member, self._cell = None, [], None, None
        self.paths, self.images, self.properties_columns, self._in_properties = [], {}, 0, False
        self._path = None

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if a.get("id") == "status":
            self.status = a
        if tag == "tr":
            self.member = a.get("data-member")
        if tag == "td" and "data-key" in a:
            self._cell = [self.member, a["data-key"], a.get("data-value"), ""]
        if tag == "td" and "data-path" in a:
            self._path = [a["data-path"], a.get("data-value"), ""]
        if tag == "table":
            self._in_properties = a.get("id") == "properties"
        if tag == "th" and self._in_properties and self.properties_columns >= 0:
            self.properties_columns += 1
        if tag == "img" and a.get("alt"):
            self.images[a["alt"]] = a.get("src", "")

    def handle_data(self, data):
        if self._cell is not None:
            self._cell[3] += data
        if self._path is not None:
            self._path[2] += data

    def handle_endtag(self, tag):
        if tag == "td" and self._cell is not None:
            self.cells.append(tuple(self._cell))
            self._cell = None
        if tag == "td" and self._path is not None:
            self.paths.append(tuple(self._path))
            self._path = None
        if tag == "tr" and self._in_properties and self.properties_columns > 0:
            self.properties_columns = -self.properties_columns  # the header row is counted
        if tag == "table":
            self._in_properties = False


def main():
    exe, page, work = sys.argv[1:4]
    folder = os.path.dirname(os.path.abspath(page))
    dom, log = chromium(exe, page, work, "--dump-dom")
    assert "Uncaught" not in log, [l for l in log.splitlines() if "Uncaught" in l]
    parsed = Cells()
    parsed.feed(dom)
    status = parsed.status
    assert status is not None, "no #status in the page"
    assert status.get("data-status") == "ok", f"page status: {status}"
    # Numbers: every cell with a data-value equals report.json's value exactly, and its text
    # shows the same number to the printed digits.
    reports = {}
    checked = 0
    for member, key, value, text in parsed.cells:
        path = os.path.join(folder, member, "report.json") if member else \
            os.path.join(folder, "report.json")
        report = reports.setdefault(path, json.load(open(path)))
        assert key in report, (path, key)
        if value is None:
            continue
        want = report[key]
        assert float(value) == float(want), (member, key, value, want)
        assert shown_matches(text, want), (key, text, want)
        checked += 1
    assert checked >= 5, f"only {checked} numbers on the page"
    # The properties table: every number equals report.json's at its pointer.
    run_report = json.load(open(os.path.join(folder, "report.json"))) \
        if os.path.exists(os.path.join(folder, "report.json")) else {}
    if "properties" in run_report:
        numbers = 0
        for path, value, text in parsed.paths:
            if value is None:
                continue
            want = pointer(run_report, path)
            assert float(value) == float(want), (path, value, want)
            assert shown_matches(text, want), (path, text, want)
            numbers += 1
        solids = run_report["properties"]
        columns = 1 + ("nodal" in solids) + ("nodal_offset" in solids)
        assert -parsed.properties_columns == columns + 1, (parsed.properties_columns, columns)
        assert numbers >= 20 * columns, f"only {numbers} property numbers on the page"
        checked += numbers
    else:
        assert not parsed.paths, "a properties table without report.json's properties"
    # Pictures: each one a PNG that is not blank; the folder's property pictures are shown.
    for name in ("youngs_modulus", "properties_chart"):
        if os.path.exists(os.path.join(folder, name + ".png")):
            assert name in parsed.images, f"{name}.png is not on the page"
    for alt, src in parsed.images.items():
        assert src.startswith("data:image/png;base64,"), (alt, src[:40])
        png = os.path.join(work, f"img-{alt}.png")
        with open(png, "wb") as f:
            f.write(base64.b64decode(src.split(",", 1)[1]))
        w, h, rows = read_png(png)
        var, _ = region_stats(rows, 0, 0, w, h)
        assert w > 200 and h > 200 and var > 50, (alt, w, h, var)
    # The 3D view is drawn: a screenshot's canvas box is not blank.
    shot = os.path.join(work, "shot.png")
    chromium(exe, page, work, f"--screenshot={shot}")
    x0, y0, x1, y1 = (int(v) for v in status["data-canvas"].split(","))
    w, h, rows = read_png(shot)
    x1, y1 = min(x1, w), min(y1, h)
    assert x1 - x0 > 100 and y1 - y0 > 100, (x0, y0, x1, y1, w, h)
    var, coloured = region_stats(rows, x0 + 2, y0 + 2, x1 - 2, y1 - 2)
    assert var > 50 and coloured > 0.05, \
        f"blank 3D view: variance {var:.1f}, coloured {coloured:.3f}"
    # The other views (nodal twin or another member, 2^3 and 3^3 tiles) from the address.
    members = [m for m, _, _, _ in parsed.cells if m]
    if members:
        views = [(f"#member={members[-1]}&tiles={t}", f"{members[-1]},{t}") for t in (2, 3)]
    else:
        views = [(f"#nodal&tiles={t}", f"nodal,{t}") for t in (2, 3)] + [("#tiles=3", "relaxed,3")]
    for fragment, shown in views:
        dom, log = chromium(exe, page, work, "--dump-dom", fragment=fragment)
        view = Cells()
        view.feed(dom)
        assert "Uncaught" not in log and view.status.get("data-status") == "ok", \
            (fragment, view.status)
        assert view.status.get("data-shown") == shown, (fragment, view.status)
    names = ", ".join(f for f, _ in views)
    print(f"check_page: {os.path.basename(folder)}: status ok, {checked} numbers equal "
          f"report.json, view variance {var:.0f}, coloured {coloured:.2f}; views {names} ok")


main()
