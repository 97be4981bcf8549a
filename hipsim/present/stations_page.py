"""Two stations drawn and written: each platform's three angle errors over the motion (the paper's Fig. 7), the
tolerance table, and the calibration's record.

:func:`write_stations` writes a folder a lab can hand on, as ``iso-check``
does: the figure as PNG and SVG, ``index.html`` (one self-contained page, the
PNG embedded) and ``stations.json``.
"""

from __future__ import annotations

import base64
import json
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from .. import records
from ..files import check_folder, json_ready, output_folder, write_atomic
from ..records import Level
from ..stations.summary import SlidersSummary, StationSummary, sliders_verdict, stations_verdict
from ..stations.tolerance_summary import ToleranceSummary, tolerance_verdict
from .figures import _figure, save_figure
from .pages import CSS, Verdict, environment
from .provenance import Provenance

__all__ = ["StationFiles", "plot_station_errors", "station_verdict", "write_stations"]

_ANGLES = (("α flexion/extension", "tab:blue"), ("β abduction/adduction", "tab:orange"), ("γ rotation", "tab:green"))


@dataclass(frozen=True)
class StationFiles:
    """What :func:`write_stations` wrote: the folder, the page, the JSON, the figure (PNG, SVG) if drawn."""

    folder: Path
    index: Path
    json: Path
    figure: tuple[Path, Path] | None


def plot_station_errors(t: np.ndarray, errors_deg: np.ndarray, control: str):
    """Each platform's attitude error α, β, γ in [deg] (N, 2, 3) over time t in [s] (N,): one panel per platform."""
    fig, axes = _figure(2, height=2.4)
    for j, ax in enumerate(axes):
        role = "controlled" if control in (str(j + 1), "both") else "following"
        for k, (label, colour) in enumerate(_ANGLES):
            ax.plot(t, errors_deg[:, j, k], color=colour, lw=1.0, label=label)
        ax.axhline(0.0, color="0.5", lw=0.6)
        ax.set_ylabel(f"m_{j + 1} error [°]")
        ax.set_title(f"platform m_{j + 1} ({role})", fontsize=10, loc="left")
        ax.legend(fontsize=8, loc="upper right", ncol=3)
    axes[-1].set_xlabel("t [s]")
    return fig


def station_verdict(summary: StationSummary, verdict: records.Verdict | None = None) -> Verdict:
    """The block at the top of the page: the largest error of the two stations, each station's ISO verdict and, in
    lines of their own, a desired motion that is not the ISO 14242-1 waveform.

    Args:
        summary: the run's summary.
        verdict: its verdict (default :func:`hipsim.stations.summary.stations_verdict`), rendered, not made here.
    """
    verdict = verdict or stations_verdict(summary)
    j, angle, value = summary.worst
    lines = [
        f"--control {summary.control}: the largest attitude error is {abs(value.peak_deg):.3g}° ({angle} of m_{j}, "
        f"t = {value.peak_at_s:.4g} s); RMS over both platforms and angles {summary.rms_error_deg:.3g}°."
    ]
    if verdict.level == Level.NOT_MADE:
        lines.append("No whole ISO 14242-1 cycle with a load to check.")
        return Verdict.of(verdict, tuple(lines), not_made="NO ISO CHECK")
    lines.append(verdict.judged)
    lines += [f"Station {p.platform}: {p.iso.desired_line}." for p in summary.platforms if p.iso and p.iso.desired_line]
    return Verdict.of(verdict, tuple(lines))


def _verdicts(
    summary: StationSummary | None, tolerance: ToleranceSummary | None, sliders: SlidersSummary | None
) -> tuple[records.Verdict, Verdict]:
    """The page's verdict (made beside its analysis) and its block: the run's, else the attitudes', else the study's."""
    if summary is not None:
        verdict = stations_verdict(summary)
        return verdict, station_verdict(summary, verdict)
    if sliders is not None:
        verdict = sliders_verdict(sliders)
        return verdict, Verdict.of(verdict, not_made="ATTITUDES")
    if tolerance is not None:
        verdict = tolerance_verdict(tolerance)
        return verdict, Verdict.of(verdict, ("Manufacturing tolerances.",), not_made="TOLERANCES")
    raise ValueError("write_stations: give a run's summary, a tolerance study or the sliders' attitudes")


def write_stations(
    out_dir: str | Path,
    document: dict[str, Any],
    summary: StationSummary | None = None,
    t: np.ndarray | None = None,
    errors_deg: np.ndarray | None = None,
    provenance: Provenance | None = None,
    tolerance: ToleranceSummary | None = None,
    sliders: SlidersSummary | None = None,
    fig7: Any = None,
) -> StationFiles:
    """Write ``stations.json``, ``index.html`` and, given the errors, the figure ``errors.png``/``.svg``, atomically.

    ``stations.json``'s ``verdict`` is the run's :func:`~hipsim.stations.summary.stations_verdict` (a
    :class:`hipsim.records.Verdict`); without a run, the attitudes' or the study's (NOT MADE: no limit is set).

    Args:
        out_dir: the folder (made if missing).
        document: what else the run found, JSON-ready: ``table`` (the per-sample table's path) or nothing.
        summary: the run's summary on the desired motion (:func:`hipsim.stations.summary.station_summary`).
        t: sample times in [s] (N,) for the figure; None for no figure.
        errors_deg: each platform's errors in [deg] (N, 2, 3).
        provenance: the page's provenance block.
        tolerance: a tolerance study's summary (percentiles and sensitivity).
        sliders: the attitudes from a log's carriages.
        fig7: a log's Fig. 7 (:func:`hipsim.present.fig7.plot_fig7`), written as ``fig7.png``/``.svg`` and shown on
            the page when there is no error figure; None for none.
    """
    from .provenance import provenance as make_provenance

    out = Path(out_dir)
    check_folder(out)
    provenance = provenance or make_provenance()
    typed, verdict = _verdicts(summary, tolerance, sliders)
    full = {"verdict": typed.to_json(), "provenance": json_ready(provenance.as_dict())}
    for key, record in (("summary", summary), ("tolerance", tolerance), ("sliders", sliders)):
        if record is not None:
            full[key] = record.to_json()
    full |= json_ready(document)
    with output_folder(out):
        figure = None
        if t is not None and errors_deg is not None:
            control = summary.control if summary else "2"
            figure = save_figure(plot_station_errors(t, errors_deg, control), out, "errors")
        if fig7 is not None:
            drawn = save_figure(fig7, out, "fig7")
            figure = figure or drawn
        json_path = write_atomic(out / "stations.json", json.dumps(full, indent=2) + "\n")
        page = (
            environment()
            .get_template("stations.html.j2")
            .render(
                css=CSS,
                verdict=verdict,
                provenance=provenance,
                title=provenance.title,
                d=full,
                summary=summary,
                tolerance=tolerance,
                sliders=sliders,
                figure=None if figure is None else base64.b64encode(figure[0].read_bytes()).decode("ascii"),
            )
        )
        index = write_atomic(out / "index.html", page)
    return StationFiles(out, index, json_path, figure)
