"""A wear run's typed summary and the comparison's ALIKE/DIFFERENT verdict, by hand-computed cases
(hipsim/wear/summary.py). The maps are four points written here, not computed by the wear kernel."""

from __future__ import annotations

import math
from dataclasses import replace

import jsonschema
import numpy as np
import pytest

from hipsim.records import Level, exit_status
from hipsim.wear.kinematics import CupSetup
from hipsim.wear.maps import WearMaps
from hipsim.wear.points import CupPoints
from hipsim.wear.summary import (
    Difference,
    WearSummary,
    compare_summaries,
    compare_verdict,
    largest_differences,
    run_verdict,
    wear_comparison,
    wear_summary,
)

NAN = math.nan


def _maps(area: np.ndarray | None) -> WearMaps:
    """Four points; point 0 carries no work (outside the loaded area)."""
    w = np.eye(3)[[2, 0, 1, 2]]
    return WearMaps(
        points=CupPoints(w, area),
        setup=CupSetup(),
        sliding_mm=np.array([5.0, 2.0, 4.0, 6.0]),
        sliding_loaded_mm=np.array([0.0, 2.0, 4.0, 6.0]),
        work_N_per_mm=np.array([0.0, 1.0, 3.0, 1.0]),
        cross_shear=np.array([NAN, 0.1, 0.2, 0.4]),
        principal=np.zeros((4, 3)),
        force_track_mm=12.0,
        force_track_load_Nm=3.0,
        cycles=1.0,
        duration_s=1.0,
        samples=100,
        name="hand",
        iterations=1,
    )


def test_means_over_the_loaded_area_weighted_by_cell_area_and_by_work():
    s = wear_summary(_maps(np.array([1.0, 2.0, 3.0, 4.0])))
    assert s.loaded_points == 3 and s.worn_area_mm2 == pytest.approx(9.0)
    assert s.sliding_mm_max == 6.0  # over every point, loaded or not
    assert s.sliding_mm_mean == pytest.approx((2 * 2 + 3 * 4 + 4 * 6) / 9)
    assert s.cross_shear_mean == pytest.approx((2 * 0.1 + 3 * 0.2 + 4 * 0.4) / 9)  # by area: 0.2667
    assert s.cross_shear_work_weighted == pytest.approx((2 * 0.1 + 9 * 0.2 + 4 * 0.4) / 15)  # by W·dA: 0.24
    assert s.cross_shear_max == 0.4 and s.work_N_per_mm_max == 3.0
    assert s.load_slide_integral_Nm == pytest.approx((2 + 9 + 4) / 1000)
    assert s.wear_law is None and s.wear_mm3_per_Mc is None
    jsonschema.validate(s.to_json(), WearSummary.json_schema())


def test_points_one_by_one_weigh_equally_and_by_work():
    s = wear_summary(_maps(None))
    assert s.cross_shear_mean == pytest.approx(0.7 / 3)
    assert s.cross_shear_work_weighted == pytest.approx((0.1 + 3 * 0.2 + 0.4) / 5)  # 0.22
    assert s.worn_area_mm2 is None and s.load_slide_integral_Nm is None and s.grid is None
    document = s.to_json()
    assert document["worn_area_mm2"] is None and "grid" in document  # the keys stay, as null
    jsonschema.validate(document, WearSummary.json_schema())


BASE = wear_summary(_maps(np.array([1.0, 2.0, 3.0, 4.0])))


def test_compare_rows_are_b_minus_a_over_the_magnitude_of_a():
    rows = {row.key: row for row in compare_summaries(BASE, replace(BASE, force_track_mm=9.0, sliding_mm_max=NAN))}
    assert rows["force_track_mm"].difference == pytest.approx(-3.0)
    assert rows["force_track_mm"].relative == pytest.approx(-0.25)
    assert rows["sliding_mm_max"].difference is None and rows["sliding_mm_max"].b is None  # NaN is unknown
    negative = compare_summaries(replace(BASE, cross_shear_mean=-2.0), replace(BASE, cross_shear_mean=-1.0))
    assert {row.key: row for row in negative}["cross_shear_mean"].relative == pytest.approx(0.5)
    zero = compare_summaries(replace(BASE, force_track_mm=0.0), BASE)
    assert {row.key: row for row in zero}["force_track_mm"].relative is None


