"""Forward kinematics: the platform orientation from the slider heights (motor encoders).

The inverse kinematics of spec §3 gives each slider height in closed form,
L_1i(q) = h_1 + r_i,z − √(l² − |horizontal gap_i|²); the inverse map has no
closed form and several solutions (assembly modes). hipsim solves
L_1(q) = L_measured by Newton's method on the three platform angles, with the
Jacobian ∂L_1/∂q = J(q)·T(q) (L̇ = J·ω, ω = T·q̇), and keeps to the assembly
mode of the published machine: every lever below its platform joint (the
root the slider-height formula takes) and det J of the sign it has at home,
away from the singular poses (inverse condition number of J ≥ 1e-6, as the
inverse kinematics asks).

Along a log (:func:`forward_kinematics`) the result is the continuation of
the start pose: every sample is solved at once (vectorised) from the
linearisation about the start pose, each step between two samples is checked
against its first-order prediction from the previous pose, and wherever the
check fails the log is walked sample by sample, each solve starting from the
previous sample's pose (in the common case nothing needs walking). A sample
that no pose reaches, a singular one, or one in another assembly mode is
refused by name.

Converged poses reproduce the slider heights to ~1e-15 m; the round trip
q → L → q is exact to ~1e-13 rad (``tests/analytic/test_forward_kinematics.py``:
1e-9 rad required, on the ISO cycle and on random poses).
"""

from __future__ import annotations

import numpy as np

from ..exceptions import PoseError
from ..machine.parameters import Parameters
from .chain_kinematics import chain_jacobian, chain_positions
from .inverse_kinematics import (
    SINGULAR_COND_INV,
    angular_velocity_map,
    inverse_condition_number,
    slider_heights,
    slider_jacobian,
)

__all__ = ["forward_kinematics", "solve_pose"]

#: Newton stops when its step is below this, in [rad].
_STEP_TOL = 1e-12
#: Largest Newton step in [rad].
_MAX_STEP = 0.05
#: Two solutions of one sample farther apart than this in [rad] are different poses.
_SAME_POSE = 1e-8
#: Samples solved together along a log (a 600,000-sample log ran about twice as fast in blocks as at once).
_BLOCK = 8192


def _heights(params: Parameters, p: np.ndarray, platform: int | None) -> np.ndarray:
    """The carriage readings at platform angles p, (n, 3): the drawing's L_1 (platform None) or platform j's own (1 or 2)."""
    with np.errstate(invalid="ignore"):
        if platform is None:
            return slider_heights(params, p)[:, 0, :]
        return chain_positions(params.chains, p, platform - 1)[0]


def _slider_jacobian(params: Parameters, p: np.ndarray, platform: int | None) -> np.ndarray:
    """J(p) of the drawing (platform None) or of platform j's own chains, (n, 3, 3)."""
    if platform is None:
        return slider_jacobian(params, p)
    _, r, d = chain_positions(params.chains, p, platform - 1)
    return chain_jacobian(r, d)


def _residual(params: Parameters, p: np.ndarray, L1: np.ndarray, platform: int | None = None) -> np.ndarray:
    """L(p) − L1 in [m], (n, 3); NaN where a lever cannot reach (p: platform angles)."""
    return _heights(params, p, platform) - L1


def _jacobian(params: Parameters, p: np.ndarray, platform: int | None = None) -> np.ndarray:
    """∂L/∂p = J(p)·T(p) in [m/rad], (n, 3, 3); NaN where a lever cannot reach."""
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.einsum("nij,njk->nik", _slider_jacobian(params, p, platform), angular_velocity_map(p))


def _solve3(D: np.ndarray, b: np.ndarray) -> np.ndarray:
    """x with D·x = b for 3x3 matrices D (n, 3, 3) and b (n, 3), by Cramer's rule (LAPACK's batched solve costs more on 3x3)."""
    c0, c1, c2 = D[:, :, 0], D[:, :, 1], D[:, :, 2]
    c12 = np.cross(c1, c2)
    det = np.einsum("ni,ni->n", c0, c12)
    x = np.empty_like(b)
    x[:, 0] = np.einsum("ni,ni->n", b, c12)
    x[:, 1] = np.einsum("ni,ni->n", c0, np.cross(b, c2))
    x[:, 2] = np.einsum("ni,ni->n", c0, np.cross(c1, b))
    return x / det[:, None]


