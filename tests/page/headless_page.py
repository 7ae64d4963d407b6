"""What check_page.py (run and sweep pages) and check_part_page.py (a part's page) share:
headless Chromium from a file URL with the network cut off (every host name resolves nowhere),
JSON pointers into the report a page came from, and whether a cell's text shows a number."""
import os
import subprocess

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
