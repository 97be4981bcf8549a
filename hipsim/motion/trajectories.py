"""Platform trajectories: the :class:`Trajectory` type and the built-in ISO 14242-1 cycle.

A :class:`Trajectory` holds the platform orientation q = [α, β, γ] in [rad]
(flexion/extension, abduction/adduction, internal/external rotation), its
first and second time derivatives, and the hydraulic load F_e in [N], all
sampled at the times t in [s].

The built-in cycle (spec §7.2) has exact derivatives. Trajectories from files
(hipsim's CSV, a lab's CSV, Parquet, OpenSim .mot/.sto) come from
:func:`hipsim.motion.readers.read_trajectory`, differentiated by
:mod:`hipsim.motion.build`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike
from scipy.interpolate import PchipInterpolator, make_interp_spline

from ..exceptions import TrajectoryError

__all__ = [
    "ANGLE_NAMES",
    "ISO_LOAD_KNOTS",
    "Trajectory",
    "interpolator",
    "iso14242",
    "iso14242_at",
    "iso14242_load",
    "iso14242_samples",
    "trajectory_arrays",
]

#: The three platform angles, in the order of q.
ANGLE_NAMES = ("alpha", "beta", "gamma")

#: Knots (cycle fraction, load in [N]) of the ISO 14242-1 twin-peak load, spec §7.2.
ISO_LOAD_KNOTS = ((0.0, 300.0), (0.12, 3000.0), (0.32, 1500.0), (0.50, 3000.0), (0.62, 300.0), (1.0, 300.0))

#: Fewest samples a trajectory file may have (a quintic spline needs six).
MIN_SAMPLES = 6

#: Most samples a built-in cycle may have: the kinematics of 10⁷ samples take some 10 GB.
MAX_SAMPLES = 10_000_000


@dataclass(frozen=True, eq=False)
class Trajectory:
    """A platform orientation trajectory with its load.

    Attributes:
        t: sample times in [s], shape (N,), increasing.
        q: orientation [α, β, γ] in [rad], shape (N, 3).
        qd: its time derivative in [rad/s], shape (N, 3).
        qdd: its second time derivative in [rad/s²], shape (N, 3).
        Fe: hydraulic load magnitude in [N], shape (N,), pushing down on the hip joints.
        name: where the trajectory came from, for messages and reports.
        periodic: True when the samples cover whole periods (the last sample is
            followed by the first), so RMS values and plots may wrap around.
        lines: for a trajectory read from a file, the file's 1-based line
            that holds each sample, shape (N,); None otherwise (or when the
            samples were resampled or interpolated, and so are no file row).
    """

    t: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray
    Fe: np.ndarray
    name: str = "trajectory"
    periodic: bool = False
    lines: np.ndarray | None = None

    def __post_init__(self):
        t = np.asarray(self.t, dtype=float)
        if t.ndim != 1 or t.size < 1:
            raise TrajectoryError(f"t must be a non-empty 1-D array, got shape {t.shape}", source=self.name)
        n = t.size
        for attr, shape in (("q", (n, 3)), ("qd", (n, 3)), ("qdd", (n, 3)), ("Fe", (n,))):
            value = np.asarray(getattr(self, attr), dtype=float)
            if value.shape != shape:
                raise TrajectoryError(f"{attr} must have shape {shape}, got {value.shape}", source=self.name)
            if not np.all(np.isfinite(value)):
                k = int(np.argwhere(~np.isfinite(value))[0][0])
                raise TrajectoryError(f"{attr} is not finite at t = {t[k]:.6g} s", source=self.name)
            value.setflags(write=False)
            object.__setattr__(self, attr, value)
        t.setflags(write=False)
        object.__setattr__(self, "t", t)
        if self.lines is not None:
            lines = np.asarray(self.lines)
            if lines.shape != (n,) or not np.issubdtype(lines.dtype, np.integer):
                raise TrajectoryError(
                    f"lines must be integers of shape ({n},), got {lines.dtype} {lines.shape}", source=self.name
                )
            lines = lines.astype(int)
            lines.setflags(write=False)
            object.__setattr__(self, "lines", lines)

    def __len__(self) -> int:
        return self.t.size

    def slice(self, index) -> Trajectory:
        """The samples selected by ``index`` (a slice, mask or index array)."""
        lines = None if self.lines is None else self.lines[index]
        return Trajectory(
            self.t[index], self.q[index], self.qd[index], self.qdd[index], self.Fe[index], self.name, False, lines
        )

    def line_at(self, time: float) -> int | None:
        """The file line of the sample at ``time`` in [s]; None if no file row holds that time.

        For messages: an error that names a sample time (a
        :class:`~hipsim.exceptions.PoseError`) can name the line a user looks
        up. Only a time that is one of the samples' (to a millionth of a step)
        has a line; a time between samples, or of a resampled file, has none.
        """
        if self.lines is None or not math.isfinite(time):
            return None
        k = int(np.clip(np.searchsorted(self.t, time), 0, self.t.size - 1))
        step = (self.t[-1] - self.t[0]) / (self.t.size - 1) if self.t.size > 1 else 1.0
        for j in (k - 1, k):
            if 0 <= j < self.t.size and abs(self.t[j] - time) <= 1e-6 * step:
                return int(self.lines[j])
        return None


def iso14242_angles(t: np.ndarray, frequency: float = 1.0) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The gait angles of the built-in cycle and their exact derivatives.

    Args:
        t: times in [s], shape (N,).
        frequency: cycle frequency f in [Hz].

    Returns:
        q, qd, qdd, each of shape (N, 3), in [rad], [rad/s], [rad/s²].
    """
    deg = math.pi / 180.0
    # (mean, amplitude, phase) of each angle: x(s) = mean + amplitude·cos(2πs − phase).
    mean = np.array([3.5, 1.5, -4.0]) * deg
    amplitude = np.array([21.5, 5.5, 6.0]) * deg
    phase = np.array([0.0, 40.0 * deg, math.pi])
    w = 2.0 * math.pi * frequency
    arg = w * np.asarray(t, dtype=float)[:, None] - phase
    q = mean + amplitude * np.cos(arg)
    qd = -amplitude * w * np.sin(arg)
    qdd = -amplitude * w**2 * np.cos(arg)
    return q, qd, qdd


