"""The checks of a drive along a run, the way industrial sizing tools make them: each with value, limit, margin and pass/fail.

The checks per module (:data:`CHECKS`), over every sample of the cycle:

- motor: every (speed, torque) point under the peak curve; the RMS torque at
  the mean speed under the S1 curve; the peak speed; the load-to-rotor inertia
  ratio, the load being the machine's inertia M(q) reflected to the motor along
  the cycle; the winding temperature rise from the copper losses (first-order
  thermal model);
- amplifier: peak and RMS current; regenerated energy per cycle and the mean
  and peak regenerative power (negative motor power);
- lead screw: L10 life in test cycles (ISO 3408-5), critical (whirling)
  speed, buckling load, stroke, permissible axial load.

A check whose data are missing is listed with ``passed`` None and says what
it needs. The formulas are in :mod:`hipsim.design.ratings` and the README.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np

from ..machine.drive_parts import DIRECT, Drive, SizingRules
from ..physics.units import RPM_PER_RAD_S
from ..records import Level, Verdict
from .demand import ScrewSide, motor_duty
from .ratings import buckling_load, critical_speed, screw_life, weighted_mean, winding_rise

__all__ = [
    "CHECKS",
    "FAILURE_ORDER",
    "MOTOR_INDEPENDENT",
    "Check",
    "binding_check",
    "checks_verdict",
    "drive_checks",
    "first_failure",
    "margin_order",
]


@dataclass(frozen=True)
class _CheckKind:
    label: str
    unit: str
    bound: str  # "max": value ≤ limit; "min": value ≥ limit
    basis: str


#: Every check: its label, unit, bound and the rule or standard it follows.
CHECKS = {
    "peak_curve": _CheckKind(
        "torque under the peak curve (worst point)",
        "N·mm",
        "max",
        "every sample's (|n|, |τ_m|) against the peak torque–speed curve",
    ),
    "s1_rms": _CheckKind(
        "RMS torque under the S1 curve at the mean speed",
        "N·mm",
        "max",
        "τ_rms = √(mean τ_m²) against S1(mean |n|), as SIZER/Motioneering do",
    ),
    "max_speed": _CheckKind("peak motor speed", "rpm", "max", "max |n| against the motor's top speed"),
    "inertia_ratio": _CheckKind(
        "load-to-rotor inertia ratio (worst pose)",
        ":1",
        "max",
        "(M_θ,ii/i² + J_g)/J_m, M_θ = the model's M(q) at the screw shafts",
    ),
    "winding_rise": _CheckKind(
        "winding temperature rise (first-order)",
        "K",
        "max",
        "copper loss 3/2·R_pp·(τ_m/k_t)² through R_th with time constant τ_th",
    ),
    "amplifier_peak_current": _CheckKind(
        "peak current", "A", "max", "max |τ_m|/k_t against the amplifier's peak current"
    ),
    "amplifier_rms_current": _CheckKind(
        "RMS current", "A", "max", "τ_rms/k_t against the amplifier's continuous current"
    ),
    "regen_energy": _CheckKind(
        "regenerated energy per cycle",
        "J",
        "max",
        "∫ max(−τ_m·ω_m, 0) dt against the DC link's energy (losses ignored)",
    ),
    "regen_power_mean": _CheckKind(
        "mean regenerative power", "W", "max", "regenerated energy / cycle time against the braking resistor's power"
    ),
    "regen_power_peak": _CheckKind(
        "peak regenerative power", "W", "max", "max(−τ_m·ω_m) against the braking resistor's peak power"
    ),
    "screw_life": _CheckKind(
        "lead screw L10 life",
        "cycles",
        "min",
        "ISO 3408-5: L10 = (C_a/F_m)³·10⁶ rev, F_m the cubic mean over revolutions",
    ),
    "critical_speed": _CheckKind(
        "screw speed against the critical (whirling) speed",
        "rpm",
        "max",
        "n_cr = λ²·d₂/(8π·l²)·√(E/ρ) (Euler–Bernoulli) × safety factor",
    ),
    "buckling": _CheckKind(
        "axial screw load against the buckling load", "N", "max", "F_k = m·π²·E·(π d₂⁴/64)/l² (Euler) × safety factor"
    ),
    "stroke": _CheckKind("carriage stroke", "mm", "max", "max L − min L against the usable stroke"),
    "axial_force": _CheckKind(
        "peak axial screw load", "N", "max", "max |2π(τ − τ_L − τ_sf)/p| against the permissible load"
    ),
}

#: The checks that compare the screw's figures with the machine's demand: the same for every motor
#: and gearbox on one screw, so a ranking reports them once rather than breaking ties with them.
MOTOR_INDEPENDENT = frozenset({"screw_life", "critical_speed", "buckling", "stroke", "axial_force"})

#: The order a failure is read in: the top speed first (past it the torque curves are zero, so
#: their "−∞" margin only repeats that the motor cannot turn so fast), then the rest as listed.
FAILURE_ORDER = ("max_speed",) + tuple(key for key in CHECKS if key != "max_speed")


@dataclass(frozen=True)
class Check:
    """One check of one module.

    Attributes:
        module: i (1, 2, 3).
        name: the key in :data:`CHECKS` (label, unit, bound, basis).
        value: what the cycle gives, in the check's unit; None when it cannot be computed.
        limit: what the part allows (or, for a "min" check, what is required); None when not given.
        margin: the unused fraction of the capacity: 1 − value/limit (or 1 − limit/value for
            a "min" check); negative when it fails; None when not checked.
        passed: True or False; None when not checked (data missing: see ``detail``).
        detail: where the worst point lies, or what is missing.
        trajectory: the trajectory's name.
    """

    module: int
    name: str
    value: float | None
    limit: float | None
    margin: float | None
    passed: bool | None
    detail: str = ""
    trajectory: str = ""

    @property
    def kind(self) -> _CheckKind:
        return CHECKS[self.name]


def _check(module: int, name: str, value, limit, detail: str = "", trajectory: str = "", missing: str = "") -> Check:
    """A :class:`Check`, with its margin and verdict; ``missing`` (what data are absent) makes it unchecked."""
    value = None if value is None else float(value)
    if missing or limit is None or value is None:
        return Check(
            module,
            name,
            value,
            None if limit is None else float(limit),
            None,
            None,
            f"not checked: {missing}" if missing else detail,
            trajectory,
        )
    limit = float(limit)
    if CHECKS[name].bound == "max":
        margin = 1.0 - value / limit if limit > 0 else (1.0 if value <= 0 else -math.inf)
        passed = value <= limit
    else:
        margin = 1.0 - limit / value if value > 0 else (1.0 if limit <= 0 else -math.inf)
        passed = value >= limit
    return Check(module, name, value, limit, float(margin), bool(passed), detail, trajectory)


def margin_order(check: Check) -> float:
    """A check's margin as a sort key: a check not made (no margin) after every one made."""
    return math.inf if check.margin is None else check.margin