def _row(relative: float, decides: bool = True, key: str = "force_track_mm") -> Difference:
    return Difference(key, key, "mm", 1.0, 1.0 + relative, relative, relative, decides)


@pytest.mark.parametrize(
    ("relative", "level"),
    [
        (0.05, Level.ALIKE),  # at the tolerance: alike
        (-0.05, Level.ALIKE),
        (np.nextafter(0.05, 1.0), Level.DIFFERENT),  # just beyond, either way
        (-np.nextafter(0.05, 1.0), Level.DIFFERENT),
        (-0.3, Level.DIFFERENT),
    ],
)
def test_alike_and_different_at_the_tolerance_both_ways(relative, level):
    rows = (_row(0.0), _row(relative, key="cross_shear_mean"), _row(0.9, decides=False, key="cross_shear_max"))
    verdict = compare_verdict(rows, 0.05, ("A", "B"))
    assert verdict.level == level
    assert exit_status([verdict]) == (1 if level == Level.DIFFERENT else 0)
    assert verdict.numbers == {"force_track_mm": 0.0, "cross_shear_mean": relative}  # the deciding ones only
    assert "cross_shear_max (shown, not judged)" in verdict.not_judged


def test_the_largest_difference_is_named_by_its_magnitude():
    rows = (_row(0.02), _row(-0.04, key="cross_shear_mean"), _row(0.9, decides=False, key="cross_shear_max"))
    verdict = compare_verdict(rows, 0.05, ("A", "B"))
    assert verdict.level == Level.ALIKE and "cross_shear_mean differs most, by -4 %" in verdict.judged
    assert compare_verdict((_row(0.9, decides=False),), 0.05, ("A", "B")).level == Level.NOT_MADE


def test_every_number_of_a_grids_summary_with_a_law():
    from hipsim.wear.laws import WearFactor, predict_wear

    maps = _maps(np.array([1.0, 2.0, 3.0, 4.0]))
    maps = replace(maps, points=CupPoints(maps.points.w, maps.points.area_mm2, (1, 4)), cycles=3.0, duration_s=2.5)
    wear = predict_wear(maps, WearFactor(2e-7))
    s = wear_summary(maps, wear)
    assert (s.source, s.cycles, s.samples, s.duration_s) == ("hand", 3.0, 100, 2.5)
    assert (s.head_diameter_mm, s.sequence, s.moving, s.cup_mount_deg) == (28.0, "ZYX", "cup", (0.0, 0.0, 0.0))
    assert s.points == 4 and s.grid == (1, 4)
    assert (s.force_track_mm, s.force_track_load_Nm) == (12.0, 3.0)
    assert s.wear_law == wear.law and s.wear_mm3_per_Mc == wear.total_mm3_per_Mc
    assert s.wear_depth_um_per_Mc_max == pytest.approx(1e-3 * 2e-7 * 3.0 * 1e9)  # the most worked point's depth
    assert s.points_beyond_law_table == 0
    mounted = wear_summary(replace(maps, setup=CupSetup(32.0, "xyz", (math.pi / 2, 0.0, 0.0), "head")))
    assert mounted.cup_mount_deg == pytest.approx((90.0, 0.0, 0.0)) and mounted.sequence == "XYZ"
    assert (mounted.head_diameter_mm, mounted.moving) == (32.0, "head")


def test_one_loaded_point_and_none():
    maps = _maps(None)
    one = replace(maps, work_N_per_mm=np.array([0.0, 0.0, 2.0, 0.0]))
    s = wear_summary(one)
    assert (s.loaded_points, s.cross_shear_mean, s.cross_shear_max, s.cross_shear_work_weighted) == (1, 0.2, 0.2, 0.2)
    assert s.sliding_mm_mean == 4.0
    none = wear_summary(replace(maps, work_N_per_mm=np.zeros(4), cross_shear=np.full(4, NAN)))
    assert none.loaded_points == 0 and math.isnan(none.cross_shear_max) and math.isnan(none.cross_shear_mean)
    assert math.isnan(none.sliding_mm_mean) and math.isnan(none.cross_shear_work_weighted)


