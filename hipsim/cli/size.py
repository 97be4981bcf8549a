"""``hipsim size``: check a drive train against the cycle, or rank a catalogue of motors × screws × gearboxes."""

from __future__ import annotations

import argparse
import math
import sys

from ..exceptions import HipsimError
from ..present.tables import format_margin, format_quantity, format_table
from .common import add_machine_options, parameters, print_json

__all__ = ["add_parser", "run"]

_DESCRIPTION = """\
Sizes the drive of the three linear modules the way industrial sizing tools do: along every sample of the
cycle, the peak torque-speed curve, the RMS torque against the S1 curve at the mean speed, the top speed,
the load-to-rotor inertia ratio (the load from the model's M(q)), the winding temperature rise, the
amplifier currents, the regenerated energy and power, and the lead screw's L10 life in test cycles
(ISO 3408-5), critical speed, buckling load, stroke and permissible load; each with value, limit, margin
and pass/fail. With --catalogue, every motor x screw x gearbox combination is checked (the model reruns
for each screw lead) and ranked the way a drive engineer ranks: the smallest combination that passes
every check first (by rated power, then rotor inertia, then a catalogue cost column), with its binding
check and margin, the failing ones after, each with its first failing check in words and numbers; the
screw's checks, the same for every motor, once per screw (--rank margin: by the smallest margin of all
checks, largest first). Exits with status 1 when the drive (or every catalogue combination) fails a check."""

_EXAMPLES = """\
examples:
  hipsim size --drive models/drive_example.toml
  hipsim size --catalogue models/motors_example.csv --screws models/screws_example.csv --gearboxes models/gearboxes_example.csv
  hipsim size --drive my_drive.toml --trajectory walking.csv --trajectory stairs.csv --life-cycles 1e7
(the example files ship inside the package: hipsim.models; `python -c "import hipsim.models, os; print(os.path.dirname(hipsim.models.__file__))"` prints where)
"""


