"""The model against the rig, drawn: measured and model motor torques with the error between them (the publication's Fig. 11).

:func:`write_comparison` writes a folder a lab can hand on: the figures as
PNG and SVG, ``index.html`` (one self-contained page, the PNGs embedded) and
``comparison.json`` (:meth:`hipsim.rig.compare.Comparison.summary`, with the
verdict and the provenance block). The page (``templates/compare.html.j2``)
opens with the verdict: the worst motor's RMS error relative to its measured
RMS torque, judged against ``accept`` when one is given.
"""

from __future__ import annotations

import base64
import json
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from .. import records
from ..exceptions import ArgumentError
from ..files import check_folder, json_ready, output_folder, write_atomic
from ..records import Level
from ..results import Torques
from ..rig.compare import Comparison
from ..rig.compare_summary import ComparisonSummary
from ..rig.compare_verdict import acceptance_verdict
from .figures import save_figure
from .numbers import significant
from .pages import CSS, Verdict, environment, sentence
from .provenance import Provenance

__all__ = [
    "ComparisonFiles",
    "comparison_block",
    "plot_comparison",
    "plot_errors",
    "plot_model_parts",
    "plot_phase_errors",
    "write_comparison",
]

_PART_COLOURS = {
    "platforms": "tab:blue",
    "levers": "tab:orange",
    "sliders": "tab:green",
    "screws": "tab:purple",
    "friction": "tab:red",
}

CAPTIONS = {
    "torques": "Measured and model motor torque per motor; the shaded band is the error between them.",
    "errors": "Model minus measured torque per motor, with ±RMS lines; grey: windows around the motor's reversals, "
    "where the real motion sticks and the filtered model cannot follow.",
    "phases": "RMS error per phase of the cycle (the log repeats).",
    "parts": "The model's torque split into its parts (platforms, levers, sliders, screws, friction).",
}


def _figure(rows: int, height: float = 2.6, width: float = 10.0):
    from matplotlib.figure import Figure

    fig = Figure(figsize=(width, height * rows + 0.6), layout="constrained")
    axes = fig.subplots(rows, 1, sharex=True, squeeze=False)[:, 0]
    for ax in axes:
        ax.grid(alpha=0.3)
    return fig, axes


def plot_comparison(comparison: Comparison, band=None):
    """Measured (black) and model (blue) torque per motor, the error between them shaded red; the model's 95 % band (half-widths in [N·m], (N, 3)) in light blue when given."""
    fig, axes = _figure(3)
    t = comparison.t
    errors = comparison.motor_errors()
    for i, ax in enumerate(axes):
        measured = comparison.measured[:, i] * 1e3
        model = comparison.model["total"][:, i] * 1e3
        ax.fill_between(t, measured, model, color="tab:red", alpha=0.3, linewidth=0, label="error")
        if band is not None:
            half = band[:, i] * 1e3
            ax.fill_between(
                t, model - half, model + half, color="tab:blue", alpha=0.25, linewidth=0, label="model's 95 % band"
            )
        ax.plot(t, measured, color="black", linewidth=1.0, label="measured")
        ax.plot(t, model, color="tab:blue", linewidth=1.0, linestyle="--", label="model")
        e = errors[str(i + 1)]
        ax.set_title(
            f"motor {i + 1}: RMS error {e['rms_error_Nmm']:.3g} N·mm ({100 * e['relative_rms_error']:.2g} %), "
            f"peak {e['peak_error_Nmm']:.3g} N·mm at {e['peak_error_t_s']:.3g} s",
            fontsize=9,
        )
        ax.set_ylabel("torque [N·mm]")
    axes[0].legend(loc="upper right", fontsize=8, ncol=3)
    axes[-1].set_xlabel("time [s]")
    return fig


def _shade_reversals(ax, t, mask):
    """Grey spans where ``mask`` is True: one collection, however many reversals an hour's log has."""
    ax.fill_between(t, 0, 1, where=mask, transform=ax.get_xaxis_transform(), color="0.85", linewidth=0)


