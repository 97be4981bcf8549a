"""The friction monitor, drawn: the control chart, the screw friction's trend, the residuals, and a page a lab can hand on.

:func:`write_monitor_report` writes a folder: the figures as PNG and SVG,
``index.html`` (self-contained, the PNGs embedded; ``templates/monitor.html.j2``)
opening with the verdict (ALARM when an alarm is active at the last snapshot)
and the provenance block, and ``monitor.json`` (the summary).
"""

from __future__ import annotations

import base64
import json
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ..files import check_folder, json_ready, output_folder, write_atomic
from ..rig.monitoring.monitor_run import MonitorResult
from .figures import save_figure
from .numbers import significant
from .pages import CSS, Verdict, environment
from .provenance import Provenance

__all__ = [
    "CAPTIONS",
    "MonitorFiles",
    "monitor_verdict",
    "plot_chart",
    "plot_residuals",
    "plot_screw",
    "write_monitor_report",
]

CAPTIONS = {
    "chart": "Load friction coefficient r_h·μ_h + r_t·μ_t per snapshot with its 95 % band, the baseline's mean, the engineering "
    "threshold (the mean plus the alarm rise × r_h), the EWMA statistic and its upper control limit; alarms are red. "
    "Snapshots before the baseline (running-in) are grey, never flagged.",
    "screw": "The screw's Coulomb and viscous friction per snapshot with 95 % bands (the guide's equal-shaped terms held at the file's values).",
    "residuals": "RMS residual motor torque of each snapshot's fit: a rise means the model no longer explains the torques.",
}
_PHASE_COLOURS = {"running-in": "0.6", "baseline": "tab:green", "monitoring": "tab:blue"}


def _figure(rows: int, height: float = 3.0, width: float = 10.0):
    from matplotlib.figure import Figure

    fig = Figure(figsize=(width, height * rows + 0.6), layout="constrained")
    axes = fig.subplots(rows, 1, sharex=True, squeeze=False)[:, 0]
    for ax in axes:
        ax.grid(alpha=0.3)
    return fig, axes


def _arrays(result: MonitorResult, *names: str) -> list[np.ndarray]:
    return [np.asarray(result.columns[name], dtype=float) for name in names]


def plot_chart(result: MonitorResult):
    """The control chart: estimates with 95 % bands, baseline, threshold, EWMA and its limit, alarms."""
    fig, (ax,) = _figure(1, 4.0)
    cycles, x, s, ewma, limit, alarm = _arrays(
        result, "cycle", "load_friction_mm", "load_friction_mm_std", "ewma_mm", "ucl_mm", "alarm"
    )
    phase = np.asarray(result.columns["phase"], dtype=object)
    for name, colour in _PHASE_COLOURS.items():
        k = phase == name
        if k.any():
            ax.errorbar(
                cycles[k], x[k], yerr=1.96 * s[k], fmt="o", ms=4, color=colour, capsize=2, label=f"{name} (95 % band)"
            )
    chart = result.chart
    if math.isfinite(chart.mean):
        ax.axhline(chart.mean, color="tab:green", lw=1, label=f"baseline mean {significant(chart.mean, 4)} mm")
        ax.axhline(
            chart.threshold, color="tab:red", lw=1, ls="--", label=f"threshold: rise of μ_h by {result.alarm_rise:g}"
        )
        ax.plot(cycles, ewma, color="tab:orange", lw=1.2, label="EWMA (λ 0.2)")
        ax.plot(cycles, limit, color="tab:orange", lw=1, ls=":", label="EWMA upper control limit (L 3)")
        low, high = result.baseline
        ax.axvspan(low, high, color="tab:green", alpha=0.08)
    k = alarm > 0
    if k.any():
        ax.plot(cycles[k], x[k], "s", ms=9, mfc="none", mec="tab:red", mew=2, label="alarm")
    ax.set_xlabel("cycle")
    ax.set_ylabel("r_h·μ_h + r_t·μ_t [mm]")
    ax.legend(fontsize=8, loc="best")
    return fig


