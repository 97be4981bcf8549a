"""``hipsim iso-check``: did a run follow the ISO 14242-1 waveforms within tolerance, cycle by cycle?

The run: a rig log (a CSV with motor torques or currents, read as ``compare``
reads it), any trajectory file the readers take, or the built-in cycle. Each
whole cycle, aligned by heel strike, is held against the standard's
waveforms (:mod:`hipsim.motion.iso_compliance`).
"""

from __future__ import annotations

import argparse
from pathlib import Path

from ..exceptions import ArgumentError, HipsimError
from ..present.tables import format_table
from .common import (
    add_machine_options,
    add_provenance_options,
    add_summary_format,
    page_provenance,
    parameters,
    print_json,
)
from .motion_options import add_trajectory_options, load_trajectory

__all__ = ["add_parser", "format_check", "parse_tolerance_option", "run"]

#: Cycles listed one by one on the terminal (the JSON and the page list them all).
MAX_LISTED = 20
#: Columns whose presence makes a CSV a rig log.
_RIG_COLUMNS = ("tau_1_Nmm", "current_1_A")


def parse_tolerance_option(text: str | None):
    """``--iso-tolerance`` text → :class:`hipsim.motion.iso_compliance.Tolerances` (the defaults when None)."""
    from ..motion.iso_compliance import DEFAULT_TOLERANCES, parse_tolerances

    if text is None:
        return DEFAULT_TOLERANCES
    try:
        return parse_tolerances(text)
    except ArgumentError as error:
        raise HipsimError(f"--iso-tolerance: expected {error.expected}, got {error.value!r}") from None


def add_parser(subparsers) -> argparse.ArgumentParser:
    """Register ``iso-check`` on the main parser's subcommands."""
    iso = subparsers.add_parser(
        "iso-check",
        help="ISO 14242-1 compliance of a log or trajectory, per cycle -> table, figure, HTML, JSON",
        description="Aligns each whole cycle of the run on heel strike (from the load curve) and compares each angle and "
        "the load with the standard's waveforms (hipsim's built-in cycle), and the cycle's frequency with 1 Hz. Prints pass "
        "or fail per quantity and per cycle; writes the figure with the tolerance bands (PNG, SVG), index.html and "
        "iso_check.json to --out. Exits with status 1 when a cycle leaves a tolerance. The default tolerances (±3° on each "
        "angle, ±3 %% of the 3000 N peak load, ±0.1 Hz) are assumed values: confirm them against your copy of the standard.",
    )
    iso.add_argument(
        "--log",
        metavar="FILE",
        help="rig log CSV (torques or currents, angles and/or slider heights) or any "
        "trajectory file (same as --trajectory); default: the built-in cycle",
    )
    add_machine_options(iso)
    add_trajectory_options(iso)
    iso.add_argument("--torque-constant", type=float, metavar="NM_PER_A", help="for a rig log of motor currents")
    iso.add_argument(
        "--iso-tolerance",
        dest="tolerance",
        metavar="SPEC",
        help="alpha=3,beta=3,gamma=3,load=3%%,frequency=0.1 (degrees, N or %% of "
        "3000 N, Hz; unnamed ones keep these defaults)",
    )
    iso.add_argument(
        "--out", default="hipsim_iso_check", metavar="DIR", help="folder to write (default hipsim_iso_check)"
    )
    add_summary_format(iso, "what to print: tables (default) or the verdict as JSON")
    add_provenance_options(iso)
    iso.set_defaults(run=run)
    return iso


def _is_rig_log(path: str, columns: str | None = None) -> bool:
    from ..exceptions import TrajectoryError
    from ..tables import cells, data_lines, detect_separator, read_text_lines
    from .common import channel_columns

    channels = channel_columns(path, columns)  # a TDMS or HDF5 log: its channels by --columns
    if channels is not None:
        return any(name in channels[0] for name in _RIG_COLUMNS)

    if Path(path).suffix.lower() in (".mot", ".sto", ".parquet"):
        return False
    numbered = data_lines(read_text_lines(path, "log", TrajectoryError))
    if not numbered:
        return False
    header = numbered[0][1]
    names = {
        cell.strip() for cell in cells(header, detect_separator(header, numbered[1][1] if len(numbered) > 1 else None))
    }
    return any(name in names for name in _RIG_COLUMNS)


