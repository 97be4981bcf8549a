"""The one headless-Chromium launcher (hipsim.present.browser.run_headless), with a stand-in browser: the flags every
run gets (offline, a fresh profile), the job's own flags after them, and the one-line errors."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

from hipsim.exceptions import HipsimError
from hipsim.present.browser import screenshot
from hipsim.present.pages import print_pdf

#: A stand-in for Chromium: records its arguments and writes the file its --screenshot= or --print-to-pdf= names.
FAKE = """#!{python}
import sys, pathlib, time
args = sys.argv[1:]
pathlib.Path({record!r}).write_text("\\n".join(args))
for arg in args:
    if arg.startswith("--screenshot="):
        pathlib.Path(arg.split("=", 1)[1]).write_bytes(b"png")
    if arg.startswith("--print-to-pdf="):
        pathlib.Path(arg.split("=", 1)[1]).write_bytes(b"%PDF-1.4 stand-in")
    if arg == "--hang":
        time.sleep(30)
"""


def _browser(tmp_path: Path) -> tuple[str, Path]:
    record = tmp_path / "args.txt"
    script = tmp_path / "chromium"
    script.write_text(FAKE.format(python=sys.executable, record=str(record)))
    script.chmod(0o755)
    return str(script), record


def test_screenshots_and_pdfs_get_the_offline_flags_then_their_own(tmp_path):
    browser, record = _browser(tmp_path)
    page = tmp_path / "page.html"
    page.write_text("<html></html>")
    shot = screenshot(page, tmp_path / "shot.png", time_s=0.5, size=(300, 200), browser=browser)
    args = record.read_text().splitlines()
    assert shot.read_bytes() == b"png" and args[0] == "--headless" and args[-1] == page.resolve().as_uri() + "#t=0.5"
    for offline in ("--no-sandbox", "--proxy-server=127.0.0.1:9", "--host-resolver-rules=MAP * ~NOTFOUND"):
        assert offline in args
    profile = next(a for a in args if a.startswith("--user-data-dir="))
    assert "hipsim-chromium-" in profile and not Path(profile.split("=", 1)[1]).exists()  # fresh, and removed
    assert "--window-size=300,200" in args and args.index(profile) < args.index("--window-size=300,200")
    pdf = print_pdf(page, tmp_path / "page.pdf", browser=browser)
    args = record.read_text().splitlines()
    assert pdf.read_bytes().startswith(b"%PDF-") and "--no-pdf-header-footer" in args and "--screenshot" not in args
    assert args[:2] == ["--headless", "--no-sandbox"]


def test_a_browser_that_hangs_or_writes_nothing_is_one_line(tmp_path):
    from hipsim.present.browser import run_headless

    browser, _ = _browser(tmp_path)
    with pytest.raises(HipsimError, match=r"did not print page\.html to PDF in 0\.5 s$"):
        run_headless(browser, "file:///x", ("--hang",), "print page.html to PDF", 0.5)
    with pytest.raises(HipsimError, match="wrote no screenshot of"):
        screenshot(tmp_path / "page.html", tmp_path / "none.png", browser=str(Path(sys.executable)))
