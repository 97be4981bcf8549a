"""``hipsim wear``: slide tracks, cross-shear, work and predicted wear on the cup, from any motion; two runs compared.

A motion source is the built-in cycle (``iso``), a trajectory file (with the
motion options), a ``hipsim stations`` output (``FILE:1`` or ``FILE:2``, or
``--platform``), a ``hipsim simulate`` output (its actual motion, or
``FILE:desired``), or a rig log (read as ``compare`` reads it). Its kind is
told from its columns.
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path

from ..exceptions import ArgumentError, HipsimError
from .common import (
    add_machine_options,
    add_provenance_options,
    add_summary_format,
    numbers,
    page_provenance,
    print_json,
)
from .motion_options import add_trajectory_options, builtin_frequency, load_trajectory, span
from .wear_sources import header, kind_of, split_source
from .wear_test import add_test_options

__all__ = ["add_parser", "format_summary", "read_motion", "run"]

#: Two wear sources are alike within this many % unless --alike says otherwise.
DEFAULT_ALIKE_PCT = 5.0


def add_parser(subparsers) -> argparse.ArgumentParser:
    """Register ``wear`` on the main parser's subcommands."""
    wear = subparsers.add_parser(
        "wear",
        help="slide tracks, cross-shear, work and predicted wear on the cup -> table, summary, figures, page",
        description="Per point of the cup and per cycle: sliding distance, work ∫p·|v| dt and cross-shear (Kang's "
        "definition), the force track's length and load integral, and, with a wear factor or law, the wear per million "
        "cycles. The definitions, the frames and the choices made are in the guide's page 'Slide tracks, cross-shear "
        "and wear'. No wear factor is assumed: without one, W and CS are given and the wear is not.",
    )
    group = wear.add_argument_group("source (default: the built-in cycle, or --trajectory)")
    group.add_argument(
        "--platform",
        choices=["1", "2"],
        help="for a 'hipsim stations' output (alpha_1_deg ... alpha_2_deg): the platform to read (or write FILE:1, FILE:2)",
    )
    group.add_argument(
        "--cycle-time",
        type=float,
        metavar="S",
        help="the length of one cycle in s (default: the built-in's, a one-cycle file's span, else the median "
        "heel-strike interval of the load)",
    )
    group.add_argument(
        "--iso-load",
        action="store_true",
        help="use the built-in ISO 14242-1 twin-peak load at the motion's times (for a motion with no load column, "
        "e.g. a simulate output)",
    )
    group.add_argument("--torque-constant", type=float, metavar="NM_PER_A", help="for a rig log of motor currents")
    add_trajectory_options(wear)
    add_machine_options(wear)
    cup = wear.add_argument_group("cup and head")
    cup.add_argument("--head-diameter", type=float, default=28.0, metavar="MM", help="head diameter in mm (default 28)")
    cup.add_argument(
        "--sequence",
        default="ZYX",
        metavar="ABC",
        help="the Euler sequence of the angles, the matrix product left to right (default ZYX: R = Rz(γ)·Ry(β)·Rx(α), "
        "the machine's); e.g. XYZ for a file written as R = Rx(α)·Ry(β)·Rz(γ)",
    )
    cup.add_argument(
        "--cup-mount", metavar="A,B,G", help="the cup's orientation in the platform, α,β,γ in degrees (default 0,0,0)"
    )
    cup.add_argument(
        "--moving",
        choices=["cup", "head"],
        default="cup",
        help="which part the platform carries (default cup; head: the cup sits in the base, R becomes Rᵀ)",
    )
    cup.add_argument(
        "--points", metavar="FILE", help="cup points to compute at: a CSV with columns x, y, z (unit vectors, z ≥ 0)"
    )
    cup.add_argument(
        "--cup-grid",
        dest="grid",
        metavar="NTHETAxNPHI",
        help="the cup grid: polar bands x azimuth sectors, up to 1000x2000 (default 90x180; 45x90 with --weighings, "
        "whose integrals ΣW·dA and ∫F ds it gives within 0.1 %%)",
    )
    law = wear.add_argument_group("wear law (none by default)").add_mutually_exclusive_group()
    law.add_argument(
        "--wear-factor",
        metavar="K:KIND",
        help="a wear factor k in mm³/(N·m), in [0, 1e-3], with its kind: K:local (Archard, pin-on-disc: V = ∫k·W dA) or "
        "K:force-track (a simulator's, Saikko: V = k·∫F ds along the force track), e.g. 8e-8:force-track",
    )
    law.add_argument(
        "--wear-law",
        metavar="FILE",
        help="k against CS: a CSV with columns cross_shear, k_mm3_per_Nm (CS increasing, k ≥ 0)",
    )
    law.add_argument(
        "--area-law", type=float, metavar="C", help="the contact-area law V = C·A·s with a dimensionless C"
    )
    wear.add_argument(
        "--compare",
        nargs=2,
        metavar=("A", "B"),
        help="compare two sources: iso, FILE, FILE:1, FILE:2 (stations), FILE:desired (simulate); writes a verdict-first page",
    )
    wear.add_argument(
        "--alike",
        dest="tolerance",
        type=float,
        metavar="PCT",
        help="with --compare: alike within this many %% (default 5)",
    )
    wear.add_argument(
        "--out",
        default="hipsim_wear.csv",
        metavar="FILE",
        help="per-point table, CSV or .parquet (default hipsim_wear.csv)",
    )
    wear.add_argument(
        "--report",
        metavar="DIR",
        help="folder for the page (index.html, figures, wear.json); default none, hipsim_wear_compare with --compare",
    )
    wear.add_argument("--pdf", action="store_true", help="also print the page to wear.pdf (needs Chromium)")
    wear.add_argument(
        "--self-check",
        action="store_true",
        help="run the analytic checks on this cup and grid instead (pure flexion: CS = 0; time reversal: the same s, W, "
        "CS; flexion alone: a force track r·(range of α)·2 long); exits 1 if one fails",
    )
    add_test_options(wear)
    add_summary_format(wear)
    add_provenance_options(wear)
    wear.set_defaults(run=run)
    return wear


