"""The wear comparison's verdict block (hipsim.present.wear_page.compare_block of hipsim.wear.summary.compare_verdict): NOT COMPARED, ALIKE at the
tolerance, DIFFERENT beyond it either way, the quantities that do not decide left out; rows made by hand. Whole pages:
cli/test_wear.py."""

from __future__ import annotations

import pytest

from hipsim.present import pages
from hipsim.present.wear_page import DEFAULT_TOLERANCE, compare_block
from hipsim.wear.summary import Difference
from hipsim.wear.summary import compare_verdict as wear_verdict


def compare_verdict(rows: tuple[Difference, ...], tolerance: float, names: tuple[str, str]) -> pages.Verdict:
    """The page's block of the wear comparison's verdict, as write_wear_compare makes it."""
    return compare_block(wear_verdict(rows, tolerance, names))


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


def _row(a: float, b: float) -> Difference:
    return Difference("cross_shear_mean", "mean CS (loaded area)", "", a, b, b - a, (b - a) / abs(a), True)


@pytest.mark.parametrize(
    ("b", "word", "state", "symbol"),
    [
        (0.105, "ALIKE", "pass", "✔"),  # +5 %: at the tolerance, alike
        (0.095, "ALIKE", "pass", "✔"),  # −5 %: alike the other way too
        (0.1051, "DIFFERENT", "fail", "✘"),  # +5.1 %
        (0.0949, "DIFFERENT", "fail", "✘"),  # −5.1 %: a fall counts as a rise does
    ],
)
def test_the_block_is_the_verdicts_level_both_ways(b, word, state, symbol):
    verdict = wear_verdict((_row(0.1, b),), 0.05 + 1e-12, ("A", "B"))
    block = compare_block(verdict)
    assert (verdict.level.value, block.word, block.state, block.symbol) == (word, word, state, symbol)
    assert block.lines == (verdict.judged,)


def test_a_row_missing_in_a_is_not_compared():
    row = Difference("cross_shear_mean", "mean CS (loaded area)", "", None, 0.1, None, None, True)
    block = compare_block(wear_verdict((row,), 0.05, ("A", "B")))
    assert (block.word, block.state, block.lines) == ("NOT COMPARED", "open", ("No quantity is known in both runs.",))
