"""Design reports: one folder a designer can hand on.

:func:`write_report` takes the runs the caller made (torques from one model,
joint forces from the Pinocchio model when there is one) and writes every
figure as PNG and SVG, ``index.html`` (one self-contained page: the PNGs are
embedded as data URIs, so it works offline and after the folder is moved or
the page is mailed alone), ``report.json`` (the summary and sizing numbers)
and ``torques.csv`` (the columns of spec §7.5). The numbers come from
:mod:`hipsim.analysis.sizing`, the figures from :mod:`hipsim.present.figures`.
"""

from __future__ import annotations

import base64
import dataclasses
import html
import json
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Mapping

import numpy as np

from ..analysis.sizing import Sizing, sizing
from ..exceptions import HipsimError
from ..files import check_folder, output_folder, write_atomic
from ..machine.drive import RATING_KEYS, MotorRatings
from ..results import Run, Torques, peak_and_rms
from .figures import (
    FIGURE_CAPTIONS,
    plot_joint_forces,
    plot_load_friction,
    plot_singularity,
    plot_slider_motion,
    plot_torque_parts,
    plot_tracking,
    save_figure,
    tracking_arrays,
)

__all__ = ["ReportFiles", "write_report"]


# ---------------------------------------------------------------------------
# Figures



# ---------------------------------------------------------------------------
# Sizing




# ---------------------------------------------------------------------------
# The report


@dataclass(frozen=True)
class ReportFiles:
    """What :func:`write_report` wrote.

    Attributes:
        folder: the output folder.
        index: the HTML page.
        figures: figure stem → (PNG path, SVG path).
        data: the other files (report.json, torques.csv).
        notes: the notes shown on the page (model fallbacks, estimates).
        sizing: the sizing table.
    """

    folder: Path
    index: Path
    figures: dict[str, tuple[Path, Path]]
    data: tuple[Path, ...]
    notes: tuple[str, ...] = field(default_factory=tuple)
    sizing: Sizing | None = None


