"""The ``hipsim`` command line: the parser assembled from one module per command, and the dispatch.

Every subcommand reads the machine from ``--params`` (default: the published
machine) with ``--set KEY=VALUE`` overrides, and the motion from
``--trajectory`` (default: the built-in ISO 14242-1 cycle). Errors print one
line starting with ``hipsim: error:`` and exit with status 2.

Building the parser loads only the standard library: each command imports
what it computes with when it runs, so ``hipsim --help`` answers at once.
"""

from __future__ import annotations

import argparse
import os
import sys

from ..exceptions import HipsimError
from ..version import __version__
from . import (
    calibrate,
    check,
    excite,
    export,
    feasible,
    iso_check,
    learn,
    mjcf,
    monitor,
    params,
    report,
    rig,
    schema,
    simulate,
    size,
    stations,
    sweep,
    torques,
    urdf,
    view,
    wear,
    workspace,
)
from .motion_options import locate
from .parser import HipsimParser, UsageError, apply_table, idle_option, rewrite_aliases

__all__ = ["build_parser", "main"]

EXAMPLES = """\
examples:
  hipsim torques                          ISO 14242-1 on the published machine -> hipsim_torques.csv
  hipsim torques --set lever.length_mm=340 --out longer.csv
  hipsim torques --trajectory gait.csv --summary-format json
  hipsim torques --trajectory walk.mot --side left --frequency 1 --out -   OpenSim hip angles, CSV to stdout
  hipsim torques --trajectory lab.csv --columns time=Time,flexion=FE,adduction=AA,rotation=IE,load=Fz:%BW --body-weight 75
  hipsim simulate --cycles 1 --mismatch friction=+20%   tracking errors of both controllers
  hipsim params                           the parameter set in use, with units
"""


def build_parser() -> argparse.ArgumentParser:
    """The ``hipsim`` parser: every command, in the order ``hipsim --help`` lists them."""
    parser = HipsimParser(
        prog="hipsim",
        description="Kinematics, closed-chain dynamics and control of the 2(3PUS+S) parallel hip joint simulator.",
        epilog=EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("--version", action="version", version=f"hipsim {__version__}")
    commands = parser.add_subparsers(dest="command", metavar="COMMAND")
    for command in (
        torques,
        simulate,
        report,
        workspace,
        check,
        feasible,
        iso_check,
        wear,
        view,
        urdf,
        mjcf,
        size,
        sweep,
        stations,
        learn,
        export,
        params,
    ):
        command.add_parser(commands)
    rig.add_parser(commands)  # compare, identify: the rig in the loop
    excite.add_parser(commands)
    calibrate.add_parser(commands)
    monitor.add_parser(commands)
    schema.add_parser(commands)
    parser.option_warnings = apply_table(parser)  # type: ignore[attr-defined]
    return parser


#: Options whose values may start with "-" (negative angles), which argparse would read as options.
_SIGNED_VALUE_OPTIONS = ("--deltas", "--gamma", "--load-column")


def _join_signed_values(argv: list[str]) -> list[str]:
    """``--deltas -90:90:1`` → ``--deltas=-90:90:1``, so that argparse takes the value as a value."""
    out: list[str] = []
    for arg in argv:
        if out and out[-1] in _SIGNED_VALUE_OPTIONS and arg.startswith("-"):
            out[-1] = f"{out[-1]}={arg}"
        else:
            out.append(arg)
    return out


def _misplaced_plant_option(words: list[str]) -> str | None:
    """One line when ``--plant-params`` is given to a command that has no plant (only ``simulate`` has one)."""
    if not any(w == "--plant-params" or w.startswith("--plant-params=") for w in words):
        return None
    command = next((w for w in words if not w.startswith("-")), None)
    if command == "simulate":
        return None
    return (
        f"--plant-params: {command or 'this command'} has no plant to give it (only hipsim simulate runs a plant "
        "apart from the controller's model); give the machine with --params"
    )


def main(argv: list[str] | None = None) -> int:
    """Run ``hipsim`` with ``argv`` (default: the process's arguments) and return the exit status."""
    parser = build_parser()
    notes: list[str] = parser.option_warnings  # type: ignore[attr-defined]
    words = rewrite_aliases(_join_signed_values(sys.argv[1:] if argv is None else list(argv)), notes)
    misplaced = _misplaced_plant_option(words)
    if misplaced:
        print(f"hipsim: error: {misplaced}", file=sys.stderr)
        return 2
    try:
        args = parser.parse_args(words)
        idle = idle_option(words)
        if idle:  # an option that would do nothing is refused, never ignored
            raise UsageError(idle)
    except UsageError as error:  # one line, not argparse's usage block
        print(f"hipsim: error: {error}", file=sys.stderr)
        return 2
    args.option_warnings = notes  # what the option table warned of, for a page's provenance
    args.command_line = ["hipsim", *words]  # what made a page, for its provenance block
    from ..files import exit_on_terminate  # after parsing: --help and --version load no NumPy

    if not getattr(args, "run", None):
        parser.print_help()
        return 2
    try:
        with exit_on_terminate():  # SIGTERM (timeout, kill, a scheduler) cleans up as Ctrl-C does
            return args.run(args)
    except HipsimError as error:
        print(f"hipsim: error: {locate(error, args)}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("hipsim: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:
        # The reader went away (``hipsim params | head``): not an error; silence the flush at exit.
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
