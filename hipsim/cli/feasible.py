"""``hipsim feasible``: is a protocol within the machine? Every limit crossed, and the speed at which it would fit.

Also the feasibility check every run makes (``torques``, ``check``, ``report``,
``simulate``, ``view``): :func:`add_strict_option`, :func:`check_run` and, for
a run streamed in pieces, :class:`FeasibilityWatch`. The limits are the
parameter file's ``[motor]`` table's, or a drive file's where the command
takes one (:meth:`hipsim.design.feasibility.Limits.from_machine`), with the
singularity measure's floor and the load's range.
"""

from __future__ import annotations

import argparse
import sys

from ..physics.units import RPM_PER_RAD_S as _RPM
from ..present.tables import format_table
from .common import add_machine_options, add_summary_format, parameters, print_json
from .motion_options import add_trajectory_options, cycle_period, load_trajectory

__all__ = ["FeasibilityWatch", "add_parser", "add_strict_option", "check_run", "limits", "report_crossings", "run"]

#: (what a table calls the limit, unit, factor from SI) by Crossing.limit.
_SHOWN = {
    "stroke": ("stroke", "mm", 1e3),
    "slider_speed": ("slider speed", "mm/s", 1e3),
    "slider_acceleration": ("slider acceleration", "mm/s²", 1e3),
    "motor_speed": ("motor speed", "rpm", _RPM),
    "motor_torque": ("motor torque", "N·mm", 1e3),
    "cond_inv": ("singularity measure (floor)", "", 1.0),
    "load_max": ("load (highest)", "N", 1.0),
    "load_min": ("load (lowest)", "N", 1.0),
}


def add_strict_option(parser: argparse.ArgumentParser) -> None:
    """``--strict``: a crossed machine limit is an error (exit status 1) instead of a warning."""
    parser.add_argument(
        "--strict",
        action="store_true",
        help="a machine limit the motion crosses (stroke, slider speed and acceleration, motor speed and torque from the "
        "[motor] table, singularity floor, load range) is an error with exit status 1 instead of a warning",
    )


def limits(params, drive=None):
    """The machine's limits (:meth:`hipsim.design.feasibility.Limits.from_machine`)."""
    from ..design.feasibility import Limits

    return Limits.from_machine(params, drive)


def check_run(run, params, drive=None) -> list:
    """The crossings of a model run (in memory) against the machine's limits."""
    from ..design.feasibility import check_feasibility

    return check_feasibility(run, limits(params, drive))


def report_crossings(crossings, strict: bool) -> int:
    """Print the warning block (standard error) naming each crossing; 1 with ``strict`` when any, else 0."""
    if not crossings:
        return 0
    kind = "error" if strict else "warning"
    print(
        f"hipsim: {kind}: the motion crosses {len(crossings)} of the machine's limits (hipsim feasible: the speed at which it fits):",
        file=sys.stderr,
    )
    for crossing in crossings:
        print(f"  {crossing.message()}", file=sys.stderr)
    return 1 if strict else 0


class FeasibilityWatch:
    """The feasibility check of a run streamed in pieces (:func:`hipsim.analysis.streaming.stream_run`'s ``write``).

    Each piece's columns are checked as they pass; the crossings are merged
    (first time, worst value). The stroke needs the whole run's extremes: it
    is crossed at the first time the slider's travel so far exceeds it.

    Args:
        limits: the machine's limits.
    """

    def __init__(self, limits):
        from dataclasses import replace

        self.limits, self.stroke = replace(limits, stroke=None), limits.stroke
        self.found: dict = {}
        self.low = self.high = None
        self.stroke_t: list = [None, None, None]

    def add(self, columns) -> None:
        """Check one piece's :meth:`hipsim.results.Run.columns`."""
        from types import SimpleNamespace

        import numpy as np

        from ..design.feasibility import Crossing, check_feasibility
        from ..plausibility import beyond

        keep = columns["flagged"] == 0 if "flagged" in columns else slice(None)
        t = np.asarray(columns["t_s"])[keep]
        if t.size == 0:
            return

        def motion(name, unit):
            return np.stack([np.asarray(columns[f"{name}_1{i}_{unit}"])[keep] * 1e-3 for i in (1, 2, 3)], axis=1)[
                :, None, :
            ]

        speed = np.stack([np.asarray(columns[f"speed_{i}_rpm"])[keep] / _RPM for i in (1, 2, 3)], axis=1)
        total = np.stack([np.asarray(columns[f"tau_{i}_Nmm"])[keep] * 1e-3 for i in (1, 2, 3)], axis=1)
        run = SimpleNamespace(
            t=t,
            L=motion("L", "mm"),
            Ld=motion("Ld", "mm_s"),
            Ldd=motion("Ldd", "mm_s2"),
            torques=SimpleNamespace(motor_speed=speed, total=total),
            cond_inv=np.asarray(columns["cond_inv"])[keep],
            trajectory=SimpleNamespace(Fe=np.asarray(columns["Fe_N"])[keep]),
        )
        for crossing in check_feasibility(run, self.limits):  # type: ignore[arg-type]  # a Run's columns, duck-typed
            key = (crossing.limit, crossing.motor)
            seen = self.found.get(key)
            if seen is None:
                self.found[key] = crossing
            else:
                worst = crossing if crossing.excess > seen.excess else seen
                self.found[key] = Crossing(
                    crossing.limit, crossing.motor, min(seen.t, crossing.t), worst.needed, worst.allowed
                )
        if self.stroke is not None:
            L = run.L[:, 0, :]
            low = np.minimum.accumulate(np.vstack([L[:1] if self.low is None else self.low, L]), axis=0)[1:]
            high = np.maximum.accumulate(np.vstack([L[:1] if self.high is None else self.high, L]), axis=0)[1:]
            for i in range(3):
                over = beyond(high[:, i] - low[:, i], self.stroke)
                if self.stroke_t[i] is None and over.any():
                    self.stroke_t[i] = float(t[np.argmax(over)])
            self.low, self.high = low[-1:], high[-1:]

    def crossings(self) -> list:
        """Every limit crossed, the one missed most first (as :func:`hipsim.design.feasibility.check_feasibility`)."""
        from ..design.feasibility import Crossing

        found = list(self.found.values())
        for i, first in enumerate(self.stroke_t):
            if first is not None and self.high is not None and self.low is not None:  # set with the first crossing
                found.append(Crossing("stroke", i + 1, first, float(self.high[0, i] - self.low[0, i]), self.stroke))
        return sorted(found, key=lambda c: -c.excess)


