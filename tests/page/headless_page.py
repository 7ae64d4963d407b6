"""What check_page.py (run and sweep pages) and check_part_page.py (a part's page) share:
headless Chromium from a file URL with the network cut off (every host name resolves nowhere),
the page's status and its data-path cells, a screenshot's 3D view, JSON pointers into the
report a page came from, and whether a cell's text shows a number."""
import html.parser
import os
import subprocess

from png_check import read_png, region_stats

FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--use-angle=swiftshader",
         "--enable-unsafe-swiftshader", "--host-resolver-rules=MAP * ~NOTFOUND",
         "--no-first-run", "--disable-extensions", "--mute-audio", "--hide-scrollbars",
         "--disable-dev-shm-usage",
         "--window-size=1200,1000", "--virtual-time-budget=15000", "--enable-logging=stderr",
         "--v=0"]


def chromium(exe, page, work, *extra, fragment=""):
    """(stdout, stderr) of Chromium opening page#fragment with a profile under work."""
    profile = os.path.join(work, "profile")
    url = "file://" + os.path.abspath(page) + fragment
    cmd = [exe, *FLAGS, f"--user-data-dir={profile}", *extra, url]
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
    assert p.returncode == 0, f"chromium exited {p.returncode}: {p.stderr[-2000:]}"
    return p.stdout, p.stderr


class StatusAndPaths(html.parser.HTMLParser):
    """The status div's attributes and every td with data-path: (path, data-value, text).
    A page's own parser extends it (calling these first)."""

    def __init__(self):
        super().__init__()
        self.status, self.paths, self._path = None, [], None

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if a.get("id") == "status":
            self.status = a
        if tag == "td" and "data-path" in a:
            self._path = [a["data-path"], a.get("data-value"), ""]

    def handle_data(self, data):
        if self._path is not None:
            self._path[2] += data

    def handle_endtag(self, tag):
        if tag == "td" and self._path is not None:
            self.paths.append(tuple(self._path))
            self._path = None


def load_page(exe, page, work, parser, fragment=""):
    """parser fed page#fragment's DOM, with no "Uncaught" error in the log and status "ok"."""
    dom, log = chromium(exe, page, work, "--dump-dom", fragment=fragment)
    assert "Uncaught" not in log, \
        (fragment, [line for line in log.splitlines() if "Uncaught" in line])
    parser.feed(dom)
    assert parser.status is not None, f"no #status in the page {fragment}"
    assert parser.status.get("data-status") == "ok", f"page {fragment} status: {parser.status}"
    return parser


def view_stats(exe, page, work, status):
    """(variance, coloured fraction) of the 3D view in a screenshot, the canvas box the status
    names; asserts it is drawn (not blank)."""
    shot = os.path.join(work, "shot.png")
    chromium(exe, page, work, f"--screenshot={shot}")
    x0, y0, x1, y1 = (int(v) for v in status["data-canvas"].split(","))
    w, h, rows = read_png(shot)
    x1, y1 = min(x1, w), min(y1, h)
    assert x1 - x0 > 100 and y1 - y0 > 100, (x0, y0, x1, y1, w, h)
    var, coloured = region_stats(rows, x0 + 2, y0 + 2, x1 - 2, y1 - 2)
    assert var > 50 and coloured > 0.05, \
        f"blank 3D view: variance {var:.1f}, coloured {coloured:.3f}"
    return var, coloured


def check_path_cells(paths, report):
    """Every data-path cell with a data-value equals report's number at its pointer, and its text
    shows it (a typographic minus read as '-'). Returns how many were checked."""
    numbers = 0
    for path, value, text in paths:
        if value is None:
            continue
        want = pointer(report, path)
        assert float(value) == float(want), (path, value, want)
        assert shown_matches(text.replace("\u2212", "-"), want), (path, text, want)
        numbers += 1
    return numbers


def pointer(doc, path):
    """The value at a JSON pointer (RFC 6901) in doc."""
    for part in path.split("/")[1:]:
        part = part.replace("~1", "/").replace("~0", "~")
        doc = doc[int(part)] if isinstance(doc, list) else doc[part]
    return doc


def shown_matches(text, want):
    """The cell's text shows want to its printed digits (a trailing % is a percentage)."""
    shown = text.split("±")[0].strip().rstrip("%")
    scale = 100.0 if text.strip().endswith("%") else 1.0
    digits = shown.lstrip("+-").split("e")[0].split(".")
    ulp = 10.0 ** -len(digits[1]) if len(digits) > 1 else 1.0
    if "e" in shown:
        ulp *= 10.0 ** int(shown.split("e")[1])
    return abs(float(shown) - scale * float(want)) <= 0.51 * ulp
