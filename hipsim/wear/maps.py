"""Slide tracks' sums per cup point over a motion: sliding distance, work, cross-shear; and the force track.

The definitions (docs/guide/wear.md), per point w of the cup and per cycle:

- sliding distance s = ∫|v| dt in [mm], with v = −r·(Ω × w);
- work W = ∫p·|v| dt in [N/mm], with p = 3F/(2πr²)·max(0, w·n);
- cross-shear CS = W⊥/(W∥ + W⊥), W∥(e) = ∫p·|v·e| dt at the tangent e that
  maximises it, W⊥ = ∫p·|v·(w × e)| dt (Kang et al.); NaN where W = 0;
- the force track, the path of n on the cup: its length r·∫|ṅ| dt in [mm]
  and its load integral ∫F·r·|ṅ| dt in [N·m], with ṅ = −Ω × n.

The integrals are the trapezoidal rule over the samples (the periodic one,
all steps alike, for a motion of whole periods), divided by the number of
cycles the motion covers. The direction e is found per point by the
fixed-point iteration of L1 principal components (m ← Σ c·sign(u·m)·u, which
never lowers the work along m and stops when the signs stop changing: the
exact maximum of its piece of the work curve), started from the principal
axis of the work tensor and checked against four fixed directions (45° apart) and the one across it, from the
best of which it restarts should one beat it.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ..exceptions import TrajectoryError
from ..motion.sources import SampledSource, TrajectorySource, pieces
from ..motion.trajectories import Trajectory
from .kernel import COARSE_ANGLES, direction_pass, exact_direction, first_pass
from .kinematics import CupSetup, relative_motion
from .points import CupPoints, cup_grid, tangent_basis

__all__ = ["PIECE", "WearMaps", "quadrature_weights", "wear_maps"]

#: Samples per piece of the motion: a piece's kinematics is some 10 arrays of (PIECE, 3).
PIECE = 20_000
#: A motion of at most this many samples is held between passes and gets the exact search (its cost per sample grows
#: with the motion: some 100 cycles at 1 kHz take minutes on the default grid); a longer one is re-read in pieces by the
#: L1 iteration, in constant memory.
KEEP_SAMPLES = 100_000
#: Cup points per step of the exact direction search, for a progress bar (the search is per point: any split is exact).
POINTS_PER_STEP = 2_000
#: Most fixed-point iterations per point (they stop in a handful).
MAX_ITERATIONS = 200


@dataclass(frozen=True, eq=False)
class WearMaps:
    """Per point and per cycle: what the cup went through (module docstring).

    Attributes:
        points: the cup's points.
        setup: the cup and head.
        sliding_mm: s per cycle in [mm], (P,).
        sliding_loaded_mm: s while the point is in contact (p > 0), per cycle in [mm], (P,).
        work_N_per_mm: W per cycle in [N/mm], (P,).
        cross_shear: CS, (P,); NaN where W = 0.
        principal: e, the tangent direction of most work, unit, (P, 3); NaN where W = 0.
        force_track_mm: the force track's length per cycle in [mm].
        force_track_load_Nm: its load integral per cycle in [N·m].
        cycles: cycles the motion covers.
        duration_s: the time the motion covers in [s].
        samples: its samples.
        name: where the motion came from.
        iterations: fixed-point passes made.
    """

    points: CupPoints
    setup: CupSetup
    sliding_mm: np.ndarray
    sliding_loaded_mm: np.ndarray
    work_N_per_mm: np.ndarray
    cross_shear: np.ndarray
    principal: np.ndarray
    force_track_mm: float
    force_track_load_Nm: float
    cycles: float
    duration_s: float
    samples: int
    name: str
    iterations: int

    @property
    def loaded(self) -> np.ndarray:
        """The points that carry work (W > 0), (P,) booleans."""
        return self.work_N_per_mm > 0.0


def quadrature_weights(source: TrajectorySource, start: int, stop: int, t: np.ndarray | None = None) -> np.ndarray:
    """The trapezoidal weights dt in [s] of samples start … stop−1 of the source (module docstring), (stop − start,).

    Args:
        source: the motion.
        start, stop: the samples.
        t: their times in [s], if at hand (else asked of the source).
    """
    n = len(source)
    t = np.array([source.time(k) for k in range(start, stop)]) if t is None else np.asarray(t, dtype=float)
    before = source.time(start - 1) if start > 0 else None
    after = source.time(stop) if stop < n else None
    if source.periodic:
        step = (source.time(n - 1) - source.time(0)) / (n - 1)
        before = t[0] - step if before is None else before
        after = t[-1] + step if after is None else after
    left = np.concatenate([[t[0] if before is None else before], t[:-1]])
    right = np.concatenate([t[1:], [t[-1] if after is None else after]])
    return (right - left) / 2.0


def _duration(source: TrajectorySource) -> float:
    n = len(source)
    first, last = source.time(0), source.time(n - 1)
    return last - first + ((last - first) / (n - 1) if source.periodic else 0.0)


#: How close (relative to the cycle) the span plus one step must come to whole cycles for a motion to close by a step.
CLOSING_TOLERANCE = 1e-6


def _closes_by_a_step(source: TrajectorySource, cycle_time_s: float, step: float) -> bool:
    """Whether a motion written without its closing sample (as ``stations`` and ``simulate`` write the built-in cycle)
    covers whole cycles with its last step: its span plus one step is a whole number of cycles, and the last sample
    runs on into the first as the samples run on into each other (angles and load within three of the end steps)."""
    n = len(source)
    cycles = (source.time(n - 1) - source.time(0) + step) / cycle_time_s
    if n < 4 or round(cycles) < 1 or abs(cycles - round(cycles)) > CLOSING_TOLERANCE * max(1.0, cycles):
        return False
    head, tail = source.piece(0, 2), source.piece(n - 2, n)
    for first, last in ((head.q, tail.q), (head.Fe[:, None], tail.Fe[:, None])):
        steps = np.maximum(np.abs(first[1] - first[0]), np.abs(last[1] - last[0]))
        if np.any(np.abs(first[0] - last[1]) > 3.0 * steps + 1e-12):
            return False
    return True


class _ClosedCycle:
    """A source whose last step closes its cycle: the same samples, periodic."""

    periodic = True

    def __init__(self, source: TrajectorySource):
        self.source, self.name = source, source.name

    def __len__(self) -> int:
        return len(self.source)

    def time(self, k: int) -> float:
        return self.source.time(k)

    def piece(self, start: int, stop: int) -> Trajectory:
        return self.source.piece(start, stop)


@dataclass
class _Piece:
    omega: np.ndarray
    n: np.ndarray
    load_dt: np.ndarray
    dt: np.ndarray
    n_speed: np.ndarray


def _pieces(source: TrajectorySource, setup: CupSetup, piece: int):
    """The motion's kinematics a piece at a time, checked."""
    for start, stop in pieces(source, piece):
        part = source.piece(start, stop)
        if np.any(part.Fe < 0):
            k = int(np.argmax(part.Fe < 0))
            raise TrajectoryError(
                f"the load is negative ({part.Fe[k]:.6g} N) at t = {part.t[k]:.6g} s: a load presses",
                source=source.name,
            )
        motion = relative_motion(part, setup)
        dt = quadrature_weights(source, start, stop, part.t)
        yield _Piece(
            np.ascontiguousarray(motion.omega),
            np.ascontiguousarray(motion.n),
            np.ascontiguousarray(part.Fe * dt),
            dt,
            np.linalg.norm(motion.n_dot, axis=1),
        )


