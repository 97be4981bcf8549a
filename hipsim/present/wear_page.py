"""The pages of ``hipsim wear``: one run (its numbers and figures) and two runs compared (verdict first), with provenance.

Each page is a folder: ``index.html`` (figures embedded), the figures as PNG
and SVG, and ``wear.json`` (the numbers, the verdict and the provenance block),
every file written atomically. ``pdf=True`` prints ``index.html`` to
``wear.pdf`` with headless Chromium (:func:`hipsim.present.pages.print_pdf`).
"""

from __future__ import annotations

import base64
import json
from dataclasses import dataclass
from pathlib import Path

from .. import records
from ..files import check_folder, json_ready, output_folder, write_atomic
from ..wear.laws import Wear
from ..wear.maps import WearMaps
from ..wear.summary import WearComparison, difference_maps, run_verdict, wear_comparison, wear_summary
from ..wear.tracks import Tracks
from .figures import save_figure
from .pages import CSS, Verdict, environment, print_pdf
from .provenance import Provenance
from .provenance import provenance as make_provenance
from .wear_figures import (
    WEAR_CAPTIONS,
    plot_cup_maps,
    plot_difference_maps,
    plot_force_track,
    plot_slide_tracks,
    plot_slide_tracks_pair,
)

__all__ = [
    "DEFAULT_TOLERANCE",
    "WearPage",
    "compare_block",
    "write_wear_compare",
    "write_wear_page",
]

#: The relative difference below which two runs count as alike, by default (5 %).
DEFAULT_TOLERANCE = 0.05


@dataclass(frozen=True)
class WearPage:
    """What a page writer wrote: the folder, the page, the JSON, the figures and the PDF (or None)."""

    folder: Path
    index: Path
    json: Path
    figures: tuple[Path, ...]
    pdf: Path | None


def _figures(out: Path, figures) -> tuple[list[tuple[str, str]], list[Path]]:
    embedded, paths = [], []
    for stem, fig in figures:
        png, svg = save_figure(fig, out, stem)
        embedded.append((stem, base64.b64encode(png.read_bytes()).decode("ascii")))
        paths += [png, svg]
    return embedded, paths


def write_wear_page(
    out_dir: str | Path,
    maps: WearMaps,
    tracks: Tracks,
    wear: Wear | None = None,
    provenance: Provenance | None = None,
    notes: tuple[str, ...] = (),
    pdf: bool = False,
) -> WearPage:
    """One run's page: its summary, the slide tracks, the maps, the force track (module docstring)."""
    out = Path(out_dir)
    check_folder(out)
    provenance = provenance or make_provenance()
    summary = wear_summary(maps, wear)
    typed = run_verdict(summary)  # NOT MADE: the page says NOT RATED, with the run's numbers
    verdict = Verdict.of(
        typed,
        (
            f"Per cycle: force track {maps.force_track_mm:.4g} mm, load integral {maps.force_track_load_Nm:.4g} N·m; "
            f"CS {summary.cross_shear_mean:.3g} mean and {summary.cross_shear_max:.3g} at most over the loaded area.",
            f"Wear {summary.wear_mm3_per_Mc:.4g} mm³/Mc ({wear.law})."
            if wear is not None and wear.total_mm3_per_Mc is not None
            else "No wear predicted: give a wear factor or law (no default k is assumed).",
        ),
        not_made="NOT RATED",
    )
    document = {"verdict": typed.to_json(), "provenance": json_ready(provenance.as_dict())} | summary.to_json()
    r = maps.setup.radius_mm
    with output_folder(out):
        embedded, paths = _figures(
            out,
            (
                ("slide_tracks", plot_slide_tracks(tracks, r, f"{maps.name}: slide tracks")),
                ("cup_maps", plot_cup_maps(maps)),
                ("force_track", plot_force_track(tracks, r, f"{maps.name}: force track")),
            ),
        )
        json_path = write_atomic(out / "wear.json", json.dumps(document, indent=2) + "\n")
        page = (
            environment()
            .get_template("wear.html.j2")
            .render(
                css=CSS,
                verdict=verdict,
                provenance=provenance,
                title=provenance.title,
                s=summary,
                notes=notes,
                figures=embedded,
                captions=WEAR_CAPTIONS,
            )
        )
        index = write_atomic(out / "index.html", page)
        printed = print_pdf(index, out / "wear.pdf") if pdf else None
    return WearPage(out, index, json_path, tuple(paths), printed)


def compare_block(verdict: records.Verdict) -> Verdict:
    """The page's block of :func:`hipsim.wear.summary.compare_verdict`: ALIKE, DIFFERENT or NOT COMPARED (NOT MADE)
    with what it judged."""
    return Verdict.of(verdict, not_made="NOT COMPARED")


def write_wear_compare(
    out_dir: str | Path,
    a: tuple[WearMaps, Tracks, Wear | None],
    b: tuple[WearMaps, Tracks, Wear | None],
    tolerance: float = DEFAULT_TOLERANCE,
    provenance: Provenance | None = None,
    notes: tuple[str, ...] = (),
    pdf: bool = False,
) -> tuple[WearPage, records.Verdict, WearComparison]:
    """Two runs on the same cup points compared: the verdict, B − A per quantity and per point (module docstring).

    Returns:
        The page, the verdict (:func:`hipsim.wear.summary.compare_verdict`), and the JSON document written.
    """
    out = Path(out_dir)
    check_folder(out)
    provenance = provenance or make_provenance()
    (maps_a, tracks_a, wear_a), (maps_b, tracks_b, wear_b) = a, b
    document = wear_comparison((maps_a, wear_a), (maps_b, wear_b), tolerance, json_ready(provenance.as_dict()))
    summary_a, summary_b, rows, verdict = document.a, document.b, document.differences, document.verdict
    differences = difference_maps(maps_a, maps_b)  # the maps drawn (the record keeps their largest points)
    r = maps_a.setup.radius_mm
    with output_folder(out):
        embedded, paths = _figures(
            out,
            (
                (
                    "difference_maps",
                    plot_difference_maps(maps_a, differences, f"B ({maps_b.name}) − A ({maps_a.name})"),
                ),
                ("slide_tracks_ab", plot_slide_tracks_pair(tracks_a, tracks_b, r, (maps_a.name, maps_b.name))),
            ),
        )
        json_path = write_atomic(out / "wear.json", json.dumps(document.to_json(), indent=2) + "\n")
        captions = WEAR_CAPTIONS | {"slide_tracks_ab": f"A (left) and B (right): {WEAR_CAPTIONS['slide_tracks']}"}
        page = (
            environment()
            .get_template("wear_compare.html.j2")
            .render(
                css=CSS,
                verdict=compare_block(verdict),
                provenance=provenance,
                title=provenance.title,
                a=summary_a,
                b=summary_b,
                rows=rows,
                tolerance=tolerance,
                notes=notes,
                figures=embedded,
                captions=captions,
            )
        )
        index = write_atomic(out / "index.html", page)
        printed = print_pdf(index, out / "wear.pdf") if pdf else None
    return WearPage(out, index, json_path, tuple(paths), printed), verdict, document
