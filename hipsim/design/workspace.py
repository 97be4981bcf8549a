"""Singularity and workspace maps, and the platform-offset sweep (issue 7).

Two questions a designer asks before building or running the machine:

* **Does a motion stay clear of singularities?** :func:`singularity_map`
  evaluates the singularity measure of spec §7.1 — the inverse condition
  number of the Jacobian J (0 singular, 1 isotropic) — over a grid of
  orientations (flexion/extension α × abduction/adduction β, at a few
  internal/external rotations γ), and :func:`trajectory_margin` finds the
  smallest value along a trajectory and where it occurs.
* **Why is the machine built with δ = 30°?** :func:`offset_sweep` reruns a
  trajectory (the ISO 14242-1 cycle by default) on machines that differ only
  in the platform offset δ (spec §7.1) and reports, per δ, the smallest
  singularity measure, the peak motor torque and the largest slider stroke.

Only positions enter J (row i = (r_i × e_i)ᵀ/e_i,z, spec §3), so the map needs
no velocities: :func:`pose_jacobian` computes J for any batch of orientations
from :func:`hipsim.analytic.inverse_kinematics.rotation_matrix` and the parameter set's joint
points, and the grid is evaluated in large vectorised chunks (no Python loop
over orientations). :func:`run_workspace` is what ``hipsim workspace`` calls:
both computations, their figures (PNG and SVG) and a short text summary.

Angles: the grid axes and all ``*_deg`` values are **gait angles** in degrees,
the same convention as trajectory files; the parameter file's
``convention.angle_signs`` is applied before the geometry, exactly as
:func:`hipsim.analytic.kinematics` does, so a trajectory drawn on the map
lands where the machine really is.

Example:
    >>> import hipsim
    >>> from hipsim import workspace
    >>> params = hipsim.load_parameters()
    >>> smap = workspace.singularity_map(params, trajectory=hipsim.iso14242())
    >>> round(smap.margin.cond_inv_min, 3)                 # doctest: +SKIP
    0.359
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ..analytic.inverse_kinematics import (
    SINGULAR_COND_INV,
    inverse_condition_number,
    kinematics,
    singularity_crossings,
    slider_jacobian,
)
from ..analytic.virtual_work import inverse_dynamics
from ..exceptions import ArgumentError
from ..machine.parameters import Parameters
from ..motion.trajectories import Trajectory
from ..records import Record

__all__ = [
    "DEFAULT_ALPHA_DEG",
    "DEFAULT_BETA_DEG",
    "DEFAULT_DELTAS_DEG",
    "DEFAULT_GAMMA_DEG",
    "OffsetRow",
    "OffsetSweep",
    "SingularityMap",
    "TrajectoryMargin",
    "offset_sweep",
    "pose_jacobian",
    "singularity_map",
    "trajectory_margin",
]

#: Default flexion/extension grid in [deg]: −30° … +35° in 0.25° steps (261 values),
#: wider than the ISO range +25°/−18° so the map shows the margin around it.
DEFAULT_ALPHA_DEG = np.linspace(-30.0, 35.0, 261)
#: Default abduction/adduction grid in [deg]: −15° … +15° in 0.25° steps (121 values).
DEFAULT_BETA_DEG = np.linspace(-15.0, 15.0, 121)
#: Default internal/external rotations in [deg], one map panel each, spanning the ISO range +2°/−10°.
DEFAULT_GAMMA_DEG = np.array([-12.0, -8.0, -4.0, 0.0, 4.0])
#: Default platform offsets δ of the sweep in [deg]: −90° … +90° in 1° steps
#: (beyond about ±103° the published levers no longer reach at home).
DEFAULT_DELTAS_DEG = np.arange(-90.0, 90.5, 1.0)

# Orientations per vectorised chunk: large enough that NumPy's per-call
# overhead vanishes, small enough (≈ 10 MB per (n, 3, 3) array) to stay in cache-friendly memory.
_CHUNK = 1 << 16
# Above this many orientations the map shows a progress bar (about three seconds at
# the 3 million orientations per second scripts/bench.py measures).
_PROGRESS_ORIENTATIONS = 10_000_000
# Above this many δ values the sweep shows a progress bar.
_PROGRESS_DELTAS = 200


# ---------------------------------------------------------------------------
# Positions-only Jacobian


def pose_jacobian(params: Parameters, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The Jacobian J of spec §3 (L̇_j = J·ω) from positions alone, for a batch of orientations.

    Row i is (r_i × e_i)ᵀ / e_i,z; with the lever vector d_i = a_i − b_i = l·e_i
    the lever length cancels: row i = (r_i × d_i)ᵀ / d_i,z. Both platforms share J.

    Args:
        params: the machine.
        q: **platform** orientations [α, β, γ] in [rad] (after any angle signs), shape (N, 3).

    Returns:
        J of shape (N, 3, 3), NaN where a pose is out of reach, and the
        boolean mask of reachable poses, shape (N,) (every lever spans its
        horizontal gap: l² − gap² > 0, as in :func:`hipsim.analytic.kinematics`).
    """
    J = slider_jacobian(params, np.asarray(q, dtype=float).reshape(-1, 3))
    return J, np.all(np.isfinite(J), axis=(1, 2))


