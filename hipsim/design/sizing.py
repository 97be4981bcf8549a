"""Sizing: what a run asks of each linear module, checked against a drive the way industrial sizing tools check it.

Pure: it returns data (the report and the command line present it).

:func:`sizing` gives one run's sizing table (per module and joint) and a
drive's checks along it. Its parts, each in its own module and every name
importable from here too:

- the demand along the run, and the two forces along each screw
  (:func:`motor_thrust`, :func:`axial_screw_load`): :mod:`hipsim.design.demand`;
- the closed-form ratings (winding rise, screw life, critical speed, buckling
  load): :mod:`hipsim.design.ratings`;
- the checks (:data:`CHECKS`, :func:`drive_checks`): :mod:`hipsim.design.checks`;
- choosing from catalogues (:func:`rank_drives`): :mod:`hipsim.design.ranking`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..machine.drive_parts import Drive, SizingRules
from ..physics.units import RPM_PER_RAD_S
from ..records import Record
from ..results import Run, peak_and_rms
from .checks import CHECKS, Check, binding_check, drive_checks
from .demand import Duty, ScrewSide, axial_screw_load, motor_duty, motor_thrust, reflected_inertia, screw_side
from .ranking import Candidate, rank_drives
from .ratings import (
    STEEL_DENSITY,
    STEEL_MODULUS,
    buckling_load,
    critical_speed,
    screw_life,
    weighted_mean,
    winding_rise,
)

__all__ = [
    "CHECKS",
    "Z95_ONE_SIDED",
    "MarginBand",
    "margin_bands",
    "STEEL_DENSITY",
    "STEEL_MODULUS",
    "Candidate",
    "Check",
    "Duty",
    "JointSizing",
    "ModuleSizing",
    "ScrewSide",
    "Sizing",
    "axial_screw_load",
    "buckling_load",
    "critical_speed",
    "drive_checks",
    "motor_duty",
    "motor_thrust",
    "rank_drives",
    "reflected_inertia",
    "screw_life",
    "screw_side",
    "sizing",
    "winding_rise",
]


@dataclass(frozen=True)
class ModuleSizing(Record):
    """What linear module i asks at its screw shaft along the trajectory (the motor's torque for a direct drive, rotor not counted).

    Attributes:
        module: i (1, 2, 3).
        tau_peak_Nmm: max |τ_i| in [N·mm].
        tau_rms_Nmm: RMS of τ_i over time in [N·mm].
        speed_peak_rpm: max |θ̇_i| in [rpm].
        speed_mean_rpm: mean |θ̇_i| over time in [rpm].
        power_peak_W: max |τ_i·θ̇_i| in [W].
        motor_thrust_peak_N: max |2π·τ_i/p| in [N] (:func:`motor_thrust`).
        axial_force_peak_N: max |F_axial,i| in [N] (:func:`axial_screw_load`).
        axial_force_cubic_mean_N: cubic mean of |F_axial,i| over the screw's revolutions in [N].
        revolutions_per_cycle: screw revolutions per test cycle.
        load_inertia_max_kgmm2: largest M_θ,ii (the inertia the screw shaft drives) in [kg·mm²].
        regen_energy_J: regenerated energy per cycle at the screw shaft in [J].
        stroke_mm: carriage stroke max L − min L in [mm].
    """

    module: int
    tau_peak_Nmm: float
    tau_rms_Nmm: float
    speed_peak_rpm: float
    speed_mean_rpm: float
    power_peak_W: float
    motor_thrust_peak_N: float
    axial_force_peak_N: float
    axial_force_cubic_mean_N: float
    revolutions_per_cycle: float
    load_inertia_max_kgmm2: float
    regen_energy_J: float
    stroke_mm: float


@dataclass(frozen=True)
class JointSizing(Record):
    """Peak and RMS reaction force magnitude at one joint, in [N]; name ``a_ji`` or ``o_j``."""

    joint: str
    peak_N: float
    rms_N: float


@dataclass(frozen=True, eq=False)
class Sizing:
    """The sizing of one run: the demands per module and joint, and the drive's checks.

    Attributes:
        modules: one :class:`ModuleSizing` per linear module.
        joints: one :class:`JointSizing` per joint, or None when the model gives no joint forces.
        checks: the :class:`Check` list (empty without a drive).
        drive: the drive checked, if any.
        rules: the rules checked against.
        duty: the motor's duty (for the figures); direct and rotor-less without a drive.
    """

    modules: tuple[ModuleSizing, ...]
    joints: tuple[JointSizing, ...] | None
    checks: tuple[Check, ...]
    drive: Drive | None
    rules: SizingRules
    duty: Duty

    @property
    def passed(self) -> bool | None:
        """True if every check made passed, False if any failed, None if none was made."""
        made = [c.passed for c in self.checks if c.passed is not None]
        return None if not made else all(made)

    @property
    def binding(self) -> Check | None:
        """The check with the smallest margin (the binding constraint), or None."""
        return binding_check(self.checks)


#: The one-sided 95 % quantile of the normal distribution: a margin passes with 95 % confidence when it exceeds this many of its standard deviations.
Z95_ONE_SIDED = 1.6448536269514722


@dataclass(frozen=True)
class MarginBand:
    """A check's margin with the uncertainty of the machine's identified parameters.

    Attributes:
        check: the check with the identified machine (its margin is the central value).
        std: the margin's standard deviation (first order), or None when the check was not made.
    """

    check: Check
    std: float | None

    @property
    def interval(self) -> tuple[float, float] | None:
        """The margin's two-sided 95 % interval, or None."""
        if self.std is None or self.check.margin is None:
            return None
        return self.check.margin - 1.959963984540054 * self.std, self.check.margin + 1.959963984540054 * self.std

    @property
    def confident(self) -> bool | None:
        """Passes with 95 % confidence: margin ≥ 1.645 standard deviations (one-sided); None when not checked."""
        if self.std is None or self.check.margin is None:
            return None
        return bool(self.check.margin - Z95_ONE_SIDED * self.std >= 0)


def margin_bands(nominal: Sizing, spread: list[Sizing]) -> tuple[MarginBand, ...]:
    """Each check's margin band from the sizing of the identified machine and of machines one standard deviation away
    along each principal direction of its covariance (:func:`hipsim.rig.identification.uncertainty.sigma_machines`): var = Σ_k (m_k − m_0)²."""
    out = []
    for j, check in enumerate(nominal.checks):
        margin = check.margin
        others = [m for m in (s.checks[j].margin for s in spread) if m is not None and math.isfinite(m)]
        if margin is None or not math.isfinite(margin) or len(others) < len(spread):
            out.append(MarginBand(check, None))
            continue
        out.append(MarginBand(check, float(math.sqrt(sum((m - margin) ** 2 for m in others)))))
    return tuple(out)


def sizing(run: Run, drive: Drive | None = None, rules: SizingRules | None = None, cycles: float = 1.0) -> Sizing:
    """The sizing table of a run, and the checks of a drive along it.

    Args:
        run: a model run (:func:`hipsim.analyse`); joint forces are
            included when it has them (Pinocchio model). Its lead and screw
            inertia are the drive's (to size another screw, run the model with
            ``params.replace(lead=…, screw_inertia=…)``: :func:`rank_drives` does).
        drive: the drive train to check; None for the demands only.
        rules: the rules; None for the drive's (or the defaults).
        cycles: test cycles the trajectory holds.

    Returns:
        The :class:`Sizing`. Values are over the samples the run kept (flagged
        poses, if any, are left out, as in :meth:`hipsim.Run.summary`).
    """
    rules = rules if rules is not None else (drive.rules if drive is not None else SizingRules())
    side = screw_side(run, cycles)
    ok = side.weights > 0
    w = side.weights
    tau_peak, _ = peak_and_rms(side.torque[ok] * 1e3)
    tau_rms = np.sqrt(weighted_mean((side.torque * 1e3) ** 2, w))
    speed_peak, _ = peak_and_rms(side.speed[ok] * RPM_PER_RAD_S)
    speed_mean = weighted_mean(np.abs(side.speed) * RPM_PER_RAD_S, w)
    power = side.torque * side.speed
    power_peak, _ = peak_and_rms(power[ok])
    regen = np.sum(np.maximum(-power, 0.0) * w[:, None], axis=0) / cycles
    thrust_peak, _ = peak_and_rms(motor_thrust(run)[ok])
    force_peak, _ = peak_and_rms(side.axial_load[ok])
    revolutions = np.abs(side.speed) * w[:, None] / (2.0 * math.pi)
    with np.errstate(invalid="ignore", divide="ignore"):
        cubic = (np.sum(np.abs(side.axial_load) ** 3 * revolutions, axis=0) / revolutions.sum(axis=0)) ** (1 / 3)
    stroke = np.ptp(run.L[ok, 0], axis=0) * 1e3
    inertia_max = np.nanmax(side.load_inertia[ok], axis=0) * 1e6
    modules = tuple(
        ModuleSizing(
            module=i + 1,
            tau_peak_Nmm=float(tau_peak[i]),
            tau_rms_Nmm=float(tau_rms[i]),
            speed_peak_rpm=float(speed_peak[i]),
            speed_mean_rpm=float(speed_mean[i]),
            power_peak_W=float(power_peak[i]),
            motor_thrust_peak_N=float(thrust_peak[i]),
            axial_force_peak_N=float(force_peak[i]),
            axial_force_cubic_mean_N=float(np.nan_to_num(cubic[i])),
            revolutions_per_cycle=float(revolutions[:, i].sum() / cycles),
            load_inertia_max_kgmm2=float(inertia_max[i]),
            regen_energy_J=float(regen[i]),
            stroke_mm=float(stroke[i]),
        )
        for i in range(3)
    )
    joints = None
    if run.joint_forces is not None:
        Fa_peak, Fa_rms = peak_and_rms(run.joint_forces.Fa[ok])
        Fo_peak, Fo_rms = peak_and_rms(run.joint_forces.Fo[ok])
        joints = tuple(
            JointSizing(f"a_{j + 1}{i + 1}", float(Fa_peak[j, i]), float(Fa_rms[j, i]))
            for j in range(2)
            for i in range(3)
        ) + tuple(JointSizing(f"o_{j + 1}", float(Fo_peak[j]), float(Fo_rms[j])) for j in range(2))
    checks = tuple(drive_checks(side, drive, rules)) if drive is not None else ()
    return Sizing(modules, joints, checks, drive, rules, motor_duty(side, drive))
