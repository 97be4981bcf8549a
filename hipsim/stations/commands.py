"""Carriage commands for two platforms on one set of carriages: control platform 1, platform 2, or both.

Both platforms hang on the same three carriages. With every chain built to
the drawing they turn alike; with per-chain deviations one carriage reading
L = (L_1, L_2, L_3) puts each platform at its own attitude q_j(L) (the forward
kinematics of :mod:`hipsim.analytic.stations`), and no command puts both
exactly where they are wanted. For a desired attitude q_d per sample:

- ``control="1"`` (or ``"2"``): L = the inverse kinematics of that platform, so
  it is exact and the other follows with its own error (the paper controls m_2
  and m_1 follows);
- ``control="both"``: L minimises w_1·|q_1(L) − q_d|² + w_2·|q_2(L) − q_d|²
  (angles in degrees, w = (1, 1) by default). The deviations are small, so
  q_j(L) ≈ q_d + A_j·(L − L_j*), A_j = (∂L/∂q)_j⁻¹ at q_d, L_j* platform j's own
  command: the weighted least squares L = (Σ w_j A_jᵀA_j)⁻¹ Σ w_j A_jᵀA_j L_j*,
  whose cost is the true minimum's to second order in δ/l (δ the deviations,
  l the lever; 1e-5 relative at 0.3 mm). Each sample keeps the best of that command and
  the two single-platform ones, so ``both`` is never worse than either in its
  summed squared error, and with identical chains (both single commands
  equal) all three are the same.

The attitudes a command gives are solved exactly: Newton on each platform's
forward kinematics from its linear prediction q_d + A_j·(L − L_j*), which two
steps bring to round-off; a sample that has not converged then goes through
:func:`hipsim.analytic.forward_kinematics.solve_pose` with its assembly-mode
and singularity checks.

Every function works on whole arrays of samples.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..analytic.chain_kinematics import chain_jacobian, chain_positions
from ..analytic.forward_kinematics import solve_pose
from ..analytic.stations import carriages_for_platform, platform_attitude, stacked_carriages
from ..arrays import readonly
from ..exceptions import ArgumentError, PoseError
from ..machine.chains import stackup_lift
from ..machine.parameters import Parameters
from ..physics.orientation import angular_velocity_map
from .sensitivity import inverse3, reading_rate

__all__ = [
    "CONTROLS",
    "Positions",
    "StationMotion",
    "attitudes",
    "newton_from_close",
    "own_command",
    "squared_errors",
    "station_commands",
]

#: (platform angles (n, 3) [rad], the samples' rows) → (L, r, d) of :func:`hipsim.analytic.chain_kinematics.chain_positions`.
Positions = Callable[[np.ndarray, Any], tuple[np.ndarray, np.ndarray, np.ndarray]]

#: The platforms a command can serve.
CONTROLS = ("1", "2", "both")
#: Newton steps from a guess within ~1e-6 rad (quadratic convergence: 1e-12, then round-off).
NEWTON_STEPS = 2
#: A carriage reading reproduced this closely in [m] (~3e-13 rad) is converged; the full solve reaches ~1e-15.
CONVERGED_GAP = 1e-13
#: A last Newton step this small in [rad] means converged: the error left is of the order of its square (~1e-16 rad).
CONVERGED_STEP = 1e-8
#: How far (relative) a single-platform command's predicted cost may be above the least squares' before it is solved
#: exactly to compare: far above the prediction's own error (~1e-5 at 0.3 mm deviations).
SAFETY = 1e-2
#: Samples solved together: a block's arrays (a few hundred kB each) stay in the cache.
BLOCK = 8192


@dataclass(frozen=True, eq=False)
class StationMotion:
    """Carriage commands and the two platforms' attitudes they give, per sample, SI.

    Attributes:
        t: sample times in [s], (N,).
        desired: the desired attitude [α, β, γ] in [rad], (N, 3).
        carriages: the carriage readings L_1, L_2, L_3 in [m] (the encoders' reading), (N, 3).
        attitudes: each platform's attitude q_j in [rad], (N, 2, 3).
        control: "1", "2" or "both".
        weights: (w_1, w_2) of ``both``'s sum of squared errors.
    """

    t: np.ndarray
    desired: np.ndarray
    carriages: np.ndarray
    attitudes: np.ndarray
    control: str
    weights: tuple[float, float] = (1.0, 1.0)

    def __post_init__(self):
        n = np.shape(self.t)[0]
        for name, shape in (("t", (n,)), ("desired", (n, 3)), ("carriages", (n, 3)), ("attitudes", (n, 2, 3))):
            value = np.asarray(getattr(self, name), dtype=float)
            if value.shape != shape:
                raise ArgumentError(name, value, f"shape {shape}")
            object.__setattr__(self, name, readonly(value))

    @property
    def errors(self) -> np.ndarray:
        """q_j − q_d in [rad], (N, 2, 3)."""
        return self.attitudes - self.desired[:, None, :]


def squared_errors(errors: np.ndarray, weights=(1.0, 1.0)) -> np.ndarray:
    """Σ_j w_j·|e_j|² per sample in [deg²], from errors (N, 2, 3) in [rad]."""
    return np.sum(np.degrees(errors) ** 2, axis=-1) @ np.asarray(weights)


def attitudes(
    params: Parameters,
    carriages: np.ndarray,
    guess: np.ndarray | None = None,
    t: np.ndarray | None = None,
    source: str | None = None,
) -> np.ndarray:
    """Both platforms' attitudes in [rad], (N, 2, 3), from carriage readings (N, 3) in [m].

    Args:
        params: the machine.
        carriages: carriage readings L_i in [m], (N, 3).
        guess: attitudes near the solution in [rad], (N, 3) for both platforms or (N, 2, 3) one each: each sample
            is solved from its own guess at once; None: each sample continues the previous one from home
            (:func:`hipsim.analytic.stations.platform_attitude`).
        t: sample times in [s], (N,), for messages.
        source: the log's or trajectory's name, for messages.

    Raises:
        PoseError: naming the sample (time) a platform cannot take.
    """
    out = np.empty((len(carriages), 2, 3))
    for j in (2, 1):  # m_2 first: m_1 on a seat rides on it, and is solved at m_2's attitude
        if guess is None:
            out[:, j - 1] = platform_attitude(params, carriages, j, t=t, source=source)
        else:
            own = guess[:, j - 1] if np.ndim(guess) == 3 else guess
            out[:, j - 1] = _attitude(params, carriages, own, j, t, source, out[:, 1] if j == 1 else None)
    return out


def _weights(weights) -> tuple[float, float]:
    w = tuple(float(x) for x in weights)
    if len(w) != 2 or not all(math.isfinite(x) and x >= 0 for x in w) or sum(w) == 0:
        raise ArgumentError("weights", weights, "two finite weights >= 0, not both zero")
    return w[0], w[1]


def station_commands(
    params: Parameters,
    t: np.ndarray,
    desired: np.ndarray,
    control: str = "2",
    weights=(1.0, 1.0),
    source: str | None = None,
) -> StationMotion:
    """The carriage commands for a desired attitude and what each platform does with them.

    Args:
        params: the machine (per-chain values or the drawing).
        t: sample times in [s], (N,).
        desired: desired attitude [α, β, γ] in [rad], (N, 3).
        control: "1" or "2" (that platform exact, the other follows) or "both" (least squares over the two).
        weights: (w_1, w_2) for "both", dimensionless.
        source: the trajectory's name, for messages.

    Raises:
        ArgumentError: an unknown control or bad weights.
        PoseError: a sample a platform cannot reach (naming it and the chain).
    """
    if control not in CONTROLS:
        raise ArgumentError("control", control, "one of 1, 2, both")
    w = _weights(weights)
    q_d = np.asarray(desired, dtype=float)
    t = np.asarray(t, dtype=float)
    L = np.empty_like(q_d)
    q = np.empty((len(q_d), 2, 3))
    # Block by block: every sample is independent, and on a long trajectory arrays of a block's size stay in the
    # cache (a 600,000-sample trajectory ran 2.5x faster in blocks of 8192, bit for bit the same).
    for start in range(0, len(q_d), BLOCK):
        block = slice(start, start + BLOCK)
        try:
            L[block], q[block] = _block_commands(params, t[block], q_d[block], control, w)
        except PoseError as error:
            raise PoseError(error.reason, error.time, start + error.index, source) from None
    return StationMotion(t, q_d, L, q, control, w)


def _block_commands(
    params: Parameters, t: np.ndarray, q_d: np.ndarray, control: str, w: tuple[float, float]
) -> tuple[np.ndarray, np.ndarray]:
    """:func:`station_commands` on one block of samples: (carriages (n, 3) [m], attitudes (n, 2, 3) [rad]).

    A sample refused is named by its time and its index in the block; :func:`station_commands` adds the source.
    """
    needed = (1, 2) if control == "both" else (3 - int(control),)
    own, A = {}, {}  # platform j's own command L_j* and A_j = ∂q_j/∂L at q_d
    for j in (1, 2):
        own[j], rate = _own_command(params, q_d, j, j in needed)
        bad = ~np.all(np.isfinite(own[j]), axis=1)
        if bad.any():
            k = int(np.argmax(bad))
            leg = int(np.argmax(~np.isfinite(own[j][k]))) + 1
            raise PoseError(f"chain {j}{leg}'s lever cannot reach platform {j}'s desired attitude", t[k], k)
        if rate is not None:
            A[j] = inverse3(rate)

    def follows(j: int, L: np.ndarray, other: np.ndarray | None = None) -> np.ndarray:
        """Platform j's attitude at carriages L, from its linear prediction about its own command (``other``: m_2's)."""
        guess = q_d + np.matmul(A[j], (L - own[j])[..., None])[..., 0]
        return _attitude(params, L, guess, j, t, other=other)

    q = np.empty((len(q_d), 2, 3))
    if control in ("1", "2"):
        j = int(control)
        q[:, j - 1] = q_d  # exact by construction: forward ∘ inverse is the identity to 1e-12
        q[:, 2 - j] = follows(3 - j, own[j], q_d if j == 2 else None)  # m_2 exact: m_1's lift from q_d
        return own[j], q
    AtA = {j: np.matmul(np.swapaxes(A[j], 1, 2), A[j]) for j in (1, 2)}
    H = w[0] * AtA[1] + w[1] * AtA[2]
    rhs = w[0] * np.matmul(AtA[1], own[1][..., None]) + w[1] * np.matmul(AtA[2], own[2][..., None])
    L = np.matmul(inverse3(H), rhs)[..., 0]
    q[:, 1] = follows(2, L)
    q[:, 0] = follows(1, L, q[:, 1])
    # The single-platform commands, each exact on its own platform: a sample keeps the best of the three. Their costs
    # are first predicted (platform j's error at the other's command is A_j·(L_o* − L_j*) to second order); only the
    # samples where one may beat the least squares are solved exactly (with identical chains, all of them).
    best = squared_errors(q - q_d[:, None], w)
    for j in (1, 2):
        o = 3 - j
        predicted = np.zeros_like(q)
        predicted[:, o - 1] = np.matmul(A[o], (own[j] - own[o])[..., None])[..., 0]
        close = np.flatnonzero(squared_errors(predicted, w) * (1.0 - SAFETY) <= best)
        if close.size == 0:
            continue
        qj = np.empty((close.size, 2, 3))
        qj[:, j - 1] = q_d[close]
        guess = q_d[close] + predicted[close, o - 1]
        qj[:, o - 1] = _attitude(params, own[j][close], guess, o, t[close], other=q_d[close] if j == 2 else None)
        cost = squared_errors(qj - q_d[close, None], w)
        better = cost < best[close]
        chosen = close[better]
        L[chosen], q[chosen], best[chosen] = own[j][chosen], qj[better], cost[better]
    return L, q


def _own_command(params: Parameters, q_d: np.ndarray, j: int, rate: bool) -> tuple[np.ndarray, np.ndarray | None]:
    """Platform j's carriages at gait angles q_d (n, 3) [rad]: (L_j* (n, 3) [m], ∂f_j/∂q (n, 3, 3) [m/rad] or None).

    The values of :func:`carriages_for_platform` and :func:`reading_rate`, from one evaluation of the chains on a
    per-chain machine.
    """
    if params.geometry is None:
        return carriages_for_platform(params, q_d, j), reading_rate(params, q_d, j) if rate else None
    L, slope = own_command(lambda p, rows: chain_positions(params.chains, p, j - 1), params.angle_signs, q_d, rate)
    if j == 1 and params.chains.stacked:  # m_1's centre rides on m_2: the stack-up's fixed point
        L = stacked_carriages(params, q_d, L, solve=lambda Lk, guess: _attitude(params, Lk, guess, 2, None))
    return L, slope


def own_command(
    positions: Positions, signs: np.ndarray, q_d: np.ndarray, rate: bool
) -> tuple[np.ndarray, np.ndarray | None]:
    """A platform's carriages at gait angles q_d (n, 3) [rad] and, if ``rate``, ∂f/∂q, its chains given by ``positions``
    (as in :func:`newton_from_close`): (L (n, 3) [m], (n, 3, 3) [m/rad] or None)."""
    p = q_d * signs
    L, r, d = positions(p, slice(None))
    if not rate:
        return L, None
    return L, np.matmul(chain_jacobian(r, d), angular_velocity_map(p)) * signs


def _attitude(
    params: Parameters,
    L: np.ndarray,
    guess: np.ndarray,
    j: int,
    t: np.ndarray | None,
    source: str | None = None,
    other: np.ndarray | None = None,
) -> np.ndarray:
    """Platform j's attitude at carriages L (N, 3) [m], each sample solved from its guess (N, 3) [rad].

    A guess within ~1e-6 rad (a linear prediction from the same machine's exact inverse kinematics) reaches round-off
    in two Newton steps, each from one evaluation of the chains (:func:`_newton_from_close`), the second no larger
    than :data:`CONVERGED_STEP` (or the readings reproduced to :data:`CONVERGED_GAP`); a sample that has not,
    and every sample of a drawing machine, goes through the full solve with its assembly-mode and singularity checks.
    ``other``: m_2's attitude at L, (N, 3) [rad], which m_1 on a machine with a stack-up rides on (every caller has
    solved m_2 first; None for m_2, or for m_1 without a stack-up). ``t``, ``source``: for messages.
    """
    q = np.empty_like(guess)
    rest = np.arange(len(L))
    if j == 1 and params.geometry is not None and params.chains.stacked:  # m_1 sees L − Δz(q_2(L))
        assert other is not None
        L = L - stackup_lift(params.chains.spline_seat, other * params.angle_signs)[:, None]
    if params.geometry is not None:
        q[:], done = _newton_from_close(params, L, guess, j)
        rest = np.flatnonzero(~done)
    if rest.size:
        try:
            q[rest] = solve_pose(params, L[rest], guess[rest], platform=None if params.geometry is None else j)
        except PoseError as error:
            k = int(rest[error.index])
            time = float(t[k]) if t is not None else float(k)
            raise PoseError(f"platform {j}: {error.reason}", time, k, source=source) from None
    return q


def _newton_from_close(params: Parameters, L: np.ndarray, guess: np.ndarray, j: int) -> tuple[np.ndarray, np.ndarray]:
    """Newton on a per-chain platform's angles from close guesses: (gait angles (N, 3), converged (N,) bool)."""
    return newton_from_close(lambda p, rows: chain_positions(params.chains, p, j - 1), params.angle_signs, L, guess)