def _samples(args, params):
    """(t, q, load, name, periodic) of the run to check."""
    if args.log and args.trajectory:
        raise HipsimError("give --log or --trajectory, not both")
    args.trajectory = args.trajectory or args.log
    if args.trajectory and _is_rig_log(args.trajectory, args.columns):
        from ..channels import channel_kind
        from ..rig import load_log

        columns = args.columns if channel_kind(args.trajectory) is not None else None
        log = load_log(args.trajectory, params, args.torque_constant, args.cutoff, columns=columns)
        usable = log.usable
        trajectory = log.trajectory
        return trajectory.t[usable], trajectory.q[usable], trajectory.Fe[usable], log.name, False
    trajectory = load_trajectory(args)
    return trajectory.t, trajectory.q, trajectory.Fe, trajectory.name, trajectory.periodic


def format_check(check, verdict=None) -> str:
    """The check as tables: per quantity, then per cycle (the failing ones when there are many), then the verdict
    (``verdict``: :func:`hipsim.motion.iso_verdict.iso_check_verdict`'s, made from ``check`` when None)."""
    from ..motion.iso_compliance import QUANTITIES
    from ..motion.iso_verdict import iso_check_summary

    verdict = verdict or iso_check_summary(check).verdict

    rows = []
    for q in QUANTITIES:
        ok = check.passes(q)
        unit = {"load": "N", "frequency": "Hz"}.get(q, "°")
        rows.append(
            [
                q,
                f"{check.worst(q):.3g} {unit}",
                f"{getattr(check.tolerances, q):.3g} {unit}",
                "pass" if ok.all() else f"FAIL ({int((~ok).sum())} of {ok.size} cycles)",
            ]
        )
    out = [
        format_table(
            ["quantity", "worst deviation", "tolerance", "verdict"],
            rows,
            f"ISO 14242-1 check of {check.source}: {len(check.cycles)} whole cycle(s), aligned by heel strike",
        )
    ]
    ok = [all(check.passes(q)[k] for q in QUANTITIES) for k in range(len(check.cycles))]
    listed = [k for k in range(len(check.cycles)) if len(check.cycles) <= MAX_LISTED or not ok[k]][:MAX_LISTED]
    if listed:
        rows = [
            [
                str(k + 1),
                f"{c.start:.4f}",
                f"{c.frequency:.4f}",
                *(f"{c.deviation(q):.3g}" for q in ("alpha", "beta", "gamma", "load")),
                "pass" if ok[k] else "FAIL",
            ]
            for k, c in ((k, check.cycles[k]) for k in listed)
        ]
        title = "Per cycle" if len(listed) == len(check.cycles) else f"Failing cycles (first {len(listed)})"
        out += [
            "",
            format_table(
                ["cycle", "start [s]", "f [Hz]", "α [°]", "β [°]", "γ [°]", "load [N]", "verdict"], rows, title
            ),
        ]
    out += [
        "",
        f"verdict: {verdict.level.value}{': ' + ', '.join(check.failing) if verdict.failed else ''} "
        "(tolerances assumed: confirm them against your copy of ISO 14242-1)",
    ]
    return "\n".join(out)


def run(args) -> int:
    """Check the run; write the folder; status 1 when a cycle leaves a tolerance."""
    from ..files import check_folder
    from ..motion.iso_compliance import iso_check, periodic_extension
    from ..motion.iso_verdict import iso_check_summary
    from ..present.iso_figures import write_iso_check
    from ..records import exit_status
    from .documents import IsoCheckRun

    tolerances = parse_tolerance_option(args.tolerance)
    params = parameters(args)
    check_folder(Path(args.out))
    t, q, load, name, periodic = _samples(args, params)
    check = iso_check(t, q, load, tolerances, source=name, periodic=periodic)
    if periodic:  # the cycles may run past the last sample: draw them on the repeated run
        t, q, load = periodic_extension(t, q, load)
    files = write_iso_check(
        args.out, check, t, q, load, page_provenance(args, log=args.trajectory, load=getattr(args, "load", None))
    )
    summary = iso_check_summary(check)
    if args.summary_format == "json":
        print_json(IsoCheckRun(summary, str(files.index)).to_json())
    else:
        print(format_check(check, summary.verdict))
        print(f"wrote {files.index}")
    return exit_status([summary])
