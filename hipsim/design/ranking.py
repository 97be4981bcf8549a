"""Choosing a drive from catalogues: every motor × gearbox × screw combination checked along every cycle and ranked by its smallest margin."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Callable, Sequence

from ..analysis.runs import analyse
from ..machine.drive_parts import Drive, Gearbox, LeadScrew, Motor, SizingRules
from ..machine.parameters import Parameters
from ..motion.trajectories import Trajectory
from .checks import Check, binding_check, drive_checks
from .demand import screw_side

__all__ = ["Candidate", "rank_drives"]


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
    def unchecked(self) -> tuple[str, ...]:
        """The checks not made for want of data, each named once."""
        return tuple(dict.fromkeys(c.name for c in self.checks if c.passed is None))

    def as_dict(self) -> dict[str, Any]:
        binding = self.binding
        return {
            "drive": self.drive.name,
            "motor": self.drive.motor.name,
            "gearbox": None if self.drive.gearbox is None else self.drive.gearbox.name,
            "screw": None if self.drive.screw is None else self.drive.screw.name,
            "passed": self.passed,
            "margin": self.margin,
            "binding": None if binding is None else binding.as_dict(),
            "unchecked": list(self.unchecked),
            "checks": [c.as_dict() for c in self.checks],
        }


def rank_drives(
    params: Parameters,
    trajectories: Sequence[tuple[Trajectory, float]],
    motors: Sequence[tuple[Motor, Any]],
    screws: Sequence[LeadScrew] | None = None,
    gearboxes: Sequence[Gearbox] | None = None,
    rules: SizingRules | None = None,
    progress: Callable[[str], None] | None = None,
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

    Returns:
        The candidates sorted by their smallest margin, largest first (every
        candidate that passes comes before every one that fails), ties broken
        by the next-smallest margin; candidates with no check made come last.
    """
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
                progress(f"{trajectory.name}, lead {machine.lead * 1e3:g} mm" + (f" ({screw.name})" if screw is not None else ""))
            sides.append(screw_side(analyse(machine, trajectory), cycles))
        for motor, amplifier in motors:
            for gearbox in gearboxes if gearboxes is not None else [None]:
                drive = Drive(motor, amplifier, gearbox, screw, rules, source="catalogue")
                checks = tuple(c for side in sides for c in drive_checks(side, drive, rules))
                candidates.append(Candidate(drive, checks))
    def order(candidate: Candidate):
        # Largest smallest margin first; ties broken by the next-smallest margins, and so on.
        margins = sorted(c.margin for c in candidate.checks if c.margin is not None)
        return (not margins, [-m for m in margins])

    return sorted(candidates, key=order)
