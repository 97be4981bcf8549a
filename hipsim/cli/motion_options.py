"""The command line's motion options: the built-in ISO 14242-1 cycle, or a trajectory file read as the options say."""

from __future__ import annotations

import argparse
import math
import re
import sys
import warnings
from pathlib import Path

from ..exceptions import HipsimError, PoseError

__all__ = [
    "add_trajectory_options",
    "builtin_frequency",
    "cycle_period",
    "load_source",
    "load_trajectory",
    "locate",
    "parse_body_weight",
    "span",
]

#: Options that only a trajectory file takes.
FILE_OPTIONS = ("columns", "side", "load_column", "body_weight", "resample", "cutoff", "load", "load_scale")
#: A body mass above this many kg is surely a weight in N typed without its unit.
MAX_BODY_MASS_KG = 500.0


def add_trajectory_options(parser: argparse.ArgumentParser, rate: bool = True) -> None:
    """The motion options; ``rate=False`` for commands sampled otherwise (``--rate`` is then refused with a reason)."""
    group = parser.add_argument_group("motion (default: the built-in ISO 14242-1 cycle; README 'Gait data')")
    group.add_argument(
        "--trajectory",
        metavar="FILE",
        help="trajectory file: CSV with t_s, alpha_deg, beta_deg, gamma_deg (or _rad) and optional Fe_N, any other CSV "
        "with --columns, or an OpenSim .mot/.sto (comma, semicolon or tab separated; decimal commas read)",
    )
    group.add_argument(
        "--rate",
        type=float,
        metavar="HZ",
        help="sample rate of the built-in cycle in Hz (default 1000)" if rate else argparse.SUPPRESS,
    )
    group.add_argument("--cycles", type=float, metavar="N", help="number of built-in cycles (default 1)")
    group.add_argument(
        "--frequency",
        type=float,
        metavar="HZ",
        help="cycle frequency in Hz: of the built-in cycle (default 1), or a file's recorded cycle rescaled in time to it",
    )
    group.add_argument("--period", type=float, metavar="S", help="cycle period in s, instead of --frequency")
    group.add_argument(
        "--columns",
        metavar="MAP",
        help="which columns to read (CSV, Parquet, OpenSim): time=COL,alpha=COL,beta=COL,gamma=COL[,load=COL] (or flexion=,adduction=,rotation= "
        "for the hip's ISB joint angles); a unit after a colon (s, ms, %%; deg, rad; N, kN, %%BW), a leading - flips the sign; "
        "zero for an angle the file does not have (a planar model); for a TDMS or HDF5 rig log (wear, iso-check), its "
        "channels: NAME=GROUP/CHANNEL,… or GROUP",
    )
    group.add_argument(
        "--side",
        choices=["right", "left"],
        help="whose hip to read from an OpenSim file (default right)",
    )
    group.add_argument(
        "--load-column",
        metavar="COL[:UNIT]",
        help="the column holding the load F_e (in N, or in %% body weight with --body-weight); a leading - flips the sign; "
        "with --load, a column of that file, or NAME for the resultant of NAME_fx, NAME_fy, NAME_fz",
    )
    group.add_argument(
        "--load",
        metavar="FILE",
        help="the load from a second file (OpenSim .sto/.mot or CSV; time in s on the motion's clock), interpolated onto "
        "the motion's times over the time both cover; name its column with --load-column",
    )
    group.add_argument(
        "--load-scale",
        metavar="K|MIN:MAX",
        help="with --load: multiply the load by K, or map its lowest to highest value linearly onto MIN to MAX N (e.g. 300:3000)",
    )
    group.add_argument(
        "--body-weight",
        metavar="KG",
        help="body weight for a load in %% body weight: in kg (75 or 75kg) or in N (736N)",
    )
    group.add_argument(
        "--resample",
        type=float,
        metavar="HZ",
        help="resample a file with uneven times (dropped samples, clock jitter) onto an even grid at HZ: "
        "the quintic spline through its samples, the load linearly",
    )
    group.add_argument(
        "--cutoff",
        type=float,
        metavar="HZ",
        help="zero-phase low-pass of a file's angles before they are differentiated (Butterworth order 4, forwards and "
        "backwards; 6 Hz is gait labs' usual); without it a noisy file is warned of",
    )


def _given(args, names) -> list[str]:
    return [f"--{name.replace('_', '-')}" for name in names if getattr(args, name, None) is not None]


def builtin_frequency(args) -> float:
    """The built-in cycle's frequency in [Hz] from --frequency or --period (default 1 Hz)."""
    _check_frequency_and_period(args)
    if args.period is not None:
        if not (math.isfinite(args.period) and args.period > 0):
            raise HipsimError(f"--period must be a positive number of seconds, got {args.period:g}")
        return 1.0 / args.period
    return 1.0 if args.frequency is None else args.frequency


def _check_frequency_and_period(args) -> None:
    if args.frequency is not None and args.period is not None:
        raise HipsimError("give --frequency or --period, not both")


