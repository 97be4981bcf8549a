"""``hipsim urdf``: the xacro model expanded with the parameter set, and its closure file."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from ..exceptions import HipsimError
from .common import add_machine_options, parameters

__all__ = ["add_parser", "run"]


def add_parser(subparsers) -> argparse.ArgumentParser:
    """Register ``urdf`` on the main parser's subcommands."""
    urdf = subparsers.add_parser("urdf", help="expand the xacro model with the parameter set and write the URDF")
    add_machine_options(urdf)
    urdf.add_argument(
        "--out", default="hip_simulator.urdf", metavar="FILE", help="URDF to write (default hip_simulator.urdf)"
    )
    urdf.add_argument(
        "--closures",
        metavar="FILE",
        help="also write the closure file (loop closures, actuated joints, lead and rotor inertia of this parameter set)",
    )
    urdf.set_defaults(run=run)
    return urdf


def run(args) -> int:
    """Write the URDF (and the closure file) and name what was written."""
    from ..files import is_stdout
    from ..machine.model_files import write_closures, write_urdf

    params = parameters(args)
    if args.closures and not is_stdout(args.out) and Path(args.closures).resolve() == Path(args.out).resolve():
        raise HipsimError(
            f"--closures {args.closures} is the --out file itself: choose another name (e.g. hip_simulator.yaml)"
        )
    messages = sys.stderr if is_stdout(args.out) or (args.closures and is_stdout(args.closures)) else sys.stdout
    path = write_urdf(params, args.out if is_stdout(args.out) else Path(args.out))
    print(f"wrote {path}", file=messages)
    if args.closures:
        print(
            f"wrote {write_closures(params, args.closures if is_stdout(args.closures) else Path(args.closures))}",
            file=messages,
        )
    return 0