def test_each_row_of_a_comparison_is_complete():
    rows = compare_summaries(BASE, replace(BASE, worn_area_mm2=12.0))
    assert [row.key for row in rows] == [
        "force_track_mm",
        "force_track_load_Nm",
        "sliding_mm_max",
        "sliding_mm_mean",
        "work_N_per_mm_max",
        "load_slide_integral_Nm",
        "cross_shear_mean",
        "cross_shear_max",
        "cross_shear_work_weighted",
        "worn_area_mm2",
        "wear_mm3_per_Mc",
    ]
    row = rows[9]
    assert (row.key, row.label, row.unit, row.a, row.b, row.difference, row.decides) == (
        "worn_area_mm2",
        "area worn (W > 0)",
        "mm²",
        9.0,
        12.0,
        3.0,
        True,
    )
    assert row.relative == pytest.approx(1 / 3)
    assert rows[7].decides is False and rows[10].a is None and rows[10].relative is None  # no law: no wear volume


def test_the_verdicts_sentences_by_hand():
    b = replace(BASE, worn_area_mm2=9.9, cross_shear_mean=BASE.cross_shear_mean * 1.02, sliding_mm_max=60.0)
    rows = compare_summaries(BASE, b)
    different = compare_verdict(rows, 0.05, ("one.csv", "two.csv"))
    assert different.judged == (
        "B (two.csv) against A (one.csv): area worn (W > 0) differs most, by +10 % (9 → 9.9 mm²). "
        "Beyond ±5 %: area worn (W > 0)."
    )
    assert different.not_judged == "largest sliding distance, largest work, largest CS (shown, not judged)"
    alike = compare_verdict(rows, 0.11, ("one.csv", "two.csv"))
    assert alike.judged.endswith("differs most, by +10 % (9 → 9.9 mm²). Every quantity judged is within ±11 %.")
    unitless = compare_verdict(compare_summaries(BASE, replace(BASE, cross_shear_mean=0.3)), 0.2, ("a", "b"))
    assert "mean CS (loaded area) differs most, by +12.5 % (0.2667 → 0.3)." in unitless.judged
    none = compare_verdict(compare_summaries(BASE, replace(BASE, force_track_mm=NAN)), 0.05, ("a", "b"))
    assert none.level == Level.ALIKE  # the others are still known
    empty = compare_verdict((_row(0.5, decides=False), _row(0.1, decides=False, key="x")), 0.05, ("a", "b"))
    assert (empty.level, empty.judged, empty.not_judged) == (
        Level.NOT_MADE,
        "no quantity is known in both runs",
        "force_track_mm, x (shown, not judged)",
    )


def test_a_quantity_unchanged_is_not_the_largest_difference():
    rows = (_row(0.0), _row(0.02, key="cross_shear_mean"))
    assert "cross_shear_mean differs most, by +2 %" in compare_verdict(rows, 0.05, ("A", "B")).judged


def test_difference_maps_are_b_minus_a_on_the_same_points():
    from hipsim.exceptions import ArgumentError
    from hipsim.wear.summary import difference_maps

    a = _maps(None)
    b = replace(a, sliding_mm=a.sliding_mm * 2, work_N_per_mm=a.work_N_per_mm + 1, cross_shear=a.cross_shear / 2)
    d = difference_maps(a, b)
    assert sorted(d) == ["cross_shear", "sliding_mm", "work_N_per_mm"]
    np.testing.assert_allclose(d["sliding_mm"], [5.0, 2.0, 4.0, 6.0])
    np.testing.assert_allclose(d["work_N_per_mm"], 1.0)
    np.testing.assert_allclose(d["cross_shear"], [NAN, -0.05, -0.1, -0.2])
    moved = replace(b, points=CupPoints(np.eye(3)[[2, 0, 1, 1]]))
    with pytest.raises(ArgumentError, match=r"points: expected the same cup points in both runs, got shape \(4, 3\)"):
        difference_maps(a, moved)
    with pytest.raises(ArgumentError, match=r"in both runs, got shape \(3, 3\)"):  # B's points named
        difference_maps(a, replace(b, points=CupPoints(np.eye(3)[[2, 0, 1]])))