def plot_errors(comparison: Comparison):
    """Model minus measured torque per motor with ±RMS lines; reversal windows shaded grey."""
    fig, axes = _figure(3, height=2.0)
    t = comparison.t
    for i, ax in enumerate(axes):
        error = comparison.error[:, i] * 1e3
        _shade_reversals(ax, t, comparison.near_reversal[:, i])
        rms = comparison.motor_errors()[str(i + 1)]["rms_error_Nmm"]  # of every sample, not only those drawn
        ax.plot(t, error, color="tab:red", linewidth=0.8)
        for sign in (-1, 1):
            ax.axhline(sign * rms, color="black", linewidth=0.7, linestyle=":")
        ax.set_ylabel(f"M{i + 1} error [N·mm]")
    axes[-1].set_xlabel("time [s]")
    return fig


def plot_phase_errors(comparison: Comparison):
    """RMS error per phase bin and motor (periodic logs only)."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(10.0, 3.4), layout="constrained")
    ax = fig.subplots()
    edges, rms = comparison.phase_edges, comparison.phase_rms
    if edges is None or rms is None:
        raise ArgumentError("comparison", comparison.period, "a comparison binned by phase (a periodic log)")
    centres = 0.5 * (edges[:-1] + edges[1:])
    width = (edges[1] - edges[0]) / 4
    for i in range(3):
        ax.bar(centres + (i - 1) * width, rms[:, i] * 1e3, width, label=f"motor {i + 1}")
    if comparison.stance is not None:
        stance_end = edges[1:][comparison.stance].max() if comparison.stance.any() else 0.0
        ax.axvspan(0.0, stance_end, color="0.9", zorder=0, label="stance")
        ax.set_xlabel(f"phase of the gait cycle from heel strike (period {comparison.period:.4g} s)")
    else:
        ax.set_xlabel(f"phase of the cycle from the first sample (period {comparison.period:.4g} s)")
    ax.set_ylabel("RMS error [N·mm]")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3, axis="y")
    return fig


def plot_model_parts(comparison: Comparison):
    """The model's torque parts per motor."""
    fig, axes = _figure(3, height=2.2)
    for i, ax in enumerate(axes):
        for part in Torques.PARTS:
            ax.plot(
                comparison.t, comparison.model[part][:, i] * 1e3, color=_PART_COLOURS[part], linewidth=0.9, label=part
            )
        ax.plot(comparison.t, comparison.model["total"][:, i] * 1e3, color="black", linewidth=1.0, label="total")
        ax.set_ylabel(f"M{i + 1} [N·mm]")
    axes[0].legend(fontsize=7, ncol=6, loc="upper right")
    axes[-1].set_xlabel("time [s]")
    return fig


@dataclass(frozen=True)
class ComparisonFiles:
    """What :func:`write_comparison` wrote: the folder, the page, the JSON, each figure's (PNG, SVG), and the verdict
    (:func:`hipsim.rig.compare_verdict.acceptance_verdict`) the page opens with."""

    folder: Path
    index: Path
    summary: Path
    figures: dict[str, tuple[Path, Path]]
    verdict: records.Verdict


def comparison_block(summary: ComparisonSummary, verdict: records.Verdict) -> Verdict:
    """The page's block of the acceptance verdict (:func:`hipsim.rig.compare_verdict.acceptance_verdict`): its word
    (NOT JUDGED when no threshold was given) and sentence, with the worst motor's numbers.

    Args:
        summary: :meth:`hipsim.rig.compare.Comparison.summary`.
        verdict: the acceptance verdict on it.
    """
    motors = summary.motors
    worst = max(motors, key=lambda i: motors[i].relative_rms_error)
    m = motors[worst]
    numbers = (
        f"Worst: motor {worst}, RMS error {significant(m.rms_error_Nmm, 3)} N·mm = "
        f"{significant(100 * m.relative_rms_error, 3)} % of its measured RMS torque "
        f"({significant(m.rms_error_away_from_reversals_Nmm, 3)} N·mm away from reversals)."
    )
    first = "No acceptance threshold given (--accept PERCENT)." if verdict.level == Level.NOT_MADE else None
    return Verdict.of(verdict, (first or sentence(verdict.judged), numbers), not_made="NOT JUDGED")