def _cond_inv(params: Parameters, gait_q: np.ndarray) -> np.ndarray:
    """Inverse condition number of J at gait orientations in [rad], shape (N, 3) → (N,), NaN out of reach."""
    J, _ = pose_jacobian(params, gait_q * params.angle_signs)
    return inverse_condition_number(J)


# ---------------------------------------------------------------------------
# Trajectory margin and the map


@dataclass(frozen=True, eq=False)
class TrajectoryMargin:
    """How close a trajectory comes to a singularity.

    Attributes:
        trajectory: the trajectory's name.
        cond_inv: inverse condition number of J per sample, NaN out of reach, shape (N,).
        cond_inv_min: its smallest value (the margin: 0 singular, 1 isotropic); NaN if no sample is reachable.
        index: the sample where it occurs (−1 if none).
        t_s: the time there in [s].
        q_deg: the gait orientation [α, β, γ] there in [deg], shape (3,).
        out_of_reach: number of samples out of reach.
        singular: number of samples below the singularity threshold
            (:data:`hipsim.analytic.inverse_kinematics.SINGULAR_COND_INV`).
        crossings: how often the motion passes through a singularity between
            samples (sign changes of det J, :func:`singularity_crossings`).
    """

    trajectory: str
    cond_inv: np.ndarray
    cond_inv_min: float
    index: int
    t_s: float
    q_deg: np.ndarray
    out_of_reach: int
    singular: int
    crossings: int = 0

    @property
    def clear(self) -> bool:
        """True when every sample is reachable and non-singular and no singularity is crossed."""
        return self.out_of_reach == 0 and self.singular == 0 and self.crossings == 0


def trajectory_margin(params: Parameters, trajectory: Trajectory) -> TrajectoryMargin:
    """The singularity measure along a trajectory and its smallest value.

    Args:
        params: the machine.
        trajectory: orientations q in [rad] (gait angles) at times t in [s].

    Returns:
        The :class:`TrajectoryMargin`; equal, sample by sample, to
        ``kinematics(params, trajectory).cond_inv``.
    """
    J, _ = pose_jacobian(params, trajectory.q * params.angle_signs)
    cond_inv = inverse_condition_number(J)
    cond_inv.setflags(write=False)
    crossings = singularity_crossings(J, trajectory.periodic)
    out_of_reach = int(np.count_nonzero(np.isnan(cond_inv)))
    singular = int(np.count_nonzero(cond_inv < SINGULAR_COND_INV))
    if out_of_reach == cond_inv.size:
        k, value, t, q = -1, math.nan, math.nan, np.full(3, np.nan)
    else:
        k = int(np.nanargmin(cond_inv))
        value, t, q = float(cond_inv[k]), float(trajectory.t[k]), np.degrees(trajectory.q[k])
    return TrajectoryMargin(trajectory.name, cond_inv, value, k, t, q, out_of_reach, singular, crossings)


