"""What the commands share: the machine options, the summary format, and helpers every run uses.

Only the standard library is imported here at module level, so that building
the parser (``hipsim --help``) stays fast; each helper imports what it needs.
"""

from __future__ import annotations

import argparse
import json
import sys

from ..clock import Clock, note_if_slow
from ..exceptions import HipsimError
from .motion_options import builtin_frequency

__all__ = [
    "CHANNEL_COLUMNS_HELP",
    "add_channel_columns",
    "channel_columns",
    "add_machine_options",
    "add_provenance_options",
    "add_summary_format",
    "desired_motion",
    "load_pinocchio_kernels",
    "note",
    "numbers",
    "page_provenance",
    "parameters",
    "print_json",
    "progress",
]


def add_machine_options(parser: argparse.ArgumentParser) -> None:
    """``--params FILE`` and ``--set KEY=VALUE``: the machine a command runs on."""
    group = parser.add_argument_group("machine")
    group.add_argument("--params", metavar="FILE", help="parameter TOML file (default: the published machine)")
    group.add_argument(
        "--set",
        dest="overrides",
        metavar="KEY=VALUE",
        action="append",
        default=[],
        help="override one parameter in the file's units, e.g. lever.length_mm=330 (repeatable)",
    )


#: ``--columns`` on a TDMS or HDF5 log (:mod:`hipsim.channels`): which channel holds which column.
CHANNEL_COLUMNS_HELP = (
    "a TDMS or HDF5 log's channels: NAME=GROUP/CHANNEL,… (NAME a CSV column's name with its unit, e.g. "
    "Fe_N=Load/Fz; an HDF5 dataset's path), GROUP to read a group's channels by their names; default: the file's one "
    "group, each channel by its name and unit (unit_string)"
)


def add_channel_columns(parser) -> None:
    """``--columns MAP``: a TDMS or HDF5 log's channel map (:data:`CHANNEL_COLUMNS_HELP`), for the commands that read
    rig logs and have no trajectory column map (those read it from their ``--columns`` when the log is TDMS or HDF5)."""
    parser.add_argument("--columns", metavar="MAP", help=CHANNEL_COLUMNS_HELP)


def channel_columns(path: str, columns: str | None) -> tuple[set[str], str | None] | None:
    """A TDMS or HDF5 log's column names and the map to read it with (``--columns``), or None for any other file.

    For the commands whose ``--columns`` maps a trajectory's columns (``wear``, ``iso-check``): on a TDMS or HDF5
    log it is the channel map (:mod:`hipsim.channels`), the only map such a file takes.

    Raises:
        TrajectoryError: the file's problem (:func:`hipsim.channels.read_channels`), or a file without torques or
            currents: such a file is read as a rig log only.
    """
    from ..channels import channel_kind, read_channels
    from ..exceptions import TrajectoryError

    if channel_kind(path) is None:
        return None
    names = set(read_channels(path, columns, "log file", TrajectoryError).names)
    if not names & {"tau_1_Nmm", "current_1_A"}:
        raise TrajectoryError(
            "a TDMS or HDF5 file is read as a rig log (t_s, Fe_N, tau_1_Nmm … or current_1_A …, the motion); this one "
            f"has no torques or currents (its columns: {', '.join(sorted(names)[:12]) or 'none'})",
            source=path,
        )
    return names, columns


def add_provenance_options(parser: argparse.ArgumentParser) -> None:
    """``--title``, ``--author``, ``--rig``: the lab's own fields of a page's provenance block."""
    group = parser.add_argument_group("provenance (shown on the page and in the JSON)")
    group.add_argument("--title", metavar="TEXT", help="the page's title, e.g. 'Drive review, rig 2, March'")
    group.add_argument("--author", metavar="NAME", help="who made the report")
    group.add_argument("--rig", metavar="NAME", help="the rig's name or serial number")


def page_provenance(args, **inputs):
    """The provenance block of a command's page: version, time, this command line, the inputs hashed, the parameters' origin.

    Args:
        args: the parsed options (``--params``, ``--set`` and, when the command has them, ``--title``, ``--author``,
            ``--rig``; ``option_warnings``, what the option table warned of, kept in the block).
        inputs: role → a file path, a list of them, or None: the command's input files (trajectory, logs, drive, ...).
    """
    from ..present.provenance import parameter_origin, provenance

    return provenance(
        {role: value for role, value in inputs.items() if value},
        parameter_origin(args.params, args.overrides),
        getattr(args, "command_line", None) or ["hipsim", *sys.argv[1:]],
        getattr(args, "title", None),
        getattr(args, "author", None),
        getattr(args, "rig", None),
        warnings=getattr(args, "option_warnings", None) or (),
    )


