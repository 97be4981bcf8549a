"""The wear comparison page's verdict block, rendered from compare_verdict (hipsim/present/wear_page.py), by hand."""

from __future__ import annotations

import pytest

from hipsim.present.wear_page import compare_block
from hipsim.wear.summary import Difference, compare_verdict


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
    verdict = compare_verdict((_row(0.1, b),), 0.05 + 1e-12, ("A", "B"))
    block = compare_block(verdict)
    assert (verdict.level.value, block.word, block.state, block.symbol) == (word, word, state, symbol)
    assert block.lines == (verdict.judged,)


def test_nothing_known_in_both_runs_is_not_compared():
    row = Difference("cross_shear_mean", "mean CS (loaded area)", "", None, 0.1, None, None, True)
    block = compare_block(compare_verdict((row,), 0.05, ("A", "B")))
    assert (block.word, block.state, block.lines) == ("NOT COMPARED", "open", ("No quantity is known in both runs.",))
