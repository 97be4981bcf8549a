"""The closure solver: the closed-chain kinematics along a trajectory, with Pinocchio only (spec §6).

Computed with Pinocchio's kinematics and Jacobians, independently of the
analytic formulas of :mod:`hipsim.analytic`, so that the two can check each
other. The platform angles are known along the trajectory, so the unknowns
are the leg coordinates (3 sliders, 12 universal-joint angles). Per sample:

* the configuration is predicted from the previous sample by a third-order
  Taylor step (jerk from the last two accelerations) and corrected by Newton
  steps that reuse the previous sample's inverse K⁻¹ (below; a chord method:
  no new factorisation while it contracts); a damped Gauss–Newton
  (Levenberg–Marquardt) on the 15 leg coordinates with fresh Jacobians takes
  over on the first sample and whenever the chord steps stall;
* with K = [P₁; J_c] (P₁ selects platform 1's three angle coordinates, J_c
  the 18×21 closure Jacobian) the velocities solve K v = [q̇; 0] and the
  accelerations K a = [q̈; −J̇_c v], J̇_c v from the closure frames' classical
  accelerations at a = 0, built from the world joint Jacobians J and v (J̇ is
  the sum of cross products J̇·v = Σ_{j before k} (S_j v_j) × (S_k v_k) along
  each frame's chain, Pinocchio's own definition of it). Platform 2's
  coordinates come out equal to platform 1's (its three closures force the
  same orientation) and are then set to the given values exactly.

Speed. A sample's work is two Pinocchio calls: forward kinematics at the
prediction and the joint Jacobians at the corrected configuration. Their
results are read through NumPy views that Pinocchio keeps current in its
Data (see :class:`~hipsim.closed_chain.workspace.Workspace`); the closures'
frames, gaps and Jacobian, the predictor, the chord step, K⁻¹ and the drift
are compiled arithmetic on them (:mod:`~hipsim.closed_chain.closure_kernel`),
writing into arrays the solver keeps. Each model keeps one workspace per
thread (:class:`~hipsim.closed_chain.solver.ClosedChainSolver`), reused from
run to run. ``scripts/bench.py --only servo`` times a sample next to its
floor, the two Pinocchio calls alone; the README's Speed section has the figures.

Sign conventions: J_c is the derivative of R₁ᵀ(p₁ − p₂) with frame 1 the lever
tip and frame 2 the platform joint.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
import pinocchio as pin

from ..arrays import check_shapes
from ..exceptions import ClosureError, PoseError
from ..motion.trajectories import trajectory_arrays
from ..physics import laws
from ..physics.orientation import angular_velocity_map, inverse_condition_number
from . import closure_kernel
from .build import ClosedChainModel, controlled_platform, require_layout

__all__ = ["ClosedKinematics", "Closer", "Continuation", "close_chain", "kinematics"]


@dataclass(frozen=True, eq=False)
class ClosedKinematics:
    """The closed configuration of the whole tree along a trajectory.

    Attributes:
        t: sample times in [s], shape (N,).
        angles: platform angles [α, β, γ] in [rad] as used (angle_signs
            applied), shape (N, 3); angle_rates [rad/s], angle_accels [rad/s²] likewise.
        q: tree configurations in [m, rad], shape (N, nq).
        v: tree velocities in [m/s, rad/s], shape (N, nv), with J_c v = 0.
        a: tree accelerations in [m/s², rad/s²], shape (N, nv), with J_c a + J̇_c v = 0.
        L, Ld, Ldd: slider heights [m], rates [m/s], accelerations [m/s²] of
            U-joint centre b_ji, shape (N, 2, 3) [platform j, screw i].
        J: the slider Jacobian L̇ = J·ω of the closed chain in [m], shape (N, 3, 3),
            from the velocity closure (independent of the analytic J).
        cond_inv: its inverse condition number (singularity measure), shape (N,).
        residual: largest closure gap of each sample in [m], shape (N,).
        iterations: configuration evaluations spent on each sample, shape (N,).
    """

    t: np.ndarray
    angles: np.ndarray
    angle_rates: np.ndarray
    angle_accels: np.ndarray
    q: np.ndarray
    v: np.ndarray
    a: np.ndarray
    L: np.ndarray
    Ld: np.ndarray
    Ldd: np.ndarray
    J: np.ndarray
    cond_inv: np.ndarray
    residual: np.ndarray
    iterations: np.ndarray

    def __post_init__(self):
        nq, nv = np.shape(self.q)[1], np.shape(self.v)[1]
        check_shapes(
            self,
            {
                "t": ("N",),
                "angles": ("N", 3),
                "angle_rates": ("N", 3),
                "angle_accels": ("N", 3),
                "q": ("N", nq),
                "v": ("N", nv),
                "a": ("N", nv),
                "L": ("N", 2, 3),
                "Ld": ("N", 2, 3),
                "Ldd": ("N", 2, 3),
                "J": ("N", 3, 3),
                "cond_inv": ("N",),
                "residual": ("N",),
                "iterations": ("N",),
            },
            samples=len(self.t),
        )


class Closer:
    """Solves the closed configuration sample after sample (one trajectory, one workspace)."""

    def __init__(self, chain: ClosedChainModel, tol: float, max_iter: int):
        self.layout = require_layout(chain)
        solver = chain.solver  # this thread's workspace and K's block order, kept from run to run
        self.ws = solver.workspace()
        self.tol2, self.max_iter = tol * tol, max_iter
        nv = chain.model.nv
        layout = self.layout
        controlled = controlled_platform(chain)
        self.per_chain = controlled is not None
        if controlled is None:
            # The drawing: both platforms held at the trajectory's angles, the 15 leg coordinates solved.
            self.platforms = layout.platform_v.ravel()
            # K = [P₁; J_c]'s selection P₁: platform 1's coordinates, and the others.
            self.platform1 = layout.platform_v[0]
            platform2 = layout.platform_v[1]  # set to the given rates exactly
            self.free = layout.leg_v
            self.order = solver.k_order()
        else:
            # Per chain: the controlled platform held, the other one solved with the legs (18 unknowns,
            # 18 closure equations); K = [P_c; J_c], and no platform's rates are overwritten.
            self.platforms = self.platform1 = platform2 = layout.platform_v[controlled]
            self.follower = layout.platform_v[1 - controlled]
            self.free = np.sort(np.concatenate([layout.leg_v, self.follower]))
            self.order = solver.k_order(controlled)
        self.K_inv = np.empty((nv, nv))  # K⁻¹ at the last closed sample: the chord method's Jacobian
        self.have_K_inv = False
        self.prediction = np.empty(nv)  # where the loop puts a sample's predicted q
        self._scratch = np.empty(nv)  # a second iterate for chord steps beyond the first
        self.evaluations = 0
        # closure_kernel.closed_sample's arguments after the gaps' limit, up to the sample's own (fixed for a run).
        ws = self.ws
        self.constants = (
            ws.J,
            ws.support_masks,
            ws.J_c,
            self.platform1,
            *self.order,
            platform2,
            layout.slider_v,
        )
        self.keep_nothing = (
            np.empty((0, nv, nv)),
            np.empty((0, 3, nv)),
            np.empty((0, len(ws.cms), 3, 3)),
            -1,
        )  # sample()'s keep without dynamics

    def _evaluate(self, q: np.ndarray, jacobians: bool = True) -> float:
        """|gaps|² at q [m²]; q's placements, gaps (and Jacobians) are left in the workspace."""
        self.evaluations += 1
        return self.ws.place(q, jacobians)

    def close(self, q: np.ndarray, angles: np.ndarray, out: np.ndarray) -> None:
        """Move q's leg coordinates until every closure holds, into ``out``.

        q: a configuration whose platform coordinates are ``angles`` already
        (both platforms', in ``platform_v.ravel()`` order); it is left as it
        is. On return ``out`` holds the closed configuration and the workspace
        its placements, Jacobians and gaps. Raises ClosureError (with the gap
        left) if the loops cannot be closed.
        """
        if not self.have_K_inv:
            size = self._evaluate(q)
            out[:] = q if size <= self.tol2 else self._levenberg_marquardt(q, size)
            return
        ws, tol2 = self.ws, self.tol2
        # A prediction is seldom closed already: its Jacobians would go unused.
        size = self._evaluate(q, jacobians=False)
        # Chord steps: Newton with the previous sample's K⁻¹, while it contracts well. The
        # first goes straight into out (the usual case: one step closes the chain to round-off).
        trial, other = out, self._scratch
        for step in range(6):
            if size <= tol2:
                if step == 0:
                    pin.computeJointJacobians(ws.model, ws.data, q)
                if q is not out:
                    out[:] = q
                return
            # The kernel of sample()'s usual course (gaps at q again, the same bits; limit −1: always step).
            closure_kernel.gaps_and_chord_step(
                *ws.frame_arguments(), q, self.K_inv, self.platforms, angles, -1.0, trial
            )
            size_trial = self._evaluate(trial)
            if size_trial > 0.01 * size:  # the gap must shrink tenfold per step, else fresh Jacobians
                out[:] = self._levenberg_marquardt(q, self._evaluate(q))
                return
            q, size = trial, size_trial
            trial, other = other, trial
        out[:] = self._levenberg_marquardt(q, size)

    def sample(self, prediction, angles, out, rates, accels, V, A, row: int, J_rates, residual, k: int, keep) -> None:
        """Close sample k from its prediction into ``out`` and compute its rates: the solver's step per sample.

        Args:
            prediction: the predicted configuration, (nq,), platform coordinates at ``angles`` (left as it is).
            angles: both platforms' coordinates at k (``platform_v.ravel()`` order) [rad].
            out: the closed configuration's row, Q[row].
            rates, accels: platform angle rates [rad/s] and accelerations [rad/s²] of every sample, (samples, 3).
            V, A, row: where the tree velocity and acceleration go, V[row], A[row].
            J_rates, residual, k: where ∂L̇/∂q̇ and the largest closure gap [m] go, J_rates[k], residual[k].
            keep: ``(K_invs, angular, tip_rotations, slot)`` where closure_kernel.store keeps what
                the inverse dynamics reuse (slot < 0: nothing).

        Raises:
            ClosureError: the loops cannot be closed, or the pose is singular.
        """
        ws, tol2 = self.ws, self.tol2
        args = (rates, accels, V, A, row, J_rates, residual, k, self.K_inv, *keep)
        frames = (
            ws.frame_args if ws.joint_rotations is not None else None
        )  # the usual course reads Pinocchio's placements through the views
        if self.have_K_inv and frames is not None:
            # close()'s usual course in two Pinocchio and two compiled calls: forward kinematics at
            # the prediction, one chord step (into out), the Jacobians there; anything else goes to close().
            pin.forwardKinematics(ws.model, ws.data, prediction)
            size = closure_kernel.gaps_and_chord_step(
                *frames, prediction, self.K_inv, self.platforms, angles, tol2, out
            )
            if size > tol2:
                pin.computeJointJacobians(ws.model, ws.data, out)
                status, _ = closure_kernel.closed_sample(*frames, min(tol2, 0.01 * size), *self.constants, *args)
                if status != closure_kernel.OPEN:
                    self.evaluations += 2
                    self._check(status)
                    return
        self.close(prediction, angles, out)
        status, _ = closure_kernel.closed_sample(*ws.frame_arguments(), math.inf, *self.constants, *args)
        self._check(status)

    def _check(self, status: int) -> None:
        """Raise for closure_kernel.rates' failure codes; on success keep K⁻¹ for the next sample's chord steps."""
        if status == closure_kernel.SINGULAR:
            raise ClosureError("singular pose: the closure Jacobian loses rank (spec §3)")
        if status == closure_kernel.LEVER_DOWN:
            raise ClosureError("a lever is horizontal or points down (singular pose, spec §3)")
        self.have_K_inv = True

    def _levenberg_marquardt(self, q: np.ndarray, cost: float) -> np.ndarray:
        """Damped Gauss–Newton on the 15 leg coordinates (and a per-chain machine's follower platform's 3) with fresh Jacobians,
        from q whose gaps (|gaps|² = cost) the workspace holds."""
        legs = self.free
        damping = 1e-6
        for iteration in range(self.max_iter):
            if cost <= self.tol2:
                return q
            J = self.ws.jacobian()[:, legs]
            H, g = J.T @ J, J.T @ self.ws.gaps
            while True:
                step = np.linalg.solve(H + damping * np.eye(len(legs)), g)
                trial = q.copy()
                trial[legs] += step  # d(q + δ) ≈ d − J_c·δ: the gaps fall along −J_c
                cost_trial = self._evaluate(trial)
                if cost_trial < cost:
                    q, cost = trial, cost_trial
                    damping = max(damping / 4.0, 1e-12)
                    break
                damping *= 8.0
                if damping > 1e8 or np.abs(step).max() < 1e-15:
                    raise ClosureError(
                        f"cannot close the loops: the closure gap stays at {math.sqrt(cost):.3g} m "
                        "(the pose is out of the levers' reach)",
                        math.sqrt(cost),
                        iteration + 1,
                    )
        if cost <= self.tol2:
            return q
        raise ClosureError(
            f"cannot close the loops in {self.max_iter} iterations (gap {math.sqrt(cost):.3g} m)",
            math.sqrt(cost),
            self.max_iter,
        )