@dataclass(frozen=True, eq=False)
class SingularityMap:
    """The singularity measure over a grid of orientations.

    Attributes:
        alpha_deg: flexion/extension grid values in [deg] (gait angles), shape (nα,).
        beta_deg: abduction/adduction grid values in [deg], shape (nβ,).
        gamma_deg: internal/external rotations in [deg], one map each, shape (nγ,).
        cond_inv: inverse condition number of J, shape (nγ, nβ, nα) (rows β,
            columns α, as an image is drawn); NaN where the pose is out of reach.
        delta_deg: the machine's platform offset δ in [deg].
        source: where the parameters came from.
        margin: the trajectory's :class:`TrajectoryMargin`, if a trajectory was given.
        trajectory_t_s: that trajectory's sample times in [s], shape (N,).
        trajectory_q_deg: its gait orientations in [deg], shape (N, 3), to draw on the map.
    """

    alpha_deg: np.ndarray
    beta_deg: np.ndarray
    gamma_deg: np.ndarray
    cond_inv: np.ndarray
    delta_deg: float
    source: str
    margin: TrajectoryMargin | None = None
    trajectory_t_s: np.ndarray | None = None
    trajectory_q_deg: np.ndarray | None = None

    @property
    def orientations(self) -> int:
        """Number of orientations on the grid."""
        return int(self.cond_inv.size)

    def reachable_fraction(self) -> np.ndarray:
        """Fraction of each γ map that is within reach, shape (nγ,)."""
        return np.mean(~np.isnan(self.cond_inv), axis=(1, 2))


def _progress(total: int, enabled: bool, unit: str, description: str):
    from tqdm.auto import tqdm

    # tqdm writes to standard error, and only when the caller turned it on.
    return tqdm(total=total, disable=not enabled, unit=unit, unit_scale=True, desc=description, leave=False)


def singularity_map(
    params: Parameters,
    alpha_deg_grid: ArrayLike | None = None,
    beta_deg_grid: ArrayLike | None = None,
    gamma_deg_values: ArrayLike | None = None,
    trajectory: Trajectory | None = None,
    progress: bool | None = None,
) -> SingularityMap:
    """The inverse condition number of J over a grid of orientations, vectorised.

    Args:
        params: the machine.
        alpha_deg_grid: flexion/extension values in [deg], 1-D; default
            :data:`DEFAULT_ALPHA_DEG` (−30° … +35°, 261 values).
        beta_deg_grid: abduction/adduction values in [deg], 1-D; default
            :data:`DEFAULT_BETA_DEG` (−15° … +15°, 121 values).
        gamma_deg_values: internal/external rotations in [deg], 1-D, one map
            each; default :data:`DEFAULT_GAMMA_DEG` (−12, −8, −4, 0, +4).
        trajectory: a motion (angles in [rad]) whose margin to compute and whose
            path to keep for drawing; None for the map alone.
        progress: show a tqdm progress bar on stderr; None to show one only on
            grids large enough to take more than a few seconds (10 million orientations).

    Returns:
        The :class:`SingularityMap`.
    """
    alpha = _grid(alpha_deg_grid, DEFAULT_ALPHA_DEG, "alpha_deg_grid")
    beta = _grid(beta_deg_grid, DEFAULT_BETA_DEG, "beta_deg_grid")
    gamma = _grid(gamma_deg_values, DEFAULT_GAMMA_DEG, "gamma_deg_values")
    shape = (gamma.size, beta.size, alpha.size)
    total = math.prod(shape)
    if progress is None:
        progress = total > _PROGRESS_ORIENTATIONS
    cond_inv = np.empty(total)
    # Orientation k of the flat grid is (γ, β, α)[unravel(k)]; chunks are built
    # from index ranges so the full (total, 3) orientation array never exists.
    radians = [np.radians(gamma), np.radians(beta), np.radians(alpha)]
    with _progress(total, progress, "pose", "singularity map") as bar:
        for start in range(0, total, _CHUNK):
            stop = min(start + _CHUNK, total)
            g, b, a = np.unravel_index(np.arange(start, stop), shape)
            q = np.stack([radians[2][a], radians[1][b], radians[0][g]], axis=1)
            cond_inv[start:stop] = _cond_inv(params, q)
            bar.update(stop - start)
    cond_inv = cond_inv.reshape(shape)
    cond_inv.setflags(write=False)
    margin = trajectory_margin(params, trajectory) if trajectory is not None else None
    times = np.asarray(trajectory.t) if trajectory is not None else None
    path = np.degrees(trajectory.q) if trajectory is not None else None
    return SingularityMap(
        alpha, beta, gamma, cond_inv, math.degrees(params.home_offset), params.source, margin, times, path
    )


