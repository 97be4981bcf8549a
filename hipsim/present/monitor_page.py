"""The friction monitor, drawn: the control charts, the other friction terms, the residuals, and a page a lab can hand on.

:func:`write_monitor_report` writes a folder: the figures as PNG and SVG,
``index.html`` (self-contained, the PNGs embedded; ``templates/monitor.html.j2``)
opening with the verdict (ALARM when an alarm is active at the last snapshot,
NOTICE when the last snapshot's change is significant but below the threshold)
and the provenance block, the skipped, waiting and missing snapshots named, the
table with every column the JSON has (printed in landscape, no column lost),
every snapshot's file with its size and SHA-256 (a collapsed list), and
``monitor.json`` (the summary); with ``pdf`` the page printed to ``report.pdf``
(headless Chromium, as ``hipsim report --pdf``).
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
from ..records import Level
from ..rig.monitoring.monitor_run import MonitorResult
from .figures import save_figure
from .numbers import significant
from .pages import CSS, Verdict, environment, print_pdf, require_pdf_renderer, sentence

__all__ = [
    "CAPTIONS",
    "MonitorFiles",
    "monitor_verdict",
    "plot_chart",
    "plot_residuals",
    "plot_terms",
    "write_monitor_report",
]

CAPTIONS = {
    "chart": "Load friction coefficient r_h·μ_h + r_t·μ_t per snapshot with its 95 % band against million cycles (Mc): "
    "the baseline's mean, the engineering thresholds either way (the mean ± the alarm's change × r_h, halved on the "
    "two stations' mean: its worst case is twice its change in one station), the EWMA statistic and its two control "
    "limits; alarms are red squares, notices orange. Snapshots before the baseline (running-in) are grey, never "
    "flagged. With per-station loads that separate the stations, a panel per station.",
    "terms": "The thrust bearing's weight term and the screw's Coulomb and viscous friction per snapshot with 95 % "
    "bands (the guide's equal-shaped terms held at the file's values).",
    "residuals": "RMS residual motor torque of each snapshot's fit: a rise means the model no longer explains the torques.",
}
_PHASE_COLOURS = {"running-in": "0.6", "baseline": "tab:green", "monitoring": "tab:blue"}
_MC = 1e-6  # cycles → million cycles


def _figure(rows: int, height: float = 3.0, width: float = 10.0):
    from matplotlib.figure import Figure

    fig = Figure(figsize=(width, height * rows + 0.6), layout="constrained")
    axes = fig.subplots(rows, 1, sharex=True, squeeze=False)[:, 0]
    for ax in axes:
        ax.grid(alpha=0.3)
        ax.ticklabel_format(axis="x", style="plain", useOffset=False)
    axes[-1].set_xlabel("cycles [Mc, million cycles]")
    return fig, axes


def _arrays(result: MonitorResult, *names: str) -> list[np.ndarray]:
    return [np.asarray(result.columns[name], dtype=float) for name in names]


def _panel(ax, result: MonitorResult, chart, value: str, std: str, ewma: str, lower: str, upper: str, label: str):
    cycles, x, s, z, lo, hi = _arrays(result, "cycle", value, std, ewma, lower, upper)
    mc = cycles * _MC
    phase = np.asarray(result.columns["phase"], dtype=object)
    for name, colour in _PHASE_COLOURS.items():
        k = (phase == name) & np.isfinite(x)
        if k.any():
            ax.errorbar(mc[k], x[k], yerr=1.96 * s[k], fmt="o", ms=4, color=colour, capsize=2, label=f"{name} (95 %)")
    if math.isfinite(chart.mean):
        ax.axhline(chart.mean, color="tab:green", lw=1, label=f"baseline mean {significant(chart.mean, 4)} mm")
        for bound in chart.threshold:
            ax.axhline(bound, color="tab:red", lw=1, ls="--")
        ax.plot([], [], color="tab:red", lw=1, ls="--", label=f"threshold: μ_h ± {result.alarm_rise:g} in one station")
        ax.plot(mc, z, color="tab:orange", lw=1.2, label="EWMA (λ 0.2)")
        ax.plot(mc, lo, color="tab:orange", lw=1, ls=":", label="EWMA control limits (L 3)")
        ax.plot(mc, hi, color="tab:orange", lw=1, ls=":")
        low, high = result.baseline
        ax.axvspan(low * _MC, high * _MC, color="tab:green", alpha=0.08)
    for kind, colour in (("alarm", "tab:red"), ("notice", "tab:orange")):
        k = (chart.flag == kind) & np.isfinite(x)
        if k.any():
            ax.plot(mc[k], x[k], "s", ms=9, mfc="none", mec=colour, mew=2, label=kind)
    ax.set_ylabel(label)
    ax.legend(fontsize=7, loc="best")


def plot_chart(result: MonitorResult):
    """The control chart of the mean (or the one station), and one per station when the logs separate them."""
    stations = result.findings.stations
    fig, axes = _figure(1 if stations is None else 3, 3.4)
    label = "r_h·μ_h + r_t·μ_t [mm]" + (" (mean)" if result.two_stations else "")
    _panel(
        axes[0],
        result,
        result.findings.mean,
        "load_friction_mm",
        "load_friction_mm_std",
        "ewma_mm",
        "lcl_mm",
        "ucl_mm",
        label,
    )
    if stations is not None:
        for p, chart in enumerate(stations, start=1):
            _panel(
                axes[p],
                result,
                chart,
                f"load_friction_{p}_mm",
                f"load_friction_{p}_mm_std",
                f"ewma_{p}_mm",
                f"lcl_{p}_mm",
                f"ucl_{p}_mm",
                f"station {p} [mm]",
            )
    return fig


def plot_terms(result: MonitorResult):
    """The weight term and the screw's Coulomb and viscous friction per snapshot, 95 % bands."""
    fig, axes = _figure(3, 2.2)
    mc = _arrays(result, "cycle")[0] * _MC
    for ax, name, label in (
        (axes[0], "weight_friction_Nmm", "weight term [N·mm]"),
        (axes[1], "screw_coulomb_Nmm", "screw Coulomb [N·mm]"),
        (axes[2], "screw_viscous_Nmm_s_rad", "screw viscous [N·mm·s/rad]"),
    ):
        value, std = _arrays(result, name, f"{name}_std")
        ax.errorbar(mc, value, yerr=1.96 * std, fmt="o-", ms=3, capsize=2, color="tab:purple")
        ax.set_ylabel(label)
    return fig


