"""The wear test's records (hipsim.wear.test_summary) by hand: a station's rate, the difference of two, the fitted
k and what it predicts, each with the JSON key it is published under."""

from __future__ import annotations

import numpy as np
import pytest

from hipsim.wear.accumulate import Exposure
from hipsim.wear.factors import FittedFactors, MotionIntegrals
from hipsim.wear.gravimetric import Gravimetry, rate_difference, station_rate
from hipsim.wear.test_context import FrictionState, MotionError, StationContext
from hipsim.wear.test_result import GivenFactor, wear_test
from hipsim.wear.test_summary import (
    DifferenceSummary,
    FittedSummary,
    FrictionSummary,
    GivenFactorSummary,
    RateSummary,
    wear_test_summary,
)
from hipsim.wear.weighings import StationWeighings


def _rate(name: str, mg_per_Mc: float):
    """Four stops 0.5 Mc apart, an exact line of ``mg_per_Mc`` (no soak uptake), density 0.94 mg/mm³."""
    cycles = np.array([0.0, 5e5, 1e6, 1.5e6])
    mass = 30_000.0 - mg_per_Mc * cycles / 1e6
    weighed = StationWeighings(name, "soak", cycles, mass, np.full(4, 500.0), np.arange(4) + 2)
    return station_rate(weighed, density_mg_per_mm3=0.94, from_cycle=0)


def test_a_rate_and_a_difference_by_hand():
    one, two = _rate("1", 10.0), _rate("2", 14.0)
    r = RateSummary.of(one)
    assert (r.stops, r.cycles, r.wear_rate_mg_per_Mc) == (4, (0, 500_000, 1_000_000, 1_500_000), pytest.approx(10.0))
    assert r.wear_rate_mm3_per_Mc == pytest.approx(10.0 / 0.94) and r.volume_mm3[-1] == pytest.approx(15.0 / 0.94)
    assert r.to_json()["wear_rate_ci95_mm3_per_Mc"] == pytest.approx([10.0 / 0.94, 10.0 / 0.94], rel=1e-6)
    d = DifferenceSummary.of(rate_difference(one, two))
    assert (d.a, d.b) == ("1", "2") and d.difference_mg_per_Mc == pytest.approx(4.0)  # b − a, not a − b
    assert d.difference_mm3_per_Mc == pytest.approx(4.0 / 0.94)


def test_the_fitted_k_and_its_prediction_by_hand():
    """k = rate / (integral · 10⁶): 10 mm³/Mc over ΣW·dA = 5 N·m is 2e-6; over ∫F ds = 20 N·m, 5e-7; on a motion of
    twice the integrals, twice the rate."""
    own = MotionIntegrals(5.0, 20.0, 0.05, "own")
    fitted = FittedFactors("1", own, 10.0, (8.0, 12.0))
    s = FittedSummary.of(fitted, MotionIntegrals(10.0, 40.0, 0.05, "ISO"))
    assert s.k_local_mm3_per_Nm == pytest.approx(2e-6) and s.k_force_track_mm3_per_Nm == pytest.approx(5e-7)
    assert s.k_local_ci95 == pytest.approx((1.6e-6, 2.4e-6))
    document = s.to_json()
    assert document["predicts"]["local_mm3_per_Mc"] == pytest.approx([20.0, 16.0, 24.0])
    assert document["predicts"]["force-track_mm3_per_Mc"] == pytest.approx([20.0, 16.0, 24.0])
    assert document["motion"] == {
        "load_slide_integral_Nm": 5.0,
        "force_track_load_Nm": 20.0,
        "cross_shear_work_weighted": 0.05,
        "name": "own",
    }
    assert "predicts" not in FittedSummary.of(fitted, None).to_json()


def test_a_friction_state_keeps_its_sentence():
    f = FrictionSummary.of(FrictionState("m.parquet", 3, 1_500_000, 0.004, 0.001, False, ""))
    assert f.own_station is False and f.summary.startswith("hip μ change +0.0040 ± 0.0010 (the two stations' mean)")