def read_motion(args, spec: str | None):
    """The motion a source names, as (trajectory or source, cycle time in [s], name, input file or None, notes)."""
    from ..motion.gait_events import gait_cycles
    from ..motion.sources import CycleSource
    from ..motion.trajectories import Trajectory, iso14242_load

    notes: list[str] = []
    if spec is None:
        spec = args.trajectory
        if spec is None:
            if args.platform:
                raise HipsimError("--platform applies to a stations output given with --trajectory")
            frequency = builtin_frequency(args)
            if args.iso_load:
                notes.append("--iso-load: the built-in cycle has it already")
            cycle = CycleSource(args.rate or 1000.0, args.cycles or 1, frequency)
            return cycle, 1.0 / frequency, cycle.name, None, notes
    if spec == "iso":
        frequency = builtin_frequency(args)
        cycle = CycleSource(args.rate or 1000.0, args.cycles or 1, frequency)
        return cycle, 1.0 / frequency, cycle.name, None, notes
    path, tag = split_source(spec)
    if tag is None and args.platform and spec == args.trajectory:
        tag = args.platform
    from .common import channel_columns

    channels = channel_columns(path, args.columns)  # a TDMS or HDF5 log: its channels by --columns
    names = header(path) if channels is None else channels[0]
    kind = kind_of(names)
    ns = argparse.Namespace(**vars(args))
    ns.trajectory, ns.rate, ns.cycles = path, None, None
    if kind == "rig log":
        if tag is not None:
            raise HipsimError(f"{spec}: a rig log has one motion; ':{tag}' applies to a stations or simulate output")
        from ..rig import load_log
        from .common import parameters

        columns = None if channels is None else channels[1]
        log = load_log(path, parameters(args), args.torque_constant, args.cutoff, columns=columns)
        trajectory = log.trajectory.slice(log.usable)
        trajectory = Trajectory(trajectory.t, trajectory.q, trajectory.qd, trajectory.qdd, trajectory.Fe, name=log.name)
        notes.append(f"{log.name}: a rig log, motion from its {log.motion_from}; the filter's edges left out")
    else:
        if kind == "stations":
            if tag not in ("1", "2"):
                raise HipsimError(
                    f"{path} is a stations output with two platforms: write {path}:1 or {path}:2, or --platform"
                )
            j = tag
            angles = f"alpha=alpha_{j}_deg:deg,beta=beta_{j}_deg:deg,gamma=gamma_{j}_deg:deg"
        elif kind == "simulate":
            if tag not in (None, "desired"):
                raise HipsimError(
                    f"{spec}: a simulate output has its actual motion (FILE) and the desired one (FILE:desired)"
                )
            suffix = "_des" if tag == "desired" else ""
            angles = f"alpha=alpha{suffix}_deg:deg,beta=beta{suffix}_deg:deg,gamma=gamma{suffix}_deg:deg"
        elif tag is not None:
            raise HipsimError(f"{spec}: ':{tag}' applies to a stations or simulate output; {path} is a trajectory file")
        if kind in ("stations", "simulate"):
            if args.columns:
                raise HipsimError(f"--columns: {path} is a {kind} output, read by its own columns")
            load = ",load=Fe_N:N" if "Fe_N" in names and args.load is None and args.load_column is None else ""
            ns.columns = f"time=t_s:s,{angles}{load}"
        trajectory = load_trajectory(ns)
        if kind in ("stations", "simulate"):
            which = f"platform {tag}" if kind == "stations" else ("desired" if tag == "desired" else "actual")
            trajectory = Trajectory(
                trajectory.t,
                trajectory.q,
                trajectory.qd,
                trajectory.qdd,
                trajectory.Fe,
                f"{trajectory.name}:{which}",
                trajectory.periodic,
                trajectory.lines,
            )
            notes.append(f"{path}: a {kind} output, {which} motion read")
    cycle_time = args.cycle_time
    if cycle_time is not None and not (math.isfinite(cycle_time) and cycle_time > 0):
        raise HipsimError(f"--cycle-time: expected a positive number of seconds, got {cycle_time:g}")
    if cycle_time is None and kind != "rig log" and (args.frequency is not None or args.period is not None):
        cycle_time = 1.0 / builtin_frequency(args)
    if args.iso_load:
        frequency = 1.0 / (cycle_time or 1.0)
        trajectory = Trajectory(
            trajectory.t,
            trajectory.q,
            trajectory.qd,
            trajectory.qdd,
            iso14242_load(trajectory.t - trajectory.t[0], frequency),
            trajectory.name,
            trajectory.periodic,
            trajectory.lines,
        )
        notes.append(
            f"the built-in ISO 14242-1 load at {frequency:g} Hz from the motion's first sample (--iso-load; "
            "--cycle-time sets its frequency)"
        )
    if not (trajectory.Fe > 0).any():
        raise HipsimError(
            f"{trajectory.name}: the motion carries no load (no load column, or zero throughout): work, CS and wear need "
            "one; give --load FILE --load-column COL, a load column, or --iso-load"
        )
    if cycle_time is None:
        events = gait_cycles(trajectory)
        if math.isfinite(events.period):
            cycle_time = events.period
            notes.append(f"cycle time {cycle_time:.4g} s: the median heel-strike interval of the load")
        elif trajectory.periodic:  # one whole cycle, repeating
            cycle_time = span(trajectory)
        else:  # one cycle without its closing sample, as the commands write the built-in cycle
            step = (trajectory.t[-1] - trajectory.t[0]) / (len(trajectory) - 1)
            cycle_time = span(trajectory) + step
            notes.append(
                f"the load marks fewer than two heel strikes: the file taken as one cycle of {cycle_time:.4g} s "
                "(its span and one step); --cycle-time says otherwise"
            )
    return trajectory, cycle_time, trajectory.name, path, notes


