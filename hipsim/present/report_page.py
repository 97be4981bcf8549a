"""The design report's page: its verdict, its tables (every value with its unit, 3–4 significant figures) and the HTML.

:func:`report_block` renders the block at the top of the page from the
drive's verdict (:func:`hipsim.design.checks.checks_verdict`, decided beside
the sizing): PASS or FAIL with the binding check and its margin, or NOT RATED
with what the cycle asks when no drive was given. :func:`report_html` renders
``templates/report.html.j2``. The numbers are the sizing's own
(:mod:`hipsim.design.sizing`); only their presentation is here.
"""

from __future__ import annotations

import base64
import json
import math
import re

from .. import records
from ..analysis.registry import engine_entry
from ..design.sizing import CHECKS, Check, Sizing
from ..machine.drive import Drive
from ..machine.parameters import SCHEMA, file_values
from ..physics.units import RPM_PER_RAD_S as _RPM
from ..records import Level
from ..results import Run, RunSummary, Torques
from .figures import FIGURE_CAPTIONS
from .numbers import quantity, significant, with_uncertainty
from .pages import CSS, Verdict, environment
from .provenance import ParameterOrigin, Provenance

__all__ = ["report_block", "report_html"]

#: An inertia's components as the identification names them → (row, column) of the matrix.
_INERTIA_AXES = {"xx": (0, 0), "yy": (1, 1), "zz": (2, 2), "xy": (0, 1), "xz": (0, 2), "yz": (1, 2)}
#: The drive parts' fields: SI inside → (factor, unit) a rig engineer reads.
_PART_UNITS = {
    "peak_current": (1.0, "A"),
    "continuous_current": (1.0, "A"),
    "dc_bus_energy": (1.0, "J"),
    "braking_power": (1.0, "W"),
    "braking_peak_power": (1.0, "W"),
    "ratio": (1.0, ":1"),
    "efficiency": (100.0, "%"),
    "inertia": (1e6, "kg·mm²"),
    "lead": (1e3, "mm"),
    "dynamic_load_rating": (1.0, "N"),
    "preload": (1.0, "N"),
    "root_diameter": (1e3, "mm"),
    "free_length": (1e3, "mm"),
    "stroke": (1e3, "mm"),
    "axial_force": (1.0, "N"),
}


def _margin(check: Check) -> str:
    if check.margin is None:
        return "—"
    return "−∞ %" if math.isinf(check.margin) else f"{100 * check.margin:+.1f} %".replace("-", "−")


def _check_sentence(check: Check) -> str:
    """ "RMS torque under the S1 curve at the mean speed, LN1: 216.6 N·mm against ≤ 300 N·mm (margin +27.8 %)"."""
    kind = CHECKS[check.name]
    bound = "≥" if kind.bound == "min" else "≤"
    if check.margin is not None and math.isinf(check.margin):
        return f"{kind.label}, LN{check.module}: beyond the limit ({check.detail or 'no finite margin'})"
    return (
        f"{kind.label}, LN{check.module}: {quantity(check.value, kind.unit)} against {bound} {quantity(check.limit, kind.unit)} "
        f"(margin {_margin(check)})"
    )


