"""Headless Chromium, offline: the one launcher (:func:`run_headless`), and screenshots of a viewer page (tests, docs).

The page (:meth:`hipsim.present.viewer.Viewer.record`) is rendered with no
network and WebGL in software, so what a test sees of it is what any browser
would draw from the page alone. :func:`hipsim.present.pages.print_pdf` prints
pages to PDF through the same launcher.
"""

from __future__ import annotations

import shutil
import subprocess
import tempfile
from collections.abc import Sequence
from pathlib import Path

from ..exceptions import HipsimError

__all__ = ["find_browser", "run_headless", "screenshot"]

_BROWSERS = ("chromium", "chromium-browser", "google-chrome", "google-chrome-stable")

#: Every run: headless, no sandbox or GPU, no first-run or background work, and no network (a dead proxy, no names).
_OFFLINE = (
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--disable-extensions",
    "--mute-audio",
    "--proxy-server=127.0.0.1:9",
    "--host-resolver-rules=MAP * ~NOTFOUND",
)


def run_headless(browser: str, url: str, options: Sequence[str], what: str, timeout_s: float) -> str:
    """Run headless Chromium offline on ``url``, in a fresh profile, with ``options`` (what to write, and how).

    Args:
        browser: the executable.
        url: the page's address.
        options: the run's own flags (``--screenshot=…``, ``--print-to-pdf=…``, window size …).
        what: the job in words, for the timeout's message ("print page.html to PDF").
        timeout_s: give up after this long, in [s].

    Returns:
        The last lines of the browser's standard error, joined by " / " (for a message when it wrote nothing).

    Raises:
        HipsimError: it did not finish in time.
    """
    with tempfile.TemporaryDirectory(prefix="hipsim-chromium-") as profile:
        args = [browser, *_OFFLINE, f"--user-data-dir={profile}", *options, url]
        try:
            run = subprocess.run(
                args, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, timeout=timeout_s
            )
        except subprocess.TimeoutExpired:
            raise HipsimError(f"{browser} did not {what} in {timeout_s:g} s") from None
    return " / ".join(run.stderr.decode("utf-8", "replace").strip().splitlines()[-3:])


def find_browser() -> str | None:
    """Path of a Chromium (or Chrome) executable on PATH, or None."""
    for name in _BROWSERS:
        path = shutil.which(name)
        if path:
            return path
    return None


def screenshot(
    page: str | Path,
    out: str | Path,
    time_s: float | None = None,
    size: tuple[int, int] = (900, 700),
    browser: str | None = None,
    timeout_s: float = 90.0,
) -> Path:
    """Render an offline page (from :meth:`hipsim.present.viewer.Viewer.record`) in headless Chromium and save a PNG.

    The browser gets no network (a dead proxy, no name resolution) and
    renders WebGL in software (SwiftShader).

    Args:
        page: the HTML file.
        out: the PNG to write.
        time_s: animation time to pause at, in [s] (the page's ``#t=`` address); None: as it loads.
        size: window width and height in pixels.
        browser: the executable; default :func:`find_browser`.
        timeout_s: give up after this long.

    Returns:
        The PNG's path.

    Raises:
        HipsimError: no browser, or it wrote no image.
    """
    browser = browser or find_browser()
    if browser is None:
        raise HipsimError("no Chromium found (apt-get install chromium)")
    out = Path(out).resolve()
    out.unlink(missing_ok=True)
    url = Path(page).resolve().as_uri() + (f"#t={float(time_s)!r}" if time_s is not None else "")
    options = (
        "--hide-scrollbars",
        "--use-angle=swiftshader",
        "--enable-unsafe-swiftshader",
        f"--window-size={int(size[0])},{int(size[1])}",
        "--virtual-time-budget=4000",
        f"--screenshot={out}",
    )
    errors = run_headless(browser, url, options, f"finish the screenshot of {page}", timeout_s)
    if not out.is_file():
        raise HipsimError(f"{browser} wrote no screenshot of {page}: " + errors)
    return out