@dataclass(eq=False)
class Continuation:
    """Where a run in pieces left the closure solver, so that the next piece goes on as one run would.

    The solver starts each sample from a prediction made of the previous
    samples and its chord steps reuse the previous sample's K⁻¹: a piece that
    started cold would close the chain to the same tolerance but not to the
    same bits. Pass one (initially empty) object to successive pieces in time
    order; each run updates it in place.

    Attributes:
        samples: samples closed so far.
        t: times of the last (up to) two samples in [s], (m,).
        q, v, a: their configurations, velocities and accelerations, (m, nq), (m, nv), (m, nv).
        K_inv: the solver's chord Jacobian at the last sample.
    """

    samples: int = 0
    t: np.ndarray | None = None
    q: np.ndarray | None = None
    v: np.ndarray | None = None
    a: np.ndarray | None = None
    K_inv: np.ndarray | None = None

    def last(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray] | None:
        """(t, q, v, a, K_inv) where the previous piece ended; None before the first piece."""
        if not self.samples or self.t is None or self.q is None or self.v is None or self.a is None:
            return None
        if self.K_inv is None:
            return None
        return self.t, self.q, self.v, self.a, self.K_inv


def kinematics(chain: ClosedChainModel, traj, *, tol: float = 1e-12, max_iter: int = 50) -> ClosedKinematics:
    """Close the chain along a platform trajectory, with Pinocchio only.

    Args:
        chain: the hip model from :func:`~hipsim.closed_chain.build.load_model`.
        traj: a Trajectory-like object: t (N,) in [s]; q, qd, qdd (N, 3):
            [α, β, γ] in [rad], [rad/s], [rad/s²]. The parameter set's
            angle_signs multiply them first (as the analytic model does).
        tol: closure gap accepted in [m] (bound on the norm of all gaps stacked).
        max_iter: damped Gauss–Newton iterations allowed per sample.

    Returns:
        The closed configurations, velocities and accelerations.

    Raises:
        PoseError: at the first sample whose pose is out of reach or singular.
        TrajectoryError: the arrays have the wrong shapes.
    """
    return close_chain(chain, traj, tol, max_iter)[0]


