"""Commands a drive takes: per motor, a position–velocity–time table at the servo rate, with the torque feed-forward.

A carriage command (one period or whole periods, periodic: its last sample
leads into its first, as ``hipsim learn`` and ``hipsim stations`` write it)
becomes, per motor i:

- positions at the servo rate: the command's trigonometric interpolant (its
  samples kept exactly when the rates agree), in carriage mm, motor
  revolutions θ/2π = L/p and encoder counts (revolutions × counts per rev);
- velocities (and accelerations): the interpolant's exact derivatives, so a
  drive's cubic Hermite between the points meets the positions;
- the torque feed-forward: the model's inverse dynamics along the motion the
  command gives the model's controlled platform (its forward kinematics, its
  rates through its Jacobian: :func:`hipsim.analytic.stations.follower_motion`).

Every machine limit (:mod:`hipsim.design.feasibility`: stroke, slider speed
and acceleration, motor speed and torque, singularity floor, load) is
checked on that motion before anything is made: a crossing is refused with
the limit, the time and the value. A command that repeats a period exactly
is computed over one period and repeated.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.signal import resample

from ..analysis.runs import analyse
from ..analytic.stations import follower_motion
from ..arrays import readonly
from ..design.feasibility import Crossing, Limits, check_feasibility
from ..exceptions import ArgumentError, TrajectoryError
from ..machine.parameters import Parameters
from ..motion.trajectories import Trajectory
from .filters import periodic_derivatives

__all__ = ["DriveTables", "command_period", "drive_tables"]

#: Two samples of a command this close in [m] are the same position (a CSV's 12 digits of mm: ~1e-12 m).
SAME_POSITION = 1e-11
#: A command's last sample may jump into its first by this many times its largest step before it is not periodic.
CLOSURE_STEPS = 3.0


@dataclass(frozen=True, eq=False)
class DriveTables:
    """The motors' tables at the servo rate, SI, and what was checked.

    Attributes:
        t: servo instants in [s], (M,).
        L, Ld, Ldd: carriage position [m], velocity [m/s], acceleration [m/s²], (M, 3).
        torque: the motors' torque feed-forward in [N·m], (M, 3).
        rate: the servo rate in [Hz].
        lead: the screw lead p in [m] per motor revolution.
        counts_per_rev: encoder counts per motor revolution.
        checked, not_checked: the limits checked and those without a figure, in words.
        platform: the model's platform whose motion the torques follow.
        period_samples: the samples of one period; the tables repeat it (a command that repeats one period within
            :data:`SAME_POSITION` is written as its first period repeated).
    """

    t: np.ndarray
    L: np.ndarray
    Ld: np.ndarray
    Ldd: np.ndarray
    torque: np.ndarray
    rate: float
    lead: float
    counts_per_rev: float
    checked: tuple[str, ...]
    not_checked: tuple[str, ...]
    platform: int
    period_samples: int

    def __post_init__(self):
        n = np.shape(self.t)[0]
        for name, shape in (("t", (n,)), ("L", (n, 3)), ("Ld", (n, 3)), ("Ldd", (n, 3)), ("torque", (n, 3))):
            value = np.asarray(getattr(self, name), dtype=float)
            if value.shape != shape:
                raise ArgumentError(name, value, f"shape {shape}")
            object.__setattr__(self, name, readonly(value))

    @property
    def revolutions(self) -> np.ndarray:
        """Motor position in revolutions, (M, 3): L/p (the carriage's zero where the motor's is)."""
        return self.L / self.lead

    def motor_columns(self, i: int) -> dict[str, np.ndarray]:
        """Motor i's (1–3) table as named columns with their units."""
        k = i - 1
        rev, rev_s = self.L[:, k] / self.lead, self.Ld[:, k] / self.lead
        return {
            "t_s": self.t,
            "position_counts": rev * self.counts_per_rev,
            "velocity_counts_s": rev_s * self.counts_per_rev,
            "position_rev": rev,
            "velocity_rev_s": rev_s,
            f"torque_ff_{i}_Nmm": self.torque[:, k] * 1e3,
        }


def command_period(L: np.ndarray) -> int:
    """The number of samples of the shortest period a command (N, 3) [m] repeats exactly (N when it does not)."""
    n = len(L)
    candidates = np.flatnonzero(np.all(np.abs(L - L[0]) <= SAME_POSITION, axis=1))
    for p in candidates[1:]:
        if n % p == 0 and np.all(np.abs(L[p:] - L[:-p]) <= SAME_POSITION):
            return int(p)
    return n


