"""The closed-form ratings (hipsim.design.ratings) against hand calculations and the ball-screw makers' charts."""

import math

import numpy as np
import pytest
from drive_support import RPM

from hipsim.design.ratings import buckling_load, critical_speed, screw_life, winding_rise
from hipsim.machine.drive_parts import LeadScrew, SizingRules


def test_winding_rise_of_a_square_wave_has_the_first_order_closed_form():
    """Loss on for half the period, off for the other half: the periodic peak is H/(1 + a), a = exp(−T/2τ)."""
    period, tau, H = 2.0, 1.5, 50.0
    n = 2000
    heating = np.where(np.arange(n) < n // 2, H, 0.0)[:, None]
    mean, peak = winding_rise(heating, np.full(n, period / n), tau)
    a = math.exp(-period / 2 / tau)
    assert mean[0] == pytest.approx(H / 2)
    assert peak[0] == pytest.approx(H / (1 + a), rel=1e-9)
    _, no_time_constant = winding_rise(heating, np.full(n, period / n), None)
    assert no_time_constant[0] == pytest.approx(H / 2)


def test_screw_life_with_a_preloaded_double_nut():
    """F₁ = F_pr(1 + F/(2^1.5 F_pr))^1.5, F₂ = F₁ − F; L = (L₁^(-10/9) + L₂^(-10/9))^(-9/10)."""
    force, preload, rating = 500.0, 300.0, 10_000.0
    n = 50
    life, equivalent = screw_life(np.full(n, force), np.full(n, 100.0), np.full(n, 0.02), rating, preload)
    f1 = preload * (1 + force / (2**1.5 * preload)) ** 1.5
    f2 = f1 - force
    l1, l2 = (rating / f1) ** 3 * 1e6, (rating / f2) ** 3 * 1e6
    assert life == pytest.approx((l1 ** (-10 / 9) + l2 ** (-10 / 9)) ** (-9 / 10), rel=1e-12)
    assert equivalent == pytest.approx(rating / (life / 1e6) ** (1 / 3))
    # A load beyond 2^1.5·F_pr lifts one half off: the other carries it all.
    life, _ = screw_life(np.full(n, 1000.0), np.full(n, 100.0), np.full(n, 0.02), rating, preload)
    assert life == pytest.approx((rating / 1000.0) ** 3 * 1e6)


def test_screw_life_under_a_load_that_changes_direction():
    """Half the revolutions pulling, half pushing, no preload: each flank sees half; L = L_F·2^(1/9)... by the combination rule."""
    force, rating = 400.0, 8000.0
    load = np.where(np.arange(100) < 50, force, -force)
    life, _ = screw_life(load, np.full(100, 50.0), np.full(100, 0.01), rating)
    each = (rating / (0.5 * force**3) ** (1 / 3)) ** 3 * 1e6  # each flank: cubic mean over all revolutions
    assert life == pytest.approx((2 * each ** (-10 / 9)) ** (-9 / 10), rel=1e-12)


@pytest.mark.parametrize(
    ("fixing", "thk_speed", "thk_buckling"),
    # Ball-screw makers' chart factors (safety factors 0.8 and 0.5 included): n = f·d₂/l²·10⁷ rpm, P = η·d₂⁴/l²·10⁴ N (mm).
    [
        ("fixed-free", 3.4, 1.3),
        ("supported-supported", 9.7, 5.1),
        ("fixed-supported", 15.1, 10.2),
        ("fixed-fixed", 21.9, 20.3),
    ],
)
def test_critical_speed_and_buckling_match_the_makers_charts(fixing, thk_speed, thk_buckling):
    d, l = 12.9, 350.0  # mm
    screw = LeadScrew("s", root_diameter=d * 1e-3, free_length=l * 1e-3, end_fixing=fixing)
    rules = SizingRules()
    assert rules.critical_speed_factor * critical_speed(screw) / RPM == pytest.approx(
        thk_speed * d / l**2 * 1e7, rel=0.02
    )
    assert rules.buckling_factor * buckling_load(screw) == pytest.approx(thk_buckling * d**4 / l**2 * 1e4, rel=0.05)


def test_a_winding_rise_with_an_undefined_sample_is_undefined():
    """A NaN heating makes the peak NaN wherever it falls in the cycle (as np.maximum would), never a smaller number."""
    for k in (0, 2, 4):
        heating = np.array([[10.0], [40.0], [20.0], [30.0], [5.0]])
        heating[k, 0] = np.nan
        mean, peak = winding_rise(heating, np.full(5, 0.2), 0.5)
        assert np.isnan(peak[0]) and np.isnan(mean[0])
