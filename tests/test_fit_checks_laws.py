"""The fits' gates by hand (hipsim/fit_checks.py): the fourth differences' noise, each gate at its edge, the patterns
tried only when asked, every sentence whole."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from hipsim.fit_checks import FitCheck, column_pattern, difference_noise, duplicate_digests, residual_gate


def test_the_noise_from_fourth_differences_by_hand():
    """x = (0, 0, 1, 0, 0, 0, 0): fourth differences 6, −4, 1, their median 1, the deviations 5, 5, 0: MAD 5."""
    x = np.array([0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0])
    assert difference_noise(x) == pytest.approx(1.4826 * 5 / math.sqrt(70), rel=1e-12)
    both = difference_noise(np.column_stack([x, 3 * x, np.arange(7.0) ** 3]))  # a cubic has no fourth difference
    assert both == pytest.approx(
        [1.4826 * 5 / math.sqrt(70), 3 * 1.4826 * 5 / math.sqrt(70), 0.0], rel=1e-12, abs=1e-12
    )
    assert difference_noise(x[:5]) == 0.0  # five samples: one fourth difference
    assert np.isnan(difference_noise(x[:4])) and difference_noise(np.zeros((4, 2))).shape == (2,)


def test_the_residual_gate_at_its_edges():
    names = ("tau_1", "tau_2", "tau_3")
    assert residual_gate([1.5, 0.3, 0.0], [0.5, 0.1, 0.0], names, "N·m") is None  # exactly 3 times passes; 0 of 0
    assert residual_gate([2.0, 0.1, 0.0], 0.5, names, "N·m") == "residuals beyond 3 times the noise: tau_1 2 N·m (4×)"
    assert residual_gate([0.2, 1.0, 0.3], [0.05, 0.0, 0.1], names, "N·m", factor=2.5) == (
        "residuals beyond 2.5 times the noise: tau_1 0.2 N·m (4×), tau_2 1 N·m (inf×), tau_3 0.3 N·m (3×)"
    )
    assert residual_gate([0.0], [0.0], ("a",), "m", factor=0.5) is None  # no residual and no noise: a ratio of 0
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no division by a zero noise, even where it is not used
        assert (
            residual_gate([1.0, 0.0], [0.0, 0.0], ("a", "b"), "m") == "residuals beyond 3 times the noise: a 1 m (inf×)"
        )


def test_a_pattern_of_small_numbers_is_named():
    """Residuals far below 1 (a base of 0.02): the swap is still named."""
    model = np.array([[0.1, 0.0], [0.0, 0.1], [0.05, -0.05]])
    assert column_pattern(model[:, ::-1], model, ("a", "b")) == "columns a and b look swapped"
    assert column_pattern(model, model, ("a", "b")) is None


def test_each_pattern_only_when_asked():
    rng = np.random.default_rng(0)
    model = rng.normal(size=(40, 4))
    halves = model[:, [2, 3, 0, 1]]
    names = ("a1", "b1", "a2", "b2")
    assert column_pattern(halves, model, names) == "the two halves (a1, b1) and (a2, b2) look swapped"
    flipped = model * [1.0, -1.0, 1.0, 1.0]
    shifted = model + [0.0, 0.0, 5.0, 0.0]
    for measured, kind, words in (
        (halves, "swap", "the two halves (a1, b1) and (a2, b2) look swapped"),
        (model[:, [1, 0, 2, 3]], "swap", "columns a1 and b1 look swapped"),
        (flipped, "sign", "column b1 looks sign-flipped"),
        (shifted, "offset", f"column a2 looks offset by {np.mean(shifted - model, axis=0)[2]:+.3g} N (a zero?)"),
        (model / 1e3, "scale", "the columns look 1/1000 of the model's (a unit: N·m for N·mm, kN for N?)"),
    ):
        assert column_pattern(measured, model, names, "N", kinds=(kind,)) == words
        others = tuple(k for k in ("swap", "sign", "offset", "scale") if k != kind)
        found = column_pattern(measured, model, names, "N", kinds=others)
        assert found is None or kind not in ("swap", "sign") or "swapped" not in found and "sign" not in found
    assert column_pattern(flipped, model, names, kinds=("swap",)) is None
    assert column_pattern(halves, model, names, kinds=("sign", "offset")) is None
    assert column_pattern(shifted, model, names, kinds=("sign",)) is None
    assert column_pattern(model * 1e3, model, names, kinds=("swap", "sign")) is None
    # Nothing tried, even at a gain that takes anything: nothing named.
    assert column_pattern(flipped, model, names, gain=-1.0, kinds=()) is None


def test_three_columns_have_no_halves():
    rng = np.random.default_rng(1)
    model = rng.normal(size=(30, 3))
    assert column_pattern(model[:, [1, 0, 2]], model, ("x", "y", "z")) == "columns x and y look swapped"


def test_a_digest_given_twice_whole():
    key = "0123456789abcdef" * 4
    assert duplicate_digests([("a.csv", key), ("b.csv", "f" * 64), ("c.csv", key)]) == (
        "c.csv holds the same bytes as a.csv (SHA-256 0123456789ab…): a log given twice counts its samples twice "
        "and halves the stated variance; give each log once"
    )
    assert duplicate_digests([("a.csv", key), ("b.csv", "f" * 64)]) is None


def test_the_self_check_s_line():
    plain = "self-check: plausible: residuals within 3 times the noise, no parameter beyond 5 prior standard deviations"
    ok = FitCheck("identify")
    assert ok.verdict() == plain and ok.verdict(0) == plain
    assert ok.verdict(1) == plain + "; 1 held-out log predicted within it"
    assert ok.verdict(2) == plain + "; 2 held-out logs predicted within it"
    bad = FitCheck("calibrate", ("one", "two"))
    assert bad.verdict(3) == "self-check: IMPLAUSIBLE, written with --force: one; two"
    assert bad.message() == "calibrate: implausible result: one; two"
    assert bad.to_json() == {"fit": "calibrate", "plausible": False, "findings": ["one", "two"]}
