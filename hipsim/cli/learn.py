"""``hipsim learn``: the next cycle's carriage commands, learned from the last run's log (iterative learning control).

Without ``--log``: cycle 0, the model's own command (as ``hipsim stations`` makes it). With ``--log RUN.csv``: the
update u_{k+1} = Q(u_k + L·e_k) of :mod:`hipsim.learning.law` from the run's sensors, checked for convergence first.
Writes NEXT (the columns of ``stations``' table: t_s, L_11_mm.., the model's prediction alpha_1_deg.., err_..,
Fe_N), one period, periodic; prints the step's summary.
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path

from ..exceptions import ArgumentError, HipsimError
from .common import add_machine_options, add_summary_format, parameters, print_json
from .motion_options import add_trajectory_options, load_trajectory

__all__ = ["add_learning_options", "add_parser", "learning_law", "run"]

#: Hard ranges of the law's options: (lowest, highest), each in the option's unit.
GAIN_RANGE = (0.0, 10.0)
LAG_RANGE_MS = (0.0, 1000.0)


def add_learning_options(parser: argparse.ArgumentParser) -> None:
    """The law's options, shared by ``learn`` and ``simulate --learn``."""
    group = parser.add_argument_group("learning law (u_{k+1} = Q(u_k + L e_k); docs/guide/learning.md)")
    group.add_argument(
        "--gain",
        type=float,
        default=1.0,
        metavar="G",
        help="learning gain γ, dimensionless, in (0, 10] (default 1: the model's whole correction at once; it "
        "converges on the model for γ < 2)",
    )
    group.add_argument(
        "--q-cutoff",
        type=float,
        default=10.0,
        metavar="HZ",
        help="cutoff of the zero-phase periodic low-pass Q in Hz, above 0 and at most half the sample rate "
        "(default 10)",
    )
    group.add_argument(
        "--drive-lag",
        type=float,
        default=0.0,
        metavar="MS",
        help="the drive's position loop as the model knows it: a first-order lag, time constant in ms, in [0, 1000] "
        "(default 0: none)",
    )


def learning_law(args, params, rate: float):
    """The law from the options, each checked against its hard range; ``rate`` the desired motion's in [Hz]."""
    from ..learning.law import LearningLaw
    from .stations import parse_weights

    low, high = GAIN_RANGE
    if not (math.isfinite(args.gain) and low < args.gain <= high):
        raise HipsimError(f"--gain: expected a learning gain in ({low:g}, {high:g}] (dimensionless), got {args.gain:g}")
    nyquist = rate / 2.0
    if not (math.isfinite(args.q_cutoff) and 0.0 < args.q_cutoff <= nyquist):
        raise HipsimError(
            f"--q-cutoff: expected a frequency in (0, {nyquist:g}] Hz (half the sample rate), got {args.q_cutoff:g} Hz"
        )
    low, high = LAG_RANGE_MS
    if not (math.isfinite(args.drive_lag) and low <= args.drive_lag <= high):
        raise HipsimError(f"--drive-lag: expected a time constant in [{low:g}, {high:g}] ms, got {args.drive_lag:g} ms")
    control = args.control or (str(params.geometry.control) if params.geometry is not None else "2")
    return LearningLaw(control, parse_weights(args), args.gain, args.q_cutoff, args.drive_lag * 1e-3)


def add_parser(subparsers) -> argparse.ArgumentParser:
    """Register ``learn`` on the main parser's subcommands."""
    p = subparsers.add_parser(
        "learn",
        help="next cycle's carriage commands learned from the last run's log (iterative learning control) -> NEXT",
        description="Iterative learning from one run to the next: reads a run's log (t_s, encoders L_11_mm.., the "
        "commands L_11_cmd_mm.. when logged, the attitude sensors alpha_1_deg..gamma_2_deg; one period or several, "
        "averaged per phase; t_s on the command's clock) and writes the next command, one period, periodic, with the "
        "columns of hipsim stations' table. Without --log, cycle 0: the model's own command. The update "
        "u_{k+1} = Q(u_k + L e_k) inverts the model's carriage-to-attitude Jacobian at the desired motion; a step "
        "the model or the log's drive response says would diverge is refused.",
    )
    add_machine_options(p)
    add_trajectory_options(p)
    p.add_argument("--log", metavar="RUN", help="the last run's log, .csv or .parquet (without it: cycle 0)")
    p.add_argument(
        "--previous",
        metavar="NEXT",
        help="the command file the run executed (the last NEXT), for a log without the command columns "
        "L_11_cmd_mm..: without either, the encoders stand for the commands (exact only for a drive that follows them)",
    )
    p.add_argument(
        "--control",
        choices=["1", "2", "both"],
        help="the platform learned: 1, 2 or both (default: the parameter file's [geometry] control, else 2)",
    )
    p.add_argument(
        "--weights", metavar="W1,W2", help="weights of the two platforms' squared errors for both (default 1,1)"
    )
    add_learning_options(p)
    p.add_argument(
        "--out",
        default="hipsim_next.csv",
        metavar="NEXT",
        help="the next command, .csv or .parquet (default hipsim_next.csv)",
    )
    add_summary_format(p, "what to print: the step's summary as a table (default) or JSON")
    p.set_defaults(run=run)
    return p


