"""Design reports: one folder a designer can hand on.

:func:`write_report` takes the runs the caller made (torques from one model,
joint forces from the Pinocchio model when there is one) and writes every
figure as PNG and SVG, ``index.html`` (one self-contained page: the PNGs are
embedded as data URIs, so it works offline and after the folder is moved or
the page is mailed alone), ``report.json`` (the summary and sizing numbers)
and ``torques.csv`` (the columns of spec §7.5). The numbers come from
:mod:`hipsim.design.sizing`, the figures from :mod:`hipsim.present.figures`,
the page from a Jinja template (``templates/report.html.j2``, autoescaped).

The folder is written whole or not at all: everything goes to a temporary
folder beside it, which then takes its place. A report interrupted halfway
leaves the folder as it was; a report re-run into its folder leaves no figure
of the earlier run behind. An existing folder is replaced only when it is
empty or holds a hipsim report, never a folder of other files.
"""

from __future__ import annotations

import base64
import dataclasses
import json
import math
import os
import shutil
import tempfile
import uuid
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Mapping

import numpy as np

from ..design.sizing import CHECKS, Sizing, sizing
from ..exceptions import HipsimError
from ..files import check_folder, json_ready, output_folder, write_atomic
from ..machine.drive import Drive
from ..machine.parameters import SCHEMA, file_values
from ..results import Run, Torques, peak_and_rms
from .figures import (
    FIGURE_CAPTIONS,
    plot_axial_load_histogram,
    plot_input_motion,
    plot_joint_forces,
    plot_load_friction,
    plot_singularity,
    plot_slider_motion,
    plot_torque_parts,
    plot_torque_speed,
    plot_tracking,
    save_figure,
    tracking_arrays,
)

__all__ = ["ReportFiles", "write_report"]

#: Marks a folder as a hipsim report, which a later report may replace.
MARKER = ".hipsim-report"
#: What an earlier report folder (before the marker) holds.
_REPORT_SUFFIXES = {".png", ".svg", ".html", ".json", ".csv"}


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
    drive: Drive | None = None,
    notes: tuple[str, ...] = (),
    cycles: float = 1.0,
) -> ReportFiles:
    """Write the design report folder of a run.

    Writes ``out_dir`` whole (its parents created if missing): ``input_motion``,
    ``slider_motion``, ``motor_torques``, ``load_friction``, ``singularity``,
    ``torque_speed``, ``axial_load`` and, when available, ``joint_forces`` and
    ``tracking_errors``, each as ``.png`` and ``.svg``; ``index.html``;
    ``report.json`` (summary and sizing) and ``torques.csv`` (spec §7.5 columns).

    Args:
        out_dir: the folder to write; if it exists it must be empty or an earlier report, which this one replaces whole.
        run: the run whose torques, motion and singularity measure are reported.
        joint_forces_run: a run along the same trajectory whose joint forces
            are reported with ``run``'s torques (the Pinocchio model's, when
            ``run`` is analytic); None to use ``run``'s own, if it has any.
        simulations: tracking simulations to plot: {controller name: object
            with ``t`` (N,) in [s] and ``err`` (N, 3) in [rad], and optionally
            ``tau`` (N, 3) in [N·m]}; None for no tracking section.
        drive: the drive train to check the sizing against; None for no check.
        notes: sentences shown at the top of the page (model fallbacks, estimates).
        cycles: test cycles the trajectory holds (screw life in cycles, energy per cycle).

    Returns:
        The :class:`ReportFiles`.

    Raises:
        HipsimError: for inputs that do not fit, a folder that holds other files, or a write that fails.
    """
    out = Path(out_dir)
    check_folder(out)  # fail now, not after the plotting
    _check_replaceable(out)
    notes = list(notes)
    if run.params.platform_mass > 0:
        notes.append(f"The platform mass m_m = {run.params.platform_mass:g} kg is an estimate (not published); it enters only the thrust-bearing friction.")
    combined = run
    joint_model = run.model
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
        joint_model = joint_forces_run.model
    if simulations is not None:
        if not isinstance(simulations, Mapping) or not simulations:
            raise HipsimError("simulations must be a non-empty mapping {controller name: result with t and err}")
        for name, sim in simulations.items():
            tracking_arrays(name, sim)
    size = sizing(combined, drive, cycles=cycles)

    plots = [
        ("input_motion", lambda: plot_input_motion(combined)),
        ("slider_motion", lambda: plot_slider_motion(combined)),
        ("motor_torques", lambda: plot_torque_parts(combined)),
        ("load_friction", lambda: plot_load_friction(combined)),
        ("singularity", lambda: plot_singularity(combined)),
        ("torque_speed", lambda: plot_torque_speed(size)),
        ("axial_load", lambda: plot_axial_load_histogram(size)),
    ]
    if combined.joint_forces is not None:
        plots.append(("joint_forces", lambda: plot_joint_forces(combined, joint_model)))
    if simulations is not None:
        plots.append(("tracking_errors", lambda: plot_tracking(simulations)))
    summary = combined.summary()
    tracking = _tracking_table(simulations) if simulations is not None else None

    def write(folder: Path) -> tuple[list[str], list[str]]:
        figures = {stem: save_figure(make(), folder, stem) for stem, make in plots}
        document = {"summary": summary, "sizing": size.as_dict(), "tracking": tracking, "notes": notes,
                    "parameters": file_values(combined.params),
                    "figures": {stem: [p.name for p in paths] for stem, paths in figures.items()}}
        write_atomic(folder / "report.json", json.dumps(json_ready(document), indent=2, default=_plain) + "\n")
        combined.write_csv(folder / "torques.csv")
        write_atomic(folder / "index.html", _html(combined, summary, size, tracking, figures, notes, joint_model))
        write_atomic(folder / MARKER, "a hipsim report: `hipsim report` may replace this folder whole\n")
        return list(figures), ["report.json", "torques.csv"]

    stems, data = _write_whole(out, write)
    folder = out
    figures = {stem: (folder / f"{stem}.png", folder / f"{stem}.svg") for stem in stems}
    return ReportFiles(folder, folder / "index.html", figures, tuple(folder / name for name in data), tuple(notes), size)


