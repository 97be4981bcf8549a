"""hipsim.wear.factors by hand: the force-track factor spread by the work, ``K:KIND`` at the ends of its range, each
law's kind, a motion's integrals (ΣW·dA and the work-weighted CS, not the area mean), fitted factors and what they
predict, and the k(CS) table fitted from stations at CS_APART's boundary."""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

from hipsim.exceptions import ArgumentError
from hipsim.wear.factors import (
    CS_APART,
    ForceTrackFactor,
    MotionIntegrals,
    fit_factors,
    fitted_wear_law,
    kind_of,
    motion_integrals,
    parse_wear_factor,
    predicted_rate,
)
from hipsim.wear.kinematics import CupSetup
from hipsim.wear.laws import ContactAreaLaw, CrossShearLaw, WearFactor, predict_wear
from hipsim.wear.maps import WearMaps
from hipsim.wear.points import CupPoints

NAN = math.nan
AREA = np.array([1.0, 2.0, 3.0, 4.0])


def _maps(area: np.ndarray | None = AREA, work=(0.0, 1.0, 3.0, 2.0)) -> WearMaps:
    return WearMaps(
        points=CupPoints(np.eye(3)[[2, 0, 1, 2]], area),
        setup=CupSetup(),
        sliding_mm=np.ones(4),
        sliding_loaded_mm=np.ones(4),
        work_N_per_mm=np.array(work),
        cross_shear=np.where(np.array(work) > 0, [NAN, 0.1, 0.2, 0.4], NAN),
        principal=np.zeros((4, 3)),
        force_track_mm=12.0,
        force_track_load_Nm=3.0,
        cycles=1.0,
        duration_s=1.0,
        samples=100,
        name="hand",
        iterations=0,
    )


def test_a_force_track_factor_spreads_the_cups_volume_by_the_work():
    """V = k·∫F ds = 1e-7·3 mm³ a cycle, spread as W/ΣW·dA with ΣW·dA = 0 + 2 + 9 + 8 = 19 N·mm."""
    law = ForceTrackFactor(1e-7)
    assert_allclose(law.depth_mm(_maps()), np.array([0.0, 1.0, 3.0, 2.0]) * 3e-7 / 19.0, rtol=1e-12)
    wear = predict_wear(_maps(), law)
    assert wear.total_mm3_per_Mc == pytest.approx(3e-7 * 1e6, rel=1e-12)
    assert law.describe() == "force-track (global, Saikko: V = k·∫F ds), k = 1e-07 mm³/(N·m)"
    assert_allclose(law.depth_mm(_maps(work=(0.0, 0.0, 0.0, 0.0))), 0.0)  # no work: nothing worn, no 0/0
    with pytest.raises(
        ArgumentError,
        match=r"^points: expected a cup grid \(a force-track factor spreads the cup's "
        r"volume by the work\), got 'points given one by one'$",
    ):
        law.depth_mm(_maps(None))
    # ΣW·dA under 1 N·mm is still spread (0.19 N·mm here), not taken for none.
    assert_allclose(law.depth_mm(_maps(work=(0.0, 0.01, 0.03, 0.02))), np.array([0.0, 1.0, 3.0, 2.0]) * 3e-7 / 19.0)
    assert ForceTrackFactor(0.0).k == 0.0
    for bad in (-1e-12, math.nan, True):
        with pytest.raises(
            ArgumentError, match=rf"^wear factor: expected a wear factor k ≥ 0 in mm³/\(N·m\), got {bad!r}$"
        ):
            ForceTrackFactor(bad)


@pytest.mark.parametrize(
    ("text", "kind", "k"),
    [("8e-8:local", WearFactor, 8e-8), ("0:force-track", ForceTrackFactor, 0.0), ("1e-3:local", WearFactor, 1e-3)],
)
def test_a_factor_with_its_kind_from_zero_to_the_most(text, kind, k):
    factor = parse_wear_factor(text)
    assert type(factor) is kind and factor.k == k


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("8e-8", "K:KIND in mm³/(N·m), KIND local"),
        ("8e-8:", "a value without its kind is ambiguous"),
        ("8e-8:Local", "KIND local (Archard, pin-on-disc"),
        ("x:local", "K:KIND in mm³/(N·m)"),
        ("1.0001e-3:local", r"k in [0, 0.001] mm³/(N·m), got '1.0001e-3:local'"),
        ("-1e-12:force-track", "k in [0, 0.001]"),
        ("nan:local", "k in [0, 0.001]"),
    ],
)
def test_a_factor_without_its_kind_or_out_of_range_is_refused(text, expected):
    with pytest.raises(ArgumentError) as caught:
        parse_wear_factor(text)
    assert str(caught.value).startswith("--wear-factor: expected") and expected in str(caught.value)
    assert str(caught.value).endswith(f", got {text!r}")
    if "K:KIND" in expected:
        assert str(caught.value) == (
            "--wear-factor: expected K:KIND in mm³/(N·m), KIND local (Archard, pin-on-disc: V = ∫k·W dA) or force-track "
            f"(Saikko, simulator: V = k·∫F ds), e.g. 8e-8:force-track; a value without its kind is ambiguous, got {text!r}"
        )