def wear_maps(
    motion: Trajectory | TrajectorySource,
    cycle_time_s: float,
    setup: CupSetup | None = None,
    points: CupPoints | None = None,
    piece: int = PIECE,
    progress: Callable[[int, int], None] | None = None,
) -> WearMaps:
    """Sliding distance, work and cross-shear per cup point, and the force track, per cycle of a motion.

    Args:
        motion: the platform's motion and load (a trajectory, or a source handed out in pieces).
        cycle_time_s: the length of one cycle in [s]; the sums are divided by the cycles the motion covers.
        setup: the cup and head (default :class:`CupSetup`: 28 mm head, cup on the platform).
        points: the cup's points (default :func:`hipsim.wear.points.cup_grid` 90 × 180).
        piece: samples per piece (memory is bounded by it, not by the motion's length).
        progress: called with (steps done, steps in all) after each piece of the first pass and each part of the
            cup's points the direction search has done (a progress bar on a fine grid); None: not called.

    Raises:
        TrajectoryError: a motion shorter than one cycle (a motion that is not periodic may lack the cycle's closing
            sample: one step short still counts), or with a negative load.
    """
    source = SampledSource(motion) if isinstance(motion, Trajectory) else motion
    setup = setup or CupSetup()
    points = points if points is not None else cup_grid(radius_mm=setup.radius_mm)
    n = len(source)
    if n < 2:
        raise TrajectoryError("a motion needs at least two samples", source=source.name)
    if not (math.isfinite(cycle_time_s) and cycle_time_s > 0):
        raise TrajectoryError(
            f"the cycle time must be a positive number of seconds, got {cycle_time_s!r}", source=source.name
        )
    step = (source.time(n - 1) - source.time(0)) / (n - 1)
    closed = not source.periodic and _closes_by_a_step(source, cycle_time_s, step)
    if closed:
        source = _ClosedCycle(source)
    duration = _duration(source)
    # A file of one cycle sampled without its closing sample covers a step less than the cycle: still one cycle. One
    # closed by its last step covers whole cycles to CLOSING_TOLERANCE, and is held to that, not refused as short.
    slack = CLOSING_TOLERANCE if closed else 1e-9
    if duration < cycle_time_s * (1.0 - slack) - (0.0 if source.periodic else step * (1.0 + 1e-9)):
        raise TrajectoryError(
            f"the motion covers {duration:.6g} s, shorter than one cycle of {cycle_time_s:.6g} s: "
            "wear is given per cycle, and this motion has no whole one",
            source=source.name,
        )
    cycles = duration / cycle_time_s
    r = setup.radius_mm
    coef = 3.0 / (2.0 * math.pi * r**2)
    w = np.ascontiguousarray(points.w)
    t1, t2 = tangent_basis(w)
    P = w.shape[0]
    angles = np.array(COARSE_ANGLES)
    directions = np.stack([np.cos(angles), np.sin(angles)], axis=1)
    s, s_loaded, work = np.zeros(P), np.zeros(P), np.zeros(P)
    tensor, coarse = np.zeros((P, 3)), np.zeros((P, angles.size))
    track = track_load = 0.0
    kept: list[_Piece] | None = [] if n <= KEEP_SAMPLES else None
    # Progress: the first pass's pieces, then the exact search's parts of the points (each point alone: exact).
    parts = [(a, min(a + POINTS_PER_STEP, P)) for a in range(0, P, POINTS_PER_STEP)] if kept is not None else []
    steps, done = -(-n // piece) + len(parts), 0
    for part in _pieces(source, setup, piece):
        first_pass(
            t1, t2, w, part.omega, part.n, part.load_dt, part.dt, coef, s, s_loaded, work, tensor, coarse, kept is None
        )
        track += float(np.sum(part.n_speed * part.dt))
        track_load += float(np.sum(part.n_speed * part.load_dt))
        if kept is not None:
            kept.append(part)
        done += 1
        if progress is not None:
            progress(done, steps)

    def again():
        return kept if kept is not None else _pieces(source, setup, piece)

    if kept is not None:  # the whole motion at hand: the exact search
        omega = np.ascontiguousarray(np.concatenate([part.omega for part in kept]))
        normal = np.ascontiguousarray(np.concatenate([part.n for part in kept]))
        load_dt = np.ascontiguousarray(np.concatenate([part.load_dt for part in kept]))
        theta, along, across = np.zeros(P), np.zeros(P), np.zeros(P)
        active = work > 0.0
        for a, b in parts:
            exact_direction(
                t1[a:b], t2[a:b], w[a:b], omega, normal, load_dt, coef, active[a:b], theta[a:b], along[a:b], across[a:b]
            )
            done += 1
            if progress is not None:
                progress(done, steps)
        m, iterations = np.stack([np.cos(theta), np.sin(theta)], axis=1), 0
    else:
        along, across, m, iterations = _principal(t1, t2, w, coef, again, work > 0.0, tensor, coarse, directions)
    with np.errstate(invalid="ignore", divide="ignore"):
        cross_shear = np.where(work > 0.0, across / (along + across), np.nan)
    m3 = m[:, :1] * t1 + m[:, 1:] * t2
    principal = np.cross(m3, w)  # e = m × w, so that m = w × e
    principal[~(work > 0.0)] = np.nan
    return WearMaps(
        points,
        setup,
        r * s / cycles,
        r * s_loaded / cycles,
        r * work / cycles,
        cross_shear,
        principal,
        r * track / cycles,
        r * track_load / cycles / 1000.0,
        cycles,
        duration,
        n,
        source.name,
        iterations,
    )


def _principal(t1, t2, w, coef, again, loaded, tensor, coarse, directions):
    """Per point: the work along and across the direction m of most work (in (t1, t2) coordinates), and m."""
    P = w.shape[0]
    # The principal axis of the work tensor Σ c·u·uᵀ/|u|: the start.
    start = 0.5 * np.arctan2(2.0 * tensor[:, 1], tensor[:, 0] - tensor[:, 2])
    m = np.stack([np.cos(start), np.sin(start)], axis=1)
    along, across = np.zeros(P), np.zeros(P)
    active = loaded.copy()
    restarts = np.zeros(P, dtype=int)
    iterations = 0
    while active.any() and iterations < MAX_ITERATIONS:
        iterations += 1
        pull, f_along, f_across = np.zeros((P, 2)), np.zeros(P), np.zeros(P)
        for part in again():
            direction_pass(t1, t2, w, part.omega, part.n, part.load_dt, coef, active, m, pull, f_along, f_across)
        size = np.linalg.norm(pull, axis=1)
        with np.errstate(invalid="ignore", divide="ignore"):
            new = pull / size[:, None]
        settled = active & ((size == 0.0) | (np.max(np.abs(new - m), axis=1) <= 1e-12))
        along[settled], across[settled] = f_along[settled], f_across[settled]
        moving = active & ~settled
        m[moving] = new[moving]
        # A local maximum only: restart (twice at most) from a direction that does better, if one of the
        # fixed ones or the one across does.
        best = np.argmax(coarse, axis=1)
        other = np.where(
            (coarse[np.arange(P), best] >= across)[:, None], directions[best], np.stack([-m[:, 1], m[:, 0]], 1)
        )
        beaten = settled & (restarts < 2) & (np.maximum(coarse[np.arange(P), best], across) > along * (1.0 + 1e-12))
        m[beaten] = other[beaten]
        restarts += beaten
        active = moving | beaten
    if active.any():  # not settled in MAX_ITERATIONS: keep the last (never lower) values
        along[active], across[active] = f_along[active], f_across[active]
    return along, across, m, iterations
