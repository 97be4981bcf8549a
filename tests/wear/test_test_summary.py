"""The wear test's records (hipsim.wear.test_summary) by hand: a station's rate, the difference of two, the fitted
k and what it predicts, each with the JSON key it is published under."""

from __future__ import annotations

import numpy as np
import pytest

from hipsim.wear.factors import FittedFactors, MotionIntegrals
from hipsim.wear.gravimetric import rate_difference, station_rate
from hipsim.wear.test_context import FrictionState
from hipsim.wear.test_summary import DifferenceSummary, FittedSummary, FrictionSummary, RateSummary
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