def plot_residuals(result: MonitorResult):
    """RMS residual torque per snapshot."""
    fig, (ax,) = _figure(1, 2.4)
    cycles, residual = _arrays(result, "cycle", "residual_rms_Nmm")
    ax.plot(cycles * _MC, residual, "o-", ms=3, color="tab:gray")
    ax.set_ylabel("RMS residual [N·mm]")
    return fig


def monitor_verdict(result: MonitorResult) -> Verdict:
    """The page's block of the run's verdict (:attr:`hipsim.rig.monitoring.monitor_run.MonitorResult.verdict`):
    ALARM, NOTICE, OK, or NO BASELINE YET before the chart can start; the lines say the change and its causes."""
    found, verdict = result.findings, result.verdict
    first = found.first
    told = [f"First {first.text} (cycle {first.cycle:,}, {first.file})."] if first else ["No alarm so far."]
    skipped = sum(1 for s in result.skipped if s.kind != "waiting")
    if skipped:
        told.append(f"{skipped} snapshot{'s' if skipped > 1 else ''} skipped (listed below with the reasons).")
    if verdict.level == Level.NOT_MADE:
        return Verdict.of(verdict, (f"{found.mean.note}.", *told[1:]), not_made="NO BASELINE YET")
    said = sentence(verdict.judged)
    raised = found.raised_at
    if verdict.level == Level.ALARM and raised is not None:
        cycles = result.columns["last_cycle"]
        said = (
            f"An alarm raised at cycle {raised:,} is held at the last snapshot"
            + (f" (cycle {int(cycles[-1]):,})" if cycles else "")
            + f" until acknowledged (hipsim monitor --acknowledge {raised})."
        )
    return Verdict.of(verdict, (said, *told))