def report_block(size: Sizing, verdict: records.Verdict) -> Verdict:
    """The page's block of the drive's verdict (:func:`hipsim.design.checks.checks_verdict` on ``size.checks``):
    PASS / FAIL with the binding check and its margin, NOT RATED with what the cycle asks when no check was made."""
    made = [c for c in size.checks if c.passed is not None]
    missing = len(size.checks) - len(made)
    if verdict.level == Level.NOT_MADE:
        peak = max(size.modules, key=lambda m: m.tau_peak_Nmm)
        rms = max(size.modules, key=lambda m: m.tau_rms_Nmm)
        fast = max(size.modules, key=lambda m: m.speed_peak_rpm)
        lines = (
            "No drive was checked: give --motor FILE or a [motor] table in the parameter file.",
            f"The cycle asks at most {quantity(peak.tau_peak_Nmm, 'N·mm')} peak (LN{peak.module}), "
            f"{quantity(rms.tau_rms_Nmm, 'N·mm')} RMS (LN{rms.module}) and {quantity(fast.speed_peak_rpm, 'rpm')} (LN{fast.module}) "
            "at the screw shafts.",
        )
        return Verdict.of(verdict, lines, not_made="NOT RATED")
    name = size.drive.name if size.drive is not None else "the drive"
    not_made = f"; {missing} not made for want of data" if missing else ""
    binding = "no check made" if size.binding is None else _check_sentence(size.binding)
    if verdict.failed:
        failing = [c for c in made if not c.passed]
        lines = (f"{name} fails {len(failing)} of the {len(made)} rating checks made{not_made}.", f"Worst: {binding}.")
    else:
        lines = (f"{name} passes all {len(made)} rating checks made{not_made}.", f"Binding: {binding}.")
    return Verdict.of(verdict, lines)


_POSTERIOR_STD = re.compile(r"(?:posterior std |± )([-+0-9.eE]+)")


def _held_reason(origin: ParameterOrigin, dotted: str) -> tuple[str, float | None] | None:
    """A parameter the logs did not determine: its origin in words ("prior-held: …") and posterior std, or None.

    Identification writes the posterior mean of such a parameter, pulled little from its prior (or
    kept, for one with no effect on the torques): not the start value as such.
    """
    reason = next((text for key, text in origin.held if key.split("[")[0] == dotted), None)
    if reason is None:
        return None
    match = _POSTERIOR_STD.search(reason)
    std = float(match.group(1)) if match else None
    return f"prior-held ({reason})", std


def _parameter_rows(params, origin: ParameterOrigin | None) -> list[dict]:
    """Key, value (identified ones with ± their standard deviation), unit, origin, meaning."""
    rows = []
    for dotted, value in file_values(params).items():
        section, key = dotted.split(".", 1)
        spec = SCHEMA[section][key]
        how, identified = origin.origin_of(dotted) if origin is not None else ("", [])
        text = _input_value(value)
        held = _held_reason(origin, dotted) if origin is not None and how == "start value, not identified" else None
        if held is not None:  # issue 38: the file holds the posterior, near its prior, not the start value
            how, std = held
            if std is not None and not isinstance(value, list):
                text = with_uncertainty(value, std)
        if identified:
            plain = [v for v in identified if not v.combination]
            if isinstance(value, list):
                stds = {_INERTIA_AXES[v.key.split("[")[1].rstrip("]")]: v.std for v in plain if "[" in v.key}
                text = _inertia_text(value, stds)
            elif plain:
                text = with_uncertainty(value, plain[0].std)
            combos = [
                f"{_shorter(v.combination)} = {with_uncertainty(v.value, v.std)} {v.unit}".strip()
                for v in identified
                if v.combination
            ]
            if combos:
                how += " as " + "; ".join(combos) + " (this value is what the combination leaves)"
        rows.append(
            {"css": "identified" if identified else "", "cells": [dotted, text, spec.unit or "–", how, spec.meaning]}
        )
    return rows


def _inertia_text(value: list, stds: dict) -> str:
    """An inertia as the file lists it (the diagonal, or the 3×3 matrix), identified components with ± their std."""
    if value and isinstance(value[0], list):

        def cell(a, b):
            std = stds.get((a, b), stds.get((b, a)))
            return with_uncertainty(value[a][b], std) if std is not None else _input_value(value[a][b])

        return "[" + ", ".join("[" + ", ".join(cell(a, b) for b in range(3)) + "]" for a in range(3)) + "]"
    return (
        "["
        + ", ".join(
            with_uncertainty(x, stds[(k, k)]) if (k, k) in stds else _input_value(x) for k, x in enumerate(value)
        )
        + "]"
    )


def _shorter(combination: str, terms: int = 3) -> str:
    """An identified combination with its first ``terms`` terms and how many more it has."""
    parts = re.split(r"(?= [+−] )", combination)
    return "".join(parts[: terms + 1]) + (f" … ({len(parts) - terms - 1} more)" if len(parts) > terms + 1 else "")


