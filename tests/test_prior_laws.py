"""hipsim.rig.identification.prior and the rows' independence factors pinned by hand.

The prior: each standard parameter's default standard deviation is 30 % of an
inertial parameter's size and 50 % of a friction coefficient's (the size a
typical value where the value is 0), overridden per entry; the base
parameters' standard deviation is s_b,k = √(Σ_j T_kj²·s_j²) (each folded
parameter's variance weighted by the square of its coefficient).
The rows: a log low-passed at f_c and sampled at f_s keeps every
D = ⌊f_s/(4·f_c)⌋-th sample; those rows are f_s/D/(2·f_c) per independent one
(the filter), and at least f_s/D/(2·min(f_c, 10 Hz)) (the model error's floor).
"""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

import hipsim
from hipsim.exceptions import HipsimError
from hipsim.rig.identification.prior import (
    DEFAULT_RELATIVE,
    HELD,
    Prior,
    parse_prior_option,
    prior,
    standard_std,
)
from hipsim.rig.identification.quantities import QUANTITIES
from hipsim.rig.identification.regressor import (
    MODEL_ERROR_BANDWIDTH,
    decimation,
    inflation,
    rows_per_independent_row,
)

INDEX = {q.label: k for k, q in enumerate(QUANTITIES)}


@pytest.fixture(scope="module")
def params():
    return hipsim.load_parameters()


def test_default_prior_by_hand(params):
    assert DEFAULT_RELATIVE == {"inertial": 0.30, "friction": 0.50}
    s = standard_std(params)
    # Slider mass 3 kg: 30 % → 0.9 kg. Lever mass 1.43 kg: 0.429 kg. μ_h = 0.095: 50 % → 0.0475.
    assert s[INDEX["m_L"]] == pytest.approx(0.9, rel=1e-12)
    assert s[INDEX["m_l"]] == pytest.approx(0.429, rel=1e-12)
    assert s[INDEX["μ_h"]] == pytest.approx(0.0475, rel=1e-12)
    # Zero values take the typical size: I_m,xy 0 → 0.3 kg·m² × 30 % = 0.09; screw Coulomb 0 → 0.05 N·m × 50 %.
    assert s[INDEX["I_m,xy"]] == pytest.approx(0.09, rel=1e-12)
    assert s[INDEX["τ_c,screw"]] == pytest.approx(0.025, rel=1e-12)


def test_prior_entries_absolute_relative_and_held(params):
    entries = {"μ_h": 0.02, "friction.screw_coulomb_Nmm": 3.0, "lever": "10 %", "slider.mass_kg": 0}
    s = standard_std(params, entries)
    # Absolute, in the file's unit: 0.02 (μ_h, no unit); 3 N·mm = 0.003 N·m.
    assert s[INDEX["μ_h"]] == pytest.approx(0.02, rel=1e-12)
    assert s[INDEX["τ_c,screw"]] == pytest.approx(0.003, rel=1e-12)
    # A key prefix: every lever parameter at 10 % of its size (m_l 1.43 kg → 0.143; I_l,xy 0 → 0.003 of 0.03).
    assert s[INDEX["m_l"]] == pytest.approx(0.143, rel=1e-12)
    assert s[INDEX["I_l,xy"]] == pytest.approx(0.003, rel=1e-12)
    # 0 holds the slider mass: HELD (1e-9) of its size, 3e-9 kg.
    assert HELD == 1e-9
    assert s[INDEX["m_L"]] == pytest.approx(3e-9, rel=1e-12)
    # Untouched: the platform's defaults.
    assert s[INDEX["I_m,xy"]] == pytest.approx(0.09, rel=1e-12)


@pytest.mark.parametrize(
    "name, value, match",
    [
        ("nothing", 1.0, "no such parameter"),
        ("μ_h", "10", "a number in the parameter's unit or a percentage"),
        ("μ_h", "ten %", "a percentage such as '10 %'"),
        ("μ_h", "-5 %", "non-negative percentage"),
        ("μ_h", "nan %", "non-negative percentage"),
        ("μ_h", -0.1, "non-negative number"),
        ("μ_h", True, "non-negative number"),
        ("μ_h", math.inf, "non-negative number"),
    ],
)
def test_bad_prior_entries(params, name, value, match):
    with pytest.raises(HipsimError, match=match):
        standard_std(params, {name: value}, source="start.toml")