def write_report(
    out_dir: str | Path,
    run: Run,
    joint_forces_run: Run | None = None,
    simulations: Mapping[str, Any] | None = None,
    ratings: MotorRatings | None = None,
    notes: tuple[str, ...] = (),
) -> ReportFiles:
    """Write the design report folder of a run.

    Writes into ``out_dir`` (created if missing): ``slider_motion``,
    ``motor_torques``, ``load_friction``, ``singularity`` and, when available,
    ``joint_forces`` and ``tracking_errors``, each as ``.png`` and ``.svg``;
    ``index.html``; ``report.json`` (summary and sizing) and ``torques.csv``
    (spec §7.5 columns). Every file is written atomically.

    Args:
        out_dir: the folder to write.
        run: the run whose torques, motion and singularity measure are reported.
        joint_forces_run: a run along the same trajectory whose joint forces
            are reported with ``run``'s torques (the Pinocchio model's, when
            ``run`` is analytic); None to use ``run``'s own, if it has any.
        simulations: tracking simulations to plot: {controller name: object
            with ``t`` (N,) in [s] and ``err`` (N, 3) in [rad], and optionally
            ``tau`` (N, 3) in [N·m]}; None for no tracking section.
        ratings: a motor/module rating to check the sizing against; None for no check.
        notes: sentences shown at the top of the page (model fallbacks, estimates).

    Returns:
        The :class:`ReportFiles`.
    """
    out = Path(out_dir)
    check_folder(out)  # fail now, not after the plotting; but make it only when there is something to write
    notes = list(notes)
    if run.params.platform_mass > 0:
        notes.append(f"The platform mass m_m = {run.params.platform_mass:g} kg is an estimate (not published); it enters only the thrust-bearing friction.")
    combined = run
    if joint_forces_run is not None and joint_forces_run is not run:
        if joint_forces_run.joint_forces is None:
            raise HipsimError(f"the {joint_forces_run.model} run has no joint forces to report")
        if joint_forces_run.trajectory.t.shape != run.trajectory.t.shape or np.any(joint_forces_run.trajectory.t != run.trajectory.t):
            raise HipsimError("the joint-force run is not along the report's trajectory")
        total, other = run.torques.total, joint_forces_run.torques.total
        difference = np.abs(other - total).max() / np.abs(total).max()
        notes.append(
            f"Torques are from the {run.model} model; joint forces from the {joint_forces_run.model} model, whose motor "
            f"torques differ from these by at most {difference:.2e} of the peak (the analytic lever does not spin, spec §7.4)."
        )
        # One run for the sizing and the figures: these torques with those joint forces.
        combined = dataclasses.replace(run, joint_forces=joint_forces_run.joint_forces)
    if simulations is not None:
        if not isinstance(simulations, Mapping) or not simulations:
            raise HipsimError("simulations must be a non-empty mapping {controller name: result with t and err}")
        for name, sim in simulations.items():
            tracking_arrays(name, sim)
    size = sizing(combined, ratings)

    figures: dict[str, tuple[Path, Path]] = {}
    plots = [
        ("slider_motion", lambda: plot_slider_motion(combined)),
        ("motor_torques", lambda: plot_torque_parts(combined)),
        ("load_friction", lambda: plot_load_friction(combined)),
        ("singularity", lambda: plot_singularity(combined)),
    ]
    if combined.joint_forces is not None:
        plots.append(("joint_forces", lambda: plot_joint_forces(combined)))
    if simulations is not None:
        plots.append(("tracking_errors", lambda: plot_tracking(simulations)))
    with output_folder(out):  # a failure from here on takes back the folder if this run made it and it is empty
        for stem, make in plots:
            figures[stem] = save_figure(make(), out, stem)

        summary = combined.summary()
        tracking = _tracking_table(simulations) if simulations is not None else None
        document = {"summary": summary, "sizing": size.as_dict(), "tracking": tracking, "notes": notes,
                    "figures": {stem: [p.name for p in paths] for stem, paths in figures.items()}}
        data = (
            write_atomic(out / "report.json", json.dumps(_finite(document), indent=2) + "\n"),
            combined.write_csv(out / "torques.csv"),
        )
        page = _html(combined, summary, size, tracking, figures, notes)
        index = write_atomic(out / "index.html", page)
    return ReportFiles(out, index, figures, data, tuple(notes), size)


def _tracking_table(sims: Mapping[str, Any]) -> dict[str, dict[str, float]]:
    """Per controller: peak and RMS error of each angle in [deg] (and torque when the result has ``tau``)."""
    table = {}
    for name, sim in sims.items():
        _, err = tracking_arrays(name, sim)
        peak, rms = peak_and_rms(np.degrees(err))
        row = {}
        for k, angle in enumerate(("alpha", "beta", "gamma")):
            row[f"{angle}_err_peak_deg"] = float(peak[k])
            row[f"{angle}_err_rms_deg"] = float(rms[k])
        tau = getattr(sim, "tau", None)
        if tau is not None and np.shape(tau) == (err.shape[0], 3):
            peak, rms = peak_and_rms(np.asarray(tau, dtype=float) * 1e3)
            row |= {f"tau_peak_{i + 1}_Nmm": float(peak[i]) for i in range(3)}
            row |= {f"tau_rms_{i + 1}_Nmm": float(rms[i]) for i in range(3)}
        table[name] = row
    return table


