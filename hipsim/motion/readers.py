"""Any trajectory file, read by its suffix: hipsim's CSV or any lab's table through a column mapping, Parquet, OpenSim .mot/.sto.

:func:`read_trajectory` chooses the reader: :func:`hipsim.motion.csv_table.load_trajectory_csv`
for a CSV table, :func:`hipsim.motion.parquet.load_trajectory_parquet` for
an Apache Parquet table, :func:`hipsim.motion.opensim.load_opensim` for an
OpenSim file. Every reader ends in the same steps
(:func:`hipsim.motion.build.build_trajectory`: units, the hip chain, time
scaling, resampling, derivatives), and every problem is reported on one line
naming the file, its line and column.
"""

from __future__ import annotations

from pathlib import Path
from typing import Literal, Unpack, overload

from ..exceptions import TrajectoryError
from .build import SampledMotion
from .csv_table import load_trajectory_csv
from .load_file import LoadScale, parse_load_scale, read_load_curve
from .opensim import load_opensim
from .parquet import load_trajectory_parquet
from .read_options import ReadOptions, check_options
from .trajectories import Trajectory

__all__ = ["OPENSIM_SUFFIXES", "PARQUET_SUFFIX", "read_trajectory"]

#: Files read as OpenSim storage files rather than CSV tables.
OPENSIM_SUFFIXES = (".mot", ".sto")
#: Files read as Apache Parquet tables.
PARQUET_SUFFIX = ".parquet"


@overload
def read_trajectory(
    path: str | Path,
    *,
    side: str | None = None,
    load: str | Path | None = None,
    load_scale: LoadScale | str | None = None,
    lazy: Literal[False] = False,
    **options: Unpack[ReadOptions],
) -> Trajectory: ...
@overload
def read_trajectory(
    path: str | Path,
    *,
    side: str | None = None,
    load: str | Path | None = None,
    load_scale: LoadScale | str | None = None,
    lazy: Literal[True],
    **options: Unpack[ReadOptions],
) -> SampledMotion: ...
@overload
def read_trajectory(
    path: str | Path,
    *,
    side: str | None = None,
    load: str | Path | None = None,
    load_scale: LoadScale | str | None = None,
    lazy: bool,
    **options: Unpack[ReadOptions],
) -> Trajectory | SampledMotion: ...
def read_trajectory(
    path: str | Path,
    *,
    side: str | None = None,
    load: str | Path | None = None,
    load_scale: LoadScale | str | None = None,
    lazy: bool = False,
    **options: Unpack[ReadOptions],
) -> Trajectory | SampledMotion:
    """Read a trajectory file of any format hipsim knows, by its suffix.

    ``.mot`` and ``.sto``: OpenSim (:func:`hipsim.motion.opensim.load_opensim`,
    which takes ``side``); ``.parquet``: an Apache Parquet table with the
    CSV's columns (:func:`hipsim.motion.parquet.load_trajectory_parquet`);
    anything else: a CSV table (:func:`hipsim.motion.csv_table.load_trajectory_csv`).
    All take the :class:`~hipsim.motion.read_options.ReadOptions` (``columns``: an OpenSim file
    is otherwise read by its hip coordinates' names; ``cutoff`` low-passes the angles at that
    many Hz before differentiation, :mod:`hipsim.motion.filtering`); ``lazy`` returns a
    :class:`hipsim.motion.build.SampledMotion` to evaluate piece by piece.

    ``load`` names a second file that holds the load
    (:mod:`hipsim.motion.load_file`): the options' ``load_column`` and ``body_weight`` then
    apply to it, ``load_scale`` (a factor, ``MIN:MAX`` in N, or a
    :class:`~hipsim.motion.load_file.LoadScale`) scales it.

    Raises:
        TrajectoryError: an argument that does not apply to the format, or
            the file's first problem.
    """
    source = str(path)
    check_options(options, ReadOptions, "read_trajectory")
    if load is not None:
        load_column = options.get("load_column")
        if load_column is None:
            raise TrajectoryError(
                "name the load file's column (load_column: a column, or NAME for NAME_fx/_fy/_fz)", source=str(load)
            )
        scale = parse_load_scale(load_scale) if isinstance(load_scale, str) else load_scale
        options["load_curve"] = read_load_curve(load, load_column, scale=scale, body_weight=options.get("body_weight"))
        options["load_column"] = options["body_weight"] = None
    elif load_scale is not None:
        raise TrajectoryError("a load scale applies to a load file", source=source)
    if Path(source).suffix.lower() in OPENSIM_SUFFIXES:
        if options.get("columns") is not None and side is not None:
            raise TrajectoryError("a column mapping names the columns itself: the side does not apply", source=source)
        return load_opensim(path, side="right" if side is None else side, lazy=lazy, **options)
    if side is not None:
        raise TrajectoryError("the side (left or right hip) applies to OpenSim .mot/.sto files", source=source)
    reader = load_trajectory_parquet if Path(source).suffix.lower() == PARQUET_SUFFIX else load_trajectory_csv
    return reader(path, lazy=lazy, **options)