def _setup(args):
    from ..wear import CupSetup

    mount = (0.0, 0.0, 0.0)
    if args.cup_mount is not None:
        alpha, beta, gamma = numbers(args.cup_mount, ",", "--cup-mount", "α,β,γ in degrees", 3)
        mount = (math.radians(alpha), math.radians(beta), math.radians(gamma))
    try:
        return CupSetup(args.head_diameter, args.sequence, mount, args.moving)
    except ArgumentError as error:
        option = {"head diameter": "--head-diameter", "sequence": "--sequence"}.get(error.name, error.name)
        raise HipsimError(f"{option}: expected {error.expected}, got {error.value!r}") from None


def _points(args, setup):
    from ..wear import cup_grid, cup_points
    from ..wear.laws import read_numeric_columns

    if args.points:
        xyz, lines = read_numeric_columns(args.points, ("x", "y", "z"), "points file")
        try:
            return cup_points(xyz, args.points)
        except ArgumentError as error:  # name the file's line, not the data row
            row = int(error.name.rsplit(" ", 1)[-1]) if "row" in error.name else 1
            raise HipsimError(f"{args.points}, line {int(lines[row - 1])}: expected {error.expected}") from None
    grid = args.grid or ("45x90" if args.weighings or args.test else "90x180")
    parts = grid.lower().split("x")
    try:
        n_theta, n_phi = (int(part) for part in parts)
        return cup_grid(n_theta, n_phi, setup.radius_mm)
    except (ValueError, ArgumentError):
        raise HipsimError(
            f"--cup-grid: expected NTHETAxNPHI, whole numbers up to 1000x2000 (e.g. 90x180), got '{grid}'"
        ) from None