#: Most values one grid axis may have (a typo such as a step of 1e-9 would ask for billions).
_MAX_GRID = 100_000


def _grid(values, default: np.ndarray, name: str) -> np.ndarray:
    try:
        grid = np.array(default if values is None else values, dtype=float).ravel()
    except (TypeError, ValueError):
        raise ArgumentError(name, values, "numbers (angles in degrees)") from None
    if grid.size == 0 or not np.all(np.isfinite(grid)):
        raise ArgumentError(name, values, "a non-empty list of finite angles in degrees")
    if grid.size > _MAX_GRID:
        raise ArgumentError(name, grid, f"at most {_MAX_GRID:,} values")
    grid.setflags(write=False)
    return grid


# ---------------------------------------------------------------------------
# Platform offset sweep


@dataclass(frozen=True, eq=False)
class OffsetSweep:
    """A trajectory run on machines that differ only in the platform offset δ (spec §7.1).

    Every array has one entry per δ. A δ at which the trajectory leaves the
    reach of the levers, comes within :data:`hipsim.analytic.inverse_kinematics.SINGULAR_COND_INV`
    of a singularity at a sample, or passes through one between samples (det J
    changes sign) is *infeasible*: its peak torque and stroke are NaN (the
    machine cannot run the motion: the torque needed there is unbounded), and
    ``out_of_reach``, ``singular`` and ``crossings`` say why.

    Attributes:
        deltas_deg: platform offsets δ in [deg], shape (n,).
        cond_inv_min: smallest inverse condition number of J along the trajectory
            (over its reachable samples; NaN if none).
        tau_peak_Nmm: largest |motor torque| of the three motors in [N·mm].
        tau_peak_motor: which motor (1, 2, 3) has it (0 when infeasible).
        stroke_max_mm: largest slider stroke (max − min height) of the three modules in [mm].
        out_of_reach: samples out of reach.
        singular: reachable samples below the singularity threshold.
        crossings: sign changes of det J along the motion (singularities passed between samples).
        trajectory: the trajectory's name.
        delta_built_deg: δ of the parameter set the sweep started from in [deg].
    """

    deltas_deg: np.ndarray
    cond_inv_min: np.ndarray
    tau_peak_Nmm: np.ndarray
    tau_peak_motor: np.ndarray
    stroke_max_mm: np.ndarray
    out_of_reach: np.ndarray
    singular: np.ndarray
    crossings: np.ndarray
    trajectory: str
    delta_built_deg: float

    @property
    def built_index(self) -> int | None:
        """The index of the built machine's δ among the swept offsets, or None when it was not swept."""
        k = int(np.argmin(np.abs(self.deltas_deg - self.delta_built_deg)))
        return k if abs(self.deltas_deg[k] - self.delta_built_deg) < 1e-9 else None

    @property
    def feasible(self) -> np.ndarray:
        """True where the whole trajectory is reachable, non-singular and crosses no singularity, shape (n,)."""
        return (self.out_of_reach == 0) & (self.singular == 0) & (self.crossings == 0)

    def rows(self) -> tuple[OffsetRow, ...]:
        """One :class:`OffsetRow` per δ (for tables and JSON)."""
        return tuple(
            OffsetRow(float(d), float(c), float(t), int(m), float(s), int(o), int(g), int(x))
            for d, c, t, m, s, o, g, x in zip(
                self.deltas_deg,
                self.cond_inv_min,
                self.tau_peak_Nmm,
                self.tau_peak_motor,
                self.stroke_max_mm,
                self.out_of_reach,
                self.singular,
                self.crossings,
                strict=True,
            )
        )