def test_parse_prior_option():
    assert parse_prior_option("μ_h=0.02, lever=10 %,") == {"μ_h": 0.02, "lever": "10 %"}
    assert parse_prior_option("") == {}
    for bad in ("μ_h", "=3", "μ_h=", "μ_h=abc"):
        with pytest.raises(HipsimError, match="--prior"):
            parse_prior_option(bad)


def test_the_prior_propagates_through_the_base_map(params):
    # Two base parameters: m_L + 0.5·m_l, and μ_h − 2·m_l (coefficients whose squares differ from
    # their absolute values). With s(m_L) = 0.9, s(m_l) = 0.2, s(μ_h) = 0.05, the rest 0:
    #   s_b0 = √(0.9² + 0.5²·0.2²) = √0.82,  s_b1 = √(0.05² + 2²·0.2²) = √0.1625;
    #   means 3 + 0.5·1.43 = 3.715 and 0.095 − 2·1.43 = −2.765.
    T = np.zeros((2, len(QUANTITIES)))
    T[0, INDEX["m_L"]], T[0, INDEX["m_l"]] = 1.0, 0.5
    T[1, INDEX["μ_h"]], T[1, INDEX["m_l"]] = 1.0, -2.0
    standard = np.zeros(len(QUANTITIES))
    standard[[INDEX["m_L"], INDEX["m_l"], INDEX["μ_h"]]] = 0.9, 0.2, 0.05
    p = Prior(SimpleNamespace(transform=T), params, standard)
    np.testing.assert_allclose(p.std, [math.sqrt(0.82), math.sqrt(0.1625)], rtol=1e-12)
    np.testing.assert_allclose(p.mean, [3.715, -2.765], rtol=1e-12)
    assert p.standard is standard
    # prior(): the same with the standard deviations of the entries (all held but three).
    entries = {q.key: 0 for q in QUANTITIES} | {"slider.mass_kg": 0.9, "lever.mass_kg": 0.2, "friction.hip_mu": 0.05}
    q = prior(SimpleNamespace(transform=T), params, entries)
    np.testing.assert_allclose(q.std, [math.sqrt(0.82), math.sqrt(0.1625)], rtol=1e-6)


@pytest.mark.parametrize(
    "rate, cutoff, D, filter_ratio, rows",
    [
        # 1 kHz, 20 Hz: D = ⌊1000/80⌋ = 12; 1000/12/40 = 2.083; the floor 1000/12/(2·10) = 4.167.
        (1000.0, 20.0, 12, 1000 / 12 / 40, 1000 / 12 / 20),
        # 1 kHz, 5 Hz: D = 50; 1000/50/10 = 2; floor with f_c below 10 Hz: 1000/50/(2·5) = 2.
        (1000.0, 5.0, 50, 2.0, 2.0),
        # 200 Hz, 90 Hz: D = ⌊200/360⌋ = 0 → 1; 200/180 = 1.11; floor 200/20 = 10.
        (200.0, 90.0, 1, 200 / 180, 10.0),
        # 200 Hz, 99 Hz: 200/198 = 1.0101 (at least 1).
        (200.0, 99.0, 1, 200 / 198, 10.0),
        # No filter: every sample, each independent by the filter; the floor 1000/20 = 50.
        (1000.0, None, 1, 1.0, 50.0),
    ],
)
def test_rows_per_independent_row_by_hand(rate, cutoff, D, filter_ratio, rows):
    assert MODEL_ERROR_BANDWIDTH == 10.0
    log = SimpleNamespace(rate=rate, cutoff=cutoff)
    assert decimation(log) == D
    assert inflation(log) == pytest.approx(filter_ratio, rel=1e-12)
    assert rows_per_independent_row(log) == pytest.approx(rows, rel=1e-12)


def test_the_filter_ratio_is_never_below_one():
    # 100 Hz, 49 Hz: D = 1, 100/98 = 1.02. A 10 Hz log "filtered" at 6 Hz (above its Nyquist frequency,
    # which the reader refuses) would give 10/12 < 1: held at 1.
    assert inflation(SimpleNamespace(rate=100.0, cutoff=49.0)) == pytest.approx(100 / 98, rel=1e-12)
    assert inflation(SimpleNamespace(rate=10.0, cutoff=6.0)) == 1.0