def _law(args):
    from ..wear.factors import parse_wear_factor
    from ..wear.laws import ContactAreaLaw, read_wear_law

    if args.wear_factor is not None:
        return parse_wear_factor(args.wear_factor)
    try:
        if args.area_law is not None:
            return ContactAreaLaw(args.area_law)
    except ArgumentError as error:
        raise HipsimError(f"--area-law: expected {error.expected}, got {error.value!r}") from None
    if args.wear_law:
        return read_wear_law(args.wear_law)
    return None


def _table(maps, wear) -> dict:
    import numpy as np

    w = maps.points.w
    columns = {
        "x": w[:, 0],
        "y": w[:, 1],
        "z": w[:, 2],
        "sliding_mm": maps.sliding_mm,
        "sliding_loaded_mm": maps.sliding_loaded_mm,
        "work_N_per_mm": maps.work_N_per_mm,
        "cross_shear": maps.cross_shear,
    }
    if maps.points.area_mm2 is not None:
        columns["area_mm2"] = maps.points.area_mm2
    if wear is not None:
        columns["wear_depth_um_per_Mc"] = wear.depth_um_per_Mc
        if wear.volume_mm3_per_Mc is not None:
            columns["wear_mm3_per_Mc"] = wear.volume_mm3_per_Mc
    return {name: np.asarray(values, dtype=float) for name, values in columns.items()}


def _write_table(path: str, columns: dict) -> None:
    from ..files import ColumnWriter

    with ColumnWriter(path) as writer:
        writer.write(columns)
        writer.close()


