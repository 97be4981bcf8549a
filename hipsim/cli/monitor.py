"""``hipsim monitor``: follow a wear test's friction from its snapshots' motor torques; alarm when it departs."""

from __future__ import annotations

import argparse
import sys

from ..exceptions import HipsimError
from .common import add_provenance_options, add_summary_format, page_provenance, print_json

__all__ = ["add_parser", "format_summary", "run"]

#: Defaults written out so that the parser loads nothing heavy (the library's: hipsim.rig.monitoring.control_chart; a test checks).
DEFAULT_BASELINE = "500000:1000000"
DEFAULT_ALARM_RISE = 0.01
DEFAULT_CUTOFF = 20.0

_DESCRIPTION = """\
Holds the identified machine (--params, a file written by hipsim identify) fixed and re-estimates, per snapshot, the
friction the motor torques determine: the load term r_h·μ_h + r_t·μ_t (the hip joint's and the thrust bearing's, which one
shared load cannot tell apart), the thrust bearing's weight term, the screw's Coulomb and viscous friction, each with its
standard deviation; with per-station loads logged (Fe_1_N, Fe_2_N), the load term per station when the loads allow.
A change of the load term is attributed to the specimen (thrust bearing unchanged): hip_mu_change. A baseline period after
running-in (--baseline) gives the reference level and spread; an EWMA chart tells significant rises, and an alarm is raised
when a significant rise of the hip friction coefficient exceeds --alarm-rise. Snapshots: CSV rig logs with a 'cycle' column
(files, folders, glob patterns), or long logs cut into --window N cycles. Runs on local worker processes (dask.distributed,
--workers) or a dask cluster (--scheduler). --out is resumed: a rerun estimates only new snapshots. Exit status: 0 no alarm
at the last snapshot, 1 an alarm active at the last snapshot, 2 bad input."""

_EXAMPLES = """\
examples:
  hipsim monitor --params identified.toml --log snapshots/ --out friction.csv --report monitor_report
  hipsim monitor --params identified.toml --log 'logs/snap_*.csv' --baseline 250000:750000 --alarm-rise 0.02
  hipsim monitor --params identified.toml --log long.csv --window 10 --summary-format json
"""


