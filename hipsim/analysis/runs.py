"""Torque runs as tables: the CSV column contract of spec §7.5 and the summary.

:func:`analyse` runs a model along a trajectory and returns a :class:`Result`
that gives the columns (SI inside, converted here at the edge to mm, N·mm,
rpm and degrees as the machine's documentation reports them), a summary, and
an atomic CSV writer.

Example:
    >>> import hipsim
    >>> result = hipsim.analyse()                     # ISO 14242-1, published machine
    >>> result.columns()["tau_1_Nmm"].max()           # doctest: +SKIP
    >>> result.write_csv("iso.csv")                   # doctest: +SKIP
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ..analytic.virtual_work import Torques, central_friction_moment, inverse_dynamics
from ..exceptions import HipsimError
from ..files import write_columns
from ..analytic.inverse_kinematics import Kinematics, kinematics
from ..machine.parameters import Parameters, load_parameters
from ..motion.trajectories import Trajectory, iso14242

__all__ = ["Result", "analyse", "column_names"]

_PART_LABELS = {"tau_m": "platforms", "tau_l": "levers", "tau_s": "sliders", "tau_L": "screws", "tau_f": "friction"}
_RPM = 60.0 / (2.0 * math.pi)


def column_names(pinocchio: bool = False) -> list[str]:
    """The CSV columns of spec §7.5, in order (the Pinocchio model adds joint forces)."""
    names = ["t_s", "alpha_deg", "beta_deg", "gamma_deg", "Fe_N"]
    for quantity, unit in (("L", "mm"), ("Ld", "mm_s"), ("Ldd", "mm_s2")):
        names += [f"{quantity}_{j}{i}_{unit}" for j in (1, 2) for i in (1, 2, 3)]
    for part in ("tau", *Torques.PARTS):
        names += [f"{part}_{i}_Nmm" for i in (1, 2, 3)]
    names += [f"speed_{i}_rpm" for i in (1, 2, 3)] + ["cond_inv"]
    if pinocchio:
        names += [f"Fa_{j}{i}_N" for j in (1, 2) for i in (1, 2, 3)] + ["Fo_1_N", "Fo_2_N"]
    return names


@dataclass(frozen=True, eq=False)
class Result:
    """One model run along one trajectory.

    Attributes:
        params: the machine.
        trajectory: the motion and load.
        kin: analytic kinematics (Jacobian and singularity measure for both models).
        torques: motor torques and parts (from the model named in ``model``).
        L, Ld, Ldd: slider motion in [m], [m/s], [m/s²], (N, 2, 3), from the model named in ``model``.
        model: "analytic" or "pinocchio".
        joint_forces: for the Pinocchio model, (Fa (N, 2, 3), Fo (N, 2)) in [N]; else None.
    """

    params: Parameters
    trajectory: Trajectory
    kin: Kinematics
    torques: Torques
    L: np.ndarray
    Ld: np.ndarray
    Ldd: np.ndarray
    model: str = "analytic"
    joint_forces: tuple[np.ndarray, np.ndarray] | None = None

    def columns(self) -> dict[str, np.ndarray]:
        """The spec §7.5 columns, in their units, by name."""
        out: dict[str, np.ndarray] = {"t_s": self.trajectory.t}
        for k, name in enumerate(("alpha", "beta", "gamma")):
            out[f"{name}_deg"] = np.degrees(self.trajectory.q[:, k])
        out["Fe_N"] = self.trajectory.Fe
        for quantity, unit in (("L", "mm"), ("Ld", "mm_s"), ("Ldd", "mm_s2")):
            values = getattr(self, quantity) * 1e3
            for j in (1, 2):
                for i in (1, 2, 3):
                    out[f"{quantity}_{j}{i}_{unit}"] = values[:, j - 1, i - 1]
        for part in ("tau", *Torques.PARTS):
            values = getattr(self.torques, part) * 1e3
            for i in (1, 2, 3):
                out[f"{part}_{i}_Nmm"] = values[:, i - 1]
        for i in (1, 2, 3):
            out[f"speed_{i}_rpm"] = self.torques.motor_speed[:, i - 1] * _RPM
        out["cond_inv"] = self.kin.cond_inv
        if self.joint_forces is not None:
            Fa, Fo = self.joint_forces
            for j in (1, 2):
                for i in (1, 2, 3):
                    out[f"Fa_{j}{i}_N"] = Fa[:, j - 1, i - 1]
            for j in (1, 2):
                out[f"Fo_{j}_N"] = Fo[:, j - 1]
        if np.any(self.kin.flagged):
            out["flagged"] = self.kin.flagged.astype(float)
        return out

    def summary(self) -> dict[str, Any]:
        """Per slider its extreme motion, per motor its torque parts, speed and RMS, and the worst singularity margin.

        Values in mm, mm/s, mm/s², N·mm, rpm (keys say which). RMS values are
        over the samples, which is the cycle RMS when the trajectory is periodic.
        """
        kin, torques = self.kin, self.torques
        ok = ~kin.flagged
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
        motors = {}
        for i in (1, 2, 3):
            tau = torques.tau[ok, i - 1] * 1e3
            entry = {f"{part}_max_Nmm": float(np.abs(getattr(torques, part)[ok, i - 1]).max() * 1e3) for part in Torques.PARTS}
            entry |= {
                "tau_peak_Nmm": float(np.abs(tau).max()),
                "tau_rms_Nmm": float(np.sqrt(np.mean(tau**2))),
                "speed_peak_rpm": float(np.abs(torques.motor_speed[ok, i - 1]).max() * _RPM),
            }
            motors[str(i)] = entry
        k = int(np.nanargmin(np.where(ok, kin.cond_inv, np.nan)))
        summary = {
            "model": self.model,
            "trajectory": self.trajectory.name,
            "parameters": self.params.source,
            "samples": int(self.trajectory.t.size),
            "flagged_samples": int(np.count_nonzero(kin.flagged)),
            "sliders": sliders,
            "motors": motors,
            "cond_inv_min": float(kin.cond_inv[k]),
            "cond_inv_min_t_s": float(kin.t[k]),
        }
        if self.joint_forces is not None:
            Fa, Fo = self.joint_forces
            summary["joints"] = {
                **{f"Fa_{j}{i}": {"peak_N": float(Fa[ok, j - 1, i - 1].max()), "rms_N": float(np.sqrt(np.mean(Fa[ok, j - 1, i - 1] ** 2)))} for j in (1, 2) for i in (1, 2, 3)},
                **{f"Fo_{j}": {"peak_N": float(Fo[ok, j - 1].max()), "rms_N": float(np.sqrt(np.mean(Fo[ok, j - 1] ** 2)))} for j in (1, 2)},
            }
        return summary

    def write_csv(self, path: str | Path) -> Path:
        """Write the columns to ``path`` atomically (a complete file or none). Returns the path."""
        return write_columns(path, self.columns())


def analyse(
    params: Parameters | None = None,
    trajectory: Trajectory | None = None,
    model: str = "analytic",
    on_error: str = "raise",
    lever_spin: bool = False,
) -> Result:
    """Run a model along a trajectory: slider motion, motor torques and their parts.

    Args:
        params: the machine; None for the published one.
        trajectory: the motion and load; None for one ISO 14242-1 cycle at 1 kHz.
        model: "analytic" (spec §4) or "pinocchio" (spec §6, adds joint forces).
        on_error: "raise" at the first pose out of reach or singular, or "flag"
            to mark such samples (analytic model only).
        lever_spin: analytic model only: give the levers the universal joints'
            spin (see :func:`hipsim.dynamics.inverse_dynamics`).

    Returns:
        The :class:`Result`.
    """
    params = params if params is not None else load_parameters()
    trajectory = trajectory if trajectory is not None else iso14242()
    if model not in ("analytic", "pinocchio"):
        raise HipsimError(f"unknown model '{model}' (expected 'analytic' or 'pinocchio')")
    kin = kinematics(params, trajectory, on_error=on_error)
    if np.all(kin.flagged):
        raise HipsimError(f"{trajectory.name}: all {len(trajectory)} samples are out of reach or singular; nothing to compute")
    if model == "analytic":
        with np.errstate(invalid="ignore", divide="ignore"):  # flagged samples are NaN and stay NaN
            torques = inverse_dynamics(params, kin, trajectory.Fe, lever_spin=lever_spin)
        return Result(params, trajectory, kin, torques, kin.L, kin.Ld, kin.Ldd, model)
    if on_error != "raise":
        raise HipsimError("the Pinocchio model cannot carry on through poses out of reach; use the analytic model to flag them")
    from ..closed_chain.model import load_model, trajectory_dynamics

    _, closed = trajectory_dynamics(load_model(params), trajectory)
    motor_speed = 2.0 * math.pi * closed.Ld[:, 0] / params.lead
    torques = Torques(
        tau=closed.tau, tau_m=closed.tau_m, tau_l=closed.tau_l, tau_s=closed.tau_s, tau_L=closed.tau_L, tau_f=closed.tau_f,
        motor_speed=motor_speed,
        friction_moment=np.linalg.norm(central_friction_moment(params, kin.omega, trajectory.Fe, kin.R), axis=-1),
        # By virtual power the motors' friction share times their speed is the whole friction loss.
        friction_power=np.sum(closed.tau_f * motor_speed, axis=1),
    )
    return Result(params, trajectory, kin, torques, closed.L, closed.Ld, closed.Ldd, model, joint_forces=(closed.Fa, closed.Fo))
