"""``hipsim monitor``: follow a wear test's friction from its snapshots' motor torques; alarm when it departs."""

from __future__ import annotations

import argparse
import shlex
import subprocess
import sys

from ..exceptions import HipsimError
from ..records import exit_status
from .common import (
    add_channel_columns,
    add_provenance_options,
    add_summary_format,
    page_provenance,
    print_json,
    progress,
)

__all__ = ["add_parser", "format_summary", "run"]

#: Defaults written out so that the parser loads nothing heavy (the library's: hipsim.rig.monitoring; a test checks).
DEFAULT_BASELINE = "500000:1000000"
DEFAULT_ALARM_RISE = 0.01
DEFAULT_CUTOFF = 20.0
#: Seconds between looks at the logs with --watch, and since a file's last change before it is read.
DEFAULT_POLL = 30.0
DEFAULT_SETTLE = 5.0
#: Snapshots the baseline needs before the chart starts (the library's MIN_BASELINE), and the fewest it may be set to.
DEFAULT_BASELINE_MIN = 5
LEAST_BASELINE_MIN = 2

_DESCRIPTION = """\
Holds the identified machine (--params, a file written by hipsim identify) fixed and re-estimates, per snapshot, the
friction the motor torques determine: the load term r_h·μ_h + r_t·μ_t (the hip joint's and the thrust bearing's, which one
shared load cannot tell apart), the thrust bearing's weight term, the screw's Coulomb and viscous friction, each with its
standard deviation; with per-station loads logged (Fe_1_N, Fe_2_N), the load term per station when the loads allow.
A change of the load term is attributed to the specimen (thrust bearing unchanged) or to the load cell's calibration
(which it cannot tell apart; with the commanded load logged, Fe_cmd_N, the two loads are compared per snapshot).
A baseline period after running-in (--baseline) gives the reference level and spread; a two-sided EWMA chart tells
significant rises and falls: an alarm when the change exceeds --alarm-rise in one station (on the stations' mean: its
worst case, twice its change), a notice when it is significant but smaller. The chart starts once the baseline holds
--baseline-min snapshots (5). An alarm stays raised (state ALARM, exit 1) until acknowledged with --acknowledge CYCLE
(recorded in the table). Snapshots: rig logs (CSV, TDMS, HDF5) with a 'cycle' column (files, folders, glob patterns),
or long logs cut into --window N cycles. A snapshot that cannot be read is skipped and named with its reason, its size
and SHA-256; a batch run waits up to --settle seconds for files still being written, then reads them; --watch follows
a test in progress (a file changed less than --settle seconds ago waits for the next look). Runs on local worker
processes (dask.distributed, --workers) or a dask cluster (--scheduler). --out is resumed: a rerun estimates only new
or changed snapshots. Exit status: 0 no alarm held at the last snapshot, 1 an alarm held (raised and not
acknowledged), 2 bad input or no usable snapshot."""