def binding_check(checks: Iterable[Check]) -> Check | None:
    """The check with the smallest margin, the one that decides; None when no check could be made."""
    made = [c for c in checks if c.margin is not None]
    return min(made, key=margin_order) if made else None


def first_failure(checks: Iterable[Check]) -> Check | None:
    """The failing check that says most plainly why: the first failing kind in :data:`FAILURE_ORDER`, its worst module; None when none fails."""
    failed = [c for c in checks if c.passed is False]
    if not failed:
        return None
    kind = min(failed, key=lambda c: FAILURE_ORDER.index(c.name)).name
    return min((c for c in failed if c.name == kind), key=margin_order)


def _worst(values: np.ndarray, weights: np.ndarray) -> int:
    """Index of the largest value among the samples that count."""
    return int(np.argmax(np.where(weights > 0, values, -np.inf)))


def drive_checks(side: ScrewSide, drive: Drive, rules: SizingRules | None = None) -> list[Check]:
    """Every check of :data:`CHECKS` for the three modules driven by ``drive`` along one run."""
    rules = rules if rules is not None else drive.rules
    duty = motor_duty(side, drive)
    motor, amplifier, screw = drive.motor, drive.amplifier, drive.screw
    gearbox = drive.gearbox if drive.gearbox is not None else DIRECT
    w = side.weights
    t = side.run.t
    name = side.run.trajectory.name
    speed, torque = np.abs(duty.speed), np.abs(duty.torque)
    tau_rms = np.sqrt(weighted_mean(duty.torque**2, w))
    mean_speed = weighted_mean(speed, w)
    regen = np.maximum(-duty.power, 0.0)
    regen_energy = np.sum(regen * w[:, None], axis=0) / side.cycles
    regen_mean = np.sum(regen * w[:, None], axis=0) / side.duration
    checks: list[Check] = []
    for i in range(3):
        module = i + 1

        def add(key, value, limit, detail="", missing="", module=module):
            checks.append(_check(module, key, value, limit, detail, name, missing))

        # Motor: peak curve, S1, speed.
        if motor.peak is not None:
            available = motor.peak.at(speed[:, i])
            with np.errstate(divide="ignore", invalid="ignore"):
                load = np.where(available > 0, torque[:, i] / available, np.where(torque[:, i] > 0, np.inf, 0.0))
            k = _worst(load, w)
            beyond = " (beyond the curve's top speed)" if available[k] == 0 else ""
            add(
                "peak_curve",
                torque[k, i] * 1e3,
                available[k] * 1e3,
                f"at {speed[k, i] * RPM_PER_RAD_S:.0f} rpm{beyond}, t = {t[k]:.3f} s",
            )
        else:
            add("peak_curve", torque[:, i].max() * 1e3, None, missing="no peak torque curve")
        if motor.continuous is not None:
            add(
                "s1_rms",
                tau_rms[i] * 1e3,
                motor.continuous.at(mean_speed[i]) * 1e3,
                f"mean speed {mean_speed[i] * RPM_PER_RAD_S:.0f} rpm",
            )
        else:
            add("s1_rms", tau_rms[i] * 1e3, None, missing="no S1 curve")
        top = motor.top_speed
        add(
            "max_speed",
            speed[:, i].max() * RPM_PER_RAD_S,
            None if top is None else top * RPM_PER_RAD_S,
            missing="" if top is not None else "no top speed",
        )

        # Load-to-rotor inertia ratio, the load from M(q) along the cycle.
        load_inertia = side.load_inertia[:, i] / gearbox.ratio**2 + gearbox.inertia
        if motor.rotor_inertia is not None:
            k = _worst(np.nan_to_num(load_inertia, nan=-np.inf), w)
            add(
                "inertia_ratio",
                load_inertia[k] / motor.rotor_inertia,
                rules.inertia_ratio_max,
                f"load {load_inertia[k] * 1e4:.3g} kg·cm² at t = {t[k]:.3f} s, rotor {motor.rotor_inertia * 1e4:.3g} kg·cm²",
            )
        else:
            add("inertia_ratio", None, rules.inertia_ratio_max, missing="no rotor inertia")

        # Winding temperature: R_th·P_cu with P_cu = 3/2·R_pp·(τ/k_t)², or scaled from the S1 stall torque.
        heating_per_torque2 = None
        if (
            motor.thermal_resistance is not None
            and motor.torque_constant is not None
            and motor.winding_resistance is not None
        ):
            heating_per_torque2 = motor.thermal_resistance * 1.5 * motor.winding_resistance / motor.torque_constant**2
            basis = "R_th given"
        elif motor.continuous is not None and motor.continuous.at(0.0) > 0:
            heating_per_torque2 = rules.rated_winding_rise / float(motor.continuous.at(0.0)) ** 2
            basis = f"R_th from the S1 stall torque at {rules.rated_winding_rise:g} K"
        if heating_per_torque2 is None:
            add(
                "winding_rise",
                None,
                rules.winding_rise_max,
                missing="needs thermal_resistance_K_W, torque_constant_Nm_A and winding_resistance_ohm, or an S1 curve",
            )
        else:
            mean_rise, peak_rise = winding_rise(
                heating_per_torque2 * duty.torque[:, i : i + 1] ** 2, w, motor.thermal_time_constant
            )
            how = (
                "peak of the periodic cycle"
                if motor.thermal_time_constant is not None
                else "mean (no thermal time constant given)"
            )
            add("winding_rise", peak_rise[0], rules.winding_rise_max, f"{how}; mean {mean_rise[0]:.3g} K; {basis}")

        # Amplifier: currents and regeneration.
        kt = motor.torque_constant
        for key, value, limit_name in (
            ("amplifier_peak_current", None if kt is None else torque[:, i].max() / kt, "peak_current"),
            ("amplifier_rms_current", None if kt is None else tau_rms[i] / kt, "continuous_current"),
        ):
            limit = None if amplifier is None else getattr(amplifier, limit_name)
            missing = (
                "no torque constant"
                if kt is None
                else ("" if limit is not None else f"no amplifier {limit_name.replace('_', ' ')}")
            )
            add(key, value, limit, missing=missing)
        for key, value, limit_name in (
            ("regen_energy", regen_energy[i], "dc_bus_energy"),
            ("regen_power_mean", regen_mean[i], "braking_power"),
            ("regen_power_peak", regen[:, i].max(), "braking_peak_power"),
        ):
            limit = None if amplifier is None else getattr(amplifier, limit_name)
            add(key, value, limit, missing="" if limit is not None else f"no {limit_name.replace('_', ' ')} given")

        # Lead screw.
        load = side.axial_load[:, i]
        if screw is not None and screw.dynamic_load_rating is not None:
            life, equivalent = screw_life(load, side.speed[:, i], w, screw.dynamic_load_rating, screw.preload)
            revolutions = np.sum(np.abs(side.speed[:, i]) * w) / (2.0 * math.pi) / side.cycles
            cycles = life / revolutions if revolutions > 0 else math.inf
            add(
                "screw_life",
                cycles,
                rules.life_target_cycles,
                f"{life:.3g} rev at {revolutions:.3g} rev/cycle; equivalent load {equivalent:.0f} N (preload {screw.preload:g} N)",
            )
        else:
            add("screw_life", None, rules.life_target_cycles, missing="no dynamic load rating C_a")
        has_geometry = screw is not None and None not in (screw.root_diameter, screw.free_length, screw.end_fixing)
        geometry = screw if has_geometry else None
        missing = "" if geometry else "needs root_diameter_mm, free_length_mm and end_fixing"
        add(
            "critical_speed",
            np.abs(side.speed[:, i]).max() * RPM_PER_RAD_S,
            rules.critical_speed_factor * critical_speed(geometry) * RPM_PER_RAD_S if geometry else None,
            f"{rules.critical_speed_factor:g} × critical speed" if geometry else "",
            missing,
        )
        add(
            "buckling",
            np.abs(load).max(),
            rules.buckling_factor * buckling_load(geometry) if geometry else None,
            f"{rules.buckling_factor:g} × Euler load" if geometry else "",
            missing,
        )
        ok = w > 0
        stroke = np.ptp(side.run.L[ok, 0, i]) * 1e3
        limit = None if screw is None or screw.stroke is None else screw.stroke * 1e3
        add("stroke", stroke, limit, missing="" if limit is not None else "no usable stroke given")
        limit = None if screw is None or screw.axial_force is None else screw.axial_force
        add(
            "axial_force",
            np.abs(load).max(),
            limit,
            missing="" if limit is not None else "no permissible axial load given",
        )
    return checks