def close_chain(
    chain: ClosedChainModel,
    traj,
    tol: float,
    max_iter: int,
    dynamics_for: Callable[..., Any] | None = None,
    continuation: Continuation | None = None,
) -> tuple[ClosedKinematics, Any]:
    """The kinematics loop; with ``dynamics_for`` it also runs the inverse dynamics on the fly.

    Args:
        chain: the hip model from :func:`~hipsim.closed_chain.build.load_model`.
        traj: the trajectory (see :func:`kinematics`).
        tol: closure gap accepted in [m].
        max_iter: damped Gauss–Newton iterations allowed per sample.
        dynamics_for: None for the kinematics alone; else called once with the
            run's (n, nv) arrays q, v, a [m, rad; /s; /s²] (filled sample by
            sample), it returns the inverse dynamics that follow the loop
            (``keep(k)``, ``stored(k, workspace)``, ``result(kin)``; see
            :mod:`~hipsim.closed_chain.dynamics`).
        continuation: for a run in pieces (see :class:`Continuation`).

    Returns:
        The closed motion, and ``result(kin)`` of the dynamics (None without).
    """
    layout = require_layout(chain)
    t, q_in, qd_in, qdd_in = trajectory_arrays(traj)
    signs = chain.params.angle_signs if chain.params is not None else np.ones(3)
    angles, rates, accels = (np.ascontiguousarray(x * signs) for x in (q_in, qd_in, qdd_in))
    closer = Closer(chain, tol, max_iter)
    # The drawing: both platforms' coordinates, in platform_v.ravel() order; per chain: the controlled platform's.
    both = angles if closer.per_chain else np.tile(angles, 2)
    n, nq, nv = len(t), chain.model.nq, chain.model.nv
    residual = np.empty(n)  # the largest closure gap per sample [m]
    iterations = np.empty(n, dtype=int)
    J_rates = np.empty((n, 3, 3))  # ∂L̇/∂(angle rates) of the sliders
    # The samples before this piece (if any) come first, so that the predictor sees one run.
    go_on = continuation.last() if continuation is not None else None
    before = len(go_on[0]) if go_on else 0
    T = np.concatenate([go_on[0], t]) if go_on else t
    Q, V, A = np.empty((before + n, nq)), np.empty((before + n, nv)), np.empty((before + n, nv))
    if go_on:
        Q[:before], V[:before], A[:before], closer.K_inv[:] = go_on[1:]
        closer.have_K_inv = True
    # The closer leaves Pinocchio's data at the closed q: the dynamics reuse its Jacobians.
    dynamics = dynamics_for(Q[before:], V[before:], A[before:]) if dynamics_for is not None else None
    # Bound once: at some 30,000 samples a second, each attribute read in the loop (~30 ns) shows.
    platforms, predict, prediction, sample, ws = (
        closer.platforms,
        closure_kernel.predict,
        closer.prediction,
        closer.sample,
        closer.ws,
    )
    keep = closer.keep_nothing
    for k in range(n):
        row = before + k  # this sample's row in Q, V, A and T, after the previous piece's last samples
        angles_k = both[k]
        if row:
            predict(T, Q, V, A, row, platforms, angles_k, prediction)
        else:
            prediction[:] = layout.initial_guess
            prediction[platforms] = angles_k
            if (
                closer.per_chain
            ):  # the follower starts at the controlled platform's attitude, a fraction of a degree off
                prediction[closer.follower] = angles_k
        if dynamics is not None:
            keep = dynamics.keep(k)
        evaluations = closer.evaluations
        try:
            sample(prediction, angles_k, Q[row], rates, accels, V, A, row, J_rates, residual, k, keep)
        except (ClosureError, np.linalg.LinAlgError) as error:
            raise PoseError(str(error), float(t[k]), k, source=getattr(traj, "name", None)) from None
        iterations[k] = closer.evaluations - evaluations
        if dynamics is not None:
            dynamics.stored(k, ws)

    if continuation is not None and n:
        last = slice(max(0, before + n - 2), before + n)
        continuation.samples += n
        continuation.t, continuation.q, continuation.v, continuation.a = (
            T[last].copy(),
            Q[last].copy(),
            V[last].copy(),
            A[last].copy(),
        )
        continuation.K_inv = closer.K_inv.copy()
    Q, V, A = Q[before:], V[before:], A[before:]
    sliders = layout.slider_v
    offset = np.stack([np.zeros(3), layout.slider_offset])[None]
    # L̇ = J_rates·q̇ and ω = T(q)·q̇, so J = J_rates·T⁻¹ (T⁻¹ in closed form: LAPACK's batched
    # solve on 3×3 matrices cost 0.5 µs a sample, 2 % of the whole). The product is three
    # elementwise terms, not einsum, whose rounding depends on the array's length: a run in
    # pieces must give the one-piece bits.
    T_inverse_rows = laws.inverse_transpose(
        np.moveaxis(angular_velocity_map(angles), (1, 2), (0, 1))
    )  # T⁻ᵀ's rows b, each (xyz, n)
    T_inverse = np.stack([np.stack(row, axis=-1) for row in T_inverse_rows], axis=-1)  # (n, c, b) = T⁻¹
    J = sum(J_rates[:, :, c, None] * T_inverse[:, None, c, :] for c in range(3))
    kin = ClosedKinematics(
        t=t,
        angles=angles,
        angle_rates=rates,
        angle_accels=accels,
        q=Q,
        v=V,
        a=A,
        L=Q[:, None, sliders] - offset,
        Ld=np.repeat(V[:, None, sliders], 2, axis=1),
        Ldd=np.repeat(A[:, None, sliders], 2, axis=1),
        J=J,
        cond_inv=inverse_condition_number(J),
        residual=residual,
        iterations=iterations,
    )
    return kin, (dynamics.result(kin) if dynamics is not None else None)