def iso14242_load(t: np.ndarray, frequency: float = 1.0) -> np.ndarray:
    """The built-in twin-peak load F_e in [N] at times t in [s] (periodic PCHIP, spec §7.2)."""
    s, load = np.array(ISO_LOAD_KNOTS).T
    # The knots at s = 0 and s = 1 are the same point of the periodic curve:
    # repeat one period before and after so the end slopes see their neighbours.
    s_inner, load_inner = s[:-1], load[:-1]
    s_ext = np.concatenate([s_inner - 1.0, s_inner, s_inner + 1.0, [2.0]])
    load_ext = np.concatenate([load_inner, load_inner, load_inner, [load[-1]]])
    curve = PchipInterpolator(s_ext, load_ext)
    return curve(np.mod(np.asarray(t, dtype=float) * frequency, 1.0))


def iso14242(rate: float = 1000.0, cycles: float = 1, frequency: float = 1.0) -> Trajectory:
    """The built-in ISO 14242-1 gait cycle of spec §7.2.

    Args:
        rate: sample rate in [Hz].
        cycles: number of cycles (whole or not).
        frequency: cycle frequency f in [Hz] (1 Hz in the standard).

    Returns:
        The trajectory sampled at t = k/rate for k = 0 … N−1 with N = cycles·rate/f,
        the end of the last cycle left out so that whole cycles tile.
    """
    n, whole = iso14242_samples(rate, cycles, frequency, MAX_SAMPLES)
    t = np.arange(n) / rate
    q, qd, qdd = iso14242_angles(t, frequency)
    return Trajectory(t, q, qd, qdd, iso14242_load(t, frequency), name="ISO 14242-1", periodic=whole)