def _one_period(args, trajectory) -> None:
    if not args.trajectory and args.cycles not in (None, 1, 1.0):
        raise HipsimError(f"--cycles {args.cycles:g}: a learned command is one period; leave --cycles out")
    if not trajectory.periodic:
        raise HipsimError(
            f"--trajectory {args.trajectory}: a learned command repeats one period; the file is not one whole period"
        )


def run(args) -> int:
    """Write the next command and print the step's summary; exit status 0."""
    import numpy as np

    from ..files import ColumnWriter, check_output
    from ..learning.step import CycleLog, first_command, first_summary, learning_step
    from ..stations.logs import read_run_log
    from ..stations.summary import station_columns

    out = Path(args.out)
    if out.suffix.lower() not in (".csv", ".parquet"):
        raise HipsimError(f"--out {args.out}: expected a .csv or .parquet file")
    for option, given in (("--log", args.log), ("--previous", args.previous)):
        if given and out.exists() and Path(given).exists() and out.resolve() == Path(given).resolve():
            raise HipsimError(f"--out {args.out} is the {option} file itself: choose another output")
    if args.previous and not args.log:
        raise HipsimError("--previous applies with --log (the command that run executed)")
    check_output(out)
    params = parameters(args)
    desired = load_trajectory(args)
    _one_period(args, desired)
    rate = (len(desired) - 1) / float(desired.t[-1] - desired.t[0])
    law = learning_law(args, params, rate)
    try:
        if args.log is None:
            summary = first_summary(desired, law)
            command = first_command(params, desired, law)
        else:
            t, encoders, commands, sensors = read_run_log(args.log, params.lead, law.platforms)
            if args.previous is not None:
                if commands is not None:
                    raise HipsimError(f"--previous {args.previous}: the log {args.log} has the commands already")
                commands = _previous_commands(args.previous, t)
            logged = commands is not None
            if commands is None:  # the encoders stand for the commands
                commands = encoders
            log = CycleLog(t, encoders, commands, sensors, logged, args.log)
            step = learning_step(params, desired, log, law)
            command, summary = step.command, step.summary
    except ArgumentError as error:  # the library names its argument; the user typed an option
        if error.name == "gain":
            raise HipsimError(f"--gain: expected {error.expected}, got {args.gain:g}") from None
        raise
    columns = station_columns(command, desired.Fe if desired.Fe.any() else None)
    if not all(np.all(np.isfinite(v)) for v in columns.values()):
        raise HipsimError(f"--out {args.out}: the next command is not finite; nothing written")
    with ColumnWriter(out) as writer:  # CSV or Parquet by the suffix, atomically
        writer.write(columns)
        writer.close()
    if args.summary_format == "json":
        print_json({"summary": summary.to_json(), "out": str(out)})
    else:
        print(format_summary(summary))
        print(f"wrote {out}")
    return 0


def _previous_commands(path: str, t):
    """The command file's carriages [m] at the log's times t (N,) [s], the file one period on the command's clock."""
    import numpy as np

    from ..learning.command_file import read_command_file

    command = read_command_file(path)
    n = len(command.t)
    if n < 2:
        raise HipsimError(f"--previous {path}: {n} row(s); a command is one period of at least 2")
    period = (command.t[-1] - command.t[0]) * n / (n - 1)
    return np.stack([np.interp(t, command.t, command.L[:, i], period=period) for i in range(3)], axis=1)


def format_summary(summary) -> str:
    """A step's summary as plain text: errors per platform and angle, convergence, the update, the verdicts."""
    from ..present.tables import format_table

    lines = []
    if summary.errors:
        rows = [
            [
                f"m_{e.platform} ({'learned' if e.controlled else 'not learned'})",
                name,
                f"{e.rms_deg[k]:.4g}",
                f"{e.peak_deg[k]:.4g}",
                f"{e.peak_at_s[k]:.4g}",
            ]
            for e in summary.errors
            for k, name in enumerate(("alpha", "beta", "gamma"))
        ]
        title = f"measured error of the run learned from ({summary.periods} period(s) averaged), --control {summary.control}"
        lines.append(format_table(["platform", "angle", "RMS [°]", "peak [°]", "at t [s]"], rows, title))
    c = summary.convergence
    data = f"{c.data:.3g} (worst at {c.data_at_Hz:.3g} Hz)" if c.data is not None else f"not measured ({c.note})"
    lines.append(f"convergence ‖Q(I − L·P)‖: on the model {c.model:.3g}; with the log's drive {data}")
    if summary.update is not None:
        u = summary.update
        lines.append(
            "update: command changed by RMS "
            + ", ".join(f"L_1{i + 1} {u.change_rms_mm[i]:.4g} mm" for i in range(3))
            + "; learned correction peak "
            + ", ".join(f"{u.learned_peak_mm[i]:.4g}" for i in range(3))
            + " mm"
        )
    for s in summary.stations:
        reason = f" ({s.reason})" if s.reason else ""
        lines.append(f"station {s.platform}: ISO 14242-1 check of its measured motion: {s.verdict}{reason}")
    d = summary.desired
    if d is not None and d.verdict == "FAIL":
        lines.append(
            "the desired motion is not the ISO 14242-1 waveform itself: worst "
            + ", ".join(f"{a} {w:.3g}°" for a, w in zip(("α", "β", "γ"), d.worst_deg))
            + " off; the stations' verdicts judge their motion against the waveform, not their tracking"
        )
    return "\n".join(lines)
