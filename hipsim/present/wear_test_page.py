"""The wear test's report: verdict first; per station motion, friction, wear measured and predicted; provenance.

A folder: ``index.html`` (figure embedded), the figure as PNG and SVG,
``wear_test.json`` (the numbers, the verdict, the provenance block), and with
``pdf=True`` ``wear_test.pdf`` (headless Chromium); every file written atomically.
"""

from __future__ import annotations

import json
from pathlib import Path

from ..files import check_folder, json_ready, output_folder, write_atomic
from ..wear.test_context import StationContext
from ..wear.test_result import ONE_STATION, WearTest
from ..wear.test_summary import wear_test_summary
from .pages import CSS, Verdict, environment, print_pdf
from .provenance import Provenance
from .wear_page import WearPage, _figures
from .wear_test_figures import WEAR_TEST_CAPTIONS, plot_measured_predicted

__all__ = ["write_wear_test_page"]


def write_wear_test_page(
    out_dir: str | Path,
    result: WearTest,
    contexts: tuple[StationContext, ...],
    provenance: Provenance,
    notes: tuple[str, ...] = (),
    pdf: bool = False,
) -> WearPage:
    """The test's page (module docstring)."""
    out = Path(out_dir)
    check_folder(out)
    verdict = Verdict.of(result.verdict, result.lines, not_made=ONE_STATION)  # rendered, not made here
    summary = wear_test_summary(result, contexts).to_json()
    document = json_ready(summary | {"notes": list(notes), "provenance": provenance.as_dict()})
    by_name = {c.station: c for c in contexts}
    with output_folder(out):
        embedded, paths = _figures(out, (("measured_predicted", plot_measured_predicted(result)),))
        json_path = write_atomic(out / "wear_test.json", json.dumps(document, indent=2) + "\n")
        page = (
            environment()
            .get_template("wear_test.html.j2")
            .render(
                css=CSS,
                verdict=verdict,
                provenance=provenance,
                title=provenance.title,
                result=result,
                contexts=by_name,
                notes=notes,
                figures=embedded,
                captions=WEAR_TEST_CAPTIONS,
            )
        )
        index = write_atomic(out / "index.html", page)
        printed = print_pdf(index, out / "wear_test.pdf") if pdf else None
    return WearPage(out, index, json_path, tuple(paths), printed)
