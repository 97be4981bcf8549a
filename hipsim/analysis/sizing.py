"""Sizing: the demands a run puts on each linear module and joint, checked against motor and module ratings.

Pure: it returns data (the report and the command line present it).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..analytic.virtual_work import screw_friction_torque
from ..machine.drive import MotorRatings
from ..results import Run, peak_and_rms

__all__ = ["JointSizing", "ModuleSizing", "RatingCheck", "Sizing", "axial_screw_force", "sizing"]

_RPM = 60.0 / (2.0 * math.pi)


@dataclass(frozen=True)
class ModuleSizing:
    """The demands on linear module i (its motor and screw) along the trajectory.

    Attributes:
        module: i (1, 2, 3).
        tau_peak_Nmm: max |τ_i| in [N·mm].
        tau_rms_Nmm: RMS of τ_i in [N·mm].
        speed_peak_rpm: max |θ̇_i| in [rpm].
        power_peak_W: max |τ_i·θ̇_i| in [W].
        axial_force_peak_N: max |F_axial,i| in [N] (see :func:`axial_screw_force`).
        stroke_mm: carriage stroke max L − min L in [mm].
    """

    module: int
    tau_peak_Nmm: float
    tau_rms_Nmm: float
    speed_peak_rpm: float
    power_peak_W: float
    axial_force_peak_N: float
    stroke_mm: float


@dataclass(frozen=True)
class JointSizing:
    """Peak and RMS reaction force magnitude at one joint, in [N]; name ``a_ji`` or ``o_j``."""

    joint: str
    peak_N: float
    rms_N: float


@dataclass(frozen=True)
class RatingCheck:
    """One demand checked against one rating.

    Attributes:
        module: i (1, 2, 3).
        item: the rating key, e.g. ``"peak_torque_Nmm"``.
        demand: what the trajectory needs, in the key's unit.
        rating: what the motor or module offers.
        margin_pct: (rating − demand)/rating in [%]; negative when it fails.
        passed: demand ≤ rating.
    """

    module: int
    item: str
    demand: float
    rating: float
    margin_pct: float
    passed: bool


@dataclass(frozen=True)
class Sizing:
    """The sizing table: per module, per joint (when known), and the rating checks.

    Attributes:
        modules: one :class:`ModuleSizing` per linear module.
        joints: one :class:`JointSizing` per joint, or None when the model gives no joint forces.
        checks: the :class:`RatingCheck` list (empty without ratings).
        ratings: the ratings checked against, if any.
    """

    modules: tuple[ModuleSizing, ...]
    joints: tuple[JointSizing, ...] | None
    checks: tuple[RatingCheck, ...] = ()
    ratings: MotorRatings | None = None

    @property
    def passed(self) -> bool | None:
        """True if every check passed, False if any failed, None without ratings."""
        return None if not self.checks else all(c.passed for c in self.checks)

    def as_dict(self) -> dict[str, Any]:
        """Plain data for JSON."""
        from dataclasses import asdict

        return {
            "modules": [asdict(m) for m in self.modules],
            "joints": None if self.joints is None else [asdict(j) for j in self.joints],
            "checks": [asdict(c) for c in self.checks],
            "ratings": None if self.ratings is None else asdict(self.ratings),
            "passed": self.passed,
        }


def axial_screw_force(run: Run) -> np.ndarray:
    """F_axial = 2π·(τ − τ_L − τ_sf)/p: the force each nut pushes on its carriage, in [N], (N, 3), positive up.

    τ_L is the screw rotor's inertia torque and τ_sf the screw's own friction
    torque (Coulomb with the smooth sign on the motor speed, plus viscous, as
    in :func:`hipsim.dynamics.inverse_dynamics`).
    """
    params, torques = run.params, run.torques
    screw_friction = screw_friction_torque(params, torques.motor_speed)
    return 2.0 * math.pi * (torques.total - torques.screws - screw_friction) / params.lead


def sizing(run: Run, ratings: MotorRatings | None = None) -> Sizing:
    """The sizing table of a run, optionally checked against a motor and module rating.

    Args:
        run: a model run (:func:`hipsim.analyse`); joint forces are
            included when it has them (Pinocchio model).
        ratings: a motor and module to check against; None for no check.

    Returns:
        The :class:`Sizing`. Values are over the samples the run kept (flagged
        poses, if any, are left out, as in :meth:`hipsim.Run.summary`).
    """
    ok = ~run.flagged
    torques = run.torques
    tau_peak, tau_rms = peak_and_rms(torques.total[ok] * 1e3)
    speed_peak, _ = peak_and_rms(torques.motor_speed[ok] * _RPM)
    power_peak, _ = peak_and_rms(torques.total[ok] * torques.motor_speed[ok])
    force_peak, _ = peak_and_rms(axial_screw_force(run)[ok])
    stroke = np.ptp(run.L[ok, 0], axis=0) * 1e3
    modules = tuple(
        ModuleSizing(
            module=i + 1,
            tau_peak_Nmm=float(tau_peak[i]),
            tau_rms_Nmm=float(tau_rms[i]),
            speed_peak_rpm=float(speed_peak[i]),
            power_peak_W=float(power_peak[i]),
            axial_force_peak_N=float(force_peak[i]),
            stroke_mm=float(stroke[i]),
        )
        for i in range(3)
    )
    joints = None
    if run.joint_forces is not None:
        Fa_peak, Fa_rms = peak_and_rms(run.joint_forces.Fa[ok])
        Fo_peak, Fo_rms = peak_and_rms(run.joint_forces.Fo[ok])
        joints = tuple(
            JointSizing(f"a_{j + 1}{i + 1}", float(Fa_peak[j, i]), float(Fa_rms[j, i])) for j in range(2) for i in range(3)
        ) + tuple(JointSizing(f"o_{j + 1}", float(Fo_peak[j]), float(Fo_rms[j])) for j in range(2))
    checks: list[RatingCheck] = []
    if ratings is not None:
        demand_of = {
            "rated_torque_Nmm": "tau_rms_Nmm",
            "peak_torque_Nmm": "tau_peak_Nmm",
            "max_speed_rpm": "speed_peak_rpm",
            "stroke_mm": "stroke_mm",
            "axial_force_N": "axial_force_peak_N",
        }
        for module in modules:
            for key, attribute in demand_of.items():
                rating = getattr(ratings, key)
                if rating is None:
                    continue
                demand = getattr(module, attribute)
                checks.append(RatingCheck(module.module, key, demand, rating, 100.0 * (rating - demand) / rating, bool(demand <= rating)))
    return Sizing(modules, joints, tuple(checks), ratings)
