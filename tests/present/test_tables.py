"""hipsim.present.tables by hand: the aligned text table, quantities to three figures, margins as signed percentages."""

from __future__ import annotations

import math

from hipsim.present.tables import format_margin, format_quantity, format_table


def test_a_table_aligns_its_first_column_left_and_the_others_right():
    text = format_table(["name", "a"], [["x", 1.234], ["long", "ok"]], title="T")
    # Widths: column 0 max(4, 1, 4) = 4, column 1 max(1, len("1.23"), 2) = 4; two spaces between columns.
    assert text.splitlines() == ["T", "name     a", "----  ----", "x     1.23", "long    ok"]
    assert format_table(["a"], [[2.0]]).splitlines() == ["a   ", "----", "2.00"]  # no title line; two decimals


def test_a_quantity_has_three_figures_whole_numbers_from_one_hundred():
    assert format_quantity(99.94, "N") == "99.9"
    assert format_quantity(100.0, "N") == "100"  # the boundary: whole from 100 up
    assert format_quantity(12345.6, "N") == "12,346"
    assert format_quantity(0.001234, "m") == "0.00123"
    assert format_quantity(123456789.0, "cycles") == "1.23e+08"  # no thousands separators for cycles
    assert format_quantity(None, "N") == "—"
    assert format_quantity(math.inf, "N") == "∞"
    assert format_quantity(-math.inf, "N") == "−∞"


def test_a_margin_is_a_signed_percentage():
    assert format_margin(0.1234) == "+12.3 %"
    assert format_margin(-0.05) == "-5.0 %"
    assert format_margin(0.0) == "+0.0 %"
    assert format_margin(None) == "—"
    assert format_margin(-math.inf) == "−∞"
