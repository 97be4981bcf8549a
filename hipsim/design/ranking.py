"""Choosing a drive from catalogues: every motor × gearbox × screw combination checked along every cycle, the smallest that passes first.

A drive engineer picks the smallest motor that does the job: among the
combinations that pass every check, :func:`rank_drives` puts first the one
with the smallest rated power (:func:`rated_power`: the catalogue's, or the
S1 curve's rated point), then the smallest rotor inertia, then the lowest
cost (a catalogue ``cost`` column), then the largest margin of the checks
that depend on the motor. The failing combinations follow in the same order,
each with the check that fails first (:func:`~hipsim.design.checks.first_failure`).
The screw's checks (:data:`~hipsim.design.checks.MOTOR_INDEPENDENT`) are the
same for every motor on one screw: :func:`screw_checks` gives them once per
screw, and they never break a tie. ``order="margin"`` ranks by the smallest
margin of all checks instead, largest first, as before.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

from ..analysis.runs import analyse
from ..machine.drive_parts import Drive, Gearbox, LeadScrew, Motor, SizingRules
from ..machine.parameters import Parameters
from ..motion.trajectories import Trajectory
from ..physics.units import RPM_PER_RAD_S
from .checks import MOTOR_INDEPENDENT, Check, binding_check, drive_checks, first_failure
from .demand import screw_side

__all__ = ["ORDERS", "Candidate", "rank_drives", "rated_power", "screw_checks"]

#: The orders :func:`rank_drives` knows: the smallest passing drive first, or the largest smallest margin first.
ORDERS = ("size", "margin")


def rated_power(motor: Motor) -> tuple[float | None, str]:
    """The motor's rated power in [W] and where it comes from.

    The catalogue's ``rated_power_W`` when given; else rated torque × rated
    speed at the S1 curve's rated point: the last point that still gives the
    stall torque (the corner of a servo's S1 curve, where the data sheets rate
    it), or, for a curve that falls from standstill, the point of most power;
    a flat S1 curve is rated at the top speed.

    Returns:
        (power in [W], source in words); (None, why) when neither is known.
    """
    if motor.rated_power is not None:
        return motor.rated_power, "catalogue"
    curve = motor.continuous
    if curve is None:
        return None, "unknown: no rated power and no S1 curve"
    if curve.flat:
        speed = motor.top_speed
        if speed is None:
            return None, "unknown: a flat S1 curve and no top speed"
        torque = float(curve.torque[0])
    else:
        corner = [k for k in range(len(curve.speed)) if curve.torque[k] >= curve.torque[0] and curve.speed[k] > 0]
        k = corner[-1] if corner else int(max(range(len(curve.speed)), key=lambda j: curve.torque[j] * curve.speed[j]))
        torque, speed = float(curve.torque[k]), float(curve.speed[k])
    return torque * speed, f"S1 curve: {torque:g} N·m × {speed * RPM_PER_RAD_S:.0f} rpm"


@dataclass(frozen=True, eq=False)
class Candidate:
    """One motor × gearbox × screw combination checked along every cycle.

    Attributes:
        drive: the combination.
        checks: every check, of every module along every trajectory.
    """

    drive: Drive
    checks: tuple[Check, ...]

    @property
    def margin(self) -> float | None:
        """The smallest margin of any check made; None if none was made."""
        binding = self.binding
        return None if binding is None else binding.margin

    @property
    def binding(self) -> Check | None:
        """The check with the smallest margin: the binding constraint."""
        return binding_check(self.checks)

    @property
    def passed(self) -> bool | None:
        made = [c.passed for c in self.checks if c.passed is not None]
        return None if not made else all(made)

    @property
    def motor_binding(self) -> Check | None:
        """The binding check among those that depend on the motor (not the screw's: :func:`screw_checks`)."""
        return binding_check(c for c in self.checks if c.name not in MOTOR_INDEPENDENT)

    @property
    def failure(self) -> Check | None:
        """The failing check that says most plainly why (:func:`~hipsim.design.checks.first_failure`); None when none fails."""
        return first_failure(self.checks)

    @property
    def rated_power(self) -> tuple[float | None, str]:
        """The motor's rated power in [W] and its source (:func:`rated_power`)."""
        return rated_power(self.drive.motor)

    @property
    def unchecked(self) -> tuple[str, ...]:
        """The checks not made for want of data, each named once."""
        return tuple(dict.fromkeys(c.name for c in self.checks if c.passed is None))


def rank_drives(
    params: Parameters,
    trajectories: Sequence[tuple[Trajectory, float]],
    motors: Sequence[tuple[Motor, Any]],
    screws: Sequence[LeadScrew] | None = None,
    gearboxes: Sequence[Gearbox] | None = None,
    rules: SizingRules | None = None,
    progress: Callable[[str], None] | None = None,
    order: str = "size",
) -> list[Candidate]:
    """Every motor × gearbox × screw combination checked along every trajectory, best first.

    For each screw the model runs again with its lead and inertia
    (``params.replace(lead=…, screw_inertia=…)``): the lead changes the motor
    speeds, torques and the reflected inertia, so nothing is rescaled.

    Args:
        params: the machine.
        trajectories: (trajectory, test cycles it holds) pairs, e.g. the ISO cycle and measured gaits.
        motors: (motor, amplifier or None) pairs (:func:`hipsim.machine.drive.load_motor_catalogue`).
        screws: lead screws; None for the machine's own screw (no screw checks).
        gearboxes: gearboxes; None for a direct coupling.
        rules: the rules (default :class:`SizingRules`).
        progress: called with a line of text before each model run.
        order: "size" (the smallest passing drive first) or "margin" (the largest smallest margin first).

    Returns:
        With ``order="size"``: the candidates that pass every check, then those
        that fail one, then those with no check made; within each, by rated
        power, rotor inertia and cost, smallest first (unknown last), then by
        the smallest margin of the checks that depend on the motor, largest
        first (a failing one: the margin of its first failing check). With ``order="margin"``: by their smallest margin, largest first
        (every candidate that passes comes before every one that fails), ties
        broken by the next-smallest margin; candidates with no check made last.
    """
    if order not in ORDERS:
        raise ValueError(f"order: expected one of {', '.join(ORDERS)}, got {order!r}")
    rules = rules if rules is not None else SizingRules()
    candidates = []
    for screw in screws if screws is not None else [None]:
        machine = params
        if screw is not None:
            changes = {"lead": screw.lead, "screw_inertia": screw.inertia}
            machine = params.replace(**{k: v for k, v in changes.items() if v is not None})
        sides = []
        for trajectory, cycles in trajectories:
            if progress is not None:
                progress(
                    f"{trajectory.name}, lead {machine.lead * 1e3:g} mm"
                    + (f" ({screw.name})" if screw is not None else "")
                )
            sides.append(screw_side(analyse(machine, trajectory), cycles))
        for motor, amplifier in motors:
            for gearbox in gearboxes if gearboxes is not None else [None]:
                drive = Drive(motor, amplifier, gearbox, screw, rules, source="catalogue")
                checks = tuple(c for side in sides for c in drive_checks(side, drive, rules))
                candidates.append(Candidate(drive, checks))
    return sorted(candidates, key=_by_size if order == "size" else _by_margin)


def _by_margin(candidate: Candidate):
    # Largest smallest margin first; ties broken by the next-smallest margins, and so on.
    margins = sorted(c.margin for c in candidate.checks if c.margin is not None)
    return (not margins, [-m for m in margins])


def _by_size(candidate: Candidate):
    passed = candidate.passed
    group = 0 if passed is True else (1 if passed is False else 2)
    motor = candidate.drive.motor
    # A passing drive with more headroom on its motor's checks first; a failing one nearest to passing its first failing check first.
    decisive = candidate.motor_binding if passed else candidate.failure
    known = [rated_power(motor)[0], motor.rotor_inertia, motor.cost]
    return (
        group,
        *(math.inf if v is None else v for v in known),
        math.inf if decisive is None or decisive.margin is None else -decisive.margin,
    )


def screw_checks(candidates: Sequence[Candidate]) -> list[tuple[LeadScrew | None, tuple[Check, ...]]]:
    """The checks that do not depend on the motor (:data:`~hipsim.design.checks.MOTOR_INDEPENDENT`), once per screw.

    They compare the screw (or the machine's own, None) with the machine's
    demand, which the motor and gearbox do not change: every candidate on one
    screw has the same. Returns (screw, its checks) in the order the screws
    first appear.
    """
    out: dict[str | None, tuple[LeadScrew | None, tuple[Check, ...]]] = {}
    for candidate in candidates:
        screw = candidate.drive.screw
        key = None if screw is None else screw.name
        if key not in out:
            out[key] = (screw, tuple(c for c in candidate.checks if c.name in MOTOR_INDEPENDENT))
    return list(out.values())