_EXAMPLES = """\
examples:
  hipsim monitor --params identified.toml --log snapshots/ --out friction.csv --report monitor_report
  hipsim monitor --params identified.toml --log 'logs/snap_*.csv' --baseline 250000:750000 --alarm-rise 0.02
  hipsim monitor --params identified.toml --log long.csv --window 10 --summary-format json
  hipsim monitor --params identified.toml --log snapshots/ --out friction.csv --acknowledge 4750000
  hipsim monitor --params identified.toml --log snapshots/ --out friction.csv --report page --watch --on-alarm 'notify.sh'
  hipsim monitor ... --watch --on-alarm "sh -c 'cat > alarm.json'"   (no shell unless you run one)
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
        help="snapshot logs: a folder (its *.csv, *.tdms, *.h5, *.hdf5), a file or a glob pattern (repeatable)",
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
        help="engineering threshold: change of the hip friction coefficient in one station, either way "
        f"(default {DEFAULT_ALARM_RISE:g})",
    )
    chart.add_argument(
        "--baseline-min",
        type=int,
        default=DEFAULT_BASELINE_MIN,
        metavar="N",
        help=f"snapshots the baseline needs before the chart starts, a count ≥ {LEAST_BASELINE_MIN} (default "
        f"{DEFAULT_BASELINE_MIN}; fewer gives notices and early alarms)",
    )
    chart.add_argument(
        "--acknowledge",
        type=int,
        action="append",
        default=[],
        metavar="CYCLE",
        help="acknowledge the alarms raised at or before this cycle (a count ≥ 0, at most the last snapshot's; "
        "recorded in --out; repeatable): an alarm is held, exit 1, until acknowledged",
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
        help=f"low-pass cutoff (default {DEFAULT_CUTOFF:g} Hz)",
    )
    add_channel_columns(logs)
    logs.add_argument("--no-filter", action="store_true", help="no low-pass filter (logs filtered already)")
    logs.add_argument(
        "--rate",
        type=float,
        metavar="HZ",
        help="sample rate: read the times from the sample index (time stamps too coarse to order the samples)",
    )
    logs.add_argument(
        "--settle",
        type=float,
        default=DEFAULT_SETTLE,
        metavar="SECONDS",
        help="seconds ≥ 0: a file changed less than this ago is still being written: a batch run waits for it (at "
        f"most this long in all) then reads it, --watch reads it at a later look (default {DEFAULT_SETTLE:g} s)",
    )
    follow = parser.add_argument_group("following a test in progress")
    follow.add_argument(
        "--watch", action="store_true", help="keep watching the logs, updating table and page (Ctrl-C stops)"
    )
    follow.add_argument(
        "--poll",
        type=float,
        default=DEFAULT_POLL,
        metavar="SECONDS",
        help=f"seconds between looks at the logs with --watch (default {DEFAULT_POLL:g})",
    )
    follow.add_argument(
        "--on-alarm",
        metavar="CMD",
        help="with --watch, run this program once each time an alarm is raised (the summary JSON on its standard "
        "input); split like a shell's words but run without a shell: for pipes or redirection run one, "
        "\"sh -c 'cat > alarm.json'\"",
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
    out.add_argument(
        "--pdf", action="store_true", help="also print the page to DIR/report.pdf (needs Chromium on PATH)"
    )
    add_provenance_options(parser)
    add_summary_format(parser)
    parser.set_defaults(run=run)
    return parser


def _check(args) -> None:
    """The options, one line each when wrong."""
    if args.workers is not None and args.workers < 1:
        raise HipsimError(f"--workers: expected a positive number of processes, got {args.workers}")
    if not (args.alarm_rise > 0):
        raise HipsimError(
            f"--alarm-rise: expected a positive change of the hip friction coefficient, got {args.alarm_rise:g}"
        )
    if args.window is not None and args.window < 1:
        raise HipsimError(f"--window: expected a positive number of cycles, got {args.window}")
    if args.rate is not None and not (0 < args.rate < float("inf")):
        raise HipsimError(f"--rate: expected a positive sample rate in Hz, got {args.rate:g}")
    if not (0 <= args.settle < float("inf")):
        raise HipsimError(f"--settle: expected seconds ≥ 0, got {args.settle:g}")
    if args.baseline_min < LEAST_BASELINE_MIN:
        raise HipsimError(
            f"--baseline-min: expected a count of snapshots ≥ {LEAST_BASELINE_MIN}, got {args.baseline_min}"
        )
    for cycle in args.acknowledge:
        if cycle < 0:
            raise HipsimError(f"--acknowledge: expected a cycle ≥ 0, got {cycle}")
    if not (0 < args.poll < float("inf")):
        raise HipsimError(f"--poll: expected seconds > 0, got {args.poll:g}")
    if args.on_alarm and not args.watch:
        raise HipsimError("--on-alarm: runs with --watch only (a single run's alarm is its exit status 1)")
    if args.pdf and not args.report:
        raise HipsimError("--pdf: prints the page, so it needs --report DIR")
    if args.on_alarm:
        try:
            if not shlex.split(args.on_alarm):
                raise ValueError("empty")
        except ValueError as error:
            raise HipsimError(f"--on-alarm: expected a command, got '{args.on_alarm}' ({error})") from None


def run(args) -> int:
    """Estimate, chart, write; exit status 1 when an alarm is active at the last snapshot."""
    from ..files import check_folder
    from ..rig.monitoring.control_chart import parse_baseline
    from ..rig.monitoring.monitor_fit import MonitorSetup
    from ..rig.monitoring.monitor_table import MONITOR_TABLE
    from ..rig.monitoring.reference import reference

    _check(args)
    try:
        baseline = parse_baseline(args.baseline)
    except HipsimError:
        raise HipsimError(
            f"--baseline: expected FROM:TO in cycles, 0 ≤ FROM ≤ TO, e.g. {DEFAULT_BASELINE}, got '{args.baseline}'"
        ) from None
    cutoff = None if args.no_filter else args.cutoff
    # Every input is read and checked before the first estimate: nothing is written on bad input.
    params, spin = reference(args.params)
    if args.out:
        MONITOR_TABLE.check_out(args.out)
    if args.report:
        check_folder(args.report)
    if args.pdf:
        from ..present.pages import require_pdf_renderer

        require_pdf_renderer()  # no Chromium: said before the computing
    setup = MonitorSetup(
        params,
        lever_spin=spin,
        cutoff=cutoff,
        torque_constant=args.torque_constant,
        window=args.window,
        rate=args.rate,
        columns=args.columns,
    )
    provenance = page_provenance(argparse.Namespace(**(vars(args) | {"overrides": []})))
    metadata = {"hipsim": provenance.version, "parameters_file": args.params}
    if args.watch:
        return _watch(args, setup, baseline, provenance, metadata)
    from ..rig.monitoring.monitor_run import run_monitor
    from ..rig.monitoring.snapshots import find_snapshots

    snapshots, skipped = find_snapshots(
        args.log, args.window, args.settle, args.torque_constant, args.rate, wait=True, columns=args.columns
    )
    result = run_monitor(
        setup,
        snapshots,
        baseline,
        args.alarm_rise,
        args.out,
        args.restart,
        args.workers,
        args.scheduler,
        progress=progress("monitor", " snapshots"),  # a bar on a terminal (a first run takes a while)
        metadata=metadata,
        skipped=skipped,
        baseline_min=args.baseline_min,
        acknowledge=args.acknowledge,
    )
    document = _outputs(args, result, provenance)
    if args.summary_format == "json":
        print_json(document.to_json())
    else:
        print(format_summary(document, result))
    return exit_status([result.state])


def _outputs(args, result, provenance, said: set | None = None):
    """Warnings for the skipped snapshots (standard error; with ``said``, each once), the page when asked; the summary."""
    for skipped in result.skipped:
        label = "waiting" if skipped.kind == "waiting" else "skipped"
        line = f"hipsim: warning: {label} {skipped.name}: {skipped.reason}"
        if said is None or line not in said:
            print(line, file=sys.stderr)
        if said is not None:
            said.add(line)
    from .documents import MonitorRun, ReportFiles

    report = None
    if args.report:
        from ..present.monitor_page import write_monitor_report

        files = write_monitor_report(args.report, result, provenance, pdf=args.pdf)
        report = ReportFiles(str(files.index), str(files.pdf) if files.pdf is not None else None)
    return MonitorRun(result.summary(), args.out, provenance.as_dict(), report)


def _watch(args, setup, baseline, provenance, metadata) -> int:
    """--watch: follow the logs until Ctrl-C; each update's line on standard output."""
    import json

    from ..files import json_ready
    from ..rig.monitoring.watch import watch

    said: set[str] = set()

    def update(result) -> None:
        summary = _outputs(args, result, provenance, said).summary
        last = result.columns
        print(
            f"{len(last['cycle'])} snapshots to cycle {summary.last_cycle}: "
            + (
                f"ALARM (raised at cycle {summary.alarm_raised_at}, held until acknowledged)"
                if summary.alarm_active
                else "no alarm held at the last snapshot"
            )
            + (f"; {last['flag'][-1]}" if last["flag"][-1] else ""),
            flush=True,
        )

    def on_alarm(result) -> None:
        document = json.dumps(json_ready(result.summary().to_json()))
        try:
            subprocess.run(shlex.split(args.on_alarm), input=document, text=True, check=False, timeout=600)
        except (OSError, subprocess.TimeoutExpired) as error:
            print(f"hipsim: warning: --on-alarm '{args.on_alarm}' did not run: {error}", file=sys.stderr)

    try:
        result = watch(
            setup,
            args.log,
            baseline,
            args.alarm_rise,
            args.out,
            args.restart,
            args.poll,
            args.settle,
            update=update,
            on_alarm=on_alarm if args.on_alarm else None,
            workers=args.workers,
            scheduler=args.scheduler,
            metadata=metadata,
            baseline_min=args.baseline_min,
            acknowledge=args.acknowledge,
        )
    except KeyboardInterrupt:
        print("hipsim: stopped watching; the table and page are those of the last update", file=sys.stderr)
        return 130
    return exit_status([None if result is None else result.state])


