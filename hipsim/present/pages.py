"""What the HTML pages share: the Jinja environment, the style sheet, the verdict block, and printing a page to PDF.

Every page (the design report, the comparison) is rendered from a template in
``templates/`` (autoescaped, undefined names an error) with the partials
``provenance.html.j2`` (where the numbers came from) and ``verdict.html.j2``
(the pass/fail block at the top of the page, its word and symbol readable in
black and white, the colour only a second cue).

PDF. :func:`print_pdf` prints a written page with headless Chromium
(``--print-to-pdf``): the PDF is the same page, laid out by the same engine
a reader's browser uses, with its tables, embedded figures and print styles.
matplotlib's PDF backend draws figures, not HTML, so it could only give
another document; WeasyPrint would add a native dependency (Pango) for what a
browser already does. The tests and the viewer already use Chromium.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from .. import records
from ..exceptions import HipsimError
from ..records import Level, Record
from .browser import find_browser, run_headless

__all__ = ["CSS", "Verdict", "environment", "print_pdf", "require_pdf_renderer", "sentence"]

CSS = """
body { font-family: system-ui, -apple-system, "Segoe UI", sans-serif; margin: 2em auto; max-width: 1200px; color: #222; padding: 0 1em; }
h1 { font-size: 1.6em; margin-bottom: 0.2em; }
h2 { font-size: 1.25em; border-bottom: 1px solid #ccc; padding-bottom: 0.2em; margin-top: 1.8em; }
table { border-collapse: collapse; margin: 0.6em 0 1em; font-size: 0.85em; }
th, td { border: 1px solid #ccc; padding: 0.25em 0.6em; text-align: right; }
th { background: #f0f0f0; }
th.l, td.l { text-align: left; }
tr.fail td { background: #fde8e8; }
tr.binding td { font-weight: bold; }
tr.unchecked td { color: #777; }
.meta { color: #555; font-size: 0.9em; }
.note { background: #fff8e0; border-left: 4px solid #e0b000; padding: 0.4em 0.8em; margin: 0.4em 0; }
.pass { color: #0a7a0a; font-weight: bold; }
.fail { color: #c00000; font-weight: bold; }
.verdict { border: 3px solid #777; padding: 0.6em 1em; margin: 1em 0; }
.verdict .word { font-size: 1.4em; font-weight: bold; letter-spacing: 0.05em; }
.verdict p { margin: 0.3em 0; }
.verdict.pass-box { border-color: #0a7a0a; background: #eef8ee; }
.verdict.fail-box { border: 5px double #c00000; background: #fdeeee; }
.verdict.open-box { border-style: dashed; background: #f6f6f6; }
.provenance { font-size: 0.85em; color: #333; border: 1px solid #ccc; padding: 0.4em 0.8em; margin: 0.6em 0; }
.provenance table { margin: 0.3em 0; font-size: 1em; }
.provenance td { text-align: left; }
.provenance td code { word-break: break-all; }
.provenance code { font-size: 0.95em; }
tr.identified td { font-weight: bold; }
figure { margin: 1em 0 2em; }
figure img { max-width: 100%; border: 1px solid #ddd; }
figcaption { font-size: 0.9em; color: #444; }
@media print {
  body { margin: 0; max-width: none; font-size: 10pt; }
  figure, table, .verdict, .provenance { break-inside: avoid; }
  h2, h3 { break-after: avoid; }
  a { color: inherit; text-decoration: none; }
}
@page { size: A4; margin: 14mm 12mm; }
"""


@dataclass(frozen=True)
class Verdict(Record):
    """The block at the top of a page.

    Attributes:
        state: "pass", "fail" or "open" (nothing decided: no rating, no acceptance threshold).
        word: the verdict in words ("PASS", "FAIL", "NOT RATED").
        lines: one or two sentences with the numbers that decide it (the binding check and its margin).
    """

    state: str
    word: str
    lines: tuple[str, ...]

    @classmethod
    def of(cls, verdict: records.Verdict, lines: tuple[str, ...] = (), not_made: str | None = None) -> Verdict:
        """The block of a verdict made beside its analysis: its level's word and colour, and ``lines``.

        The page decides nothing: the state is the level's (:attr:`hipsim.records.Level.state`) and so is the word,
        except that a verdict NOT MADE may say on the page what was not made (``not_made``: "NOT RATED").

        Args:
            verdict: the verdict (:class:`hipsim.records.Verdict`).
            lines: the sentences under the word (default: what it judged, as a sentence).
            not_made: the page's word for a verdict NOT MADE (default: "NOT MADE").
        """
        word = not_made if not_made is not None and verdict.level is Level.NOT_MADE else verdict.level.value
        return cls(verdict.level.state, word, lines or (sentence(verdict.judged),))

    @property
    def symbol(self) -> str:
        return {"pass": "✔", "fail": "✘"}.get(self.state, "–")

    def as_dict(self) -> dict:
        """The block as JSON data (:meth:`to_json`)."""
        return self.to_json()


def sentence(text: str) -> str:
    """``text`` as a sentence on a page: its first letter upper case, a full stop at its end."""
    if not text:
        return text
    text = text[0].upper() + text[1:]
    return text if text.endswith((".", "!", "?")) else text + "."


def environment():
    """The Jinja environment of the page templates (autoescaped, strict)."""
    import jinja2

    return jinja2.Environment(
        loader=jinja2.PackageLoader("hipsim.present", "templates"),
        autoescape=True,
        undefined=jinja2.StrictUndefined,
        trim_blocks=True,
        lstrip_blocks=True,
    )


def require_pdf_renderer() -> str:
    """The Chromium that prints pages to PDF, or a clear error before any work is done."""
    browser = find_browser()
    if browser is None:
        raise HipsimError(
            "--pdf needs Chromium (or Chrome) to print the page, and none is on PATH "
            "(apt-get install chromium); run without --pdf and print index.html from a browser"
        )
    return browser


def print_pdf(page: str | Path, out: str | Path, browser: str | None = None, timeout_s: float = 120.0) -> Path:
    """Print an offline HTML page to a PDF with headless Chromium, no network, no header or footer lines.

    Args:
        page: the HTML file.
        out: the PDF to write.
        browser: the Chromium executable; default :func:`hipsim.present.browser.find_browser`.
        timeout_s: give up after this long, in [s].

    Returns:
        The PDF's path.

    Raises:
        HipsimError: no browser, or it wrote no PDF.
    """
    browser = browser or require_pdf_renderer()
    out = Path(out).resolve()
    out.unlink(missing_ok=True)
    options = ("--no-pdf-header-footer", "--print-to-pdf-no-header", f"--print-to-pdf={out}")
    errors = run_headless(browser, Path(page).resolve().as_uri(), options, f"print {page} to PDF", timeout_s)
    if not out.is_file() or out.stat().st_size == 0 or not out.read_bytes()[:5] == b"%PDF-":
        raise HipsimError(f"{browser} wrote no PDF of {page}: " + errors)
    return out