def checks_verdict(checks: Iterable[Check], what: str = "the drive") -> Verdict:
    """The verdict of a drive's checks: FAIL when one made fails, PASS when every one made passes, NOT MADE when none
    could be made. Judged: the checks made, the binding one (smallest margin) named with its margin; not judged: the
    checks missing their data.

    Args:
        checks: the checks (:func:`drive_checks`).
        what: the drive's name, for the sentence.
    """
    checks = tuple(checks)
    made = [c for c in checks if c.passed is not None]
    missing = sorted({CHECKS[c.name].label for c in checks if c.passed is None})
    not_judged = f"not checked for want of data: {', '.join(missing)}" if missing else ""
    binding = binding_check(checks)
    if not made or binding is None or binding.margin is None:
        return Verdict(Level.NOT_MADE, f"no check of {what} could be made", not_judged)
    failed = [c for c in made if c.passed is False]
    judged = (
        f"{len(made) - len(failed)} of {len(made)} checks of {what} pass; binding: {binding.kind.label}, "
        f"LN{binding.module}, margin {binding.margin:+.3g}"
    )
    numbers = {"checks_made": float(len(made)), "checks_failed": float(len(failed)), "binding_margin": binding.margin}
    return Verdict(Level.FAIL if failed else Level.PASS, judged, not_judged, numbers)
