"""A wear run's numbers as plain data (the JSON summary, the page's tables), and the differences of two runs.

Two runs compared (:func:`wear_comparison`): per quantity A, B and (B − A)/|A|
(:func:`compare_summaries`), the verdict on them (:func:`compare_verdict`,
ALIKE/DIFFERENT either way), and per map the largest |B − A| of a point
(:func:`largest_differences`), gathered in the :class:`WearComparison` record
that ``wear --compare`` prints and its page renders.

Means over "the loaded area" are over the points that carry work (W > 0),
weighted by their cells' areas on a grid (plain means for points given one by one).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..exceptions import ArgumentError
from ..records import Level, Record, Verdict
from .laws import Wear
from .maps import WearMaps

__all__ = [
    "QUANTITIES",
    "Difference",
    "WearComparison",
    "WearSummary",
    "compare_summaries",
    "compare_verdict",
    "difference_maps",
    "largest_differences",
    "run_verdict",
    "wear_comparison",
    "wear_summary",
]

#: The numbers two runs are compared by: key, label, unit, and whether it decides the verdict (the extremes of
#: a few rim points with little work are shown, not judged).
QUANTITIES = (
    ("force_track_mm", "force track length", "mm", True),
    ("force_track_load_Nm", "force track load integral", "N·m", True),
    ("sliding_mm_max", "largest sliding distance", "mm", False),
    ("sliding_mm_mean", "mean sliding distance (loaded area)", "mm", True),
    ("work_N_per_mm_max", "largest work", "N/mm", False),
    ("load_slide_integral_Nm", "work over the cup ΣW·dA", "N·m", True),
    ("cross_shear_mean", "mean CS (loaded area)", "", True),
    ("cross_shear_max", "largest CS", "", False),
    ("cross_shear_work_weighted", "work-weighted CS", "", True),
    ("worn_area_mm2", "area worn (W > 0)", "mm²", True),
    ("wear_mm3_per_Mc", "wear volume", "mm³/Mc", True),
)


def _mean(values: np.ndarray, weights: np.ndarray | None) -> float:
    if values.size == 0:
        return math.nan
    return float(np.average(values, weights=weights))  # weights None: the plain mean


@dataclass(frozen=True)
class WearSummary(Record):
    """One wear run's numbers per cycle (docs/guide/wear.md); the wear ones None without a law (or without cells).

    Attributes:
        source: the motion's name.
        cycles: cycles of the motion; samples: its samples; duration_s: its duration in [s].
        head_diameter_mm: the head in [mm]; sequence: the angles' composition; moving: what the platform moves.
        cup_mount_deg: the cup's mount angles in [deg].
        points: cup points; grid: (n_theta, n_phi) on a grid, None for points given one by one.
        force_track_mm, force_track_load_Nm: the force track's length in [mm] and load integral in [N·m].
        sliding_mm_max, sliding_mm_mean: the largest and the loaded area's mean sliding distance in [mm].
        work_N_per_mm_max: the largest work in [N/mm].
        load_slide_integral_Nm: ΣW·dA over the cup in [N·m] (None without cell areas).
        cross_shear_mean, cross_shear_max: the loaded area's mean and largest cross-shear.
        cross_shear_work_weighted: cross-shear weighted by work × area over the loaded area.
        worn_area_mm2: the area with W > 0 in [mm²]; loaded_points: the points with W > 0.
        wear_law, wear_mm3_per_Mc, wear_depth_um_per_Mc_max, points_beyond_law_table: the predicted wear.
    """

    source: str
    cycles: float
    samples: int
    duration_s: float
    head_diameter_mm: float
    sequence: str
    moving: str
    cup_mount_deg: tuple[float, ...]
    points: int
    grid: tuple[int, int] | None
    force_track_mm: float
    force_track_load_Nm: float
    sliding_mm_max: float
    sliding_mm_mean: float
    work_N_per_mm_max: float
    load_slide_integral_Nm: float | None
    cross_shear_mean: float
    cross_shear_max: float
    cross_shear_work_weighted: float
    worn_area_mm2: float | None
    loaded_points: int
    wear_law: str | None
    wear_mm3_per_Mc: float | None
    wear_depth_um_per_Mc_max: float | None
    points_beyond_law_table: int | None


def wear_summary(maps: WearMaps, wear: Wear | None = None) -> WearSummary:
    """The run's numbers per cycle (:class:`WearSummary`); means over the loaded area weighted by the cells' areas."""
    loaded = maps.loaded
    area = maps.points.area_mm2
    weights = None if area is None else area[loaded]
    cs = maps.cross_shear[loaded]
    work = maps.work_N_per_mm
    setup = maps.setup
    return WearSummary(
        source=maps.name,
        cycles=maps.cycles,
        samples=maps.samples,
        duration_s=maps.duration_s,
        head_diameter_mm=setup.head_diameter_mm,
        sequence=setup.sequence,
        moving=setup.moving,
        cup_mount_deg=tuple(math.degrees(a) for a in setup.cup_mount_rad),
        points=len(maps.points),
        grid=(int(maps.points.shape[0]), int(maps.points.shape[1])) if maps.points.shape else None,
        force_track_mm=maps.force_track_mm,
        force_track_load_Nm=maps.force_track_load_Nm,
        sliding_mm_max=float(np.max(maps.sliding_mm)),
        sliding_mm_mean=_mean(maps.sliding_mm[loaded], weights),
        work_N_per_mm_max=float(np.max(work)),
        load_slide_integral_Nm=None if area is None else float(np.sum(work * area)) / 1000.0,
        cross_shear_mean=_mean(cs, weights),
        cross_shear_max=float(np.max(cs)) if cs.size else math.nan,
        cross_shear_work_weighted=_mean(cs, work[loaded] if area is None else work[loaded] * area[loaded]),
        worn_area_mm2=None if area is None else float(np.sum(area[loaded])),
        loaded_points=int(np.sum(loaded)),
        wear_law=None if wear is None else wear.law,
        wear_mm3_per_Mc=None if wear is None else wear.total_mm3_per_Mc,
        wear_depth_um_per_Mc_max=None if wear is None else float(np.max(wear.depth_um_per_Mc)),
        points_beyond_law_table=None if wear is None else wear.beyond_table,
    )


def run_verdict(summary: WearSummary) -> Verdict:
    """One run's verdict: NOT MADE, always (no acceptance limit is set for a run's wear numbers); the numbers it
    reports per cycle (the wear volume only when a law predicted it).

    Args:
        summary: the run's numbers (:func:`wear_summary`).
    """
    keys = ("force_track_mm", "force_track_load_Nm", "cross_shear_mean", "cross_shear_max", "wear_mm3_per_Mc")
    numbers = {key: value for key in keys if (value := getattr(summary, key)) is not None}
    return Verdict(
        Level.NOT_MADE,
        f"{summary.source}: one run's sliding, cross-shear and wear per cycle, not rated",
        "the numbers against a limit (none is set): compare two runs with --compare A B, or weigh a test with "
        "--weighings",
        numbers,
    )


@dataclass(frozen=True)
class Difference(Record):
    """One quantity of two runs compared: A, B, B − A and (B − A)/|A| (None where a value is missing).

    Attributes:
        key: the summary's key; label: its words; unit: its unit ("" for none).
        a, b: the two runs' values; difference: B − A; relative: (B − A)/|A| (None when A is 0).
        decides: whether it decides the verdict.
    """

    key: str
    label: str
    unit: str
    a: float | None
    b: float | None
    difference: float | None
    relative: float | None
    decides: bool


def _finite(value: float | None) -> float | None:
    return value if value is not None and math.isfinite(value) else None


def compare_summaries(a: WearSummary, b: WearSummary) -> tuple[Difference, ...]:
    """Per quantity of :data:`QUANTITIES`: A, B, B − A and (B − A)/|A| (None where a value is missing), and whether it decides."""
    rows = []
    for key, label, unit, decides in QUANTITIES:
        x, y = _finite(getattr(a, key)), _finite(getattr(b, key))
        difference = relative = None
        if x is not None and y is not None:
            difference = y - x
            relative = difference / abs(x) if x != 0 else None
        rows.append(Difference(key, label, unit, x, y, difference, relative, decides))
    return tuple(rows)


def compare_verdict(rows: tuple[Difference, ...], tolerance: float, names: tuple[str, str]) -> Verdict:
    """ALIKE when every deciding quantity differs by at most ``tolerance`` (relative, either way), else DIFFERENT,
    naming the largest; NOT MADE when no deciding quantity is known in both runs.

    Args:
        rows: the quantities compared (:func:`compare_summaries`).
        tolerance: the largest |B − A|/|A| of runs alike, a fraction (0.05 for 5 %).
        names: the runs A and B, for the sentence.
    """
    known = [(row, row.relative) for row in rows if row.relative is not None and row.decides]
    not_judged = ", ".join(row.label for row in rows if not row.decides) + " (shown, not judged)"
    if not known:
        return Verdict(Level.NOT_MADE, "no quantity is known in both runs", not_judged)
    worst, largest = max(known, key=lambda pair: abs(pair[1]))
    numbers = {row.key: relative for row, relative in known}
    beyond = [row.label for row, relative in known if abs(relative) > tolerance]
    head = (
        f"B ({names[1]}) against A ({names[0]}): {worst.label} differs most, by {100 * largest:+.3g} % "
        f"({worst.a:.4g} → {worst.b:.4g}{' ' + worst.unit if worst.unit else ''})."
    )
    if beyond:
        return Verdict(
            Level.DIFFERENT, f"{head} Beyond ±{100 * tolerance:g} %: {', '.join(beyond)}.", not_judged, numbers
        )
    return Verdict(Level.ALIKE, f"{head} Every quantity judged is within ±{100 * tolerance:g} %.", not_judged, numbers)


def difference_maps(a: WearMaps, b: WearMaps) -> dict[str, np.ndarray]:
    """B − A per point of sliding, work and CS (the runs on the same points).

    Raises:
        ArgumentError: the runs are on different points.
    """
    if a.points.w.shape != b.points.w.shape or not np.array_equal(a.points.w, b.points.w):
        raise ArgumentError("points", b.points.w, "the same cup points in both runs")
    return {
        "sliding_mm": b.sliding_mm - a.sliding_mm,
        "work_N_per_mm": b.work_N_per_mm - a.work_N_per_mm,
        "cross_shear": b.cross_shear - a.cross_shear,
    }


def largest_differences(differences: Mapping[str, np.ndarray]) -> dict[str, float | None]:
    """Per map the largest |B − A| of a point, its magnitude whichever its sign (None when no point is finite)."""
    out: dict[str, float | None] = {}
    for key, values in differences.items():
        finite = np.abs(values)
        finite = finite[np.isfinite(finite)]
        out[key] = float(finite.max()) if finite.size else None
    return out


@dataclass(frozen=True)
class WearComparison(Record):
    """Two wear runs compared, as ``wear.json`` holds it: the verdict, the provenance, both summaries, B − A.

    Attributes:
        verdict: :func:`compare_verdict` (ALIKE, DIFFERENT, NOT MADE).
        provenance: the provenance block.
        tolerance: the relative difference of runs alike, a fraction.
        a, b: the two runs' summaries.
        differences: per quantity A, B, B − A, (B − A)/|A|.
        largest_point_differences: per map (sliding_mm, work_N_per_mm, cross_shear) the largest |B − A| of a point.
    """

    verdict: Verdict
    provenance: dict[str, Any]
    tolerance: float
    a: WearSummary
    b: WearSummary
    differences: tuple[Difference, ...]
    largest_point_differences: dict[str, float | None]


def wear_comparison(
    a: tuple[WearMaps, Wear | None], b: tuple[WearMaps, Wear | None], tolerance: float, provenance: dict[str, Any]
) -> WearComparison:
    """Run B against run A on the same cup points: the summaries, their differences, the verdict, the largest point
    differences.

    Args:
        a, b: each run's maps and its wear (None: none predicted).
        tolerance: the largest |B − A|/|A| of runs alike, a fraction (0.05 for 5 %).
        provenance: the provenance block, as JSON data.

    Raises:
        ArgumentError: the runs are on different points.
    """
    summary_a, summary_b = wear_summary(*a), wear_summary(*b)
    rows = compare_summaries(summary_a, summary_b)
    largest = largest_differences(difference_maps(a[0], b[0]))
    verdict = compare_verdict(rows, tolerance, (a[0].name, b[0].name))
    return WearComparison(verdict, provenance, tolerance, summary_a, summary_b, rows, largest)