def newton_from_close(
    positions: Positions, signs: np.ndarray, L: np.ndarray, guess: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Newton on a platform's angles from close guesses, its chains given by ``positions``.

    Args:
        positions: (p, rows) → :func:`hipsim.analytic.chain_kinematics.chain_positions`' (L, r, d) at platform
            angles p [rad] of the samples ``rows`` (a slice or indices: for chains that differ by sample).
        signs: the parameter file's angle signs, (3,).
        L: carriage readings in [m], (N, 3).
        guess: gait angles in [rad] within ~1e-6 rad of the solution, (N, 3).

    Returns:
        Gait angles in [rad], (N, 3), and converged (N,) bool.
    """
    p = guess * signs  # the signs are floats: so is p
    converged = np.empty(len(p), dtype=bool)
    for start in range(0, len(p), BLOCK):  # blocks that stay in the cache; every sample is independent
        rows = slice(start, start + BLOCK)
        p[rows], converged[rows] = _newton_block(positions, L[rows], p[rows], start)
    return p * signs, converged


def _newton_block(positions: Positions, L: np.ndarray, p: np.ndarray, start: int) -> tuple[np.ndarray, np.ndarray]:
    """:func:`newton_from_close` on the samples start, start + 1, ... (platform angles p (n, 3)): (p, converged)."""
    rows = slice(start, start + len(p))
    with np.errstate(invalid="ignore", divide="ignore"):
        for _ in range(NEWTON_STEPS):
            heights, r, d = positions(p, rows)
            D = np.matmul(chain_jacobian(r, d), angular_velocity_map(p))  # ∂L/∂p
            step = np.matmul(inverse3(D), (heights - L)[..., None])[..., 0]
            p = p - step
        # Newton converges quadratically: after a last step this small the error is ~|step|² (≤ ~1e-16 rad), so
        # only the other samples need the chains evaluated to check their readings. NaN fails both tests.
        converged = np.abs(step).max(axis=1) <= CONVERGED_STEP
        rest = np.flatnonzero(~converged)
        if rest.size:
            gap = np.abs(positions(p[rest], start + rest)[0] - L[rest]).max(axis=1)
            converged[rest] = gap <= CONVERGED_GAP
    return p, converged
