"""What a sweep's table says (``hipsim sweep``'s summary): counts by status and rating, the best variant of each
objective with where to look next, the Pareto front, and the verdict, as typed records.

Pure functions of the table's columns (:func:`sweep_result`, :func:`pareto_points`): the summary reads every row of
the file, the rows of earlier runs into it among them. The verdict (:func:`sweep_verdict`): FEASIBLE when some variant
passes the drive's rating (without a rating: when some variant can run the motion at all: it assembles and stays in
the workspace), else NOT FEASIBLE.

The table's rows themselves stay columns of values by name (:mod:`hipsim.design.sweep_table`): their columns are the
swept keys the user chose.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..records import Level, Record, Verdict, flattened
from .sweep import pareto_front
from .sweep_edges import Edge, edges_of, nearest_failing

__all__ = [
    "Best",
    "Neighbour",
    "ParetoEdgePoint",
    "ParetoPoint",
    "SweepResult",
    "pareto_points",
    "sweep_result",
    "sweep_verdict",
]

Columns = Mapping[str, Sequence[Any]]


@dataclass(frozen=True)
class Neighbour(Record):
    """The failing row nearest to a best variant: its row, swept values, status, rating, margin, binding check, reason."""

    row: int
    variant: dict[str, float]
    status: str
    rating: str
    margin: float | None
    binding: str | None
    reason: str | None


@dataclass(frozen=True)
class Best(Record):
    """The best variant of one objective: min or max, its value, row and swept values, its rating; the edges of the
    swept range it lies on, its own margin, and its nearest failing neighbour."""

    goal: str
    value: float
    row: int
    variant: dict[str, float]
    rating: str
    edges: tuple[Edge, ...]
    margin: float | None
    nearest_failing: Neighbour | None


@dataclass(frozen=True)
class ParetoPoint(Record):
    """A variant on the Pareto front: its swept values and the two objectives' values, by name."""

    values: dict[str, float] = flattened()


@dataclass(frozen=True)
class ParetoEdgePoint(Record):
    """A Pareto point on an edge of the swept range: its swept values by name, and the edges."""

    variant: dict[str, float] = flattened()
    edges: tuple[Edge, ...] = ()


@dataclass(frozen=True)
class SweepResult(Record):
    """Over every row of the table: the rows, by status (ok, cannot assemble, out of the workspace) and rating (pass,
    FAIL, unchecked; ``rated`` when any row was rated), the rows that pass (rated: the rating; else: ok), the best
    variant per objective, and the verdict."""

    rows: int
    ok: int
    cannot_assemble: int
    out_of_workspace: int
    rated: bool
    passed: int = field(metadata={"key": "pass"})
    fail: int
    unchecked: int
    passing: int
    best: dict[str, Best]
    verdict: Verdict


def sweep_verdict(rows: int, ok: int, rated: bool, passing: int) -> Verdict:
    """FEASIBLE when some row passes (rated: the rating; unrated: it runs the motion), else NOT FEASIBLE.

    Args:
        rows: the rows of the table; ok: those that assemble and stay in the workspace; rated: any row was rated;
        passing: the rows that pass (rated: the rating, else: ok).
    """
    numbers = {"rows": float(rows), "ok": float(ok), "passing": float(passing)}
    if rated:
        judged = f"{passing} of {rows} variants pass the drive's rating"
        not_judged = ""
    else:
        judged = f"{passing} of {rows} variants run the motion (they assemble and stay in the workspace)"
        not_judged = "the drive's rating: no drive given"
    return Verdict(Level.FEASIBLE if passing > 0 else Level.NOT_FEASIBLE, judged, not_judged, numbers)


def _floats(columns: Columns, names: Sequence[str]) -> np.ndarray:
    """The named columns as floats, (n, len(names)): a Parquet null (None) as NaN."""
    return np.column_stack([np.asarray(columns[name], dtype=float) for name in names])


def _variant(columns: Columns, keys: Sequence[str], row: int) -> dict[str, float]:
    return {key: float(columns[key][row]) for key in keys}


def _or_none(value: float) -> float | None:
    return None if np.isnan(value) else value


