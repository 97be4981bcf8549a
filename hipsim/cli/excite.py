"""``hipsim excite``: an excitation trajectory that makes the identification (or, with ``--for calibration``, the
kinematic calibration) well-posed.
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

from ..exceptions import ArgumentError, OutputError
from .common import add_machine_options, add_summary_format, numbers, parameters, print_json

__all__ = ["add_parser", "run"]


def add_parser(subparsers) -> None:
    """Register ``excite``."""
    excite = subparsers.add_parser(
        "excite",
        help="design an excitation trajectory for identification -> trajectory CSV",
        description="A periodic finite Fourier series in the three angles and the load, optimised for the identification "
        "regressor's condition number within the rig's reach, singularity margin, slider speed and acceleration and motor "
        "torque limits. Writes a trajectory CSV every command reads and prints its condition number next to the ISO cycle's.",
    )
    add_machine_options(excite)
    excite.add_argument(
        "--duration", type=float, default=10.0, metavar="S", help="length of the CSV in s, whole periods (default 10)"
    )
    excite.add_argument("--harmonics", type=int, default=5, metavar="N", help="harmonics per series (default 5)")
    excite.add_argument(
        "--frequency", type=float, default=0.5, metavar="HZ", help="base frequency, 1/period (default 0.5)"
    )
    excite.add_argument(
        "--rate", type=float, default=1000.0, metavar="HZ", help="sample rate of the CSV (default 1000)"
    )
    excite.add_argument("--seeds", type=int, default=1, metavar="N", help="random starts of the optimiser (default 1)")
    excite.add_argument(
        "--iterations", type=int, default=40, metavar="N", help="optimiser iterations per start (default 40)"
    )
    excite.add_argument(
        "--max-speed",
        type=float,
        metavar="MM_S",
        help="slider speed limit in mm/s (default 350, or the [motor] rating)",
    )
    excite.add_argument(
        "--max-acceleration", type=float, metavar="MM_S2", help="slider acceleration limit in mm/s² (default 2500)"
    )
    excite.add_argument(
        "--torque-limit",
        type=float,
        metavar="NMM",
        help="motor torque limit in N·mm (default: control.torque_limit_Nmm, [motor] peak, or 600)",
    )
    excite.add_argument("--min-cond-inv", type=float, metavar="X", help="smallest singularity measure (default 0.25)")
    excite.add_argument("--max-angle", type=float, metavar="DEG", help="largest |angle| in degrees (default 30)")
    excite.add_argument("--load-range", dest="load", metavar="MIN:MAX", help="load range in N (default 300:3000)")
    excite.add_argument(
        "--for",
        dest="target",
        choices=["dynamics", "calibration"],
        default="dynamics",
        help="what the motion is for: identify's dynamics (default), or hipsim calibrate's kinematics (both attitude "
        "sensors; 8 random candidates per --seeds, ±20° unless --max-angle, no load)",
    )
    excite.add_argument("--out", required=True, metavar="FILE", help="trajectory CSV to write")
    add_summary_format(excite, "what to print: a text summary (default) or JSON")
    excite.set_defaults(run=run)


def run(args) -> int:
    """Design the excitation, write it to ``--out`` as a trajectory CSV and print its condition number; exit status 1
    when its peaks break the rig's limits (the design keeps them: never, short of a bug), else 0."""
    from ..records import exit_status
    from ..rig.identification.excitation import Limits, excitation
    from .documents import ExciteRun

    params = parameters(args)
    if Path(args.out).is_dir():
        raise OutputError(args.out, "is a folder; give a CSV file name")
    for option, value in (("--duration", args.duration), ("--rate", args.rate)):
        if not (math.isfinite(value) and value > 0):
            raise ArgumentError(option, value, "a positive number")
    if args.rate < 4 * args.harmonics * args.frequency:
        raise ArgumentError(
            "--rate",
            args.rate,
            f"at least {4 * args.harmonics * args.frequency:g} Hz for harmonics up to {args.harmonics * args.frequency:g} Hz",
        )
    changes = {}
    if args.max_speed is not None:
        changes["max_speed"] = args.max_speed * 1e-3
    if args.max_acceleration is not None:
        changes["max_acceleration"] = args.max_acceleration * 1e-3
    if args.torque_limit is not None:
        changes["torque_limit"] = args.torque_limit * 1e-3
    if args.min_cond_inv is not None:
        changes["min_cond_inv"] = args.min_cond_inv
    if args.max_angle is not None:
        changes["max_angle"] = math.radians(args.max_angle)
    if args.load is not None:
        changes["min_load"], changes["max_load"] = numbers(args.load, ":", "--load-range", "MIN:MAX in N", count=2)
    for option, key in (
        ("--max-speed", "max_speed"),
        ("--max-acceleration", "max_acceleration"),
        ("--torque-limit", "torque_limit"),
        ("--min-cond-inv", "min_cond_inv"),
        ("--max-angle", "max_angle"),
    ):
        if key in changes and not (math.isfinite(changes[key]) and changes[key] > 0):
            raise ArgumentError(option, getattr(args, key), "a positive number")
    if "min_load" in changes and not 0 <= changes["min_load"] < changes["max_load"]:
        raise ArgumentError("--load-range", args.load, "MIN:MAX with 0 <= MIN < MAX")
    limits = Limits.for_machine(params, **changes)
    if args.target == "calibration":
        from .calibrate import run_excite_calibration

        return run_excite_calibration(args, params, limits)
    json_out = args.summary_format == "json"
    print(
        f"designing: {args.harmonics} harmonics of {args.frequency:g} Hz (period {1 / args.frequency:g} s), {args.seeds} start(s) …",
        flush=True,
        file=sys.stderr if json_out else sys.stdout,
    )
    if args.seeds < 1 or args.iterations < 1:
        raise ArgumentError("--seeds, --iterations", (args.seeds, args.iterations), "at least 1 each")
    design = excitation(
        params,
        frequency=args.frequency,
        harmonics=args.harmonics,
        limits=limits,
        seeds=args.seeds,
        max_iter=args.iterations,
    )
    path = design.write_csv(args.out, rate=args.rate, duration=args.duration)
    summary = design.summary()
    if json_out:
        print_json(ExciteRun(summary, str(path)).to_json())
        return exit_status([summary])
    peaks = summary.peaks
    print(
        f"condition number of the identification regressor: {summary.condition_number:.4g} "
        f"(ISO 14242-1 cycle: {summary.iso_condition_number:.4g}), for {', '.join(summary.quantities)}"
    )
    print(
        f"largest |angle| {peaks.angle_deg:.3g}° (limit {math.degrees(limits.max_angle):.3g}°), "
        f"slider speed {peaks.speed_mm_s:.4g} mm/s (limit {limits.max_speed * 1e3:.4g}), "
        f"acceleration {peaks.acceleration_mm_s2:.4g} mm/s² (limit {limits.max_acceleration * 1e3:.4g}), "
        f"motor torque {peaks.torque_Nmm:.4g} N·mm (limit {limits.torque_limit * 1e3:.4g}), "
        f"singularity measure ≥ {peaks.cond_inv_min:.3g} (limit {limits.min_cond_inv:.3g}), "
        f"load {peaks.load_min_N:.4g} to {peaks.load_max_N:.4g} N"
    )
    print(f"limits: {summary.verdict.level.value}: {summary.verdict.judged}")
    print(f"designed in {summary.design_seconds:.1f} s; wrote {path}")
    return exit_status([summary])
