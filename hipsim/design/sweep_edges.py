"""Where a sweep should look next: a best variant on the edge of the swept range, and its nearest failing neighbour.

Pure: given the swept keys' values of every row, :func:`edges_of` says on
which edge of the swept range (the smallest and largest value of each key
among the rows, a grid's or a sample's alike) one row lies, with a range
extended past that edge to sweep next; :func:`nearest_failing` finds the
row nearest to it (each key scaled by its swept range) that fails.

A value is on an edge when it lies within one stratum of it: less than
range / m from the end, m the number of distinct values of the key (a grid
of m values has its second value a step of range / (m − 1) in, so only the
end value counts; a Latin hypercube of m samples has one per stratum of
width range / m, so only the outermost one counts).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ..records import Record

__all__ = ["Edge", "edges_of", "nearest_failing"]


@dataclass(frozen=True)
class Edge(Record):
    """One key of one variant on the edge of the swept range.

    Attributes:
        key: the swept key (its name).
        side: "lower" or "upper".
        value: the variant's value, in the key's file unit.
        low, high: the swept range of the key (the smallest and largest value among the rows).
        step: the grid's step when the values are evenly spaced; None for a sample.
        suggestion: (low, high) of a range extended by half the present span past this edge.
    """

    key: str
    side: str
    value: float
    low: float
    high: float
    step: float | None
    suggestion: tuple[float, float]


def _step(distinct: np.ndarray) -> float | None:
    """The grid's step when the distinct values are evenly spaced (to 1e-6 of a step), else None."""
    gaps = np.diff(distinct)
    if gaps.size == 0 or not np.allclose(gaps, gaps[0], rtol=1e-6, atol=0.0):
        return None
    return float(gaps[0])


def _extended(low: float, high: float, side: str, step: float | None) -> tuple[float, float]:
    """The range extended by half its span past ``side`` (whole steps on a grid); a positive low end stays positive."""
    reach = (high - low) / 2
    if step is not None:
        reach = max(step, round(reach / step) * step)
    if side == "upper":
        return low, high + reach
    new_low = low - reach
    if low > 0 >= new_low:  # a length or a mass: halve towards zero rather than cross it
        new_low = low / 2
    return new_low, high


def edges_of(values: np.ndarray, keys: Sequence[str], row: int) -> list[Edge]:
    """The edges of the swept range that row ``row`` lies on.

    Args:
        values: (n, k) the swept keys' values of every row, in the keys' file units (NaN rows ignored).
        keys: the k key names.
        row: the row to look at.

    Returns:
        One :class:`Edge` per key whose value lies on its lower or upper edge;
        none for a key swept over a single value.
    """
    values = np.asarray(values, dtype=float)
    out = []
    for j, key in enumerate(keys):
        column = values[:, j]
        distinct = np.unique(column[np.isfinite(column)])
        if distinct.size < 2 or not np.isfinite(column[row]):
            continue
        low, high = float(distinct[0]), float(distinct[-1])
        stratum = (high - low) / distinct.size
        step = _step(distinct)
        for side, end in (("lower", low), ("upper", high)):
            if abs(column[row] - end) < stratum:
                out.append(Edge(key, side, float(column[row]), low, high, step, _extended(low, high, side, step)))
    return out


def nearest_failing(values: np.ndarray, failing: np.ndarray, row: int) -> int | None:
    """The failing row nearest to row ``row``, each key's distance scaled by its swept range; None when none fails.

    Args:
        values: (n, k) the swept keys' values of every row.
        failing: (n,) bool, True for a row that fails (its rating, or it cannot be computed).
        row: the row to look from.
    """
    values = np.asarray(values, dtype=float)
    failing = np.asarray(failing, dtype=bool).copy()
    failing[row] = False
    if not failing.any():
        return None
    span = np.nanmax(values, axis=0) - np.nanmin(values, axis=0)
    span = np.where(span > 0, span, 1.0)
    distance = np.sqrt(np.nansum(((values - values[row]) / span) ** 2, axis=1))
    candidates = np.flatnonzero(failing)
    return int(candidates[np.argmin(distance[candidates])])