def parse_body_weight(text: str) -> float:
    """``75``, ``75kg`` or ``736N`` → body weight in [N] (kg through standard gravity)."""
    from ..motion.columns import STANDARD_GRAVITY

    match = re.fullmatch(r"\s*([0-9]*\.?[0-9]+(?:[eE][+-]?[0-9]+)?)\s*(kg|n)?\s*", text, flags=re.IGNORECASE)
    if not match or not float(match.group(1)) > 0:
        raise HipsimError(
            f"--body-weight: expected a positive mass in kg (75, 75kg) or weight in N (736N), got '{text}'"
        )
    value, unit = float(match.group(1)), (match.group(2) or "kg").lower()
    if unit == "n":
        return value
    if value > MAX_BODY_MASS_KG:
        raise HipsimError(
            f"--body-weight {text}: more than {MAX_BODY_MASS_KG:g} kg; for a weight in newtons write {text.strip()}N"
        )
    return value * STANDARD_GRAVITY


def load_source(args):
    """The motion the options ask for as a source to run in pieces (:mod:`hipsim.motion.sources`); see :func:`load_trajectory`."""
    return load_trajectory(args, source=True)


def load_trajectory(args, source: bool = False):
    """The motion the options ask for: a file read as they say, or the built-in cycle.

    Warnings about the file (e.g. radians under a degree header) print as
    ``hipsim: warning: …`` on standard error. The trajectory is kept on
    ``args`` so that :func:`locate` can name a file line in a pose error.
    With ``source``, a :mod:`hipsim.motion.sources` source instead (a file's
    derivatives, the built-in cycle itself, made a piece at a time).
    """
    from ..motion import TrajectoryWarning, read_trajectory
    from ..motion.sources import CycleSource, FileSource
    from ..motion.trajectories import iso14242

    _check_frequency_and_period(args)
    if not args.trajectory:
        given = _given(args, FILE_OPTIONS)
        if given:
            verb = "applies" if len(given) == 1 else "apply"
            raise HipsimError(f"{', '.join(given)} {verb} to a --trajectory file, not to the built-in cycle")
        return (CycleSource if source else iso14242)(
            rate=args.rate if args.rate is not None else 1000.0,
            cycles=args.cycles if args.cycles is not None else 1,
            frequency=builtin_frequency(args),
        )
    given = _given(args, ("rate", "cycles"))
    if given:
        verb = "applies" if len(given) == 1 else "apply"
        hint = " (to resample a file, use --resample)" if args.rate is not None else ""
        raise HipsimError(
            f"{', '.join(given)} {verb} to the built-in cycle, not to --trajectory {args.trajectory}{hint}"
        )
    _check_not_input(args)
    cutoff = getattr(args, "cutoff", None)
    if cutoff is not None and not (math.isfinite(cutoff) and cutoff > 0):
        raise HipsimError(f"--cutoff: expected a positive frequency in Hz, got {cutoff:g}")
    load, load_scale = getattr(args, "load", None), getattr(args, "load_scale", None)
    if load is not None and args.load_column is None:
        raise HipsimError(f"--load {load}: name its column with --load-column (a column, or NAME for NAME_fx/_fy/_fz)")
    if load_scale is not None and load is None:
        raise HipsimError("--load-scale applies to a --load file")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", TrajectoryWarning)
        trajectory = read_trajectory(
            args.trajectory,
            columns=args.columns,
            side=args.side,
            load_column=args.load_column,
            body_weight=parse_body_weight(args.body_weight) if args.body_weight is not None else None,
            frequency=args.frequency,
            period=args.period,
            resample=args.resample,
            lazy=source,
            cutoff=cutoff,
            load=load,
            load_scale=load_scale,
        )
    args.trajectory_warnings = [(w.category, str(w.message)) for w in caught]
    for warning in caught:
        if issubclass(warning.category, TrajectoryWarning):
            print(f"hipsim: warning: {warning.message}", file=sys.stderr)
        else:
            warnings.showwarning(warning.message, warning.category, warning.filename, warning.lineno)
    if source:
        return FileSource(trajectory)
    args.loaded_trajectory = trajectory
    return trajectory


def _check_not_input(args) -> None:
    """Refuse an output that would overwrite the trajectory being read."""
    out = getattr(args, "out", None)
    if out and Path(out).exists() and Path(out).resolve() == Path(args.trajectory).resolve():
        raise HipsimError(f"--out {out} is the --trajectory file itself: choose another output")


def cycle_period(args, trajectory) -> float | None:
    """The length in [s] of one cycle of the motion, where known: the built-in's, or a file's (one cycle, periodic or rescaled)."""
    if not args.trajectory:
        return 1.0 / builtin_frequency(args)
    if args.period is not None:
        return args.period
    if args.frequency is not None:
        return 1.0 / args.frequency
    if trajectory.periodic and len(trajectory) > 1:
        return span(trajectory)
    return None


def span(motion) -> float:
    """The time a trajectory or source covers in [s]: first to last sample, and one step more when periodic."""
    n = len(motion)
    first, last = (
        (float(motion.t[0]), float(motion.t[-1])) if hasattr(motion, "t") else (motion.time(0), motion.time(n - 1))
    )
    return last - first + ((last - first) / (n - 1) if motion.periodic and n > 1 else 0.0)


def locate(error: HipsimError, args) -> HipsimError:
    """A pose error from the file that was read, with the file's line of its sample added."""
    trajectory = getattr(args, "loaded_trajectory", None)
    if (
        not isinstance(error, PoseError)
        or trajectory is None
        or error.line is not None
        or error.source != trajectory.name
    ):
        return error
    line = trajectory.line_at(error.time)
    return error if line is None else PoseError(error.reason, error.time, error.index, source=error.source, line=line)
