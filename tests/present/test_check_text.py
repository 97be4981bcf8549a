"""hipsim.present.check_text by hand: a drive check as its label, module and what the cycle needs against what the part offers."""

from __future__ import annotations

from hipsim.design.checks import Check
from hipsim.present.check_text import check_sentence


def test_a_speed_check_in_words():
    check = Check(2, "max_speed", 7478.2, 6000.0, 1 - 7478.2 / 6000.0, False)
    assert check_sentence(check) == "peak motor speed, LN2: needs 7,478 rpm; the motor's top speed is 6,000"


def test_figures_are_four_significant_with_separators_and_without_trailing_zeros():
    check = Check(1, "inertia_ratio", 3.14159, 10.0, 0.69, True)
    assert check_sentence(check).endswith("LN1: 3.142 : 1; at most 10 : 1 allowed")


def test_the_peak_curve_names_only_the_first_part_of_its_detail():
    check = Check(3, "peak_curve", 1234.56, 1500.0, 0.18, True, detail="at 2500 rpm, t = 0.41 s")
    assert check_sentence(check).endswith("LN3: needs 1,235 N·mm at 2500 rpm; the peak curve gives 1,500 N·mm there")


def test_an_empty_detail_leaves_no_empty_brackets():
    check = Check(1, "buckling", 2000.0, 8000.0, 0.75, True)
    assert check_sentence(check).endswith("LN1: 2,000 N; 8,000 N allowed")
    detailed = Check(1, "buckling", 2000.0, 8000.0, 0.75, True, detail="fixed-free")
    assert check_sentence(detailed).endswith("LN1: 2,000 N; 8,000 N allowed (fixed-free)")
