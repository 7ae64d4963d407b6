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
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from headless_page import (  # noqa: E402
    StatusAndPaths, check_path_cells, load_page, shown_matches, view_stats)
from png_check import read_png, region_stats  # noqa: E402

class Cells(StatusAndPaths):
    """The status, the data-path cells, every td with data-key (with its row's data-member, if
    any), the properties table's columns and the pictures."""

    def __init__(self):
        super().__init__()
        self.cells, self.member, self._cell = [], None, None
        self.images, self.properties_columns, self._in_properties = {}, 0, False

    def handle_starttag(self, tag, attrs):
        super().handle_starttag(tag, attrs)
        a = dict(attrs)
        if tag == "tr":
            self.member = a.get("data-member")
        if tag == "td" and "data-key" in a:
            self._cell = [self.member, a["data-key"], a.get("data-value"), ""]
        if tag == "table":
            self._in_properties = a.get("id") == "properties"
        if tag == "th" and self._in_properties and self.properties_columns >= 0:
            self.properties_columns += 1
        if tag == "img" and a.get("alt"):
            self.images[a["alt"]] = a.get("src", "")

    def handle_data(self, data):
        super().handle_data(data)
        if self._cell is not None:
            self._cell[3] += data

    def handle_endtag(self, tag):
        super().handle_endtag(tag)
        if tag == "td" and self._cell is not None:
            self.cells.append(tuple(self._cell))
            self._cell = None
        if tag == "tr" and self._in_properties and self.properties_columns > 0:
            self.properties_columns = -self.properties_columns  # the header row is counted
        if tag == "table":
            self._in_properties = False


def main():
    exe, page, work = sys.argv[1:4]
    folder = os.path.dirname(os.path.abspath(page))
    parsed = load_page(exe, page, work, Cells())
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
        numbers = check_path_cells(parsed.paths, run_report)
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
    var, coloured = view_stats(exe, page, work, parsed.status)
    # The other views (nodal twin or another member, 2^3 and 3^3 tiles) from the address.
    members = [m for m, _, _, _ in parsed.cells if m]
    if members:
        views = [(f"#member={members[-1]}&tiles={t}", f"{members[-1]},{t}") for t in (2, 3)]
    else:
        views = [(f"#nodal&tiles={t}", f"nodal,{t}") for t in (2, 3)] + [("#tiles=3", "relaxed,3")]
    for fragment, shown in views:
        view = load_page(exe, page, work, Cells(), fragment=fragment)
        assert view.status.get("data-shown") == shown, (fragment, view.status)
    names = ", ".join(f for f, _ in views)
    print(f"check_page: {os.path.basename(folder)}: status ok, {checked} numbers equal "
          f"report.json, view variance {var:.0f}, coloured {coloured:.2f}; views {names} ok")


main()
