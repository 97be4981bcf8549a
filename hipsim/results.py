"""The result type every model returns: a :class:`Run` along a trajectory.

Both models (and any engine added later) fill the same fields, each with what
it computed itself: the slider motion, the motor torques split into the parts
of spec §4.4, the singularity measure and, when the model has them, the joint
reaction forces. The CSV columns of spec §7.5 and the summary come from here,
so they are the same whichever model ran.

Units: SI inside (m, s, rad, N, N·m); :meth:`Run.columns` and
:meth:`Run.summary` convert to the report units named in their keys.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from .arrays import check_shapes
from .exceptions import ArgumentError
from .files import write_columns
from .machine.parameters import Parameters
from .motion.trajectories import Trajectory

__all__ = ["JointForces", "Run", "Torques", "column_names", "peak_and_rms"]

_RPM = 60.0 / (2.0 * math.pi)


def peak_and_rms(values: np.ndarray, axis: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """Peak of |values| and root mean square along ``axis`` (the sample axis), in the values' unit.

    Args:
        values: samples, e.g. (N, 3) torques in [N·m].
        axis: the axis to reduce.

    Returns:
        (peak, rms), each the shape of ``values`` without ``axis``.
    """
    values = np.asarray(values, dtype=float)
    return np.abs(values).max(axis=axis), np.sqrt(np.mean(values**2, axis=axis))


@dataclass(frozen=True, eq=False)
class Torques:
    """Motor torques and their parts along a trajectory (spec §4.4), (N, 3) per motor.

    Attributes:
        total: motor torque in [N·m]; the sum of the five parts below.
        platforms: moving platforms' inertia (both platforms) in [N·m] (τ_m).
        levers: levers' gravity and inertia in [N·m] (τ_l).
        sliders: sliders' gravity and inertia in [N·m] (τ_s).
        screws: lead screws' rotor inertia in [N·m] (τ_L).
        friction: all friction in [N·m] (τ_f).
        motor_speed: θ̇_i = 2π·L̇_i/p in [rad/s].
        friction_moment: magnitude of each platform's central-chain friction moment in [N·m], (N,).
        friction_power: power lost in all friction in [W], (N,), ≥ 0.
    """

    total: np.ndarray
    platforms: np.ndarray
    levers: np.ndarray
    sliders: np.ndarray
    screws: np.ndarray
    friction: np.ndarray
    motor_speed: np.ndarray
    friction_moment: np.ndarray
    friction_power: np.ndarray

    #: The five parts, in the order of spec §4.4.
    PARTS = ("platforms", "levers", "sliders", "screws", "friction")
    #: Each field's name in the CSV columns of spec §7.5 (``tau_m_1_Nmm`` …).
    COLUMN = {"total": "tau", "platforms": "tau_m", "levers": "tau_l", "sliders": "tau_s", "screws": "tau_L", "friction": "tau_f"}

    def __post_init__(self):
        shapes = {name: ("N", 3) for name in ("total", *self.PARTS, "motor_speed")}
        check_shapes(self, shapes | {"friction_moment": ("N",), "friction_power": ("N",)})


@dataclass(frozen=True, eq=False)
class JointForces:
    """Reaction force magnitudes in the passive spherical joints, in [N].

    Attributes:
        Fa: at each lever's platform joint a_ji, (N, 2, 3) [platform j, leg i].
        Fo: through each platform's central joint o_j, (N, 2), load F_e and platform weight included.
    """

    Fa: np.ndarray
    Fo: np.ndarray

    def __post_init__(self):
        check_shapes(self, {"Fa": ("N", 2, 3), "Fo": ("N", 2)})


def column_names(joint_forces: bool = False) -> list[str]:
    """The CSV columns of spec §7.5, in order; ``joint_forces`` adds ``Fa_ji_N`` and ``Fo_j_N``."""
    names = ["t_s", "alpha_deg", "beta_deg", "gamma_deg", "Fe_N"]
    for quantity, unit in (("L", "mm"), ("Ld", "mm_s"), ("Ldd", "mm_s2")):
        names += [f"{quantity}_{j}{i}_{unit}" for j in (1, 2) for i in (1, 2, 3)]
    for field in ("total", *Torques.PARTS):
        names += [f"{Torques.COLUMN[field]}_{i}_Nmm" for i in (1, 2, 3)]
    names += [f"speed_{i}_rpm" for i in (1, 2, 3)] + ["cond_inv"]
    if joint_forces:
        names += [f"Fa_{j}{i}_N" for j in (1, 2) for i in (1, 2, 3)] + ["Fo_1_N", "Fo_2_N"]
    return names


@dataclass(frozen=True, eq=False)
class Run:
    """One model run along one trajectory: what every model returns.

    Attributes:
        model: the model that ran ("analytic", "pinocchio", …).
        params: the machine.
        trajectory: the motion and load.
        L, Ld, Ldd: slider motion in [m], [m/s], [m/s²], (N, 2, 3) [platform j, module i].
        torques: motor torques and their parts.
        cond_inv: singularity measure, the inverse condition number of J (0 = singular), (N,).
        flagged: samples out of reach or singular, carried as NaN, (N,) bool
            (only a model asked to flag rather than raise has any).
        joint_forces: the joint reaction forces, or None when the model has none.
    """

    model: str
    params: Parameters
    trajectory: Trajectory
    L: np.ndarray
    Ld: np.ndarray
    Ldd: np.ndarray
    torques: Torques
    cond_inv: np.ndarray
    flagged: np.ndarray
    joint_forces: JointForces | None = None

    def __post_init__(self):
        n = len(self.trajectory.t)
        check_shapes(self, {"L": (n, 2, 3), "Ld": (n, 2, 3), "Ldd": (n, 2, 3), "cond_inv": (n,), "flagged": (n,)})
        if self.torques.total.shape[0] != n:
            raise ArgumentError("Run.torques", self.torques.total, f"{n} samples, one per trajectory sample")

    @property
    def t(self) -> np.ndarray:
        """Sample times in [s], (N,)."""
        return self.trajectory.t

    def columns(self) -> dict[str, np.ndarray]:
        """The spec §7.5 columns, in their units, by name (``flagged`` added when any sample is)."""
        out: dict[str, np.ndarray] = {"t_s": self.trajectory.t}
        for k, name in enumerate(("alpha", "beta", "gamma")):
            out[f"{name}_deg"] = np.degrees(self.trajectory.q[:, k])
        out["Fe_N"] = self.trajectory.Fe
        for quantity, unit in (("L", "mm"), ("Ld", "mm_s"), ("Ldd", "mm_s2")):
            values = getattr(self, quantity) * 1e3
            for j in (1, 2):
                for i in (1, 2, 3):
                    out[f"{quantity}_{j}{i}_{unit}"] = values[:, j - 1, i - 1]
        for field in ("total", *Torques.PARTS):
            values = getattr(self.torques, field) * 1e3
            for i in (1, 2, 3):
                out[f"{Torques.COLUMN[field]}_{i}_Nmm"] = values[:, i - 1]
        for i in (1, 2, 3):
            out[f"speed_{i}_rpm"] = self.torques.motor_speed[:, i - 1] * _RPM
        out["cond_inv"] = self.cond_inv
        if self.joint_forces is not None:
            for j in (1, 2):
                for i in (1, 2, 3):
                    out[f"Fa_{j}{i}_N"] = self.joint_forces.Fa[:, j - 1, i - 1]
            for j in (1, 2):
                out[f"Fo_{j}_N"] = self.joint_forces.Fo[:, j - 1]
        if np.any(self.flagged):
            out["flagged"] = self.flagged.astype(float)
        return out

    def summary(self) -> dict[str, Any]:
        """Per slider its extreme motion, per motor its torque parts, speed and RMS, and the worst singularity margin.

        Values in mm, mm/s, mm/s², N·mm, rpm (keys say which), over the samples
        that are not flagged. RMS values are over the samples, which is the
        cycle RMS when the trajectory is periodic.
        """
        ok = ~self.flagged
        sliders = {}
        for j in (1, 2):
            for i in (1, 2, 3):
                L = self.L[ok, j - 1, i - 1] * 1e3
                sliders[f"{j}{i}"] = {
                    "L_max_mm": float(L.max()),
                    "L_min_mm": float(L.min()),
                    "stroke_mm": float(L.max() - L.min()),
                    "Ld_max_mm_s": float(np.abs(self.Ld[ok, j - 1, i - 1]).max() * 1e3),
                    "Ldd_max_mm_s2": float(np.abs(self.Ldd[ok, j - 1, i - 1]).max() * 1e3),
                }
        torques = self.torques
        tau_peak, tau_rms = peak_and_rms(torques.total[ok] * 1e3)
        speed_peak, _ = peak_and_rms(torques.motor_speed[ok] * _RPM)
        part_peaks = {field: peak_and_rms(getattr(torques, field)[ok] * 1e3)[0] for field in Torques.PARTS}
        motors = {}
        for i in range(3):
            entry = {f"{Torques.COLUMN[field]}_max_Nmm": float(peaks[i]) for field, peaks in part_peaks.items()}
            entry |= {"tau_peak_Nmm": float(tau_peak[i]), "tau_rms_Nmm": float(tau_rms[i]), "speed_peak_rpm": float(speed_peak[i])}
            motors[str(i + 1)] = entry
        k = int(np.nanargmin(np.where(ok, self.cond_inv, np.nan)))
        summary = {
            "model": self.model,
            "trajectory": self.trajectory.name,
            "parameters": self.params.source,
            "samples": int(self.trajectory.t.size),
            "flagged_samples": int(np.count_nonzero(self.flagged)),
            "sliders": sliders,
            "motors": motors,
            "cond_inv_min": float(self.cond_inv[k]),
            "cond_inv_min_t_s": float(self.trajectory.t[k]),
        }
        if self.joint_forces is not None:
            Fa_peak, Fa_rms = peak_and_rms(self.joint_forces.Fa[ok])
            Fo_peak, Fo_rms = peak_and_rms(self.joint_forces.Fo[ok])
            summary["joints"] = {
                **{f"Fa_{j}{i}": {"peak_N": float(Fa_peak[j - 1, i - 1]), "rms_N": float(Fa_rms[j - 1, i - 1])} for j in (1, 2) for i in (1, 2, 3)},
                **{f"Fo_{j}": {"peak_N": float(Fo_peak[j - 1]), "rms_N": float(Fo_rms[j - 1])} for j in (1, 2)},
            }
        return summary

    def write_csv(self, path: str | Path) -> Path:
        """Write :meth:`columns` to ``path`` atomically (a complete file or none). Returns the path."""
        return write_columns(path, self.columns())