def _rows(summary: ComparisonSummary) -> list[list[str]]:
    return [
        [
            f"M{name}",
            significant(m.measured_rms_Nmm),
            significant(m.measured_peak_Nmm),
            significant(m.rms_error_Nmm, 3),
            significant(100 * m.relative_rms_error, 3),
            significant(m.peak_error_Nmm, 3),
            significant(100 * m.relative_peak_error, 3),
            f"{m.peak_error_t_s:.3f}",
            significant(m.rms_error_away_from_reversals_Nmm, 3),
        ]
        for name, m in summary.motors.items()
    ]


def write_comparison(
    out_dir: str | Path,
    comparison: Comparison,
    extra: dict[str, Any] | None = None,
    provenance: Provenance | None = None,
    accept: float | None = None,
    band=None,
    residual=None,
) -> ComparisonFiles:
    """Write the comparison folder: figures (PNG, SVG), ``index.html`` and ``comparison.json``, each atomically.

    Args:
        out_dir: the folder (made if missing; taken back if the writing fails and it is still empty).
        comparison: what :func:`hipsim.rig.compare.compare_torques` returned.
        extra: more entries for the JSON.
        provenance: where the numbers came from (:func:`hipsim.present.provenance.provenance`); None: the version and time only.
        accept: the largest relative RMS error accepted, as a fraction; None: the verdict is not judged.
        band: the model's 95 % band half-widths in [N·m] at the comparison's samples, (N, 3)
            (:func:`hipsim.rig.identification.uncertainty.log_torque_std` × 1.96), from an identified file's covariance; None: no band.
        residual: the identification's residual RMS per motor in [N·m], (3,), for the prediction band in the JSON; None: none.

    Returns:
        The files written.
    """
    from .provenance import provenance as make_provenance

    out = Path(out_dir)
    check_folder(out)
    provenance = provenance or make_provenance()
    summary = comparison.summary()
    document = summary.to_json() | (extra or {})
    captions = CAPTIONS
    if band is not None:
        from ..rig.identification.uncertainty import band_summary

        document["model_band95"] = band_summary(band, comparison.error, residual)
        captions = CAPTIONS | {
            "torques": CAPTIONS["torques"] + " Light blue: the model's 95 % band from the parameter file's covariance."
        }
    verdict = acceptance_verdict({i: m.relative_rms_error for i, m in summary.motors.items()}, accept)
    document = {"verdict": verdict.to_json(), "provenance": provenance.as_dict()} | document
    plots = [("torques", lambda c: plot_comparison(c, band)), ("errors", plot_errors)]
    if comparison.phase_rms is not None:
        plots.append(("phases", plot_phase_errors))
    plots.append(("parts", plot_model_parts))
    figures: dict[str, tuple[Path, Path]] = {}
    with output_folder(out):
        for stem, plot in plots:
            figures[stem] = save_figure(plot(comparison), out, stem)
        json_path = write_atomic(out / "comparison.json", json.dumps(json_ready(document), indent=2) + "\n")
        embedded = [(stem, base64.b64encode(png.read_bytes()).decode("ascii")) for stem, (png, _) in figures.items()]
        page = (
            environment()
            .get_template("compare.html.j2")
            .render(
                css=CSS,
                verdict=comparison_block(summary, verdict),
                provenance=provenance,
                title=provenance.title,
                summary=summary,
                rows=_rows(summary),
                rate=significant(summary.rate_Hz),
                period=significant(summary.period_s) if summary.period_s else "",
                notes=summary.notes,
                figures=embedded,
                captions=captions,
            )
        )
        index = write_atomic(out / "index.html", page)
    return ComparisonFiles(out, index, json_path, figures, verdict)
