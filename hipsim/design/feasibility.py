"""Is a protocol within the machine? Every limit a run crosses, when it first does and by how much.

A run (any model's :class:`~hipsim.results.Run`) is held against the
machine's :class:`Limits`: the usable stroke of the linear modules, the
slider speed and acceleration, the motor speed and peak torque (from the
parameter file's ``[motor]`` table or a drive file, :meth:`Limits.from_machine`),
the singularity measure's floor and the load's range. A limit with no figure
is not checked. Each crossing is a :class:`Crossing`: which limit, on which
motor, the first time it happens, the worst value needed and the limit; they
come ordered by how far the worst one goes beyond its limit, so the limit a
protocol misses most is named first.

Speeds, accelerations and torques fall when the protocol runs slower;
strokes, the singularity measure and the load do not. :func:`fitting_speed`
finds the largest time scale k ≤ 1 (the protocol at k times its speed,
k times its cycle frequency) at which nothing is crossed, by bisection on
reruns of the model.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..motion.trajectories import Trajectory
from ..physics.units import RAD_S_PER_RPM, RPM_PER_RAD_S
from ..plausibility import below, beyond
from ..results import Run

__all__ = [
    "CHECKED_LIMITS",
    "Crossing",
    "Limits",
    "DEFAULT_COND_INV_FLOOR",
    "DEFAULT_LOAD_RANGE",
    "check_feasibility",
    "fitting_speed",
    "time_scaled",
]

#: Below this inverse condition number of J a pose is too close to a singularity to run (forces amplified 20×).
DEFAULT_COND_INV_FLOOR = 0.05

#: The hydraulic load's range in [N] (spec §1: up to 3000 N; it only pushes).
DEFAULT_LOAD_RANGE = (0.0, 3000.0)

# (limit, what the message calls it, unit shown, factor from SI to that unit, True if the limit is a floor)
_LIMITS = {
    "stroke": ("stroke", "mm", 1e3, False),
    "slider_speed": ("slider speed", "mm/s", 1e3, False),
    "slider_acceleration": ("slider acceleration", "mm/s²", 1e3, False),
    "motor_speed": ("speed", "rpm", RPM_PER_RAD_S, False),
    "motor_torque": ("torque", "N·mm", 1e3, False),
    "cond_inv": ("singularity measure", "", 1.0, True),
    "load_max": ("load", "N", 1.0, False),
    "load_min": ("load", "N", 1.0, True),
}

#: The limits a verdict may cover, in the order it names them: (field of :class:`Limits`, name in words).
#: The slider's speed and acceleration are not among them: the motor's speed (through the lead) and torque cover them,
#: and no file gives them; set as overrides, they are checked and named.
CHECKED_LIMITS = (
    ("stroke", "stroke"),
    ("motor_speed", "motor speed"),
    ("motor_torque", "motor torque"),
    ("cond_inv_floor", "singularity measure"),
    ("load_range", "load range"),
)
_EXTRA_LIMITS = (("slider_speed", "slider speed"), ("slider_acceleration", "slider acceleration"))

#: Limits that do not change when the protocol runs slower.
_POSITION_LIMITS = ("stroke", "cond_inv", "load_max", "load_min")


@dataclass(frozen=True)
class Limits:
    """The machine's limits, SI; None for a figure not known (not checked).

    Attributes:
        stroke: usable stroke of a linear module in [m].
        slider_speed: highest slider speed in [m/s].
        slider_acceleration: highest slider acceleration in [m/s²].
        motor_speed: highest motor speed in [rad/s].
        motor_torque: the peak motor torque in [N·m] at a motor speed in [rad/s]
            (a function of the speeds' absolute values, for a torque–speed curve), or a number.
        cond_inv_floor: lowest inverse condition number of J allowed.
        load_range: (lowest, highest) load in [N].
    """

    stroke: float | None = None
    slider_speed: float | None = None
    slider_acceleration: float | None = None
    motor_speed: float | None = None
    motor_torque: float | Callable[[np.ndarray], np.ndarray] | None = None
    cond_inv_floor: float = DEFAULT_COND_INV_FLOOR
    load_range: tuple[float, float] = DEFAULT_LOAD_RANGE

    def unchecked(self) -> list[str]:
        """The limits with no figure, in words (:data:`CHECKED_LIMITS` order): a verdict does not cover them."""
        return [name for field, name in CHECKED_LIMITS if getattr(self, field) is None]

    def checked(self) -> list[str]:
        """The limits with a figure, in words: what a verdict covers."""
        return [name for field, name in CHECKED_LIMITS + _EXTRA_LIMITS if getattr(self, field) is not None]

    @classmethod
    def from_machine(cls, params, drive=None, **overrides) -> Limits:
        """The limits a parameter set's ``[motor]`` table and a drive (:class:`hipsim.machine.drive.Drive`) give.

        The drive's figures win over the parameter file's: its motor's top speed
        and peak torque–speed curve, its lead screw's stroke.

        Args:
            params: the machine (:class:`~hipsim.machine.parameters.Parameters`).
            drive: a drive, or None.
            overrides: any field of :class:`Limits` to set outright.
        """
        motor = params.motor
        values: dict[str, Any] = {  # keyword arguments of several field types
            "stroke": motor["stroke_mm"] * 1e-3 if "stroke_mm" in motor else None,
            "motor_speed": motor["max_speed_rpm"] * RAD_S_PER_RPM if "max_speed_rpm" in motor else None,
            "motor_torque": motor["peak_torque_Nmm"] * 1e-3 if "peak_torque_Nmm" in motor else None,
        }
        if drive is not None:
            if drive.motor.top_speed is not None and math.isfinite(drive.motor.top_speed):
                values["motor_speed"] = drive.motor.top_speed
            if drive.motor.peak is not None:
                values["motor_torque"] = drive.motor.peak.at
            if drive.screw is not None and drive.screw.stroke is not None:
                values["stroke"] = drive.screw.stroke
        return cls(**(values | overrides))


@dataclass(frozen=True)
class Crossing:
    """One limit crossed along a run.

    Attributes:
        limit: the limit's key (stroke, slider_speed, slider_acceleration, motor_speed, motor_torque, cond_inv, load_max, load_min).
        motor: the linear module 1–3, or None for a limit of the whole machine.
        t: when it is first crossed, in [s].
        needed: the worst value the run needs, SI.
        allowed: the limit, SI (for a speed-dependent torque, at the worst sample's speed).
    """

    limit: str
    motor: int | None
    t: float
    needed: float
    allowed: float

    @property
    def excess(self) -> float:
        """How far beyond the limit, as a ratio ≥ 1 (needed/allowed, or allowed/needed for a floor)."""
        floor = _LIMITS[self.limit][3]
        a, b = (self.allowed, self.needed) if floor else (self.needed, self.allowed)
        return a / b if b > 0 else math.inf

    def message(self) -> str:
        """One line, e.g. "motor 2 needs 12,339 rpm at t = 0.412 s; its top is 6,000 rpm"."""
        name, unit, factor, floor = _LIMITS[self.limit]
        who = f"motor {self.motor}" if self.motor is not None else "the run"
        needed, allowed = self.needed * factor, self.allowed * factor
        unit = f" {unit}" if unit else ""
        bound = "lowest allowed" if floor else "limit"
        if self.excess < 1.0005:  # 4 digits would show the same number twice and "1×": show the digits that differ
            return (
                f"{who} needs a {name} of {needed:,.10g}{unit} at t = {self.t:.4g} s; the {bound} is {allowed:,.10g}{unit} "
                f"({self.excess - 1.0:.2g} beyond it, relative)"
            )
        return f"{who} needs a {name} of {needed:,.4g}{unit} at t = {self.t:.4g} s; the {bound} is {allowed:,.4g}{unit} ({self.excess:.3g}×)"


def _first(t: np.ndarray, over: np.ndarray) -> float:
    return float(t[np.argmax(over)])


def _ceiling(crossings, limit, t, values, allowed, motor=None):
    """Add a crossing where |values| exceed ``allowed`` (a number or an array per sample)."""
    allowed = np.broadcast_to(np.asarray(allowed, dtype=float), values.shape)
    over = beyond(np.abs(values), allowed)  # at the limit within rounding is not beyond it
    if over.any():
        worst = int(np.argmax(np.where(over, np.abs(values) / np.maximum(allowed, 1e-300), -np.inf)))
        crossings.append(Crossing(limit, motor, _first(t, over), float(abs(values[worst])), float(allowed[worst])))


def check_feasibility(run: Run, limits: Limits) -> list[Crossing]:
    """Every limit ``run`` crosses, the one it misses most first.

    Args:
        run: a model run along the protocol.
        limits: the machine's limits.

    Returns:
        The crossings, ordered by :attr:`Crossing.excess`, largest first; empty if the run fits.
    """
    t = run.t
    crossings: list[Crossing] = []
    L, Ld, Ldd = run.L[:, 0, :], run.Ld[:, 0, :], run.Ldd[:, 0, :]  # platform 2's sliders ride the same carriage
    speed = run.torques.motor_speed
    for i in range(3):
        if limits.stroke is not None:
            travel = L[:, i] - L[:, i].min()
            over = beyond(travel, limits.stroke)
            if over.any():
                crossings.append(Crossing("stroke", i + 1, _first(t, over), float(np.ptp(L[:, i])), limits.stroke))
        if limits.slider_speed is not None:
            _ceiling(crossings, "slider_speed", t, Ld[:, i], limits.slider_speed, i + 1)
        if limits.slider_acceleration is not None:
            _ceiling(crossings, "slider_acceleration", t, Ldd[:, i], limits.slider_acceleration, i + 1)
        if limits.motor_speed is not None:
            _ceiling(crossings, "motor_speed", t, speed[:, i], limits.motor_speed, i + 1)
        if limits.motor_torque is not None:
            torque = limits.motor_torque
            tau = run.torques.total[:, i]
            if callable(torque):
                allowed = np.asarray(torque(np.abs(speed[:, i])), dtype=float)
                # Beyond its curve's end the motor has no torque to give: that is the speed's crossing, reported as
                # such; the torque is checked where the curve says what the motor gives.
                on_curve = allowed > 0
                _ceiling(crossings, "motor_torque", t[on_curve], tau[on_curve], allowed[on_curve], i + 1)
            else:
                _ceiling(crossings, "motor_torque", t, tau, torque, i + 1)
    under = below(run.cond_inv, limits.cond_inv_floor)
    if under.any():
        crossings.append(
            Crossing("cond_inv", None, _first(t, under), float(np.nanmin(run.cond_inv)), limits.cond_inv_floor)
        )
    low, high = limits.load_range
    Fe = run.trajectory.Fe
    over, under = beyond(Fe, high), below(Fe, low)
    if over.any():
        crossings.append(Crossing("load_max", None, _first(t, over), float(Fe.max()), high))
    if under.any():
        crossings.append(Crossing("load_min", None, _first(t, under), float(Fe.min()), low))
    return sorted(crossings, key=lambda c: -c.excess)


def time_scaled(trajectory: Trajectory, k: float) -> Trajectory:
    """The same motion and load at k times the speed: t/k, q̇·k, q̈·k²; k > 0."""
    return Trajectory(
        trajectory.t / k,
        trajectory.q,
        trajectory.qd * k,
        trajectory.qdd * k * k,
        trajectory.Fe,
        f"{trajectory.name} at {k:.4g}× speed",
        trajectory.periodic,
        trajectory.lines,
    )


def fitting_speed(
    run_at: Callable[[Trajectory], Run], trajectory: Trajectory, limits: Limits, tolerance: float = 1e-3
) -> float | None:
    """The largest speed factor k in (0, 1] at which the protocol crosses no limit.

    Args:
        run_at: runs the model along a trajectory (e.g. ``lambda tr: analyse(params, tr)``).
        trajectory: the protocol at its own speed.
        limits: the machine's limits.
        tolerance: relative precision of k.

    Returns:
        k (1.0 when it fits as it is), or None when a limit that does not
        depend on speed (stroke, singularity measure, load) is crossed, or
        nothing fits even at 1/1000 of the speed.
    """
    crossings = check_feasibility(run_at(trajectory), limits)
    if not crossings:
        return 1.0
    if any(c.limit in _POSITION_LIMITS for c in crossings):
        return None
    fits = lambda k: not check_feasibility(run_at(time_scaled(trajectory, k)), limits)  # noqa: E731
    low, high = 1e-3, 1.0
    if not fits(low):
        return None
    while high - low > tolerance * high:
        mid = math.sqrt(low * high)
        low, high = (mid, high) if fits(mid) else (low, mid)
    return low