def test_the_largest_point_difference_is_by_magnitude_and_skips_the_missing():
    differences = {
        "cross_shear": np.array([0.1, -0.3, np.nan, 0.2]),  # the fall is the largest, whatever its sign
        "sliding_mm": np.array([np.nan, np.inf]),  # no finite point
        "work_N_per_mm": np.array([0.0]),
    }
    assert largest_differences(differences) == {"cross_shear": 0.3, "sliding_mm": None, "work_N_per_mm": 0.0}


def test_one_runs_verdict_is_not_made_with_its_numbers():
    from hipsim.records import Level, exit_status
    from hipsim.wear.laws import WearFactor, predict_wear

    maps = _maps(np.array([1.0, 2.0, 3.0, 4.0]))
    verdict = run_verdict(wear_summary(maps))
    assert verdict.level == Level.NOT_MADE and exit_status([verdict]) == 0
    assert verdict.judged == "hand: one run's sliding, cross-shear and wear per cycle, not rated"
    assert verdict.not_judged == (
        "the numbers against a limit (none is set): compare two runs with --compare A B, or weigh a test with "
        "--weighings"
    )
    assert dict(verdict.numbers) == pytest.approx(  # no wear key without a law
        {"force_track_mm": 12.0, "force_track_load_Nm": 3.0, "cross_shear_mean": 2.4 / 9, "cross_shear_max": 0.4}
    )
    with_law = run_verdict(wear_summary(maps, predict_wear(maps, WearFactor(2e-7))))
    assert set(with_law.numbers) == {*verdict.numbers, "wear_mm3_per_Mc"} and with_law.level == Level.NOT_MADE


def test_two_runs_compared_whole_by_hand():
    """Run B against run A (``wear --compare``): B's force track 25 % longer, its CS at point 3 up 0.1 and its
    sliding at the unloaded point 0 down 1 mm; B alone with a law. The relative differences by hand: force track
    +0.25, mean CS (2·0.1 + 3·0.2 + 4·0.5)/2.4 − 1 = +0.1667, work-weighted CS (2·0.1 + 9·0.2 + 4·0.5)/3.6 − 1 = +0.1111."""
    from hipsim.wear.laws import WearFactor, predict_wear

    maps_a = _maps(np.array([1.0, 2.0, 3.0, 4.0]))
    maps_b = replace(
        maps_a,
        name="two",
        force_track_mm=15.0,
        sliding_mm=np.array([4.0, 2.0, 4.0, 6.0]),
        cross_shear=np.array([NAN, 0.1, 0.2, 0.5]),
    )
    wear_b = predict_wear(maps_b, WearFactor(2e-7))
    provenance = {"command": "wear --compare"}
    result = wear_comparison((maps_a, None), (maps_b, wear_b), 0.15, provenance)
    assert result.provenance is provenance and result.tolerance == 0.15
    assert (result.a.source, result.a.wear_law, result.a.force_track_mm) == ("hand", None, 12.0)
    assert (result.b.source, result.b.wear_law, result.b.force_track_mm) == ("two", wear_b.law, 15.0)
    assert result.b.cross_shear_mean == pytest.approx(2.8 / 9)
    relative = {row.key: row.relative for row in result.differences}
    assert relative["force_track_mm"] == pytest.approx(0.25)
    assert relative["cross_shear_mean"] == pytest.approx(1 / 6)
    assert relative["cross_shear_work_weighted"] == pytest.approx(1 / 9)
    assert relative["wear_mm3_per_Mc"] is None  # A has no law
    assert result.largest_point_differences == pytest.approx(
        {"sliding_mm": 1.0, "work_N_per_mm": 0.0, "cross_shear": 0.1}
    )
    # 0.1111 < 0.15 < 0.1667: two quantities beyond, named in their order
    assert result.verdict.level == Level.DIFFERENT
    assert result.verdict.judged == (
        "B (two) against A (hand): force track length differs most, by +25 % (12 → 15 mm). "
        "Beyond ±15 %: force track length, mean CS (loaded area)."
    )
    alike = wear_comparison((maps_a, None), (maps_b, wear_b), 0.25, provenance).verdict
    assert alike.level == Level.ALIKE and alike.judged.endswith("Every quantity judged is within ±25 %.")
    jsonschema.validate(result.to_json(), type(result).json_schema())
