"""The wear comparison's verdict block (hipsim.present.wear_page.compare_verdict): NOT COMPARED, ALIKE at the
tolerance, DIFFERENT beyond it either way, the quantities that do not decide left out; rows made by hand. Whole pages:
cli/test_wear.py."""

from __future__ import annotations

import pytest

from hipsim.present.wear_page import DEFAULT_TOLERANCE, compare_verdict
from hipsim.wear.summary import Difference


def row(key, a, b, decides=True):
    relative = None if a is None or b is None or a == 0 else (b - a) / abs(a)
    difference = None if a is None or b is None else b - a
    return Difference(key, key.replace("_", " "), "mm", a, b, difference, relative, decides)


def test_nothing_known_in_both_runs_is_not_compared():
    verdict = compare_verdict(
        (row("work", None, 1.0), row("cs", 0.0, 1.0), row("v", 1.0, 9.0, False)), 0.05, ("a", "b")
    )
    assert (verdict.state, verdict.word, verdict.lines) == (
        "open",
        "NOT COMPARED",
        ("No quantity is known in both runs.",),
    )


@pytest.mark.parametrize(
    ("b", "word"), [(1.25, "ALIKE"), (0.75, "ALIKE"), (1.2501, "DIFFERENT"), (0.7499, "DIFFERENT")]
)
def test_the_tolerance_either_way(b, word):
    # a quarter of A: exact in binary, so the edge is the comparison's own
    rows = (row("work", 1.0, b), row("volume", 1.0, 3.0, decides=False))
    verdict = compare_verdict(rows, 0.25, ("a", "b"))
    assert verdict.word == word and verdict.state == ("pass" if word == "ALIKE" else "fail")
    assert verdict.lines[0].startswith("B (b) against A (a): work differs most")


def test_the_largest_difference_by_its_size_is_named():
    rows = (row("work", 10.0, 10.2), row("cross_shear", 2.0, 1.8), row("sliding", 5.0, 5.05))
    (line,) = compare_verdict(rows, 0.05, ("first", "second")).lines
    assert line == (
        "B (second) against A (first): cross shear differs most, by -10 % (2 → 1.8 mm). Beyond ±5 %: cross shear."
    )
    assert DEFAULT_TOLERANCE == 0.05
