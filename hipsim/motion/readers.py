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
from typing import Mapping

from ..exceptions import TrajectoryError
from .columns import Column, ColumnMap
from .csv_table import load_trajectory_csv
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
) -> Trajectory:
    """Read a trajectory file of any format hipsim knows, by its suffix.

    ``.mot`` and ``.sto``: OpenSim (:func:`hipsim.motion.opensim.load_opensim`,
    which takes ``side``); ``.parquet``: an Apache Parquet table with the
    CSV's columns (:func:`hipsim.motion.parquet.load_trajectory_parquet`);
    anything else: a CSV table (:func:`hipsim.motion.csv_table.load_trajectory_csv`; these two take
    ``columns``). The other arguments are as those functions have them;
    ``lazy`` returns a :class:`hipsim.motion.build.SampledMotion` to evaluate piece by piece.

    Raises:
        TrajectoryError: an argument that does not apply to the format, or
            the file's first problem.
    """
    source = str(path)
    if Path(source).suffix.lower() in OPENSIM_SUFFIXES:
        if columns is not None:
            raise TrajectoryError(
                "a column mapping applies to CSV tables; an OpenSim file is read by its hip coordinates' names", source=source
            )
        return load_opensim(
            path, side="right" if side is None else side, periodic=periodic, load_column=load_column, body_weight=body_weight,
            frequency=frequency, period=period, resample=resample, lazy=lazy,
        )
    if side is not None:
        raise TrajectoryError("the side (left or right hip) applies to OpenSim .mot/.sto files", source=source)
    load = load_trajectory_parquet if Path(source).suffix.lower() == PARQUET_SUFFIX else load_trajectory_csv
    return load(
        path, periodic, columns=columns, load_column=load_column, body_weight=body_weight, frequency=frequency, period=period,
        resample=resample, lazy=lazy,
    )