@dataclass(frozen=True)
class MonitorFiles:
    """What :func:`write_monitor_report` wrote: the folder, the page, the JSON, each figure's (PNG, SVG), the PDF."""

    folder: Path
    index: Path
    summary: Path
    figures: dict[str, tuple[Path, Path]]
    pdf: Path | None = None


def _shown(result: MonitorResult) -> tuple[str, ...]:
    """The table's columns on the page: every estimate and chart column (per station and the load gain when known)."""
    c = result.columns
    names = ["cycle", "file", "phase", "load_friction_mm", "load_friction_mm_std", "hip_mu_change", "hip_mu_change_std"]
    if result.findings.stations is not None or any(s == "separated" for s in c["stations"]):
        names += [
            "load_friction_1_mm",
            "load_friction_1_mm_std",
            "load_friction_2_mm",
            "load_friction_2_mm_std",
            "hip_mu_change_1",
            "hip_mu_change_2",
        ]
    names += ["weight_friction_Nmm", "weight_friction_Nmm_std", "screw_coulomb_Nmm", "screw_viscous_Nmm_s_rad"]
    names += ["ewma_mm", "lcl_mm", "ucl_mm"]
    if result.findings.stations is not None:
        names += [f"{name}_{p}_mm" for p in (1, 2) for name in ("ewma", "lcl", "ucl")]
    names += ["residual_rms_Nmm"]
    if any(math.isfinite(v) for v in c["load_gain"]):
        names += ["load_gain", "load_gain_change"]
    return (*names, "stations", "flag", "state", "acknowledged", "note")


def _cell(name: str, value: Any) -> str:
    if isinstance(value, str):
        return value
    if name == "cycle":
        return f"{int(value) * _MC:.3f}"
    if name == "alarm":
        return str(int(value))
    if name == "acknowledged":
        return "" if not math.isfinite(float(value)) else f"{int(value):,}"
    return "" if not math.isfinite(float(value)) else significant(float(value), 4)


def write_monitor_report(
    out_dir: str | Path,
    result: MonitorResult,
    provenance=None,
    notes: tuple[str, ...] = (),
    pdf: bool = False,
) -> MonitorFiles:
    """Write the report folder: figures (PNG, SVG), ``index.html`` and ``monitor.json``, each atomically; with
    ``pdf`` also ``report.pdf``.

    Raises:
        HipsimError: ``pdf`` without a Chromium to print with (said before anything is written).
    """
    from .provenance import provenance as make_provenance

    out = Path(out_dir)
    check_folder(out)
    browser = require_pdf_renderer() if pdf else None
    provenance = provenance or make_provenance()
    summary = result.summary()
    verdict = monitor_verdict(result)
    # the verdict (the summary's records.Verdict) first, then the provenance, as on every page's JSON
    document = {"verdict": None, "provenance": provenance.as_dict()} | summary.to_json()
    figures: dict[str, tuple[Path, Path]] = {}
    with output_folder(out):
        for stem, plot in (("chart", plot_chart), ("terms", plot_terms), ("residuals", plot_residuals)):
            figures[stem] = save_figure(plot(result), out, stem)
        json_path = write_atomic(out / "monitor.json", json.dumps(json_ready(document), indent=2) + "\n")
        embedded = [(stem, base64.b64encode(png.read_bytes()).decode("ascii")) for stem, (png, _) in figures.items()]
        c = result.columns
        shown = _shown(result)
        rows = [([_cell(name, c[name][k]) for name in shown], c["flag"][k]) for k in range(len(c["cycle"]))]
        header = ["Mc" if name == "cycle" else name for name in shown]
        page = (
            environment()
            .get_template("monitor.html.j2")
            .render(
                css=CSS,
                verdict=verdict,
                provenance=provenance,
                title=provenance.title,
                summary=summary,
                notes=list(notes) + ([summary.note] if summary.note else []),
                figures=embedded,
                captions=CAPTIONS,
                header=header,
                rows=rows,
            )
        )
        index = write_atomic(out / "index.html", page)
        printed = None
        if browser is not None:
            printed = print_pdf(index, out / "report.pdf", browser)
    return MonitorFiles(out, index, json_path, figures, printed)