def _closure(t: np.ndarray, L: np.ndarray, source: str) -> None:
    steps = np.abs(np.diff(L, axis=0)).max(axis=0)
    jump = np.abs(L[0] - L[-1])
    bad = jump > CLOSURE_STEPS * steps + SAME_POSITION
    if bad.any():
        i = int(np.argmax(bad))
        raise TrajectoryError(
            f"the command is not periodic: carriage {i + 1} jumps {jump[i] * 1e3:.4g} mm from its last sample "
            f"(t = {t[-1]:.6g} s) into its first (its largest step is {steps[i] * 1e3:.4g} mm)",
            source=source,
        )


def drive_tables(
    model: Parameters,
    t: np.ndarray,
    L: np.ndarray,
    load: np.ndarray,
    rate: float,
    counts_per_rev: float,
    limits: Limits,
    guess: np.ndarray | None = None,
    source: str = "commands",
) -> DriveTables:
    """The motors' tables of a periodic carriage command, every limit checked first.

    Args:
        model: the controller's machine (its lead, its dynamics, its controlled platform).
        t: the command's sample times in [s], (N,), evenly spaced.
        L: carriage commands in [m], (N, 3).
        load: the axial load in [N], (N,) (the feed-forward's friction and the load check).
        rate: the servo rate in [Hz]; the command's period must be a whole number of servo periods.
        counts_per_rev: encoder counts per motor revolution, > 0.
        limits: the machine's limits.
        guess: the platform's attitude near each sample in [rad], (N, 3) (the command file's prediction), or None.
        source: the command file's name, for messages.

    Raises:
        TrajectoryError: a command that is not periodic, not finite, or whose period is no whole number of servo
            periods; a limit crossed (naming it, the motor, the time and the value).
        PoseError: a sample the model cannot reach.
    """
    t, L, load = np.asarray(t, dtype=float), np.asarray(L, dtype=float), np.asarray(load, dtype=float)
    n = len(t)
    if n < 4:
        raise TrajectoryError(f"{n} samples: a command needs at least 4", source=source)
    if not counts_per_rev > 0:
        raise ArgumentError("counts_per_rev", counts_per_rev, "a positive number of counts per revolution")
    bad = ~np.all(np.isfinite(L), axis=1)
    if bad.any():
        k = int(np.argmax(bad))
        raise TrajectoryError(f"the command is not a finite number at t = {t[k]:.6g} s", source=source)
    dt = (t[-1] - t[0]) / (n - 1)
    if np.abs(np.diff(t) - dt).max() > 1e-6 * dt:
        raise TrajectoryError("the command's samples are not evenly spaced in time", source=source)
    _closure(t, L, source)
    p = command_period(L)
    repeats = n // p
    period = p * dt
    m = int(round(period * rate))
    if m < 4 or abs(period * rate - m) > 1e-6 * m:
        raise TrajectoryError(
            f"the command's period {period:.6g} s is not a whole number of servo periods at {rate:g} Hz", source=source
        )
    one = L[:p] if m == p else resample(L[:p], m, axis=0)
    Ld, Ldd = periodic_derivatives(one, period)
    ts = t[0] + np.arange(m) / rate
    Fe = load[:p] if m == p else np.interp(ts, t[0] + np.arange(p) * dt, load[:p], period=period)
    if guess is not None and m != p:
        guess = np.stack([np.interp(ts, t[:p], guess[:p, k], period=period) for k in range(3)], axis=1)
    platform = model.geometry.control if model.geometry is not None else 2
    q, qd, qdd = follower_motion(
        model, one, Ld, Ldd, platform, t=ts, source=source, guess=None if guess is None else guess[:m]
    )
    run = analyse(model, Trajectory(ts, q, qd, qdd, Fe, source, periodic=True))
    crossings: list[Crossing] = check_feasibility(run, limits)
    if crossings:
        raise TrajectoryError(f"a limit a drive must not cross: {crossings[0].message()}", source=source)
    torque = run.torques.total
    whole = t[0] + np.arange(m * repeats) / rate
    return DriveTables(
        whole,
        np.tile(one, (repeats, 1)),
        np.tile(Ld, (repeats, 1)),
        np.tile(Ldd, (repeats, 1)),
        np.tile(torque, (repeats, 1)),
        rate,
        model.lead,
        counts_per_rev,
        tuple(limits.checked()),
        tuple(limits.unchecked()),
        platform,
        m,
    )