def add_summary_format(
    parser: argparse.ArgumentParser, help: str = "summary on standard output: tables (default) or JSON"
) -> None:
    """``--summary-format table|json``."""
    parser.add_argument("--summary-format", choices=["table", "json"], default="table", help=help)


def print_json(document, stream=None) -> None:
    """A summary as indented JSON (NaN and infinities as null)."""
    from ..files import json_ready

    print(json.dumps(json_ready(document), indent=2), file=stream if stream is not None else sys.stdout)


def parameters(args):
    """The parameter set the machine options ask for: ``--params`` (or the published machine) with the ``--set`` overrides."""
    import warnings

    from ..machine.parameters import ParameterWarning, load_parameters, parse_override

    overrides = dict(parse_override(text, source="--set") for text in args.overrides)
    with warnings.catch_warnings(record=True) as caught:  # a value outside its plausible range: one line each
        warnings.simplefilter("always", ParameterWarning)
        params = load_parameters(args.params, overrides, overrides_source="--set")
    for warning in caught:
        if issubclass(warning.category, ParameterWarning):
            print(f"hipsim: warning: {warning.message}", file=sys.stderr)
        else:
            warnings.showwarning(warning.message, warning.category, warning.filename, warning.lineno)
    return params


def numbers(text: str, separator: str, option: str, expected: str, count: int | None = None) -> list[float]:
    """Finite numbers from an option's text, or a one-line error naming the option."""
    import numpy as np

    try:
        if "_" in text:  # Python's float() reads "1_0" as 10; a user would not mean that
            raise ValueError(text)
        values = [float(part) for part in text.split(separator)]
    except ValueError:
        raise HipsimError(f"{option}: expected {expected}, got '{text}'") from None
    if (count is not None and len(values) != count) or not all(np.isfinite(values)):
        raise HipsimError(f"{option}: expected {expected}, got '{text}'")
    return values


def progress(what: str, unit: str = " samples"):
    """A progress callback (done, total) drawing a tqdm bar on a terminal once a run takes over 2 s; None elsewhere.

    Args:
        what: the bar's label.
        unit: what is counted, as the bar says it (" samples", " snapshots", " steps").
    """
    if not sys.stderr.isatty():
        return None
    from tqdm import tqdm

    bars: list[tqdm] = []

    def update(done: int, total: int) -> None:
        if not bars:
            bars.append(
                tqdm(total=total, desc=what, unit=unit, unit_scale=True, delay=2.0, file=sys.stderr, leave=False)
            )
        bars[0].update(done - bars[0].n)
        if done >= total:
            bars[0].close()

    return update


def note(message: str) -> None:
    """A message of the library's for the user, on standard error (standard output may carry results)."""
    print(message, file=sys.stderr, flush=True)


def load_pinocchio_kernels(clock: Clock | None = None) -> None:
    """Load the Pinocchio model's compiled kernels before a run, saying so when numba compiles them (a machine's first run).

    Args:
        clock: the clock of the note's one-second timer (:mod:`hipsim.clock`; a test passes its own).
    """
    from ..closed_chain.dynamics import warm_up

    with note_if_slow("Pinocchio model: compiling (first run only) ...", note, clock=clock):
        warm_up()


def desired_motion(args, trajectory):
    """The desired motion as a function of time, and the duration of the run in [s] (``simulate`` and ``report --simulate``).

    Args:
        args: the parsed options (the motion options).
        trajectory: the ``--trajectory`` file's motion, read; None for the built-in cycle.
    """
    from ..motion.trajectories import interpolator, iso14242, iso14242_at

    if args.trajectory:
        span = trajectory.t[-1] - trajectory.t[0]
        if trajectory.periodic:  # one whole period: the last sample's step closes it
            span += trajectory.t[1] - trajectory.t[0]
        return interpolator(trajectory), span
    frequency = builtin_frequency(args)
    iso = iso14242(
        rate=1000.0, cycles=1 if args.cycles is None else args.cycles, frequency=frequency
    )  # checks them as torques does
    return (lambda t: iso14242_at(t, frequency)), len(iso) / 1000.0