def _input_value(value) -> str:
    """An input as written when it is short (an input is not a result), else to 4 significant figures."""
    if isinstance(value, list):
        return "[" + ", ".join(_input_value(x) for x in value) + "]"
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return json.dumps(value)
    if isinstance(value, float) and not math.isfinite(value):
        return significant(value)
    written = repr(value)
    return written if len(written) <= 9 else significant(value)


def _drive_rows(drive: Drive) -> list[list[str]]:
    rows = []

    def curve_text(curve):
        torques = ", ".join(significant(x * 1e3) for x in curve.torque)
        if curve.flat:
            return f"{torques} N·mm at every speed"
        speeds = ", ".join(f"{x * _RPM:.0f}" for x in curve.speed)
        return f"{torques} N·mm at {speeds} rpm"

    motor = drive.motor
    rows.append(["motor", "name", motor.name])
    for label, curve in (("S1 curve", motor.continuous), ("peak curve", motor.peak)):
        if curve is not None:
            rows.append(["motor", label, curve_text(curve)])
    for label, value, scale, unit in (
        ("top speed", motor.top_speed, _RPM, "rpm"),
        ("rotor inertia", motor.rotor_inertia, 1e6, "kg·mm²"),
        ("torque constant", motor.torque_constant, 1.0, "N·m/A"),
        ("winding resistance (phase-phase)", motor.winding_resistance, 1.0, "Ω"),
        ("thermal time constant", motor.thermal_time_constant, 1.0, "s"),
        ("thermal resistance", motor.thermal_resistance, 1.0, "K/W"),
    ):
        if value is not None:
            rows.append(["motor", label, quantity(value * scale, unit)])
    for part in (drive.amplifier, drive.gearbox, drive.screw):
        if part is None:
            continue
        name = type(part).__name__.lower().replace("leadscrew", "lead screw")
        for key, value in vars(part).items():
            if value is None:
                continue
            if isinstance(value, str):
                rows.append([name, key.replace("_", " "), value])
            else:
                scale, unit = _PART_UNITS.get(key, (1.0, ""))
                rows.append([name, key.replace("_", " "), quantity(value * scale, unit)])
    return rows


def _rule_texts(size: Sizing) -> list[str]:
    rules = size.rules
    return [
        f"inertia ratio ≤ {rules.inertia_ratio_max:g}:1",
        f"screw L10 life ≥ {significant(rules.life_target_cycles, 3)} cycles",
        f"winding rise ≤ {rules.winding_rise_max:g} K (S1 rated at {rules.rated_winding_rise:g} K)",
        f"screw speed ≤ {rules.critical_speed_factor:g} × critical",
        f"axial load ≤ {rules.buckling_factor:g} × Euler buckling load",
    ]


def _check_rows(size: Sizing) -> list[dict]:
    rows = []
    for c in size.checks:
        kind = CHECKS[c.name]
        verdict = "not checked" if c.passed is None else ("pass" if c.passed else "FAIL")
        css = "unchecked" if c.passed is None else ("fail" if not c.passed else "")
        if c is size.binding:
            css += " binding"
        limit = "—" if c.limit is None else f"{'≥' if kind.bound == 'min' else '≤'} {quantity(c.limit, kind.unit)}"
        rows.append(
            {
                "css": css.strip(),
                "cells": [
                    f"LN{c.module}",
                    kind.label,
                    quantity(c.value, kind.unit),
                    limit,
                    _margin(c),
                    verdict,
                    c.detail,
                    kind.basis,
                ],
            }
        )
    return rows


def _tracking_rows(tracking):
    if tracking is None:
        return None, None
    angles = [
        [
            name,
            *(
                significant(row[f"{a}_err_{s}_deg"], 3, zeros=False)
                for a in ("alpha", "beta", "gamma")
                for s in ("peak", "rms")
            ),
        ]
        for name, row in tracking.items()
    ]
    torques = [
        [name, *(significant(row[f"tau_{s}_{i}_Nmm"]) for i in (1, 2, 3) for s in ("peak", "rms"))]
        for name, row in tracking.items()
        if "tau_peak_1_Nmm" in row
    ]
    return angles, torques