def _newton(
    params: Parameters, L1: np.ndarray, guess: np.ndarray, max_iter: int, platform: int | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """Newton on the platform angles p (after the angle signs) from ``guess``, damped where a step leaves the reach.

    Returns:
        p (n, 3) and a converged mask (n,).
    """
    p = np.array(guess, dtype=float)
    converged = np.zeros(len(p), dtype=bool)
    active = np.flatnonzero(np.all(np.isfinite(p), axis=1))
    residual = _residual(params, p[active], L1[active], platform)
    for _ in range(max_iter):
        if active.size == 0:
            break
        with np.errstate(invalid="ignore", divide="ignore"):
            step = -_solve3(_jacobian(params, p[active], platform), residual)
        ok = np.all(np.isfinite(step), axis=1)
        step[~ok] = 0.0
        # At most _MAX_STEP per iteration: far from the solution a full Newton step can leap into another assembly mode.
        size = np.abs(step).max(axis=1, keepdims=True)
        step *= np.minimum(1.0, _MAX_STEP / np.maximum(size, 1e-300))
        # Halve a step that takes a lever out of reach (a few times at most).
        trial = p[active] + step
        new_residual = _residual(params, trial, L1[active], platform)
        for _ in range(20):
            out = ~np.all(np.isfinite(new_residual), axis=1) & ok
            if not np.any(out):
                break
            step[out] *= 0.5
            trial[out] = p[active][out] + step[out]
            new_residual[out] = _residual(params, trial[out], L1[active][out], platform)
        p[active] = trial
        residual = new_residual
        done = ok & (np.abs(step).max(axis=1) < _STEP_TOL) & np.all(np.isfinite(residual), axis=1)
        failed = ~ok
        converged[active[done]] = True
        keep = ~(done | failed)
        active, residual = active[keep], residual[keep]
    return p, converged


def _home_sign(params: Parameters, platform: int | None = None) -> float:
    """The sign of det J at home: the published machine's assembly mode."""
    return float(np.sign(np.linalg.det(_slider_jacobian(params, np.zeros((1, 3)), platform)[0])))


def _check_mode(params: Parameters, p: np.ndarray, platform: int | None = None) -> tuple[np.ndarray, np.ndarray]:
    """(in the machine's assembly mode, clear of singular poses) per pose (n,), bool each."""
    with np.errstate(invalid="ignore"):
        J = _slider_jacobian(params, p, platform)
        same_mode = np.sign(np.linalg.det(J)) == _home_sign(params, platform)
        clear = inverse_condition_number(J) >= SINGULAR_COND_INV
    return same_mode, clear


def solve_pose(
    params: Parameters,
    L1: np.ndarray,
    guess: np.ndarray | None = None,
    max_iter: int = 50,
    platform: int | None = None,
) -> np.ndarray:
    """Platform orientations from platform 1's slider heights, each from its own guess.

    Args:
        params: the machine.
        L1: slider heights L_11, L_12, L_13 in [m], (N, 3).
        guess: gait angles [α, β, γ] in [rad] to start from, (N, 3) or (3,);
            None for home (all zero).
        max_iter: Newton iterations at most.
        platform: None for the drawing (both platforms alike; L1 are platform 1's slider
            heights); 1 or 2 for that platform's own chains (:mod:`hipsim.machine.chains`),
            L1 then the carriage readings.

    Returns:
        Gait angles [α, β, γ] in [rad], (N, 3) (after the parameter file's angle signs).

    Raises:
        PoseError: naming the first sample (index; time 0) that no pose in the
            machine's assembly mode reaches from its guess.
    """
    L1 = np.atleast_2d(np.asarray(L1, dtype=float))
    signs = params.angle_signs
    guess = np.zeros_like(L1) if guess is None else np.broadcast_to(np.asarray(guess, dtype=float), L1.shape)
    p, converged = _newton(params, L1, guess * signs, max_iter, platform)
    same_mode, clear = _check_mode(params, p, platform)
    bad = ~(converged & same_mode & clear)
    if np.any(bad):
        k = int(np.argmax(bad))
        raise PoseError(_failure(converged[k], same_mode[k], L1[k]), 0.0, k)
    return p * signs


def _failure(converged: bool, same_mode: bool, L1: np.ndarray) -> str:
    heights = ", ".join(f"{x * 1e3:.3f}" for x in L1)
    if not converged:
        return f"no platform orientation gives the slider heights ({heights}) mm: out of reach, or not the heights of this machine"
    if not same_mode:
        return f"the slider heights ({heights}) mm give a pose in another assembly mode (det J changes sign): not reachable without passing a singular pose"
    return f"the slider heights ({heights}) mm give a singular pose (inverse condition number of J below {SINGULAR_COND_INV:g})"


def _continues(params: Parameters, p: np.ndarray, L1: np.ndarray, platform: int | None = None) -> np.ndarray:
    """Does each pose p[k] (k ≥ 1) continue p[k − 1]? (n − 1,) bool.

    The step between two samples must match its first-order prediction
    D(p[k−1])⁻¹·(L1[k] − L1[k−1]) up to the second-order rest (half the step
    allowed): distinct solutions of the forward kinematics lie far apart,
    so another solution fails this by far.
    """
    with np.errstate(invalid="ignore"):
        predicted = _solve3(_jacobian(params, p[:-1], platform), np.diff(L1, axis=0))
    step = np.diff(p, axis=0)
    size = np.abs(predicted).max(axis=1)
    return np.abs(step - predicted).max(axis=1) <= 0.5 * size + _SAME_POSE


def forward_kinematics(
    params: Parameters,
    L1: np.ndarray,
    t: np.ndarray | None = None,
    q0: np.ndarray | None = None,
    source: str | None = None,
    max_iter: int = 50,
    platform: int | None = None,
    guess: np.ndarray | None = None,
) -> np.ndarray:
    """Platform orientations along a log of slider heights, each sample continuing the previous one.

    All samples are solved at once from the linearisation about the start
    pose; then each step between two samples is checked against its
    first-order prediction from the previous pose, and wherever the check
    fails (the solve found another solution) the log is walked sample by
    sample, each Newton solve starting from the previous sample's pose, until
    the two agree again. The first sample is reached from the start pose by
    continuation in the slider heights.

    Args:
        params: the machine.
        L1: platform 1's slider heights L_11, L_12, L_13 in [m] along the log, (N, 3).
        t: sample times in [s], (N,), for messages; None for the indices.
        q0: gait angles in [rad] near the first sample, (3,); None for home.
        source: the log's name, for messages.
        max_iter: Newton iterations at most per solve.
        platform: None for the drawing (both platforms alike; L1 are platform 1's slider
            heights); 1 or 2 for that platform's own chains (:mod:`hipsim.machine.chains`),
            L1 then the carriage readings.
        guess: gait angles in [rad] near each sample's solution, (N, 3), for the all-at-once solve
            (e.g. the other platform's attitude on a per-chain machine, a fraction of a degree off);
            None for the linearisation about the start pose. Each result is still checked to continue
            the previous sample's.

    Returns:
        Gait angles [α, β, γ] in [rad], (N, 3).

    Raises:
        PoseError: naming the time and sample where the heights are out of
            reach, singular, or in another assembly mode than the published
            machine's, or where the motion jumps to another solution.
    """
    L1 = np.atleast_2d(np.asarray(L1, dtype=float))
    n = len(L1)
    times = np.arange(n, dtype=float) if t is None else np.asarray(t, dtype=float)

    def fail(k: int, message: str):
        raise PoseError(message, float(times[k]), int(k), source=source)

    if not np.all(np.isfinite(L1)):
        fail(int(np.argmax(~np.all(np.isfinite(L1), axis=1))), "slider heights are not finite")
    signs = params.angle_signs
    start = np.zeros(3) if q0 is None else np.asarray(q0, dtype=float) * signs
    L_start = _heights(params, start[None], platform)[0]
    if not np.all(np.isfinite(L_start)):
        raise PoseError("the start pose q0 is out of reach", float(times[0]), 0, source=source)

    # The first sample by continuation from the start pose, in ten steps of slider heights.
    first = start
    for s in np.linspace(0.1, 1.0, 10):
        solved, ok = _newton(params, (L_start + s * (L1[0] - L_start))[None], first[None], max_iter, platform)
        if not ok[0]:
            fail(0, _failure(False, True, L1[0]))
        first = solved[0]

    # Every sample at once, from the guesses given or the linearisation about the start pose.
    if guess is None:
        guess = start + np.linalg.solve(_jacobian(params, start[None], platform)[0], (L1 - L_start).T).T
    else:
        guess = np.broadcast_to(np.asarray(guess, dtype=float), L1.shape) * signs
    p = np.empty((n, 3))
    converged = np.empty(n, dtype=bool)
    for begin in range(0, n, _BLOCK):  # every sample on its own: blocks whose arrays stay in the cache
        rows = slice(begin, begin + _BLOCK)
        p[rows], converged[rows] = _newton(params, L1[rows], guess[rows], max_iter, platform)
    p[~converged] = np.nan  # left to the walk below
    broken = np.zeros(n, dtype=bool)
    if not np.allclose(p[0], first, rtol=0.0, atol=_SAME_POSE):
        p[0] = first
        broken[1:2] = True
    if n > 1:
        broken[1:] |= ~_continues(params, p, L1, platform)

    # Walk from each break, one sample at a time, until the old poses continue the new ones again.
    k = 1
    while True:
        later = np.flatnonzero(broken[k:])
        if later.size == 0:
            break
        k += int(later[0])
        while k < n:
            solved, ok = _newton(params, L1[k][None], p[k - 1][None], max_iter, platform)
            if not ok[0]:
                fail(k, _failure(False, True, L1[k]))
            p[k] = solved[0]
            k += 1
            if (
                k < n
                and np.all(np.isfinite(p[k]))
                and _continues(params, p[k - 1 : k + 1], L1[k - 1 : k + 1], platform)[0]
            ):
                break
        if k >= n:
            break
        broken[k] = False  # p[k] continues the walked pose before it

    same_mode, clear = _check_mode(params, p, platform)
    bad = ~(same_mode & clear)
    if np.any(bad):
        k = int(np.argmax(bad))
        if k > 0 and same_mode[k - 1] and not same_mode[k]:
            fail(
                k,
                "the slider heights jump to another assembly mode since the previous sample (det J changes sign): "
                "an encoder glitch, or a motion through a singular pose",
            )
        fail(k, _failure(True, same_mode[k], L1[k]))
    return p * signs