def format_summary(document, result) -> str:
    """The monitor's summary (:class:`hipsim.cli.documents.MonitorRun`) as plain text, the snapshots as a table."""
    from ..present.numbers import significant
    from ..present.tables import format_table

    summary = document.summary
    b = summary.baseline
    lines = [
        f"monitor of {summary.snapshots} snapshots, cycles {summary.first_cycle}-{summary.last_cycle}: "
        f"{summary.new} estimated, {summary.kept} kept from {document.out or 'no table'}",
        f"parameters: {summary.parameters}; chart: {summary.chart}; alarm at a change of {summary.alarm_rise:g} "
        f"in one station, judged on {summary.judged}",
    ]
    if summary.note:
        lines.append(summary.note)
    else:
        lines.append(
            f"baseline cycles {b.from_}-{b.to}: {b.snapshots} snapshots, load friction "
            f"{significant(b.load_friction_mm, 5)} mm ± {significant(b.spread_mm, 2)} mm between snapshots"
        )
    for label, items in (("skipped", summary.skipped), ("waiting", summary.waiting)):
        for item in items:
            known = f" ({item.bytes:,} bytes, SHA-256 {item.sha256})" if item.sha256 and item.bytes is not None else ""
            lines.append(f"{label} {item.file}: {item.reason}{known}")
    if summary.missing:
        lines.append("missing: " + ", ".join(f"{c:,}" for c in summary.missing))
    c = result.columns
    rows = []
    for k in range(len(c["cycle"])):
        change, ack = c["hip_mu_change"][k], c["acknowledged"][k]
        rows.append(
            [
                f"{c['cycle'][k] / 1e6:.3f}",
                c["file"][k],
                c["phase"][k],
                f"{c['load_friction_mm'][k]:.4f}",
                f"{c['load_friction_mm_std'][k]:.4f}",
                "" if change != change else f"{change:+.4f}",
                f"{c['residual_rms_Nmm'][k]:.3g}",
                c["flag"][k],
                c["state"][k] + ("" if ack != ack else f" (acknowledged {int(ack):,})"),
                c["note"][k],
            ]
        )
    lines += [
        "",
        format_table(
            [
                "Mc",
                "file",
                "phase",
                "load friction [mm]",
                "std [mm]",
                "Δμ_h",
                "residual [N·mm]",
                "flag",
                "state",
                "note",
            ],
            rows,
            "Snapshots",
        ),
    ]
    first = summary.first_alarm
    lines.append("\nfirst " + first.text + f" (cycle {first.cycle}, {first.file})" if first else "\nno alarm")
    notice = summary.latest_notice
    if notice:
        lines.append("latest " + notice.text + f" (cycle {notice.cycle}, {notice.file})")
    if summary.acknowledged:
        lines.append("acknowledged: " + ", ".join(f"cycle {c:,}" for c in summary.acknowledged))
    lines.append(
        f"state: ALARM, raised at cycle {summary.alarm_raised_at:,} and held until acknowledged "
        f"(--acknowledge {summary.alarm_raised_at})"
        if summary.alarm_active
        else f"state: {summary.state} at the last snapshot"
    )
    if document.out:
        lines.append(f"wrote {document.out} ({summary.snapshots} rows)")
    if document.report is not None:
        pdf = document.report.pdf
        lines.append(f"wrote {document.report.report}" + (f" and {pdf}" if pdf else ""))
    return "\n".join(lines)