def add_parser(subparsers) -> argparse.ArgumentParser:
    """Register ``monitor``."""
    parser = subparsers.add_parser(
        "monitor",
        help="follow a wear test's friction from snapshot logs; alarm when it departs (exit 1)",
        description=_DESCRIPTION,
        epilog=_EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument(
        "--params", required=True, metavar="FILE", help="identified parameter TOML (hipsim identify --out)"
    )
    parser.add_argument(
        "--log",
        required=True,
        action="append",
        metavar="DIR_OR_FILES",
        help="snapshot logs: a folder (its *.csv), a file or a glob pattern (repeatable)",
    )
    parser.add_argument("--window", type=int, metavar="N", help="cut each log into windows of N cycles (one long log)")
    chart = parser.add_argument_group("chart")
    chart.add_argument(
        "--baseline",
        default=DEFAULT_BASELINE,
        metavar="FROM:TO",
        help=f"baseline cycles, after running-in (default {DEFAULT_BASELINE})",
    )
    chart.add_argument(
        "--alarm-rise",
        type=float,
        default=DEFAULT_ALARM_RISE,
        metavar="D",
        help=f"engineering threshold: rise of the hip friction coefficient (default {DEFAULT_ALARM_RISE:g})",
    )
    logs = parser.add_argument_group("logs")
    logs.add_argument(
        "--torque-constant", type=float, metavar="NM_PER_A", help="motor torque constant in N·m/A, for logs of currents"
    )
    logs.add_argument(
        "--cutoff",
        type=float,
        default=DEFAULT_CUTOFF,
        metavar="HZ",
        help=f"low-pass cutoff (default {DEFAULT_CUTOFF:g} Hz; 0: none)",
    )
    engine = parser.add_argument_group("engine (dask.distributed; pip install 'hipsim[sweep]')")
    engine.add_argument(
        "--workers", type=int, default=1, metavar="N", help="local worker processes (default 1: in this process)"
    )
    engine.add_argument(
        "--scheduler", metavar="ADDRESS", help="run on the dask cluster of this scheduler, e.g. tcp://10.0.0.5:8786"
    )
    out = parser.add_argument_group("output")
    out.add_argument(
        "--out", metavar="FILE", help="the table, .csv or .parquet; an existing one of the same set-up is extended"
    )
    out.add_argument("--restart", action="store_true", help="replace an existing --out instead of extending it")
    out.add_argument(
        "--report", metavar="DIR", help="write the report (index.html, figures PNG/SVG, monitor.json) to this folder"
    )
    add_provenance_options(parser)
    add_summary_format(parser)
    parser.set_defaults(run=run)
    return parser


def run(args) -> int:
    """Estimate, chart, write; exit status 1 when an alarm is active at the last snapshot."""
    from ..files import check_folder
    from ..rig.monitoring.control_chart import parse_baseline
    from ..rig.monitoring.monitor_fit import MonitorSetup, reference
    from ..rig.monitoring.monitor_run import run_monitor
    from ..rig.monitoring.monitor_table import check_out
    from ..rig.monitoring.snapshots import find_snapshots

    if args.workers is not None and args.workers < 1:
        raise HipsimError(f"--workers: expected a positive number of processes, got {args.workers}")
    if not (args.alarm_rise > 0):
        raise HipsimError(
            f"--alarm-rise: expected a positive rise of the hip friction coefficient, got {args.alarm_rise:g}"
        )
    if args.window is not None and args.window < 1:
        raise HipsimError(f"--window: expected a positive number of cycles, got {args.window}")
    try:
        baseline = parse_baseline(args.baseline)
    except HipsimError:
        raise HipsimError(
            f"--baseline: expected FROM:TO in cycles, 0 ≤ FROM ≤ TO, e.g. {DEFAULT_BASELINE}, got '{args.baseline}'"
        ) from None
    cutoff = args.cutoff if args.cutoff and args.cutoff > 0 else None
    # Every input is read and checked before the first estimate: nothing is written on bad input.
    params, spin = reference(args.params)
    if args.out:
        check_out(args.out)
    if args.report:
        check_folder(args.report)
    setup = MonitorSetup(
        params, lever_spin=spin, cutoff=cutoff, torque_constant=args.torque_constant, window=args.window
    )
    snapshots = find_snapshots(args.log, args.window, cutoff)
    provenance = page_provenance(argparse.Namespace(**(vars(args) | {"overrides": []})), parameters=args.params)
    bar = _progress_bar(len(snapshots))
    try:
        result = run_monitor(
            setup,
            snapshots,
            baseline,
            args.alarm_rise,
            args.out,
            args.restart,
            args.workers,
            args.scheduler,
            progress=lambda n, total: bar.update(n - bar.n),
            metadata={"hipsim": provenance.version, "parameters_file": args.params},
        )
    finally:
        bar.close()
    summary = result.summary() | {"out": args.out, "provenance": provenance.as_dict()}
    if args.report:
        from ..present.monitor_page import write_monitor_report

        files = write_monitor_report(args.report, result, provenance)
        summary["report"] = str(files.index)
    if args.summary_format == "json":
        print_json(summary)
    else:
        print(format_summary(summary, result))
    return 1 if summary["alarm_active"] else 0


def _progress_bar(total: int):
    from tqdm.auto import tqdm

    return tqdm(total=total, disable=not sys.stderr.isatty(), unit="snapshot", delay=2.0, leave=False)


def format_summary(summary: dict, result) -> str:
    """The monitor's summary as plain text, the snapshots as a table."""
    from ..present.numbers import significant
    from ..present.tables import format_table

    b = summary["baseline"]
    lines = [
        f"monitor of {summary['snapshots']} snapshots, cycles {summary['first_cycle']}-{summary['last_cycle']}: "
        f"{summary['new']} estimated, {summary['kept']} kept from {summary['out'] or 'no table'}",
        f"parameters: {summary['parameters']}; chart: {summary['chart']}; alarm rise {summary['alarm_rise']:g}",
    ]
    if summary["note"]:
        lines.append(summary["note"])
    else:
        lines.append(
            f"baseline cycles {b['from']}-{b['to']}: {b['snapshots']} snapshots, load friction {significant(b['load_friction_mm'], 5)} mm "
            f"± {significant(b['spread_mm'], 2)} mm between snapshots; threshold {significant(summary['threshold_mm'], 5)} mm"
        )
    c = result.columns
    rows = []
    for k in range(len(c["cycle"])):
        change = c["hip_mu_change"][k]
        rows.append(
            [
                str(c["cycle"][k]),
                c["file"][k],
                c["phase"][k],
                f"{c['load_friction_mm'][k]:.4f}",
                f"{c['load_friction_mm_std'][k]:.4f}",
                "" if change != change else f"{change:+.4f}",
                f"{c['residual_rms_Nmm'][k]:.3g}",
                "ALARM" if c["alarm"][k] else "",
            ]
        )
    lines += [
        "",
        format_table(
            ["cycle", "file", "phase", "load friction [mm]", "std [mm]", "Δμ_h", "residual [N·mm]", "alarm"],
            rows,
            "Snapshots",
        ),
    ]
    first = summary["first_alarm"]
    if first:
        lines.append(
            f"\nfirst alarm at cycle {first['cycle']} ({first['file']}): hip friction coefficient up by {first['hip_mu_change']:+.4f} "
            f"± {first['hip_mu_change_std']:.2g} (load friction {first['load_friction_change_mm']:+.4g} mm)"
        )
    else:
        lines.append("\nno alarm")
    lines.append("ALARM ACTIVE at the last snapshot" if summary["alarm_active"] else "no alarm at the last snapshot")
    if summary.get("out"):
        lines.append(f"wrote {summary['out']} ({summary['snapshots']} rows)")
    if summary.get("report"):
        lines.append(f"wrote {summary['report']}")
    return "\n".join(lines)
