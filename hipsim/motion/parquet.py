"""Trajectories from Apache Parquet tables: the CSV's columns and checks, read column-wise with pyarrow.

A Parquet trajectory has the columns a CSV trajectory has (``t_s``,
``alpha_deg`` … or a column mapping) as numbers; rows are counted from 1
where an error names a line. From there it goes through the same steps as
every reader (:func:`hipsim.motion.build.build_trajectory`).
"""

from __future__ import annotations

from pathlib import Path
from typing import Literal, Unpack, overload

import numpy as np

from ..exceptions import TrajectoryError
from ..tables import open_parquet
from .build import SampledMotion, Table, build_trajectory
from .columns import column_options
from .headers import table_columns
from .read_options import ReadOptions, build_options
from .trajectories import MIN_SAMPLES, Trajectory

__all__ = ["load_trajectory_parquet"]


@overload
def load_trajectory_parquet(
    path: str | Path, *, lazy: Literal[False] = False, **options: Unpack[ReadOptions]
) -> Trajectory: ...
@overload
def load_trajectory_parquet(
    path: str | Path, *, lazy: Literal[True], **options: Unpack[ReadOptions]
) -> SampledMotion: ...
@overload
def load_trajectory_parquet(
    path: str | Path, *, lazy: bool, **options: Unpack[ReadOptions]
) -> Trajectory | SampledMotion: ...
def load_trajectory_parquet(
    path: str | Path, *, lazy: bool = False, **options: Unpack[ReadOptions]
) -> Trajectory | SampledMotion:
    """Read a trajectory from a Parquet table and differentiate it (the arguments as :func:`hipsim.motion.csv_table.load_trajectory_csv`).

    Raises:
        TrajectoryError: naming the file, row and column of the first problem.
    """
    source = str(path)
    rest = build_options(options, "load_trajectory_parquet")
    mapping, load = column_options(options.get("columns"), options.get("load_column"), source)
    parquet = open_parquet(path, "trajectory file", TrajectoryError)
    header = list(parquet.schema_arrow.names)
    mapping, index = table_columns(header, mapping, load, source, 1)
    n = parquet.metadata.num_rows
    if n < MIN_SAMPLES:
        raise TrajectoryError(f"{n} samples; at least {MIN_SAMPLES} are needed", source=source)
    names = {key: header[c] for key, c in index.items()}
    data = parquet.read(columns=sorted(set(names.values())))
    values = {}
    for key, name in names.items():
        try:
            column = data.column(name).to_numpy(zero_copy_only=False).astype(float)
        except (TypeError, ValueError):
            raise TrajectoryError(
                f"holds {data.schema.field(name).type}, not numbers", source=source, column=name
            ) from None
        bad = ~np.isfinite(column)
        if bad.any():
            k = int(np.argmax(bad))
            raise TrajectoryError(f"'{column[k]:g}' is not finite", source=source, line=k + 2, column=name)
        values[key] = column
    # Rows are numbered as the CSV's lines would be: the header is line 1.
    return build_trajectory(
        Table(
            source=source,
            lines=np.arange(2, n + 2),
            time=values["time"],
            angles=np.column_stack([values[key] if key in values else np.zeros(n) for key in mapping.angle_keys]),
            load=values.get("load"),
            columns=mapping,
            time_quantum=0.0,
        ),
        lazy=lazy,
        **rest,
    )