def _check_replaceable(out: Path) -> None:
    """Refuse to replace a folder that is neither empty nor a hipsim report."""
    target = _target(out)
    if not target.is_dir():
        return
    entries = list(target.iterdir())
    if not entries or (target / MARKER).is_file():
        return
    looks_like_report = [p.is_file() and p.suffix in _REPORT_SUFFIXES for p in entries]
    if all(looks_like_report) and {"index.html", "report.json"} <= {p.name for p in entries}:
        return  # a report from before the marker
    other = next((p.name for p, ok in sorted(zip(entries, looks_like_report)) if not ok), sorted(p.name for p in entries)[0])
    raise HipsimError(f"{out}: the folder holds other files (e.g. '{other}'), and a report replaces its folder whole: "
                      "choose a new or empty folder")


def _target(out: Path) -> Path:
    """The folder to replace: a symbolic link's target (the link is kept), as an absolute path."""
    try:
        return Path(os.path.realpath(out)) if out.is_symlink() else Path(os.path.abspath(out))
    except OSError:
        return Path(os.path.abspath(out))


def _write_whole(out: Path, write):
    """Run ``write(folder)`` into a fresh folder beside ``out``, then put that folder in ``out``'s place.

    On any failure (a write refused, Ctrl-C) the fresh folder is removed and
    ``out`` is as it was; parents made for it are taken back if empty.
    """
    target = _target(out)
    with output_folder(target.parent):
        try:
            staging = Path(tempfile.mkdtemp(dir=target.parent, prefix=f".{target.name}.", suffix=".part"))
        except OSError as error:
            raise HipsimError(f"{out}: cannot make the output folder ({error.strerror or error})") from None
        try:
            umask = os.umask(0)
            os.umask(umask)
            os.chmod(staging, 0o777 & ~umask)  # mkdtemp makes it private; give it a new folder's permissions
            result = write(staging)
            if target.exists():
                old = target.parent / f".{target.name}.{uuid.uuid4().hex[:8]}.old"
                os.rename(target, old)
                try:
                    os.rename(staging, target)
                except BaseException:
                    os.rename(old, target)
                    raise
                shutil.rmtree(old, ignore_errors=True)
            else:
                os.rename(staging, target)
        except OSError as error:
            shutil.rmtree(staging, ignore_errors=True)
            raise HipsimError(f"{out}: cannot write the report ({error.strerror or error})") from None
        except BaseException:
            shutil.rmtree(staging, ignore_errors=True)
            raise
    return result


def _plain(value):
    """JSON for what json does not know (NumPy numbers and arrays)."""
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, np.generic):
        return value.item()
    raise TypeError(f"not JSON: {type(value).__name__}")


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