def format_summary(summary, notes=()) -> str:
    """The summary (:class:`hipsim.wear.summary.WearSummary`) as a table."""
    from ..present.tables import format_table

    def value(key, digits=4):
        x = getattr(summary, key)
        return "–" if x is None or (isinstance(x, float) and not math.isfinite(x)) else f"{x:.{digits}g}"

    rows = [
        ["force track length", value("force_track_mm"), "mm"],
        ["force track load integral", value("force_track_load_Nm"), "N·m"],
        ["sliding distance, largest", value("sliding_mm_max"), "mm"],
        ["sliding distance, mean over the loaded area", value("sliding_mm_mean"), "mm"],
        ["work, largest", value("work_N_per_mm_max"), "N/mm"],
        ["work over the cup ΣW·dA", value("load_slide_integral_Nm"), "N·m"],
        ["cross-shear, mean over the loaded area", value("cross_shear_mean", 3), ""],
        ["cross-shear, work-weighted", value("cross_shear_work_weighted", 3), ""],
        ["cross-shear, largest", value("cross_shear_max", 3), ""],
        ["area worn (W > 0)", value("worn_area_mm2"), "mm²"],
        ["wear", value("wear_mm3_per_Mc") if summary.wear_law else "not predicted (no law given)", "mm³/Mc"],
    ]
    title = (
        f"Wear of {summary.source}: per cycle ({summary.cycles:.4g} cycles, head {summary.head_diameter_mm:g} mm, "
        f"{summary.points} points)"
    )
    out = [format_table(["quantity", "value", "unit"], rows, title)]
    if summary.wear_law:
        out.append(f"wear law: {summary.wear_law}")
    out += [f"note: {note}" for note in notes]
    return "\n".join(out)


def _one(args, spec, setup, points, law):
    from ..wear import wear_maps
    from ..wear.laws import predict_wear
    from ..wear.tracks import cycle_tracks

    motion, cycle_time, name, path, notes = read_motion(args, spec)
    from .common import progress

    maps = wear_maps(motion, cycle_time, setup, points, progress=progress("wear", " steps"))
    wear = predict_wear(maps, law) if law is not None else None
    if wear is not None and wear.beyond_table:
        notes.append(
            f"{wear.beyond_table} loaded point(s) have a CS outside the wear-law table: k held at its end value"
        )
    if wear is not None and wear.total_mm3_per_Mc is None:
        notes.append("points given one by one have no areas: the wear depth per point is given, not the cup's volume")
    if maps.cycles > 1.0 + 1e-9:
        notes.append(
            f"{name}: {maps.cycles:.4g} cycles, the values are per cycle (the sums over the motion divided by them)"
        )
    return maps, cycle_tracks(motion, cycle_time, setup), wear, path, notes


def run(args) -> int:
    """Compute, write the table (and the page), print the summary."""
    from ..files import check_folder, check_output
    from ..present.pages import require_pdf_renderer
    from ..records import exit_status
    from ..wear.summary import run_verdict, wear_summary
    from .documents import WearRun

    setup = _setup(args)
    points = _points(args, setup)
    if args.self_check:
        return _self_check(args, setup, points)
    if args.weighings or args.test:
        from .wear_test import run_test

        return run_test(args, setup, points, read_motion, _law)
    if args.balance_noise is not None:
        raise HipsimError("--balance-noise applies to --weighings or --test: give one, or drop --balance-noise")
    law = _law(args)
    if args.tolerance is not None and not args.compare:
        raise HipsimError(f"--alike {args.tolerance:g} % applies to --compare A B: give --compare, or drop --alike")
    if args.tolerance is None:
        args.tolerance = DEFAULT_ALIKE_PCT
    check_output(args.out)
    report = args.report or ("hipsim_wear_compare" if args.compare else None)
    if report:
        check_folder(Path(report))
    if args.pdf:
        if not report:
            raise HipsimError("--pdf prints the page: give --report DIR")
        require_pdf_renderer()
    if args.compare:
        return _compare(args, setup, points, law, report)
    maps, tracks, wear, path, notes = _one(args, None, setup, points, law)
    _write_table(args.out, _table(maps, wear))
    summary = wear_summary(maps, wear)
    verdict = run_verdict(summary)  # NOT MADE (not rated): exits 0, as every verdict that decides nothing
    index = None
    if report:
        from ..present.wear_page import write_wear_page

        page = write_wear_page(
            report,
            maps,
            tracks,
            wear,
            page_provenance(args, trajectory=path, points=args.points, wear_law=args.wear_law),
            tuple(notes),
            args.pdf,
        )
        index = str(page.index)
    if args.summary_format == "json":
        print_json(WearRun(verdict, summary, tuple(notes), str(args.out), index).to_json())
    else:
        print(format_summary(summary, notes))
        print(f"wrote {', '.join(path for path in (str(args.out), index) if path)}")
    return exit_status([verdict])