def _onward(
    columns: Columns, keys: Sequence[str], row: int, status: np.ndarray, rating: np.ndarray, objective: np.ndarray
) -> tuple[tuple[Edge, ...], float | None, Neighbour | None]:
    """Where to look next from the best row: the edges of the swept range it lies on, its own margin, and its nearest
    failing neighbour. An edge counts only when every row as good as the best (to 1e-9 of it) lies on it: a flat
    objective points nowhere."""
    values = _floats(columns, keys)
    best = objective[row]
    tied = np.flatnonzero(np.abs(objective - best) <= 1e-9 * max(abs(best), 1e-300))
    edges = edges_of(values, list(keys), row)
    for tie in tied:
        theirs = {(e.key, e.side) for e in edges_of(values, list(keys), int(tie))}
        edges = [e for e in edges if (e.key, e.side) in theirs]
    failing = (rating == "fail") | (status != "ok")
    k = nearest_failing(values, failing, row)
    neighbour = None
    if k is not None:
        neighbour = Neighbour(
            k,
            _variant(columns, keys, k),
            str(status[k]),
            str(rating[k]),
            _or_none(float(columns["margin"][k])),
            str(columns["binding"][k]) or None,
            str(columns["reason"][k]) or None,
        )
    return tuple(edges), _or_none(float(columns["margin"][row])), neighbour


def sweep_result(
    columns: Columns, keys: Sequence[str], objectives: Mapping[str, bool], pareto: Sequence[tuple[str, bool]] = ()
) -> SweepResult:
    """Counts by status and rating, the best variant of each objective (and of the margin when rated, and of each
    Pareto objective), over every row of the table.

    Args:
        columns: the table's columns by name (swept keys and :func:`hipsim.design.sweep.metric_columns`).
        keys: the swept keys.
        objectives: objective column → True to maximise.
        pareto: (column, maximise) pairs of a Pareto front asked for.
    """
    status = np.array(columns["status"])
    rating = np.array(columns["rating"])
    rated = bool(np.any((rating == "pass") | (rating == "fail")))
    wanted = dict(objectives)
    if rated:
        wanted["margin"] = True
    for name, maximise in pareto:
        wanted[name] = maximise
    best = {}
    for name, maximise in wanted.items():
        values = _floats(columns, [name])[:, 0]
        if not np.any(np.isfinite(values)):
            continue
        k = int(np.nanargmax(values) if maximise else np.nanargmin(values))
        edges, margin, neighbour = _onward(columns, keys, k, status, rating, values)
        variant = _variant(columns, keys, k)
        best[name] = Best(
            "max" if maximise else "min", float(values[k]), k, variant, str(rating[k]), edges, margin, neighbour
        )
    ok = int(np.count_nonzero(status == "ok"))
    passing = int(np.count_nonzero(rating == "pass")) if rated else ok
    rows = int(status.size)
    return SweepResult(
        rows,
        ok,
        int(np.count_nonzero(status == "cannot_assemble")),
        int(np.count_nonzero(status == "out_of_workspace")),
        rated,
        int(np.count_nonzero(rating == "pass")),
        int(np.count_nonzero(rating == "fail")),
        int(np.count_nonzero(rating == "unchecked")),
        passing,
        best,
        sweep_verdict(rows, ok, rated, passing),
    )


def pareto_points(
    columns: Columns, keys: Sequence[str], pareto: Sequence[tuple[str, bool]]
) -> tuple[np.ndarray, tuple[ParetoPoint, ...], tuple[ParetoEdgePoint, ...]]:
    """The Pareto front of two objectives over every row: which rows are on it ((n,) bool), each point's swept values
    and objectives, and the points that lie on an edge of the swept range with their edges."""
    (x_name, x_max), (y_name, y_max) = pareto
    values = _floats(columns, [x_name, y_name])
    front = pareto_front(values, (x_max, y_max))
    swept = _floats(columns, keys)
    on = [int(k) for k in np.flatnonzero(front)]
    points = tuple(
        ParetoPoint(_variant(columns, keys, k) | {x_name: float(values[k, 0]), y_name: float(values[k, 1])}) for k in on
    )
    edged = ((k, tuple(edges_of(swept, list(keys), k))) for k in on)
    return front, points, tuple(ParetoEdgePoint(_variant(columns, keys, k), edges) for k, edges in edged if edges)