def add_parser(subparsers) -> argparse.ArgumentParser:
    """Register ``size`` on the main parser's subcommands."""
    parser = subparsers.add_parser(
        "size",
        help="motor, amplifier and lead-screw sizing checks along the cycle; rank a catalogue",
        description=_DESCRIPTION,
        epilog=_EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    add_machine_options(parser)
    motion = parser.add_argument_group("motion")
    motion.add_argument(
        "--trajectory",
        action="append",
        default=[],
        metavar="FILE",
        help="a trajectory CSV to check as well, one test cycle each (repeatable)",
    )
    motion.add_argument(
        "--without-iso", action="store_true", help="leave out the built-in ISO 14242-1 cycle (needs --trajectory)"
    )
    motion.add_argument(
        "--rate", type=float, metavar="HZ", help="sample rate of the built-in cycle in Hz (default 1000)"
    )
    motion.add_argument("--cycles", type=float, metavar="N", help="number of built-in cycles (default 1)")
    motion.add_argument(
        "--frequency", type=float, metavar="HZ", help="cycle frequency of the built-in cycle in Hz (default 1)"
    )
    parts = parser.add_argument_group("drive")
    parts.add_argument(
        "--drive",
        metavar="FILE",
        help="drive file (TOML: [motor], [amplifier], [gearbox], [lead_screw], [rules]); "
        "default: the parameter file's [motor] table",
    )
    parts.add_argument(
        "--catalogue", metavar="CSV", help="motor catalogue to rank (one motor and its amplifier a line)"
    )
    parts.add_argument(
        "--screws", metavar="CSV", help="lead screw catalogue (with --catalogue; default: the machine's screw)"
    )
    parts.add_argument(
        "--gearboxes", metavar="CSV", help="gearbox catalogue (with --catalogue; default: direct coupling)"
    )
    rules = parser.add_argument_group("rules")
    rules.add_argument(
        "--life-cycles", type=float, metavar="N", help="screw L10 life to reach in test cycles (default 5e6)"
    )
    rules.add_argument(
        "--inertia-ratio", type=float, metavar="R", help="largest load-to-rotor inertia ratio (default 10)"
    )
    out = parser.add_argument_group("output")
    out.add_argument(
        "--rank",
        choices=["size", "margin"],
        default="size",
        help="catalogue order: size (default: the smallest drive that passes first, by rated power, rotor inertia, "
        "cost) or margin (the largest smallest margin first)",
    )
    out.add_argument("--top", type=int, metavar="N", help="show the N best catalogue combinations (default all)")
    out.add_argument(
        "--summary-format",
        choices=["table", "json"],
        default="table",
        help="output on standard output",
    )
    parser.set_defaults(run=run)
    return parser


def _trajectories(args):
    from ..motion import iso14242, read_trajectory

    chosen = []
    if args.without_iso:
        if not args.trajectory:
            raise HipsimError("--without-iso leaves no cycle to check: give --trajectory FILE")
        given = [f"--{name}" for name in ("rate", "cycles", "frequency") if getattr(args, name) is not None]
        if given:
            raise HipsimError(f"{', '.join(given)} apply to the built-in cycle, which --without-iso leaves out")
    else:
        cycles = args.cycles if args.cycles is not None else 1.0
        trajectory = iso14242(
            rate=args.rate if args.rate is not None else 1000.0,
            cycles=cycles,
            frequency=args.frequency if args.frequency is not None else 1.0,
        )
        chosen.append((trajectory, cycles))
    chosen += [(read_trajectory(path), 1.0) for path in args.trajectory]
    return chosen


def _rules(args, base):
    import dataclasses

    changes = {}
    for option, key in (("life_cycles", "life_target_cycles"), ("inertia_ratio", "inertia_ratio_max")):
        value = getattr(args, option)
        if value is not None:
            if not (math.isfinite(value) and value > 0):
                raise HipsimError(f"--{option.replace('_', '-')}: expected a positive number, got {value:g}")
            changes[key] = value
    return dataclasses.replace(base, **changes)


def format_checks(checks, title: str) -> str:
    """A check table as plain text."""
    rows = []
    for c in checks:
        verdict = "not checked" if c.passed is None else ("pass" if c.passed else "FAIL")
        rows.append(
            [
                f"LN{c.module}",
                c.kind.label,
                f"{format_quantity(c.value, c.kind.unit)} {c.kind.unit}",
                f"{'≥' if c.kind.bound == 'min' else '≤'} {format_quantity(c.limit, c.kind.unit)}",
                format_margin(c.margin),
                verdict,
                c.detail,
            ]
        )
    return format_table(["module", "check", "value", "limit", "margin", "result", "detail"], rows, title)


def _sentence(check, trajectories) -> str:
    from ..present.check_text import check_sentence

    return check_sentence(check) + (f" ({check.trajectory})" if len(trajectories) > 1 else "")


def _screw_name(drive, params) -> str:
    return drive.screw.name if drive.screw else f"machine's ({params.lead * 1e3:g} mm)"


def format_ranking(candidates, shown, trajectories, params) -> str:
    """The catalogue ranked by size: each line's rated power, and its binding check (pass) or first failing check (FAIL); then the screw's checks once."""
    from ..design.checks import margin_order
    from ..design.ranking import screw_checks
    from ..present.numbers import significant

    rows = []
    for rank, c in enumerate(shown, start=1):
        power, source = c.rated_power
        power_text = (
            "—"
            if power is None
            else f"{significant(power, 3, zeros=False)} W" + ("" if source == "catalogue" else " *")
        )
        if c.passed:
            b = c.motor_binding
            verdict = "pass"
            why = (
                "—"
                if b is None
                else (
                    f"{b.kind.label}, LN{b.module}: {format_quantity(b.value, b.kind.unit)} / "
                    f"{format_quantity(b.limit, b.kind.unit)} {b.kind.unit}"
                    + (f" ({b.trajectory})" if len(trajectories) > 1 else "")
                )
            )
        elif c.passed is False:
            b = c.failure
            verdict, why = "FAIL", _sentence(b, trajectories)
        else:
            b, verdict, why = None, "—", "no check made"
        rows.append(
            [
                str(rank),
                c.drive.motor.name,
                c.drive.gearbox.name if c.drive.gearbox else "direct",
                _screw_name(c.drive, params),
                power_text,
                verdict,
                "—" if b is None else format_margin(b.margin),
                why,
            ]
        )
    cycles = ", ".join(t.name for t, _ in trajectories)
    passing = sum(1 for c in candidates if c.passed)
    title = (
        f"{len(candidates)} combinations along {cycles}, {passing} pass: the smallest that passes first "
        "(by rated power, then rotor inertia, then cost); each with its binding check, or its first failing check"
    )
    lines = [
        format_table(
            ["rank", "motor", "gearbox", "screw", "rated power", "result", "margin", "binding check / why it fails"],
            rows,
            title,
        )
    ]
    sources = {c.rated_power[1] for c in shown}
    if any(source != "catalogue" for source in sources):
        lines.append(
            "* rated power = rated torque × rated speed at the S1 curve's rated point (the catalogue gives no rated_power_W)"
        )
    rows = []
    for screw, checks in screw_checks(candidates):
        made = [c for c in checks if c.passed is not None]
        failed = [c for c in made if c.passed is False]
        b = min(failed or made, key=margin_order) if made else None
        rows.append(
            [
                screw.name if screw is not None else f"machine's ({params.lead * 1e3:g} mm)",
                "—" if b is None else f"{b.kind.label}, LN{b.module}",
                "—"
                if b is None
                else f"{format_quantity(b.value, b.kind.unit)} / {format_quantity(b.limit, b.kind.unit)} {b.kind.unit}",
                "—" if b is None else format_margin(b.margin),
                "not checked" if b is None else ("FAIL" if failed else "pass"),
            ]
        )
    lines += [
        "",
        format_table(
            ["screw", "binding check", "value / limit", "margin", "result"],
            rows,
            "Checks that do not depend on the motor (the screw against the machine's demand), once per screw; they break no tie",
        ),
    ]
    return "\n".join(lines)


def format_margin_ranking(candidates, shown, trajectories, params) -> str:
    """The catalogue ranked by the smallest margin of all checks (``--rank margin``), each line's binding constraint."""
    rows = []
    for rank, c in enumerate(shown, start=1):
        b = c.binding
        verdict = "—" if c.passed is None else ("pass" if c.passed else "FAIL")
        binding = (
            "—"
            if b is None
            else f"{b.kind.label}, LN{b.module}" + (f", {b.trajectory}" if len(trajectories) > 1 else "")
        )
        rows.append(
            [
                str(rank),
                c.drive.motor.name,
                c.drive.gearbox.name if c.drive.gearbox else "direct",
                _screw_name(c.drive, params),
                format_margin(c.margin),
                verdict,
                binding,
                f"{format_quantity(b.value, b.kind.unit)} / {format_quantity(b.limit, b.kind.unit)} {b.kind.unit}"
                if b
                else "—",
            ]
        )
    cycles = ", ".join(t.name for t, _ in trajectories)
    return format_table(
        ["rank", "motor", "gearbox", "screw", "smallest margin", "result", "binding constraint", "value / limit"],
        rows,
        f"{len(candidates)} combinations along {cycles}, ranked by their smallest margin",
    )


def format_demands(size) -> str:
    rows = [
        [
            f"LN{m.module}",
            m.tau_peak_Nmm,
            m.tau_rms_Nmm,
            m.speed_peak_rpm,
            m.speed_mean_rpm,
            m.motor_thrust_peak_N,
            m.axial_force_peak_N,
            m.axial_force_cubic_mean_N,
            m.load_inertia_max_kgmm2,
            m.regen_energy_J,
        ]
        for m in size.modules
    ]
    header = [
        "module",
        "τ peak [N·mm]",
        "τ RMS [N·mm]",
        "n peak [rpm]",
        "n mean [rpm]",
        "motor thrust peak [N]",
        "axial screw load peak [N]",
        "cubic mean [N]",
        "M_θ,ii max [kg·mm²]",
        "regen [J/cycle]",
    ]
    return format_table(
        header, rows, "At each screw shaft (motor thrust 2πτ/p; axial screw load 2π(τ − τ_L − τ_screw friction)/p)"
    )


def _margin_bands(args, params, machine, drive, rules, trajectories, results):
    """Each trajectory's margin bands from an identified parameter file's covariance (None without one, or without a drive)."""
    from ..rig.identification.uncertainty import read_covariance, sigma_machines

    covariance = read_covariance(args.params, params)
    if covariance is None or drive is None:
        return None
    from ..analysis.runs import analyse
    from ..design.sizing import margin_bands, sizing

    changes = {"lead": machine.lead, "screw_inertia": machine.screw_inertia} if machine is not params else {}
    variants = [v.replace(**changes) if changes else v for v in sigma_machines(params, covariance)]
    return [
        margin_bands(size, [sizing(analyse(v, trajectory), drive, rules, cycles) for v in variants])
        for (trajectory, cycles), (_, size) in zip(trajectories, results)
    ]


def format_bands(bands) -> str:
    """The checks' margins with the identified parameters' uncertainty: the 95 % interval, and whether each passes with 95 % confidence."""
    rows = []
    for b in bands:
        if b.std is None:
            continue
        c = b.check
        lo, hi = b.interval
        rows.append(
            [
                f"LN{c.module}",
                c.kind.label,
                format_margin(c.margin),
                f"±{100 * b.std:.2g} %",
                f"{format_margin(lo)} to {format_margin(hi)}",
                "yes" if b.confident else "NO",
            ]
        )
    return format_table(
        ["module", "check", "margin", "std", "95 % interval", "passes with 95 % confidence"],
        rows,
        "Margins with the uncertainty of the identified parameters (the parameter file's covariance; one-sided 95 %: margin ≥ 1.645 std)",
    )


def run(args) -> int:
    """Check ``--drive`` (or rank ``--catalogue``) along the cycles and print the checks; exit status 1 when the drive fails one."""
    from ..analysis.runs import analyse
    from ..design.checks import checks_verdict
    from ..design.ranking import screw_checks
    from ..design.sizing import rank_drives, sizing
    from ..design.sizing_summary import ranking_verdict
    from ..machine.drive import (
        SizingRules,
        drive_from_motor_table,
        load_drive,
        load_gearbox_catalogue,
        load_motor_catalogue,
        load_screw_catalogue,
    )
    from ..records import exit_status

    params = parameters(args)
    if args.top is not None and args.top < 1:
        raise HipsimError(f"--top: expected a positive whole number, got {args.top}")
    if args.catalogue is None:
        if args.rank != "size":
            raise HipsimError("--rank applies to a catalogue: give --catalogue FILE too")
        for option in ("screws", "gearboxes", "top"):
            if getattr(args, option) is not None:
                raise HipsimError(f"--{option} applies to a catalogue: give --catalogue FILE too")
    elif args.drive is not None:
        raise HipsimError("give either --drive FILE (check one drive) or --catalogue FILE (rank many), not both")
    # Read every input before the first model run: a bad line fails at once.
    trajectories = _trajectories(args)
    if args.catalogue is not None:
        motors = load_motor_catalogue(args.catalogue)
        screws = load_screw_catalogue(args.screws) if args.screws else None
        gearboxes = load_gearbox_catalogue(args.gearboxes) if args.gearboxes else None
        rules = _rules(args, SizingRules())
        progress = (
            None
            if args.summary_format == "json"
            else (lambda text: print(f"running the model: {text}", file=sys.stderr))
        )
        candidates = rank_drives(params, trajectories, motors, screws, gearboxes, rules, progress, order=args.rank)
        shown = candidates[: args.top] if args.top else candidates
        if args.summary_format == "json":
            from ..design.sizing_summary import ranking_summary

            by_size = args.rank == "size"
            summary = ranking_summary(
                candidates,
                shown,
                rules,
                args.rank,
                [(None if s is None else s.name, checks) for s, checks in screw_checks(candidates)]
                if by_size
                else None,
                [None if c.failure is None else _sentence(c.failure, trajectories) for c in shown] if by_size else None,
            )
            print_json(summary.to_json())
        else:
            if args.rank == "size":
                print(format_ranking(candidates, shown, trajectories, params))
            else:
                print(format_margin_ranking(candidates, shown, trajectories, params))
            unchecked = sorted({name for c in shown for name in c.unchecked})
            if unchecked:
                print(f"\nnot checked for want of data (see --summary-format json for which): {', '.join(unchecked)}")
            if shown:
                best = shown[0]
                print()
                print(format_checks(best.checks, f"Every check of rank 1: {best.drive.name}"))
            ranked = ranking_verdict(candidates)
            print(f"\nverdict: {ranked.level.value}: {ranked.judged}")
        return exit_status([ranking_verdict(candidates)])

    if args.drive is not None:
        drive = load_drive(args.drive)
    elif params.motor:
        drive = drive_from_motor_table(params.motor, params.source)
    else:
        drive = None
    rules = _rules(args, drive.rules if drive is not None else SizingRules())
    machine = params
    if drive is not None and drive.screw is not None:
        changes = {"lead": drive.screw.lead, "screw_inertia": drive.screw.inertia}
        machine = params.replace(**{k: v for k, v in changes.items() if v is not None})
    results = [
        (trajectory, sizing(analyse(machine, trajectory), drive, rules, cycles)) for trajectory, cycles in trajectories
    ]
    bands = _margin_bands(args, params, machine, drive, rules, trajectories, results)
    if args.summary_format == "json":
        from ..design.sizing_summary import sizing_summary
        from .documents_more import SizeRun

        summaries = {t.name: sizing_summary(s, None if bands is None else bands[k]) for k, (t, s) in enumerate(results)}
        print_json(SizeRun(summaries).to_json())
    else:
        for trajectory, size in results:
            print(
                f"trajectory: {trajectory.name} ({len(trajectory)} samples); parameters: {machine.source}; lead {machine.lead * 1e3:g} mm"
            )
            print(format_demands(size))
            if drive is None:
                print(
                    "\nno drive to check: give --drive FILE (models/drive_example.toml is an example) or a [motor] table in the parameter file"
                )
            else:
                print()
                print(format_checks(size.checks, f"Checks of {drive.name} ({drive.source})"))
                b = size.binding
                if b is not None:
                    verdict = "PASS" if size.passed else "FAIL"
                    print(
                        f"-> {verdict}; binding: {b.kind.label}, LN{b.module}: {format_quantity(b.value, b.kind.unit)} against "
                        f"{format_quantity(b.limit, b.kind.unit)} {b.kind.unit} (margin {format_margin(b.margin)})"
                    )
                if bands:
                    print()
                    print(format_bands(bands[[t for t, _ in results].index(trajectory)]))
            print()
    return exit_status(checks_verdict(size.checks) for _, size in results)