def _finite(value):
    """NaN and infinity become None: JSON has neither."""
    if isinstance(value, dict):
        return {k: _finite(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_finite(v) for v in value]
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


# ---------------------------------------------------------------------------
# HTML

_CSS = """
body { font-family: system-ui, -apple-system, "Segoe UI", sans-serif; margin: 2em auto; max-width: 1100px; color: #222; padding: 0 1em; }
h1 { font-size: 1.6em; margin-bottom: 0.2em; }
h2 { font-size: 1.25em; border-bottom: 1px solid #ccc; padding-bottom: 0.2em; margin-top: 1.8em; }
table { border-collapse: collapse; margin: 0.6em 0 1em; font-size: 0.9em; }
th, td { border: 1px solid #ccc; padding: 0.25em 0.6em; text-align: right; }
th { background: #f0f0f0; }
th.l, td.l { text-align: left; }
.meta { color: #555; font-size: 0.9em; }
.note { background: #fff8e0; border-left: 4px solid #e0b000; padding: 0.4em 0.8em; margin: 0.4em 0; }
.pass { color: #0a7a0a; font-weight: bold; }
.fail { color: #c00000; font-weight: bold; }
figure { margin: 1em 0 2em; }
figure img { max-width: 100%; border: 1px solid #ddd; }
figcaption { font-size: 0.9em; color: #444; }
"""


def _esc(value) -> str:
    return html.escape(str(value))


def _table(header: list[str], rows: list[list], digits: int = 1, left: int = 1) -> str:
    """An HTML table; numbers right-aligned with ``digits`` decimals, the first ``left`` columns left-aligned."""

    def cell(value):
        if isinstance(value, str):
            return value  # already HTML (escaped by the caller)
        if value is None or (isinstance(value, float) and not math.isfinite(value)):
            return "—"
        return f"{value:,.{digits}f}" if isinstance(value, float) else _esc(value)

    def align(k):
        return " class='l'" if k < left else ""

    head = "".join(f"<th{align(k)}>{_esc(h)}</th>" for k, h in enumerate(header))
    body = "".join("<tr>" + "".join(f"<td{align(k)}>{cell(v)}</td>" for k, v in enumerate(row)) + "</tr>" for row in rows)
    return f"<table><thead><tr>{head}</tr></thead><tbody>{body}</tbody></table>"


def _html(result: Run, summary: dict, size: Sizing, tracking, figures, notes) -> str:
    from .. import __version__

    traj = result.trajectory
    parts = []
    parts.append("<h1>hipsim design report</h1>")
    parts.append(
        f"<p class='meta'>Trajectory: <b>{_esc(traj.name)}</b> ({len(traj)} samples, {traj.t[-1] - traj.t[0] + (traj.t[1] - traj.t[0] if len(traj) > 1 else 0):.4g} s)"
        f" &middot; parameters: {_esc(result.params.source)} &middot; platform offset δ = {math.degrees(result.params.home_offset):g}°"
        f" &middot; hipsim {_esc(__version__)}</p>"
    )
    for note in notes:
        parts.append(f"<p class='note'>{_esc(note)}</p>")

    # Summary
    parts.append("<h2>Summary</h2>")
    rows = [[f"S{name}", s["L_max_mm"], s["L_min_mm"], s["stroke_mm"], s["Ld_max_mm_s"], s["Ldd_max_mm_s2"]] for name, s in summary["sliders"].items()]
    parts.append("<h3>Sliders (S<sub>ji</sub>: platform j, module i)</h3>")
    parts.append(_table(["slider", "L max [mm]", "L min [mm]", "stroke [mm]", "|L̇| max [mm/s]", "|L̈| max [mm/s²]"], rows))
    parts.append("<h3>Motor torques [N·mm] (largest |part|; peak and RMS of the total)</h3>")
    rows = [
        [f"M{i}", *(m[f"{Torques.COLUMN[p]}_max_Nmm"] for p in Torques.PARTS), m["tau_peak_Nmm"], m["tau_rms_Nmm"], m["speed_peak_rpm"]]
        for i, m in summary["motors"].items()
    ]
    parts.append(_table(["motor", "platforms", "levers", "sliders", "screws", "friction", "peak", "RMS", "peak speed [rpm]"], rows))
    parts.append(
        f"<p>Smallest singularity measure (inverse condition number of J): <b>{summary['cond_inv_min']:.4f}</b>"
        f" at t = {summary['cond_inv_min_t_s']:.4g} s (0 singular, 1 isotropic).</p>"
    )

    # Sizing
    parts.append("<h2>Sizing</h2>")
    rows = [[f"LN{m.module}", m.tau_peak_Nmm, m.tau_rms_Nmm, m.speed_peak_rpm, m.power_peak_W, m.axial_force_peak_N, m.stroke_mm] for m in size.modules]
    parts.append(_table(["linear module", "peak torque [N·mm]", "RMS torque [N·mm]", "peak speed [rpm]", "peak power [W]", "peak axial screw force [N]", "stroke [mm]"], rows))
    parts.append(
        "<p class='meta'>Peak power is max |τ·θ̇| of the motor. The axial screw force is the force the nut pushes on the "
        "carriage (both sliders of the module), F = 2π(τ − τ<sub>L</sub> − τ<sub>screw friction</sub>)/p: the motor torque "
        "less the screw rotor's inertia and the screw's own friction, turned into thrust by an ideal screw of lead p.</p>"
    )
    if size.joints is not None:
        parts.append("<h3>Joint reaction forces</h3>")
        parts.append(_table(["joint", "peak [N]", "RMS [N]"], [[j.joint, j.peak_N, j.rms_N] for j in size.joints]))
    else:
        parts.append("<p class='meta'>Joint reaction forces: not available in this report (see the note above).</p>")
    if size.ratings is not None:
        verdict = "<span class='pass'>PASS</span>" if size.passed else "<span class='fail'>FAIL</span>"
        parts.append(f"<h3>Rating check ({_esc(size.ratings.source)}): {verdict}</h3>")
        rows = []
        for c in size.checks:
            unit, meaning = RATING_KEYS[c.item]
            mark = "<span class='pass'>pass</span>" if c.passed else "<span class='fail'>FAIL</span>"
            rows.append([f"LN{c.module}", _esc(f"{meaning} vs {c.item}"), f"{c.demand:,.1f} {_esc(unit)}", f"{c.rating:,.1f} {_esc(unit)}", f"{c.margin_pct:+.1f} %", mark])
        parts.append(_table(["module", "check", "demand", "rating", "margin", "result"], rows, left=2))

    # Tracking
    if tracking is not None:
        parts.append("<h2>Tracking</h2>")
        rows = []
        for name, row in tracking.items():
            rows.append([_esc(name), *(row[f"{a}_err_{s}_deg"] for a in ("alpha", "beta", "gamma") for s in ("peak", "rms"))])
        parts.append(_table(["controller", "α peak [deg]", "α RMS [deg]", "β peak [deg]", "β RMS [deg]", "γ peak [deg]", "γ RMS [deg]"], rows, digits=4))
        with_torque = [(name, row) for name, row in tracking.items() if "tau_peak_1_Nmm" in row]
        if with_torque:
            rows = [[_esc(name), *(row[f"tau_{s}_{i}_Nmm"] for i in (1, 2, 3) for s in ("peak", "rms"))] for name, row in with_torque]
            header = ["controller"] + [f"M{i} {s} [N·mm]" for i in (1, 2, 3) for s in ("peak", "RMS")]
            parts.append(_table(header, rows))

    # Figures
    parts.append("<h2>Figures</h2>")
    for stem, (png, svg) in figures.items():
        data = base64.b64encode(png.read_bytes()).decode("ascii")
        caption = FIGURE_CAPTIONS.get(stem, stem)
        parts.append(
            f"<figure id='{stem}'><img src='data:image/png;base64,{data}' alt='{_esc(stem)}: {_esc(caption)}'>"
            f"<figcaption>{_esc(caption)} Files: <a href='{_esc(svg.name)}'>{_esc(svg.name)}</a>, "
            f"<a href='{_esc(png.name)}'>{_esc(png.name)}</a>.</figcaption></figure>"
        )
    body = "\n".join(parts)
    return (
        "<!DOCTYPE html>\n<html lang='en'><head><meta charset='utf-8'>"
        f"<meta name='viewport' content='width=device-width, initial-scale=1'><title>hipsim report: {_esc(traj.name)}</title>"
        f"<style>{_CSS}</style></head><body>\n{body}\n</body></html>\n"
    )
