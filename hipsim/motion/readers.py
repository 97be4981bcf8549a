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

from collections.abc import Mapping
from pathlib import Path

from ..exceptions import TrajectoryError
from .build import SampledMotion
from .columns import Column, ColumnMap
from .csv_table import load_trajectory_csv
from .load_file import LoadScale, parse_load_scale, read_load_curve
from .opensim import load_opensim
from .parquet import load_trajectory_parquet
from .trajectories import Trajectory

__all__ = ["OPENSIM_SUFFIXES", "PARQUET_SUFFIX", "read_trajectory"]

#: Files read as OpenSim storage files rather than CSV tables.
OPENSIM_SUFFIXES = (".mot", ".sto")
#: Files read as Apache Parquet tables.
PARQUET_SUFFIX = ".parquet"


def read_trajectory(
    path: str | Path,
    *,
    periodic: bool | None = None,
    columns: ColumnMap | Mapping | str | None = None,
    side: str | None = None,
    load_column: Column | str | None = None,
    body_weight: float | None = None,
    frequency: float | None = None,
    period: float | None = None,
    resample: float | None = None,
    lazy: bool = False,
    cutoff: float | None = None,
    load: str | Path | None = None,
    load_scale: LoadScale | str | None = None,
) -> Trajectory | SampledMotion:
    """Read a trajectory file of any format hipsim knows, by its suffix.

    ``.mot`` and ``.sto``: OpenSim (:func:`hipsim.motion.opensim.load_opensim`,
    which takes ``side``); ``.parquet``: an Apache Parquet table with the
    CSV's columns (:func:`hipsim.motion.parquet.load_trajectory_parquet`);
    anything else: a CSV table (:func:`hipsim.motion.csv_table.load_trajectory_csv`).
    All take ``columns`` (an OpenSim file is otherwise read by its hip
    coordinates' names). The other arguments are as those functions have them;
    ``lazy`` returns a :class:`hipsim.motion.build.SampledMotion` to evaluate piece by piece;
    ``cutoff`` low-passes the angles at that many Hz before differentiation
    (:mod:`hipsim.motion.filtering`).

    ``load`` names a second file that holds the load
    (:mod:`hipsim.motion.load_file`): ``load_column`` and ``body_weight`` then
    apply to it, ``load_scale`` (a factor, ``MIN:MAX`` in N, or a
    :class:`~hipsim.motion.load_file.LoadScale`) scales it.

    Raises:
        TrajectoryError: an argument that does not apply to the format, or
            the file's first problem.
    """
    source = str(path)
    curve = None
    if load is not None:
        if load_column is None:
            raise TrajectoryError(
                "name the load file's column (load_column: a column, or NAME for NAME_fx/_fy/_fz)", source=str(load)
            )
        scale = parse_load_scale(load_scale) if isinstance(load_scale, str) else load_scale
        curve = read_load_curve(load, load_column, scale=scale, body_weight=body_weight)
        load_column = body_weight = None
    elif load_scale is not None:
        raise TrajectoryError("a load scale applies to a load file", source=source)
    if Path(source).suffix.lower() in OPENSIM_SUFFIXES:
        if columns is not None and side is not None:
            raise TrajectoryError("a column mapping names the columns itself: the side does not apply", source=source)
        return load_opensim(
            path,
            side="right" if side is None else side,
            periodic=periodic,
            load_column=load_column,
            body_weight=body_weight,
            frequency=frequency,
            period=period,
            resample=resample,
            lazy=lazy,
            cutoff=cutoff,
            load_curve=curve,
            columns=columns,
        )
    if side is not None:
        raise TrajectoryError("the side (left or right hip) applies to OpenSim .mot/.sto files", source=source)
    reader = load_trajectory_parquet if Path(source).suffix.lower() == PARQUET_SUFFIX else load_trajectory_csv
    return reader(
        path,
        periodic,
        columns=columns,
        load_column=load_column,
        body_weight=body_weight,
        frequency=frequency,
        period=period,
        resample=resample,
        lazy=lazy,
        cutoff=cutoff,
        load_curve=curve,
    )