# ---------------------------------------------------------------------------
# HTML

_CSS = """
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
figure { margin: 1em 0 2em; }
figure img { max-width: 100%; border: 1px solid #ddd; }
figcaption { font-size: 0.9em; color: #444; }
"""


def _environment():
    import jinja2

    return jinja2.Environment(
        loader=jinja2.PackageLoader("hipsim.present", "templates"),
        autoescape=True,
        undefined=jinja2.StrictUndefined,
        trim_blocks=True,
        lstrip_blocks=True,
    )


def _fixed(value, digits: int = 1) -> str:
    """A number with thousands separators and fixed decimals; — for none."""
    if value is None or (isinstance(value, float) and not math.isfinite(value)):
        return "—" if value is None or math.isnan(value) else ("∞" if value > 0 else "−∞")
    return f"{value:,.{digits}f}"


def _significant(value, digits: int = 3) -> str:
    """A number to ``digits`` significant figures (small tracking errors stay readable); — for none."""
    if value is None or (isinstance(value, float) and not math.isfinite(value)):
        return "—" if value is None or math.isnan(value) else ("∞" if value > 0 else "−∞")
    return f"{value:.{digits}g}"


def _check_value(value, unit: str) -> str:
    if value is None:
        return "—"
    if unit == "cycles" or (math.isfinite(value) and (abs(value) >= 1e6 or 0 < abs(value) < 0.01)):
        return f"{_significant(value)} {unit}"
    return f"{_fixed(value, 1 if abs(value) < 1e4 else 0)} {unit}"


def _parameter_rows(params) -> list[list[str]]:
    rows = []
    for dotted, value in file_values(params).items():
        section, key = dotted.split(".", 1)
        spec = SCHEMA[section][key]
        rows.append([dotted, json.dumps(value).replace("Infinity", "inf"), spec.unit or "–", spec.meaning])
    return rows


def _drive_rows(drive: Drive) -> list[list[str]]:
    rows = []

    def curve_text(curve):
        torques = ", ".join(f"{x * 1e3:g}" for x in curve.torque)
        if curve.flat:
            return f"{torques} N·mm at every speed"
        speeds = ", ".join(f"{x * 60 / (2 * math.pi):.0f}" for x in curve.speed)
        return f"{torques} N·mm at {speeds} rpm"

    motor = drive.motor
    rows.append(["motor", "name", motor.name])
    for label, curve in (("S1 curve", motor.continuous), ("peak curve", motor.peak)):
        if curve is not None:
            rows.append(["motor", label, curve_text(curve)])
    for label, value, scale, unit in (
        ("top speed", motor.top_speed, 60 / (2 * math.pi), "rpm"), ("rotor inertia", motor.rotor_inertia, 1e4, "kg·cm²"),
        ("torque constant", motor.torque_constant, 1.0, "N·m/A"), ("winding resistance (phase-phase)", motor.winding_resistance, 1.0, "Ω"),
        ("thermal time constant", motor.thermal_time_constant, 1.0, "s"), ("thermal resistance", motor.thermal_resistance, 1.0, "K/W"),
    ):
        if value is not None:
            rows.append(["motor", label, f"{value * scale:.4g} {unit}"])
    for part in (drive.amplifier, drive.gearbox, drive.screw):
        if part is None:
            continue
        name = type(part).__name__.lower().replace("leadscrew", "lead screw")
        for key, value in vars(part).items():
            if value is not None:
                rows.append([name, key.replace("_", " "), value if isinstance(value, str) else f"{value:.6g} (SI)"])
    return rows


