"""Screenshots of an offline viewer page in headless Chromium (tests, docs).

The page (:meth:`hipsim.present.viewer.Viewer.record`) is rendered with no
network and WebGL in software, so what a test sees of it is what any browser
would draw from the page alone.
"""

from __future__ import annotations

import shutil
import subprocess
import tempfile
from pathlib import Path

from ..exceptions import HipsimError

__all__ = ["find_browser", "screenshot"]

_BROWSERS = ("chromium", "chromium-browser", "google-chrome", "google-chrome-stable")


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
    with tempfile.TemporaryDirectory(prefix="hipsim-chromium-") as profile:
        args = [
            browser,
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--disable-quic",
            "--no-first-run",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--disable-extensions",
            "--hide-scrollbars",
            "--mute-audio",
            f"--user-data-dir={profile}",
            "--use-angle=swiftshader",
            "--enable-unsafe-swiftshader",
            "--proxy-server=127.0.0.1:9",
            "--host-resolver-rules=MAP * ~NOTFOUND",
            f"--window-size={int(size[0])},{int(size[1])}",
            "--virtual-time-budget=4000",
            f"--screenshot={out}",
            url,
        ]
        try:
            run = subprocess.run(
                args, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, timeout=timeout_s
            )
        except subprocess.TimeoutExpired:
            raise HipsimError(f"{browser} did not finish the screenshot of {page} in {timeout_s:g} s") from None
    if not out.is_file():
        tail = run.stderr.decode("utf-8", "replace").strip().splitlines()[-3:]
        raise HipsimError(f"{browser} wrote no screenshot of {page}: " + " / ".join(tail))
    return out