def test_each_law_has_its_kind():
    assert kind_of(ForceTrackFactor(1e-7)) == "force-track"
    assert kind_of(WearFactor(1e-7)) == "local"
    assert kind_of(CrossShearLaw(np.array([0.0]), np.array([1e-7]))) == "local"
    assert kind_of(ContactAreaLaw(1e-9)) == "contact-area"


def test_a_motions_integrals_weigh_cs_by_work_times_area():
    """ΣW·dA = 19 N·mm = 0.019 N·m; CS weighted by W·dA: (0.1·2 + 0.2·9 + 0.4·8)/19 (the area mean would be 0.2667)."""
    integrals = motion_integrals(_maps())
    assert integrals.load_slide_integral_Nm == pytest.approx(0.019, rel=1e-12)
    assert integrals.force_track_load_Nm == 3.0 and integrals.name == "hand"
    assert integrals.cross_shear_work_weighted == pytest.approx(5.2 / 19, rel=1e-12)
    assert integrals.integral("local") == integrals.load_slide_integral_Nm
    assert integrals.integral("force-track") == 3.0
    small = motion_integrals(_maps(work=(0.0, 0.01, 0.03, 0.02)))  # ΣW·dA of 0.19 N·mm still weighs CS
    assert small.cross_shear_work_weighted == pytest.approx(5.2 / 19, rel=1e-12)
    idle = motion_integrals(_maps(work=(0.0, 0.0, 0.0, 0.0)))
    assert idle.load_slide_integral_Nm == 0.0 and math.isnan(idle.cross_shear_work_weighted)
    with pytest.raises(
        ArgumentError,
        match=r"^points: expected a cup grid \(ΣW·dA needs the cells' areas\), got 'points given one by one'$",
    ):
        motion_integrals(_maps(None))
    assert integrals.to_json() == {
        "name": "hand",
        "load_slide_integral_Nm": integrals.load_slide_integral_Nm,
        "force_track_load_Nm": 3.0,
        "cross_shear_work_weighted": integrals.cross_shear_work_weighted,
    }


def test_fitted_factors_by_hand():
    motion = MotionIntegrals(40.0, 30.0, 0.15, "own")
    other = MotionIntegrals(80.0, 45.0, 0.2, "ISO")
    fit = fit_factors("1", 12.0, (11.0, 13.0), motion)
    assert predicted_rate(2e-7, "local", other) == pytest.approx(2e-7 * 80.0 * 1e6)
    assert predicted_rate(2e-7, "force-track", other) == pytest.approx(2e-7 * 45.0 * 1e6)
    assert fit.ci95("force-track") == pytest.approx((11.0 / 30e6, 13.0 / 30e6))
    assert fit.station == "1" and fit.motion is motion
    assert fit.k("local") == pytest.approx(12.0 / 40e6) and fit.k("force-track") == pytest.approx(12.0 / 30e6)
    assert fit.ci95("local") == pytest.approx((11.0 / 40e6, 13.0 / 40e6))
    predicts = fit.predict(other)
    assert predicts["local"] == pytest.approx((24.0, 22.0, 26.0))
    assert predicts["force-track"] == pytest.approx((18.0, 16.5, 19.5))


@pytest.mark.parametrize(("local", "track"), [(0.0, 30.0), (40.0, 0.0), (-1.0, 30.0)])
def test_a_motion_without_work_gives_no_factor(local, track):
    with pytest.raises(
        ArgumentError,
        match=r"^station 2's motion: expected a loaded motion that slides \(ΣW·dA and ∫F ds > 0\), got 'still'$",
    ):
        fit_factors("2", 12.0, (11.0, 13.0), MotionIntegrals(local, track, 0.1, "still"))
    assert fit_factors("2", 12.0, (11.0, 13.0), MotionIntegrals(1e-12, 1e-12, 0.1)).station == "2"


def _fit(name: str, cs: float, rate: float = 12.0):
    return fit_factors(name, rate, (rate - 1, rate + 1), MotionIntegrals(40.0, 30.0, cs, name))


def test_a_cs_table_from_stations_at_least_cs_apart():
    assert CS_APART == 0.01
    law = fitted_wear_law((_fit("2", 0.01, 24.0), _fit("1", 0.0)))  # exactly CS_APART: a table, sorted by CS
    assert law is not None and law.cross_shear.tolist() == [0.0, 0.01]
    assert law.k.tolist() == pytest.approx([12.0 / 40e6, 24.0 / 40e6])
    assert law.source == "fitted from the weighings"
    assert fitted_wear_law((_fit("1", 0.0), _fit("2", 0.0099))) is None
    assert fitted_wear_law((_fit("1", 0.1),)) is None
    assert fitted_wear_law((_fit("1", 0.0), _fit("2", 0.2), _fit("3", 0.205))) is None  # any pair too close
    three = fitted_wear_law((_fit("1", 0.0), _fit("2", 0.2), _fit("3", 0.1)))
    assert three is not None and three.cross_shear.tolist() == [0.0, 0.1, 0.2]
    assert fitted_wear_law((_fit("1", 0.0), _fit("2", 0.2, -1.0))) is None  # a negative rate: no table
    assert fitted_wear_law((_fit("1", 0.0), _fit("2", 0.2, 0.0))) is not None  # k = 0 is a law's k
