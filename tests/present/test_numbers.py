"""hipsim.present.numbers by hand: significant figures, the bounds of plain notation (10⁻³ … 10⁷), uncertainties."""

from __future__ import annotations

import math

import pytest

from hipsim.present.numbers import quantity, significant, with_uncertainty


@pytest.mark.parametrize(
    ("value", "digits", "zeros", "text"),
    [
        (1638.7, 4, True, "1,639"),  # 1.639e3: no decimals left
        (0.35874, 4, True, "0.3587"),
        (562, 4, True, "562.0"),  # the trailing zero is a figure
        (562, 4, False, "562"),
        (9999.6, 4, True, "10,000"),  # rounds into the next power of ten: no decimal for 10⁴
        (-0.5, 4, True, "−0.5000"),  # a true minus sign
        (0.0123456, 3, True, "0.0123"),
        (0, 4, True, "0"),
    ],
)
def test_significant_figures(value, digits, zeros, text):
    assert significant(value, digits, zeros=zeros) == text


def test_plain_notation_ends_at_ten_million_and_at_a_thousandth():
    assert significant(9_994_000) == "9,994,000"  # 10⁶ ≤ x < 10⁷: plain
    assert significant(9_999_999) == "1.000 × 10⁷"  # rounds to 10⁷: a power of ten
    assert significant(12_340_000, zeros=False) == "1.234 × 10⁷"
    assert significant(0.001) == "0.001000"  # 10⁻³ itself is plain
    assert significant(0.00099994) == "9.999 × 10⁻⁴"
    assert significant(-2.5e-5, 2, zeros=False) == "−2.5 × 10⁻⁵"


def test_missing_values_and_infinities():
    assert significant(None) == "—"
    assert significant(math.nan) == "—"
    assert significant(math.inf) == "∞"
    assert significant(-math.inf) == "−∞"


def test_an_uncertainty_rounds_both_at_its_second_figure():
    assert with_uncertainty(0.050971, 0.000123) == "0.05097 ± 0.00012"  # std 1.2e-4: 5 decimals
    assert with_uncertainty(1.23456, 0.0456) == "1.235 ± 0.046"
    assert with_uncertainty(12346.0, 678.0) == "12,350 ± 680"  # std 6.8e2: rounded to tens
    assert with_uncertainty(-3.14159, 0.25) == "−3.14 ± 0.25"


def test_without_a_usable_uncertainty_the_value_has_its_figures():
    for std in (None, 0.0, -1.0, math.nan, math.inf):
        assert with_uncertainty(1.5, std) == "1.500"
    assert with_uncertainty(None, 0.1) == "—"


def test_a_quantity_carries_its_unit():
    assert quantity(431.14, "N·mm") == "431.1 N·mm"
    assert quantity(3.5, ":1") == "3.500:1"  # a ratio joins without a space
    assert quantity(2, "") == "2.000"
    assert quantity(None, "N") == "—"  # no unit on a missing value
