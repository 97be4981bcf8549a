"""The MuJoCo model's chain closed sample by sample, with MuJoCo's own closure rows.

Per sample, both platforms' angle coordinates are set to the trajectory's
(angle_signs applied) and the 15 leg coordinates solved by Gauss–Newton on the
18 closure residuals (consistent, so it converges quadratically), warm-started
by a Taylor step from the previous sample. With K = [P₁; J_c] (P₁ picks
platform 1's angles) the velocities solve K v = [q̇; 0] and the accelerations
K a = [q̈; −J̇_c v], J̇_c·v from ``mj_jacDot``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.linalg import lapack

from ..arrays import check_shapes
from ..exceptions import ClosureError, ModelError
from ._dependency import mujoco
from .machine import MujocoMachine

__all__ = ["MujocoKinematics"]


@dataclass(frozen=True, eq=False)
class MujocoKinematics:
    """The closed configuration of the MuJoCo model along a trajectory.

    Attributes:
        t: sample times in [s], (N,).
        q, v, a: qpos, qvel, qacc in [m, rad, s], (N, nv); J_c v = 0 and J_c a + J̇_c v = 0.
        L, Ld, Ldd: height of each universal-joint centre b_ji (MuJoCo's joint
            anchor) in [m], its rate [m/s] and acceleration [m/s²], (N, 2, 3).
        cond_inv: inverse condition number of J = ∂L̇/∂ω (from K⁻¹ and the
            platform's angular Jacobian), (N,).
        residual: largest closure gap of each sample in [m], (N,).
    """

    t: np.ndarray
    q: np.ndarray
    v: np.ndarray
    a: np.ndarray
    L: np.ndarray
    Ld: np.ndarray
    Ldd: np.ndarray
    cond_inv: np.ndarray
    residual: np.ndarray

    def __post_init__(self):
        nv = np.shape(self.q)[1]
        shapes = {
            "t": ("N",),
            "q": ("N", nv),
            "v": ("N", nv),
            "a": ("N", nv),
            "L": ("N", 2, 3),
            "Ld": ("N", 2, 3),
            "Ldd": ("N", 2, 3),
            "cond_inv": ("N",),
            "residual": ("N",),
        }
        check_shapes(self, shapes, samples=len(self.t))


class _Closer:
    """Closes the chain sample after sample with MuJoCo's closure rows."""

    def __init__(self, machine: MujocoMachine, tol: float, max_iter: int):
        self.machine, self.tol, self.max_iter = machine, tol, max_iter
        model = machine.model
        if np.any(model.eq_objtype != mujoco.mjtObj.mjOBJ_SITE):
            raise ModelError("the closures must be site-to-site connect equalities")
        geometry = machine.params.geometry
        # The drawing: both platforms held at the trajectory's angles, K = [P₁; J_c]. A per-chain machine
        # (hipsim.machine.chains): only the controlled platform held, K = [P_c; J_c], the other one solved with the legs.
        self.controlled = 0 if geometry is None else geometry.control - 1
        self.per_chain = geometry is not None
        self.K = np.zeros((model.nv, model.nv))
        self.K[np.arange(3), machine.platform_dof[self.controlled]] = 1.0
        self.K_inv: np.ndarray | None = None  # K⁻¹ at the last closed sample: the chord steps' Jacobian
        self.platforms = machine.platform_dof[self.controlled] if self.per_chain else machine.platform_dof.ravel()
        self.follower = machine.platform_dof[1 - self.controlled]
        self.free = np.sort(np.concatenate([machine.leg_dof, self.follower])) if self.per_chain else machine.leg_dof
        # Both ends of every closure, (site, body), closure after closure; their J̇ stacked.
        self.ends = [
            (int(site), int(model.site_bodyid[site]))
            for k in range(model.neq)
            for site in (model.eq_obj1id[k], model.eq_obj2id[k])
        ]
        self.jacdot = np.zeros((len(self.ends), 3, model.nv))

    def _rows(self, q: np.ndarray):
        self.machine.place(q)
        e, J = self.machine.closure_rows()
        return e, J, float(np.abs(e).max())

    def close(self, q: np.ndarray, angles: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """q with both platforms (per chain: the controlled one) at ``angles`` and the legs moved until the closures hold; its residual and J_c.

        On return MuJoCo's data holds q's positions. Raises ClosureError (with the gap) if the loops cannot close.
        """
        q = q.copy()
        q[self.platforms] = angles if self.per_chain else np.tile(angles, 2)
        e, J, gap = self._rows(q)
        if self.K_inv is not None:
            # Chord steps: Newton with the previous sample's K⁻¹ while the gap shrinks tenfold a step.
            for _ in range(6):
                if gap <= self.tol:
                    return q, e, J
                trial = q - self.K_inv[:, 3:] @ e
                trial[self.platforms] = q[self.platforms]
                e_trial, J_trial, gap_trial = self._rows(trial)
                if gap_trial > 0.1 * gap:
                    break
                q, e, J, gap = trial, e_trial, J_trial, gap_trial
        legs, best = self.free, math.inf
        for _ in range(self.max_iter):
            if gap <= self.tol:
                return q, e, J
            if best < 1e-6 and not gap < 0.5 * best:
                break  # no longer contracting: rounding reached
            best = min(best, gap)
            step, *_ = np.linalg.lstsq(J[:, legs], e, rcond=None)
            q[legs] -= step
            e, J, gap = self._rows(q)
        if gap > 1e3 * self.tol:
            raise ClosureError(
                f"cannot close the loops: the closure gap stays at {gap:.3g} m (the pose is out of the levers' reach)",
                gap,
            )
        return q, e, J

    def rates(self, J: np.ndarray, qd: np.ndarray, qdd: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """v and a at the closed q whose positions MuJoCo's data holds; leaves its velocities computed at v."""
        model, data = self.machine.model, self.machine.data
        self.K[3:] = J
        K_inv = _inverse(self.K)
        # K⁻¹ blows up near a singularity (its entries are O(1..10) in m, rad, s elsewhere).
        if K_inv is None or not np.abs(K_inv).max() < 1e8:
            raise ClosureError("singular pose: the closure Jacobian loses rank (spec §3)")
        self.K_inv = K_inv
        v = K_inv[:, :3] @ qd
        data.qvel[:] = v
        mujoco.mj_fwdVelocity(model, data)
        for jacdot, (site, body) in zip(self.jacdot, self.ends):
            mujoco.mj_jacDot(model, data, jacdot, None, data.site_xpos[site], body)
        drift = (self.jacdot[0::2] - self.jacdot[1::2]).reshape(-1, model.nv) @ v
        a = K_inv[:, :3] @ qdd - K_inv[:, 3:] @ drift
        return v, a


def _inverse(matrix: np.ndarray) -> np.ndarray | None:
    """The inverse through LAPACK (np.linalg.inv's checks cost as much again on small matrices); None if singular."""
    lu, pivots, info = lapack.dgetrf(matrix)
    if info != 0:
        return None
    inverse, info = lapack.dgetri(lu, pivots)
    return inverse if info == 0 else None


def _initial_guess(machine: MujocoMachine) -> np.ndarray:
    """Levers upright and the carriages so that the m1 levers' tips reach platform 1's height."""
    q = np.zeros(machine.model.nv)
    q[machine.slider_dof] = machine.params.heights[0] - machine.params.lever_length
    return q