def add_parser(subparsers) -> argparse.ArgumentParser:
    """Register ``feasible`` on the main parser's subcommands."""
    feasible = subparsers.add_parser(
        "feasible",
        help="is the protocol within the machine's limits? each limit crossed, and the speed at which it fits",
        description="Runs the analytic model along the motion and holds it against the machine's limits: slider stroke, "
        "speed and acceleration, motor speed and peak torque (the parameter file's [motor] table or --drive), the "
        "singularity measure's floor and the load's range. Prints each limit crossed (first time, worst value, by how much) "
        "and the largest fraction of its speed at which the protocol fits. Exits with status 1 when a limit is crossed.",
    )
    add_machine_options(feasible)
    add_trajectory_options(feasible)
    feasible.add_argument(
        "--drive",
        metavar="FILE",
        help="drive file (TOML, see hipsim size) whose motor and screw limits apply "
        "(default: the parameter file's [motor] table)",
    )
    add_summary_format(feasible)
    feasible.set_defaults(run=run)
    return feasible


def _cell(value: float, limit: str) -> str:
    _, unit, factor = _SHOWN[limit]
    return f"{value * factor:,.4g}" + (f" {unit}" if unit else "")


def format_crossings(crossings) -> str:
    """The crossings as a table: limit, motor, first time, needed, allowed, excess."""
    rows = [
        [
            _SHOWN[c.limit][0],
            "—" if c.motor is None else f"M{c.motor}",
            f"{c.t:.4g}",
            _cell(c.needed, c.limit),
            _cell(c.allowed, c.limit),
            f"{c.excess:.3g}×",
        ]
        for c in crossings
    ]
    return format_table(
        ["limit", "motor", "first at [s]", "needed", "allowed", "excess"], rows, "Machine limits crossed (worst first)"
    )


def run(args) -> int:
    """Print the limits crossed and the speed at which the protocol fits; status 1 when any is crossed."""
    from ..analysis.runs import analyse
    from ..design.feasibility import check_feasibility, fitting_speed
    from ..design.feasibility_summary import feasibility_summary
    from ..machine.drive import load_drive
    from ..records import exit_status

    params = parameters(args)
    trajectory = load_trajectory(args)
    drive = load_drive(args.drive) if args.drive else None
    machine = limits(params, drive)
    crossings = check_feasibility(analyse(params, trajectory), machine)
    k = fitting_speed(lambda motion: analyse(params, motion), trajectory, machine) if crossings else 1.0
    period = cycle_period(args, trajectory)
    noisy = noise_flagged(args)
    summary = feasibility_summary(
        trajectory.name, params.source, machine, crossings, k, period, drive is not None, noisy
    )
    if args.summary_format == "json":
        print_json(summary.to_json())
    else:
        print(f"trajectory: {trajectory.name} ({len(trajectory)} samples); parameters: {params.source}")
        if crossings:
            print(format_crossings(crossings))
        print(summary.verdict)
        if crossings:
            print(_suggestion(k, period) + (" (by the noisy motion's accelerations)" if noisy else ""))
    return exit_status([summary])


def noise_flagged(args) -> bool:
    """True when reading the motion gave a noise warning (:class:`hipsim.motion.build.NoiseWarning`)."""
    from ..motion.build import NoiseWarning

    return any(issubclass(category, NoiseWarning) for category, _ in getattr(args, "trajectory_warnings", ()))


def _suggestion(k: float | None, period: float | None) -> str:
    if k is None:
        return "does not fit at any speed: a limit that does not depend on speed (stroke, singularity measure, load) is crossed"
    frequency = f" (cycle frequency {k / period:.3g} Hz)" if period else ""
    return f"fits at up to {k:.3g}× its speed{frequency}"
