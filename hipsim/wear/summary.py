"""A wear run's numbers as plain data (the JSON summary, the page's tables), and the differences of two runs.

Means over "the loaded area" are over the points that carry work (W > 0),
weighted by their cells' areas on a grid (plain means for points given one by one).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ..exceptions import ArgumentError
from .laws import Wear
from .maps import WearMaps

__all__ = ["QUANTITIES", "compare_summaries", "difference_maps", "wear_summary"]

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
    return float(np.average(values, weights=weights)) if weights is not None else float(np.mean(values))


def wear_summary(maps: WearMaps, wear: Wear | None = None) -> dict[str, Any]:
    """The summary's keys (docs/guide/wear.md): per cycle; the wear ones None without a law (or without cells)."""
    loaded = maps.loaded
    area = maps.points.area_mm2
    weights = None if area is None else area[loaded]
    cs = maps.cross_shear[loaded]
    work = maps.work_N_per_mm
    setup = maps.setup
    summary: dict[str, Any] = {
        "source": maps.name,
        "cycles": maps.cycles,
        "samples": maps.samples,
        "duration_s": maps.duration_s,
        "head_diameter_mm": setup.head_diameter_mm,
        "sequence": setup.sequence,
        "moving": setup.moving,
        "cup_mount_deg": [math.degrees(a) for a in setup.cup_mount_rad],
        "points": len(maps.points),
        "grid": list(maps.points.shape) if maps.points.shape else None,
        "force_track_mm": maps.force_track_mm,
        "force_track_load_Nm": maps.force_track_load_Nm,
        "sliding_mm_max": float(np.max(maps.sliding_mm)),
        "sliding_mm_mean": _mean(maps.sliding_mm[loaded], weights),
        "work_N_per_mm_max": float(np.max(work)),
        "load_slide_integral_Nm": None if area is None else float(np.sum(work * area)) / 1000.0,
        "cross_shear_mean": _mean(cs, weights),
        "cross_shear_max": float(np.max(cs)) if cs.size else math.nan,
        "cross_shear_work_weighted": _mean(cs, work[loaded] * (1.0 if area is None else area[loaded])),
        "worn_area_mm2": None if area is None else float(np.sum(area[loaded])),
        "loaded_points": int(np.sum(loaded)),
        "wear_law": None if wear is None else wear.law,
        "wear_mm3_per_Mc": None if wear is None else wear.total_mm3_per_Mc,
        "wear_depth_um_per_Mc_max": None if wear is None else float(np.max(wear.depth_um_per_Mc)),
        "points_beyond_law_table": None if wear is None else wear.beyond_table,
    }
    return summary


def compare_summaries(a: dict[str, Any], b: dict[str, Any]) -> list[dict[str, Any]]:
    """Per quantity of :data:`QUANTITIES`: A, B, B − A and (B − A)/|A| (None where a value is missing), and whether it decides."""
    rows = []
    for key, label, unit, decides in QUANTITIES:
        x, y = a.get(key), b.get(key)
        difference = relative = None
        if x is not None and y is not None and math.isfinite(x) and math.isfinite(y):
            difference = y - x
            relative = difference / abs(x) if x != 0 else None
        rows.append(
            {
                "key": key,
                "label": label,
                "unit": unit,
                "a": x,
                "b": y,
                "difference": difference,
                "relative": relative,
                "decides": decides,
            }
        )
    return rows


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