def iso14242_samples(
    rate: float, cycles: float, frequency: float, limit: int, why: str = "fit in memory"
) -> tuple[int, bool]:
    """How many samples ``cycles`` built-in cycles of ``frequency`` [Hz] at ``rate`` [Hz] have, and whether they are whole cycles.

    Raises:
        TrajectoryError: a value that is not a positive number, fewer than 2 samples, or more than ``limit``.
    """
    for name, value in (("rate", rate), ("cycles", cycles), ("frequency", frequency)):
        if isinstance(value, bool) or not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
            raise TrajectoryError(f"{name} must be a positive number, got {value!r}", source="ISO 14242-1")
    n = int(round(cycles * rate / frequency))
    if n < 2:
        raise TrajectoryError(
            f"{cycles} cycle(s) of {frequency} Hz sampled at {rate} Hz give fewer than 2 samples", source="ISO 14242-1"
        )
    if n > limit:
        raise TrajectoryError(
            f"{cycles} cycle(s) at {rate} Hz gives {n:,} samples; at most {limit:,} {why}", source="ISO 14242-1"
        )
    return n, abs(cycles - round(cycles)) < 1e-12 and abs(n - cycles * rate / frequency) < 1e-9


def iso14242_at(t: ArrayLike, frequency: float = 1.0) -> Trajectory:
    """The built-in cycle evaluated at any times t in [s] (exact, like :func:`iso14242`)."""
    t = np.atleast_1d(np.asarray(t, dtype=float))
    q, qd, qdd = iso14242_angles(t, frequency)
    return Trajectory(t, q, qd, qdd, iso14242_load(t, frequency), name="ISO 14242-1", periodic=False)


def interpolator(trajectory: Trajectory):
    """A function of time giving the trajectory between (and, if periodic, beyond) its samples.

    Angles through a quintic spline of the samples (periodic if the trajectory
    is), so velocity and acceleration stay smooth; the load linearly.

    Args:
        trajectory: the sampled trajectory.

    Returns:
        ``at(times)`` returning a :class:`Trajectory` at the times in [s].

    Raises:
        TrajectoryError: (from ``at``) for times outside a non-periodic trajectory.
    """
    t, q, load = trajectory.t, trajectory.q, trajectory.Fe
    if t.size < MIN_SAMPLES:
        raise TrajectoryError(
            f"{t.size} samples; at least {MIN_SAMPLES} are needed to interpolate", source=trajectory.name
        )
    if trajectory.periodic:
        dt = (t[-1] - t[0]) / (t.size - 1)
        period = t[-1] - t[0] + dt
        t, q, load = np.append(t, t[0] + period), np.vstack([q, q[:1]]), np.append(load, load[0])
    spline = make_interp_spline(t, q, k=5, bc_type="periodic" if trajectory.periodic else None, axis=0)

    def at(times) -> Trajectory:
        times = np.atleast_1d(np.asarray(times, dtype=float))
        if trajectory.periodic:
            local = t[0] + np.mod(times - t[0], period)
        else:
            if times.min() < t[0] - 1e-12 or times.max() > t[-1] + 1e-12:
                raise TrajectoryError(
                    f"times {times.min():g} to {times.max():g} s reach outside the trajectory ({t[0]:g} to {t[-1]:g} s)",
                    source=trajectory.name,
                )
            local = np.clip(times, t[0], t[-1])
        return Trajectory(
            times, spline(local), spline(local, 1), spline(local, 2), np.interp(local, t, load), trajectory.name
        )

    return at


def trajectory_arrays(traj) -> tuple[np.ndarray, ...]:
    """t (N,) in [s], q, qd, qdd (N, 3) in [rad], [rad/s], [rad/s²] of a Trajectory-like object, checked (any object with those attributes)."""
    try:
        t = np.asarray(traj.t, dtype=float)
        angles = [np.asarray(getattr(traj, name), dtype=float) for name in ("q", "qd", "qdd")]
    except AttributeError as error:
        raise TrajectoryError(f"expected a trajectory with t, q, qd, qdd ({error})") from None
    if t.ndim != 1 or len(t) == 0:
        raise TrajectoryError(f"t must be a non-empty 1-D array, got shape {t.shape}")
    for name, value in zip(("q", "qd", "qdd"), angles):
        if value.shape != (len(t), 3):
            raise TrajectoryError(f"{name} must have shape ({len(t)}, 3), got {value.shape}", column=name)
    if len(t) > 1 and np.any(np.diff(t) <= 0):
        raise TrajectoryError("t must increase strictly", column="t")
    return (t, *angles)