def _html(result: Run, summary: dict, size: Sizing, tracking, figures, notes, joint_model: str) -> str:
    from .. import __version__

    traj = result.trajectory
    duration = traj.t[-1] - traj.t[0] + (traj.t[1] - traj.t[0] if len(traj) > 1 else 0)
    sliders = [[f"S{name}", *(_fixed(s[k]) for k in ("L_max_mm", "L_min_mm", "stroke_mm", "Ld_max_mm_s", "Ldd_max_mm_s2"))]
               for name, s in summary["sliders"].items()]
    motors = [[f"M{i}", *(_fixed(m[f"{Torques.COLUMN[p]}_max_Nmm"]) for p in Torques.PARTS), _fixed(m["tau_peak_Nmm"]),
               _fixed(m["tau_rms_Nmm"]), _fixed(m["speed_peak_rpm"])] for i, m in summary["motors"].items()]
    demands = [[f"LN{m.module}", *(_fixed(getattr(m, k)) for k in (
        "tau_peak_Nmm", "tau_rms_Nmm", "speed_peak_rpm", "speed_mean_rpm", "power_peak_W", "motor_thrust_peak_N",
        "axial_force_peak_N", "axial_force_cubic_mean_N", "revolutions_per_cycle", "load_inertia_max_kgmm2", "regen_energy_J", "stroke_mm"))]
        for m in size.modules]
    joints = [[j.joint, _fixed(j.peak_N), _fixed(j.rms_N)] for j in size.joints] if size.joints is not None else None
    binding = size.binding
    checks = []
    for c in size.checks:
        kind = CHECKS[c.name]
        verdict = "not checked" if c.passed is None else ("pass" if c.passed else "FAIL")
        css = "unchecked" if c.passed is None else ("fail" if not c.passed else "")
        if c is binding:
            css += " binding"
        margin = "—" if c.margin is None else ("−∞" if math.isinf(c.margin) else f"{100 * c.margin:+.1f} %")
        limit = "—" if c.limit is None else f"{'≥' if kind.bound == 'min' else '≤'} {_check_value(c.limit, kind.unit)}"
        checks.append({"css": css.strip(), "cells": [f"LN{c.module}", kind.label, _check_value(c.value, kind.unit), limit, margin, verdict, c.detail, kind.basis]})
    rules = size.rules
    rule_texts = [f"inertia ratio ≤ {rules.inertia_ratio_max:g}:1", f"screw L10 life ≥ {rules.life_target_cycles:.3g} cycles",
                  f"winding rise ≤ {rules.winding_rise_max:g} K (S1 rated at {rules.rated_winding_rise:g} K)",
                  f"screw speed ≤ {rules.critical_speed_factor:g} × critical", f"axial load ≤ {rules.buckling_factor:g} × Euler buckling load"]
    tracking_rows = tracking_torques = None
    if tracking is not None:
        tracking_rows = [[name, *(_significant(row[f"{a}_err_{s}_deg"]) for a in ("alpha", "beta", "gamma") for s in ("peak", "rms"))]
                         for name, row in tracking.items()]
        tracking_torques = [[name, *(_fixed(row[f"tau_{s}_{i}_Nmm"]) for i in (1, 2, 3) for s in ("peak", "rms"))]
                            for name, row in tracking.items() if "tau_peak_1_Nmm" in row]
    figure_items = [
        {"stem": stem, "data": base64.b64encode(png.read_bytes()).decode("ascii"), "caption": FIGURE_CAPTIONS.get(stem, stem),
         "png": png.name, "svg": svg.name}
        for stem, (png, svg) in figures.items()
    ]
    binding_text = None
    if binding is not None:
        binding_text = (f"{CHECKS[binding.name].label}, LN{binding.module}: {_check_value(binding.value, CHECKS[binding.name].unit)} "
                        f"against {_check_value(binding.limit, CHECKS[binding.name].unit)} (margin {100 * binding.margin:+.1f} %)"
                        if math.isfinite(binding.margin) else f"{CHECKS[binding.name].label}, LN{binding.module}: beyond the limit")
    return _environment().get_template("report.html.j2").render(
        css=_CSS,
        trajectory={"name": traj.name, "samples": len(traj), "duration": f"{duration:.4g}"},
        params_source=result.params.source,
        delta=f"{math.degrees(result.params.home_offset):g}",
        version=__version__,
        notes=notes,
        sliders=sliders,
        motors=motors,
        cond_inv_min=f"{summary['cond_inv_min']:.4f}",
        cond_inv_t=f"{summary['cond_inv_min_t_s']:.4g}",
        demands=demands,
        joints=joints,
        joint_model="Pinocchio closed-chain" if joint_model == "pinocchio" else joint_model,
        checks=checks,
        passed=size.passed,
        binding=binding_text,
        drive_name=size.drive.name if size.drive is not None else "",
        drive_source=size.drive.source if size.drive is not None else "",
        rules=rule_texts,
        tracking=tracking_rows,
        tracking_torques=tracking_torques,
        tracking_torque_header=["controller"] + [f"M{i} {s} [N·mm]" for i in (1, 2, 3) for s in ("peak", "RMS")],
        figures=figure_items,
        parameters=_parameter_rows(result.params),
        drive_rows=_drive_rows(size.drive) if size.drive is not None else None,
    )