def _self_check(args, setup, points) -> int:
    from ..present.tables import format_table
    from ..wear.checks import self_checks

    checks = self_checks(setup, points)
    passed = all(check.passed for check in checks)
    if args.summary_format == "json":
        print_json(
            {
                "passed": passed,
                "checks": [
                    {
                        "name": c.name,
                        "law": c.law,
                        "deviation": c.deviation,
                        "tolerance": c.tolerance,
                        "passed": c.passed,
                    }
                    for c in checks
                ],
            }
        )
    else:
        rows = [
            [c.name, c.law, f"{c.deviation:.3g}", f"{c.tolerance:.3g}", "pass" if c.passed else "FAIL"] for c in checks
        ]
        print(
            format_table(
                ["check", "what must hold", "worst deviation", "tolerance", "verdict"],
                rows,
                f"Analytic checks on a {setup.head_diameter_mm:g} mm head, {len(points)} points",
            )
        )
        print(f"verdict: {'PASS' if passed else 'FAIL'}")
    return 0 if passed else 1


def _compare(args, setup, points, law, report) -> int:
    import numpy as np

    from ..present.wear_page import write_wear_compare
    from ..records import exit_status
    from ..wear.summary import difference_maps
    from .documents import WearCompare

    a = _one(args, args.compare[0], setup, points, law)
    b = _one(args, args.compare[1], setup, points, law)
    notes = tuple(f"A: {note}" for note in a[4]) + tuple(f"B: {note}" for note in b[4])
    page, verdict, document = write_wear_compare(
        report,
        a[:3],
        b[:3],
        args.tolerance / 100.0,
        page_provenance(args, a=a[3], b=b[3], points=args.points, wear_law=args.wear_law),
        notes,
        args.pdf,
    )
    table_a, table_b = _table(a[0], a[2]), _table(b[0], b[2])
    columns = {key: table_a[key] for key in ("x", "y", "z")}
    differences = difference_maps(a[0], b[0])
    for key in ("sliding_mm", "work_N_per_mm", "cross_shear"):
        columns[f"{key}_a"], columns[f"{key}_b"] = table_a[key], table_b[key]
        columns[f"{key}_b_minus_a"] = np.asarray(differences[key])
    _write_table(args.out, columns)
    if args.summary_format == "json":
        print_json(WearCompare(document, str(page.index), str(args.out)).to_json())
    else:
        from ..present.tables import format_table

        rows = [
            [
                row.label + (f" [{row.unit}]" if row.unit else ""),
                "–" if row.a is None else f"{row.a:.4g}",
                "–" if row.b is None else f"{row.b:.4g}",
                "–" if row.relative is None else f"{100 * row.relative:+.3g} %",
            ]
            for row in document.differences
        ]
        print(format_table(["quantity", "A", "B", "(B − A)/A"], rows, f"A: {a[0].name}   B: {b[0].name} (per cycle)"))
        print(f"verdict: {verdict.level.value}: {verdict.judged}")
        for note in notes:
            print(f"note: {note}")
        print(f"wrote {page.index}, {args.out}")
    return exit_status([verdict])  # DIFFERENT exits 1