def report_html(
    result: Run,
    summary: RunSummary,
    size: Sizing,
    tracking,
    figures,
    notes,
    joint_model: str,
    provenance: Provenance | None,
    verdict: Verdict,
) -> str:
    """The page of :func:`hipsim.present.report.write_report`."""
    traj = result.trajectory
    duration = traj.t[-1] - traj.t[0] + (traj.t[1] - traj.t[0] if len(traj) > 1 else 0)
    sliders = [
        [
            f"S{name}",
            *(significant(v) for v in (s.L_max_mm, s.L_min_mm, s.stroke_mm, s.Ld_max_mm_s, s.Ldd_max_mm_s2)),
        ]
        for name, s in summary.sliders.items()
    ]
    motors = [
        [
            f"M{i}",
            *(significant(getattr(m, f"{Torques.COLUMN[p]}_max_Nmm")) for p in Torques.PARTS),
            significant(m.tau_peak_Nmm),
            significant(m.tau_rms_Nmm),
            significant(m.speed_peak_rpm),
        ]
        for i, m in summary.motors.items()
    ]
    demands = [
        [
            f"LN{m.module}",
            *(
                significant(getattr(m, k))
                for k in (
                    "tau_peak_Nmm",
                    "tau_rms_Nmm",
                    "speed_peak_rpm",
                    "speed_mean_rpm",
                    "power_peak_W",
                    "motor_thrust_peak_N",
                    "axial_force_peak_N",
                    "axial_force_cubic_mean_N",
                    "revolutions_per_cycle",
                    "load_inertia_max_kgmm2",
                    "regen_energy_J",
                    "stroke_mm",
                )
            ),
        ]
        for m in size.modules
    ]
    joints = (
        [[j.joint, significant(j.peak_N), significant(j.rms_N)] for j in size.joints]
        if size.joints is not None
        else None
    )
    tracking_rows, tracking_torques = _tracking_rows(tracking)
    figure_items = [
        {
            "stem": stem,
            "data": base64.b64encode(png.read_bytes()).decode("ascii"),
            "caption": FIGURE_CAPTIONS.get(stem, stem),
            "png": png.name,
            "svg": svg.name,
        }
        for stem, (png, svg) in figures.items()
    ]
    binding = size.binding
    origin = provenance.parameters if provenance is not None else None
    return (
        environment()
        .get_template("report.html.j2")
        .render(
            css=CSS,
            verdict=verdict,
            provenance=provenance,
            title=provenance.title if provenance is not None and provenance.title else None,
            trajectory={"name": traj.name, "samples": len(traj), "duration": significant(duration)},
            params_source=result.params.source,
            delta=f"{math.degrees(result.params.home_offset):g}",
            notes=notes,
            sliders=sliders,
            motors=motors,
            cond_inv_min=f"{summary.cond_inv_min:.4f}",
            cond_inv_t=significant(summary.cond_inv_min_t_s),
            demands=demands,
            joints=joints,
            joint_model=engine_entry(joint_model).title,
            checks=_check_rows(size) if size.checks else None,
            passed=size.passed,
            binding=_check_sentence(binding) if binding is not None else None,
            drive_name=size.drive.name if size.drive is not None else "",
            drive_source=size.drive.source if size.drive is not None else "",
            rules=_rule_texts(size),
            tracking=tracking_rows,
            tracking_torques=tracking_torques,
            tracking_torque_header=["controller"] + [f"M{i} {s} [N·mm]" for i in (1, 2, 3) for s in ("peak", "RMS")],
            figures=figure_items,
            parameters=_parameter_rows(result.params, origin),
            drive_rows=_drive_rows(size.drive) if size.drive is not None else None,
        )
    )
