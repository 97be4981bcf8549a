"""The keyword options every trajectory reader takes, declared once (typed keyword arguments, PEP 692).

:func:`hipsim.motion.csv_table.load_trajectory_csv`,
:func:`hipsim.motion.parquet.load_trajectory_parquet`,
:func:`hipsim.motion.opensim.load_opensim` and
:func:`hipsim.motion.readers.read_trajectory` take ``**options`` of
:class:`ReadOptions`; :func:`hipsim.motion.build.build_trajectory` takes the
:class:`BuildOptions` among them (the columns are a format's business, read
before it). ``lazy`` stays a parameter of its own in each: it chooses the
return type (a :class:`~hipsim.motion.trajectories.Trajectory`, or a
:class:`~hipsim.motion.build.SampledMotion` to evaluate piece by piece), which
each reader's overloads tell the type checker.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Protocol, TypedDict, cast

import numpy as np

from .columns import Column, ColumnMap

__all__ = ["BuildOptions", "LoadSource", "ReadOptions", "build_options", "check_options"]


class LoadSource(Protocol):
    """A load given apart from the motion's table: :class:`hipsim.motion.load_file.LoadCurve` (described by what
    :func:`hipsim.motion.build.build_trajectory` asks of it, so that this module need not import the load reader)."""

    def onto(self, t: np.ndarray, motion: str) -> tuple[np.ndarray, np.ndarray]:
        """(mask of the motion's samples at times ``t`` [s] the load covers, the load there in [N])."""
        ...


class BuildOptions(TypedDict, total=False):
    """The options of the steps every reader ends in (:func:`hipsim.motion.build.build_trajectory`).

    Attributes:
        periodic: True if the motion repeats with the file's period (its last
            row equals its first); None (the default) to decide from the data.
        frequency: cycle frequency in [Hz]: the file holds one cycle, rescaled in time to it.
        period: cycle period in [s], instead of ``frequency``.
        resample: rate in [Hz] of an even grid to resample uneven data onto
            (the quintic spline of the samples; the load linearly).
        body_weight: body weight in [N], for a load in % body weight (the
            default unit of the load when a body weight is given).
        cutoff: zero-phase low-pass cutoff in [Hz] for the angles before
            differentiation (:mod:`hipsim.motion.filtering`); None for none
            (then noisy motion is warned of).
        load_curve: the load from its own file (:func:`hipsim.motion.load_file.read_load_curve`),
            in place of a load column.
    """

    periodic: bool | None
    frequency: float | None
    period: float | None
    resample: float | None
    body_weight: float | None
    cutoff: float | None
    load_curve: LoadSource | None


class ReadOptions(BuildOptions, total=False):
    """A reader's options: :class:`BuildOptions` and which columns to read.

    Attributes:
        columns: a column mapping (:func:`~hipsim.motion.columns.parse_columns` text, a mapping
            ``{"time": "Time", "alpha": "FE", …}`` or a :class:`~hipsim.motion.columns.ColumnMap`);
            an OpenSim file is otherwise read by its hip coordinates' names.
        load_column: the load's column (``[-]NAME[:UNIT]`` or a Column): N by
            default, or % body weight when a body weight is given.
    """

    columns: ColumnMap | Mapping[str, str] | str | None
    load_column: Column | str | None


def check_options(options: Mapping[str, object], declared: type, function: str) -> None:
    """Refuse a keyword a function's ``**options`` does not declare, as Python refuses one a signature does not name.

    Args:
        options: the keyword arguments given.
        declared: the TypedDict that declares them (:class:`ReadOptions` or :class:`BuildOptions`).
        function: the function's name, for the message.

    Raises:
        TypeError: ``function() got an unexpected keyword argument 'name'`` (a misspelt option is never ignored).
    """
    unknown = sorted(set(options) - set(declared.__annotations__))
    if unknown:
        raise TypeError(f"{function}() got an unexpected keyword argument {unknown[0]!r}")


def build_options(options: ReadOptions, function: str) -> BuildOptions:
    """The options :func:`hipsim.motion.build.build_trajectory` takes: ``options`` (checked, see :func:`check_options`,
    in the name of the reader ``function``) without the columns."""
    check_options(options, ReadOptions, function)
    rest = {key: value for key, value in options.items() if key not in ("columns", "load_column")}
    return cast(BuildOptions, rest)
