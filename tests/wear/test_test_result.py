"""hipsim.wear.test_result by hand: two stations' rates, exposures and a given factor made here; the steady-state
motion each k is fitted over (from the fit's first stop on), the prediction held to the measured interval at its
ends, the intervals' law, the k(CS) table, and the verdict's word and lines (DIFFERENT / ALIKE / ONE STATION)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from hipsim.records import Level
from hipsim.wear.accumulate import Exposure
from hipsim.wear.factors import MotionIntegrals
from hipsim.wear.gravimetric import Gravimetry, RateDifference, StationRate
from hipsim.wear.test_result import GivenFactor, verdict_lines, wear_test, wear_verdict

NAN = math.nan


def _rate(station: str, loss, from_cycle: int, rate: float, ci: tuple[float, float]) -> StationRate:
    return StationRate(
        station, "soak", (0, 1_000_000, 2_000_000), tuple(loss), from_cycle, "none", NAN, rate, 0.5, 1, ci, 1.0, ()
    )


RATES = (
    _rate("1", (0.0, 10.0, 20.0), 0, 10.0, (9.0, 11.0)),
    _rate("2", (0.0, 30.0, 50.0), 1_000_000, 20.0, (18.0, 22.0)),
)
EXPOSURES = {
    "1": Exposure("1", np.array([0.0, 2e6]), (MotionIntegrals(40.0, 30.0, 0.1, "one"),), "station 1's motion"),
    "2": Exposure(
        "2",
        np.array([0.0, 1e6, 2e6]),
        (MotionIntegrals(40.0, 30.0, 0.1, "early"), MotionIntegrals(80.0, 60.0, 0.3, "late")),
        "station 2's motion",
    ),
}


def _gravimetry(*differences: RateDifference) -> Gravimetry:
    return Gravimetry("w.csv", 1.0, "1 mg/mm³ (given)", RATES, differences)


DIFFERENT = RateDifference("1", "2", 10.0, (8.0, 12.0), 1.0)


def test_each_k_is_fitted_over_its_steady_state_motion_and_predicts_with_the_given_factor():
    test = wear_test(_gravimetry(DIFFERENT), EXPOSURES, GivenFactor(2.5e-7, "local"))
    one, two = test.stations
    # Station 2's fit starts at 1 Mc: its steady motion is the late one (80 N·m a cycle), not the mean 60.
    assert two.fitted.motion.load_slide_integral_Nm == pytest.approx(80.0)
    assert two.fitted.k("local") == pytest.approx(20.0 / 80e6) and one.fitted.k("local") == pytest.approx(10.0 / 40e6)
    assert (one.predicted_mm3_per_Mc, two.predicted_mm3_per_Mc) == pytest.approx((10.0, 20.0))  # k·integral·10⁶
    assert one.within is True and two.within is True
    # Per interval with the given k: 2.5e-7 × (40e6, 80e6) N·m against the measured 30 and 20 mm³ of station 2.
    assert [(r.first_cycle, r.last_cycle) for r in two.intervals] == [(0, 1_000_000), (1_000_000, 2_000_000)]
    assert [r.predicted_mm3 for r in two.intervals] == pytest.approx([10.0, 20.0])
    assert [r.measured_mm3 for r in two.intervals] == pytest.approx([30.0, 20.0])
    assert two.interval_law == "k = 2.5e-07 mm³/(N·m), local"
    assert test.fitted_law is not None and test.fitted_law.cross_shear.tolist() == [0.1, 0.3]
    assert test.word == "DIFFERENT" and test.verdict.level == Level.DIFFERENT
    assert test.lines == (
        "station 2 − station 1: +10 mm³/Mc, 95 % [+8, +12]: the rates differ",
        "station 1: predicted 10 mm³/Mc (k = 2.5e-07 mm³/(N·m), local), measured 10 [9, 11]: within",
        "station 2: predicted 20 mm³/Mc (k = 2.5e-07 mm³/(N·m), local), measured 20 [18, 22]: within",
    )


def test_a_force_track_factor_predicts_from_the_force_track():
    test = wear_test(_gravimetry(DIFFERENT), EXPOSURES, GivenFactor(2.5e-7, "force-track"))
    one, two = test.stations
    assert (one.predicted_mm3_per_Mc, two.predicted_mm3_per_Mc) == pytest.approx((7.5, 15.0))
    assert one.within is False and two.within is False
    assert [r.predicted_mm3 for r in two.intervals] == pytest.approx([7.5, 15.0])
    assert test.lines[1].endswith("measured 10 [9, 11]: outside")


def test_without_a_factor_the_intervals_use_the_stations_own_local_k():
    test = wear_test(_gravimetry(), EXPOSURES, reference=MotionIntegrals(20.0, 10.0, 0.2, "ISO"))
    one, two = test.stations
    assert math.isnan(one.predicted_mm3_per_Mc) and one.within is None
    assert two.interval_law == "the station's own fitted local k = 2.5e-07 mm³/(N·m)"
    assert [r.predicted_mm3 for r in two.intervals] == pytest.approx([10.0, 20.0])
    assert test.word == "ONE STATION" and test.verdict.level == Level.NOT_MADE
    assert test.lines == ("one station weighed: no other to compare its rate with",)
    assert test.verdict.judged == test.lines[0] and test.verdict.not_judged == (
        "the stations' rates against each other: the comparison needs two stations weighed"
    )
    assert test.reference == MotionIntegrals(20.0, 10.0, 0.2, "ISO") and test.given is None
    assert two.exposure.source == "station 2's motion" and two.within is None
    assert two.fitted.predict(test.reference)["local"] == pytest.approx((5.0, 4.5, 5.5))
    assert len(two.intervals) == 2
    assert test.fitted_law is not None and test.fitted_law.k.tolist() == pytest.approx([2.5e-7] * 2)


def _station_with(predicted: float, ci: tuple[float, float]):
    test = wear_test(_gravimetry(), EXPOSURES, GivenFactor(2.5e-7, "local"))
    one = test.stations[0]
    rate = _rate("1", (0.0, 10.0, 20.0), 0, 10.0, ci)
    return type(one)(rate, one.exposure, one.fitted, predicted, one.intervals, one.interval_law)


@pytest.mark.parametrize(
    ("predicted", "ci", "within"),
    [
        (9.0, (9.0, 11.0), True),  # at either end: within
        (11.0, (9.0, 11.0), True),
        (np.nextafter(9.0, 0.0), (9.0, 11.0), False),
        (np.nextafter(11.0, 12.0), (9.0, 11.0), False),
        (NAN, (9.0, 11.0), None),
        (10.0, (NAN, 11.0), None),
        (10.0, (9.0, NAN), None),
    ],
)
def test_a_prediction_within_the_interval_at_its_ends(predicted, ci, within):
    assert _station_with(predicted, ci).within is within


@pytest.mark.parametrize(
    ("interval", "level"),
    [
        ((0.0, 12.0), Level.ALIKE),  # an interval that reaches 0 shows no difference
        ((1e-12, 12.0), Level.DIFFERENT),
        ((-12.0, 0.0), Level.ALIKE),
        ((-12.0, -1e-12), Level.DIFFERENT),
    ],
)
def test_the_verdict_follows_the_differences_intervals(interval, level):
    """Significant: the interval excludes 0; one pair of two beyond is DIFFERENT, which exits 1."""
    from hipsim.records import exit_status

    alike = RateDifference("1", "2", 6.0, (-1.0, 13.0), 1.0)
    gravimetry = _gravimetry(alike, RateDifference("1", "3", 1.0, interval, 1.0))
    verdict = wear_verdict(gravimetry)
    assert verdict.level == level and exit_status([verdict]) == (1 if level == Level.DIFFERENT else 0)
    lines = verdict_lines(gravimetry, (), None)
    assert lines[0] == "station 2 − station 1: +6 mm³/Mc, 95 % [-1, +13]: no difference shown"
    assert len(lines) == 2 and verdict.judged == (
        "each pair of stations' wear rates, its difference's 95 % interval against 0: " + "; ".join(lines)
    )
    assert verdict.not_judged == ""  # no factor given: no prediction to leave unjudged
    assert dict(verdict.numbers) == {
        "station_2_minus_1_mm3_per_Mc": 6.0,
        "station_2_minus_1_ci95_low_mm3_per_Mc": -1.0,
        "station_2_minus_1_ci95_high_mm3_per_Mc": 13.0,
        "station_3_minus_1_mm3_per_Mc": 1.0,
        "station_3_minus_1_ci95_low_mm3_per_Mc": interval[0],
        "station_3_minus_1_ci95_high_mm3_per_Mc": interval[1],
    }


def test_a_verdict_without_an_interval_to_hold_the_prediction_against():
    test = wear_test(_gravimetry(DIFFERENT), EXPOSURES, GivenFactor(2.5e-7, "local"))
    station = _station_with(10.0, (NAN, NAN))
    lines = verdict_lines(_gravimetry(DIFFERENT), (station,), GivenFactor(2.5e-7, "local"))
    assert lines[1].endswith("measured 10 [nan, nan]: no interval to hold it against")
    assert test.given == GivenFactor(2.5e-7, "local")
    assert test.verdict.not_judged == (
        "each station's prediction with the given factor against its measured rate's 95 % interval (shown, not judged)"
    )


def test_a_verdicts_word_and_level():
    one = wear_test(_gravimetry(), EXPOSURES, GivenFactor(2.5e-7, "local"))
    assert (one.word, one.verdict.level) == ("ONE STATION", Level.NOT_MADE)
    assert one.verdict.not_judged == (
        "the stations' rates against each other: the comparison needs two stations weighed; each station's "
        "prediction with the given factor against its measured rate's 95 % interval (shown, not judged)"
    )
    assert one.lines[0] == "one station weighed: no other to compare its rate with" and len(one.lines) == 3
    assert GivenFactor(8e-8, "force-track").describe() == "k = 8e-08 mm³/(N·m), force-track"


def test_the_steady_motion_runs_to_the_last_stop_and_one_station_has_no_table():
    """Four stops, a motion of 40 N·m a cycle for 2 Mc then 100 for 1 Mc: the fit's motion is their mean over
    0–3 Mc, (2·40 + 100)/3 = 60 N·m, not the mean to an earlier stop."""
    rate = StationRate(
        "9",
        "soak",
        (0, 1_000_000, 2_000_000, 3_000_000),
        (0.0, 6.0, 12.0, 18.0),
        0,
        "none",
        NAN,
        6.0,
        0.1,
        2,
        (5.0, 7.0),
        1.0,
        (),
    )
    motions = (MotionIntegrals(40.0, 30.0, 0.1, "a"), MotionIntegrals(100.0, 50.0, 0.2, "b"))
    exposure = Exposure("9", np.array([0.0, 2e6, 3e6]), motions, "log")
    test = wear_test(Gravimetry("w.csv", 1.0, "1 mg/mm³ (given)", (rate,), ()), {"9": exposure})
    (station,) = test.stations
    assert station.fitted.motion.load_slide_integral_Nm == pytest.approx(60.0)
    assert station.fitted.station == "9" and [r.station for r in station.intervals] == ["9", "9", "9"]
    assert test.fitted_law is None and math.isnan(station.predicted_mm3_per_Mc)