def test_the_whole_document_by_hand():
    """Two stations (1: 10 mg/Mc, 2: 14 mg/Mc) over one motion each, a given local factor, the reference motion, a
    context for station 2 only: each station under its own name with its own numbers, the difference b − a, the
    verdict's word, the density and the weighings' file as given, the k(CS) law one entry per station."""
    one, two = _rate("1", 10.0), _rate("2", 14.0)
    gravimetry = Gravimetry("w.csv", 0.94, "0.94 mg/mm³ (given)", (one, two), (rate_difference(one, two),))
    # the same ΣW·dA, two cross-shears: the k(CS) law has two points
    motions = {"1": MotionIntegrals(5.0, 20.0, 0.05, "one"), "2": MotionIntegrals(5.0, 20.0, 0.1, "two")}
    exposures = {n: Exposure(n, np.array([0.0, 1.5e6]), (m,), f"station {n}'s motion") for n, m in motions.items()}
    reference = MotionIntegrals(10.0, 40.0, 0.1, "ISO")
    result = wear_test(gravimetry, exposures, GivenFactor(2e-6, "local"), reference=reference)
    friction = FrictionState("m.parquet", 3, 1_500_000, 0.004, 0.001, True, "")
    error = MotionError("m.csv", (0.1, 0.2, 0.3), (0.5, 0.6, 0.7))
    context = StationContext("2", error, friction)
    mg_of = {"1": 10.0, "2": 14.0}
    s = wear_test_summary(result, (context,))
    assert (
        s.verdict is result.verdict
        and s.to_json()["verdict"] == result.verdict.to_json()
        and "lines" not in s.to_json()
    )
    assert (s.density_mg_per_mm3, s.density, s.weighings) == (0.94, "0.94 mg/mm³ (given)", "w.csv")
    assert s.wear_factor == GivenFactorSummary(2e-6, "local") and s.reference_motion == reference
    assert list(s.stations) == ["1", "2"]
    for name, mg in (("1", 10.0), ("2", 14.0)):
        station = s.stations[name]
        assert station.rate.wear_rate_mg_per_Mc == pytest.approx(mg)
        # k = rate / ΣW·dA: (mg / 0.94) mm³/Mc over 5 N·m per cycle
        assert station.fitted.k_local_mm3_per_Nm == pytest.approx(mg / 0.94 / 5.0 / 1e6)
    for name, wear in zip("12", result.stations, strict=True):  # every field the record copies, from its station
        station, rate = s.stations[name], wear.rate
        r = station.rate
        assert (r.station, r.soak_control, r.from_cycle, r.bedding_in) == (
            name,
            rate.soak_control,
            rate.from_cycle,
            rate.bedding_in,
        )
        assert r.wear_rate_ci95_mg_per_Mc == rate.ci95_mg_per_Mc and r.standard_error_mg_per_Mc == rate.se_mg_per_Mc
        assert r.degrees_of_freedom == rate.dof == 2 and r.loss_mg == tuple(rate.loss_mg) and r.outliers == ()
        assert r.bedding_in_rate_mg_per_Mc is rate.bedding_in_rate_mg_per_Mc  # NaN: no bedding-in
        assert station.motion == f"station {name}'s motion" and station.interval_law == wear.interval_law
        assert station.predicted_mm3_per_Mc == wear.predicted_mm3_per_Mc and station.intervals == wear.intervals
        assert station.prediction_within_ci95 is wear.within
        f = station.fitted
        assert f.station == name and f.motion == wear.fitted.motion  # the steady state's motion, named by its cycles
        assert f.motion.name == f"station {name}'s motion, cycles 0 to 1500000"
        assert f.k_force_track_mm3_per_Nm == pytest.approx(wear.fitted.k("force-track"))  # over ∫F ds = 20 N·m
        assert f.k_force_track_mm3_per_Nm == pytest.approx(f.k_local_mm3_per_Nm / 4.0)
        assert f.k_force_track_ci95 == wear.fitted.ci95("force-track") != f.k_local_ci95
        assert f.predicts is not None and f.predicts.motion == reference  # on the reference motion: twice the rate
        assert f.predicts.local_mm3_per_Mc[0] == pytest.approx(2 * mg_of[name] / 0.94)
    assert s.stations["1"].friction is None and s.stations["1"].motion_error is None  # no context given for it
    assert s.stations["2"].motion_error == error
    friction_summary = s.stations["2"].friction
    assert friction_summary is not None and friction_summary.own_station is True
    assert len(s.differences) == 1 and s.differences[0].difference_mg_per_Mc == pytest.approx(4.0)
    d, given = s.differences[0], gravimetry.differences[0]
    assert d.ci95_mg_per_Mc == given.ci95_mg_per_Mc and d.significant is given.significant
    assert d.ci95_mm3_per_Mc == pytest.approx(tuple(x / 0.94 for x in given.ci95_mg_per_Mc), nan_ok=True)  # exact lines
    assert (
        friction_summary.source,
        friction_summary.snapshots,
        friction_summary.last_cycle,
        friction_summary.hip_mu_change,
        friction_summary.hip_mu_change_std,
        friction_summary.flag,
    ) == ("m.parquet", 3, 1_500_000, 0.004, 0.001, "")
    law = s.fitted_wear_law
    assert law is not None and law.cross_shear == pytest.approx((0.05, 0.1))
    assert law.k_mm3_per_Nm == pytest.approx((10.0 / 0.94 / 5e6, 14.0 / 0.94 / 5e6))
    assert s.to_json()["stations"]["2"]["wear_rate_mg_per_Mc"] == pytest.approx(14.0)  # the rate's keys flattened in


def test_one_station_is_a_verdict_not_made():
    one = _rate("1", 10.0)
    motion = MotionIntegrals(5.0, 20.0, 0.05, "own")
    exposures = {"1": Exposure("1", np.array([0.0, 1.5e6]), (motion,), "station 1's motion")}
    result = wear_test(Gravimetry("w.csv", 0.94, "given", (one,), ()), exposures)
    verdict = wear_test_summary(result).to_json()["verdict"]
    assert verdict["level"] == "NOT MADE" and verdict["numbers"] == {} and result.word == "ONE STATION"
    assert verdict["not_judged"] == "the stations' rates against each other: the comparison needs two stations weighed"