@dataclass(frozen=True)
class OffsetRow(Record):
    """One δ of an :class:`OffsetSweep`: the offset [deg], the margin, the peak torque [N·mm] and its motor (0:
    infeasible), the largest stroke [mm], the samples out of reach and singular, the singularities crossed."""

    delta_deg: float
    cond_inv_min: float
    tau_peak_Nmm: float
    tau_peak_motor: int
    stroke_max_mm: float
    out_of_reach_samples: int
    singular_samples: int
    singularity_crossings: int


def offset_sweep(
    params: Parameters,
    deltas_deg: ArrayLike | None = None,
    trajectory: Trajectory | None = None,
    progress: bool | None = None,
) -> OffsetSweep:
    """Singularity margin, peak motor torque and slider stroke of a trajectory against δ.

    Each δ is one vectorised run of :func:`hipsim.analytic.kinematics`
    (``on_error="flag"``) and :func:`hipsim.analytic.inverse_dynamics` on
    ``params.replace(home_offset=δ)``; poses out of reach or singular are
    counted, not raised, and so are singularities crossed between samples.

    Args:
        params: the machine (every parameter but δ is kept).
        deltas_deg: platform offsets δ in [deg], 1-D; default
            :data:`DEFAULT_DELTAS_DEG` (−90° … +90° in 1° steps).
        trajectory: the motion (angles in [rad], load in [N]); default one ISO
            14242-1 cycle at 1 kHz.
        progress: show a tqdm progress bar on stderr; None for one only on long sweeps.

    Returns:
        The :class:`OffsetSweep`.
    """
    from ..motion.trajectories import iso14242

    deltas = _grid(deltas_deg, DEFAULT_DELTAS_DEG, "deltas_deg")
    trajectory = trajectory if trajectory is not None else iso14242()
    n = deltas.size
    cond_min, tau_peak, stroke = np.full(n, np.nan), np.full(n, np.nan), np.full(n, np.nan)
    motor, out_of_reach, singular, crossings = (np.zeros(n, int) for _ in range(4))
    if progress is None:
        progress = n > _PROGRESS_DELTAS
    with _progress(n, progress, "δ", "offset sweep") as bar, np.errstate(all="ignore"):
        for k, delta in enumerate(deltas):
            machine = params.replace(home_offset=math.radians(delta))
            kin = kinematics(machine, trajectory, on_error="flag")
            reach = ~np.isnan(kin.cond_inv)
            out_of_reach[k] = np.count_nonzero(~reach)
            singular[k] = np.count_nonzero(reach & (kin.cond_inv < SINGULAR_COND_INV))
            if np.any(reach):
                cond_min[k] = np.min(kin.cond_inv[reach])
            crossings[k] = singularity_crossings(np.where(reach[:, None, None], kin.J, np.nan), trajectory.periodic)
            if not np.any(kin.flagged) and crossings[k] == 0:
                # Only a motion the machine can run has a meaningful torque and stroke.
                tau = np.abs(inverse_dynamics(machine, kin, trajectory.Fe).total).max(axis=0)
                motor[k] = int(np.argmax(tau)) + 1
                tau_peak[k] = tau.max() * 1e3
                stroke[k] = np.ptp(kin.L[:, 0], axis=0).max() * 1e3
            bar.update(1)
    for array in (deltas, cond_min, tau_peak, motor, stroke, out_of_reach, singular, crossings):
        array.setflags(write=False)
    return OffsetSweep(
        deltas,
        cond_min,
        tau_peak,
        motor,
        stroke,
        out_of_reach,
        singular,
        crossings,
        trajectory.name,
        math.degrees(params.home_offset),
    )


# ---------------------------------------------------------------------------
# Figures


# ---------------------------------------------------------------------------
# The command