def plot_screw(result: MonitorResult):
    """The screw's Coulomb and viscous friction per snapshot, 95 % bands."""
    fig, axes = _figure(2, 2.4)
    cycles = _arrays(result, "cycle")[0]
    for ax, name, label in (
        (axes[0], "screw_coulomb_Nmm", "screw Coulomb [N·mm]"),
        (axes[1], "screw_viscous_Nmm_s_rad", "screw viscous [N·mm·s/rad]"),
    ):
        value, std = _arrays(result, name, f"{name}_std")
        ax.errorbar(cycles, value, yerr=1.96 * std, fmt="o-", ms=3, capsize=2, color="tab:purple")
        ax.set_ylabel(label)
    axes[-1].set_xlabel("cycle")
    return fig


def plot_residuals(result: MonitorResult):
    """RMS residual torque per snapshot."""
    fig, (ax,) = _figure(1, 2.4)
    cycles, residual = _arrays(result, "cycle", "residual_rms_Nmm")
    ax.plot(cycles, residual, "o-", ms=3, color="tab:gray")
    ax.set_xlabel("cycle")
    ax.set_ylabel("RMS residual [N·mm]")
    return fig


def monitor_verdict(summary: dict) -> Verdict:
    """ALARM when an alarm is active at the last snapshot; OK otherwise; NO BASELINE before the chart can start."""
    first = summary["first_alarm"]
    told = (
        (
            f"First alarm at cycle {first['cycle']} ({first['file']}): the hip friction coefficient up by "
            f"{significant(first['hip_mu_change'], 3)} ± {significant(first['hip_mu_change_std'], 2)}."
        )
        if first
        else "No alarm so far."
    )
    if summary["note"]:
        return Verdict("open", "NO BASELINE YET", (summary["note"] + ".",))
    if summary["alarm_active"]:
        return Verdict(
            "fail",
            "ALARM",
            (
                "An alarm is active at the last snapshot (cycle "
                f"{summary['last_cycle']}): the friction has risen beyond the threshold.",
                told,
            ),
        )
    return Verdict("pass", "OK", ("No alarm at the last snapshot.", told))


@dataclass(frozen=True)
class MonitorFiles:
    """What :func:`write_monitor_report` wrote: the folder, the page, the JSON, each figure's (PNG, SVG)."""

    folder: Path
    index: Path
    summary: Path
    figures: dict[str, tuple[Path, Path]]


_SHOWN = (
    "cycle",
    "file",
    "phase",
    "load_friction_mm",
    "load_friction_mm_std",
    "hip_mu_change",
    "hip_mu_change_std",
    "screw_coulomb_Nmm",
    "screw_viscous_Nmm_s_rad",
    "residual_rms_Nmm",
    "alarm",
)


def _cell(name: str, value: Any) -> str:
    if isinstance(value, str):
        return value
    if name in ("cycle", "alarm"):
        return str(int(value))
    return "" if not math.isfinite(float(value)) else significant(float(value), 4)


def write_monitor_report(
    out_dir: str | Path, result: MonitorResult, provenance: Provenance | None = None, notes: tuple[str, ...] = ()
) -> MonitorFiles:
    """Write the report folder: figures (PNG, SVG), ``index.html`` and ``monitor.json``, each atomically."""
    from .provenance import provenance as make_provenance

    out = Path(out_dir)
    check_folder(out)
    provenance = provenance or make_provenance()
    summary = result.summary()
    verdict = monitor_verdict(summary)
    document = {"verdict": verdict.as_dict(), "provenance": provenance.as_dict()} | summary
    figures: dict[str, tuple[Path, Path]] = {}
    with output_folder(out):
        for stem, plot in (("chart", plot_chart), ("screw", plot_screw), ("residuals", plot_residuals)):
            figures[stem] = save_figure(plot(result), out, stem)
        json_path = write_atomic(out / "monitor.json", json.dumps(json_ready(document), indent=2) + "\n")
        embedded = [(stem, base64.b64encode(png.read_bytes()).decode("ascii")) for stem, (png, _) in figures.items()]
        c = result.columns
        rows = [([_cell(name, c[name][k]) for name in _SHOWN], bool(c["alarm"][k])) for k in range(len(c["cycle"]))]
        page = (
            environment()
            .get_template("monitor.html.j2")
            .render(
                css=CSS,
                verdict=verdict,
                provenance=provenance,
                title=provenance.title,
                summary=json_ready(summary),
                notes=list(notes) + ([summary["note"]] if summary["note"] else []),
                figures=embedded,
                captions=CAPTIONS,
                header=_SHOWN,
                rows=rows,
            )
        )
        index = write_atomic(out / "index.html", page)
    return MonitorFiles(out, index, json_path, figures)
