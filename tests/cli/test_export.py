"""The export's own logic (hipsim.cli.export): the servo rate's and counts' ranges at their edges, each column's
decimals, a periodic table formatted one period and repeated. The command itself: learning/test_export.py."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from hipsim.cli.export import COUNTS_RANGE, RATE_RANGE_HZ, _check, _decimals, csv_bytes, formatted_lines
from hipsim.exceptions import HipsimError

PARAMS = SimpleNamespace(control=SimpleNamespace(servo_rate=1000.0))


@pytest.mark.parametrize(("rate", "counts"), [(1.0, 1.0), (100_000.0, 1e9), (None, 10_000.0)])
def test_the_ranges_include_their_ends(rate, counts):
    assert _check(SimpleNamespace(rate=rate, counts_per_rev=counts), PARAMS) == (rate or 1000.0)


@pytest.mark.parametrize(
    ("rate", "counts", "message"),
    [
        (0.999, 1.0, r"--rate: expected a servo rate in \[1, 100000\] Hz, got 0.999 Hz"),
        (float("nan"), 1.0, "--rate"),
        (100.0, 1e9 * 1.0001, r"--counts-per-rev: expected counts per motor revolution in \[1, 1e\+09\]"),
        (100.0, 0.5, "--counts-per-rev"),
    ],
)
def test_beyond_the_ranges_is_refused_naming_the_option(rate, counts, message):
    with pytest.raises(HipsimError, match=message):
        _check(SimpleNamespace(rate=rate, counts_per_rev=counts), PARAMS)
    assert RATE_RANGE_HZ == (1.0, 100_000.0) and COUNTS_RANGE == (1.0, 1e9)


def test_each_column_is_rounded_to_its_decimals():
    assert [_decimals(n) for n in ("t_s", "position_counts_1", "torque_Nm_2", "position_rev_3")] == [9, 6, 9, 10]
    assert formatted_lines(np.array([0.1234567891234, 2.0]), "t_s") == ["0.123456789", "2"]
    assert formatted_lines(np.array([1.23456789]), "position_counts_1") == ["1.234568"]


def test_a_periodic_table_is_its_period_repeated_beside_each_time():
    t = np.arange(6) * 0.25
    columns = {"t_s": t, "torque_1": np.tile([1.0, -2.5, 0.125], 2)}
    whole = csv_bytes(columns)
    assert whole.decode() == "t_s,torque_1\n0,1\n0.25,-2.5\n0.5,0.125\n0.75,1\n1,-2.5\n1.25,0.125\n"
    assert csv_bytes(columns, period_rows=3) == whole
    shared = csv_bytes(columns, period_rows=3, times=["a", "b", "c", "d", "e", "f"]).decode().splitlines()
    assert shared[1:3] == ["a,1", "b,-2.5"]
    # a period that does not divide the rows: formatted whole
    odd = {"t_s": t[:5], "torque_1": np.arange(5.0)}
    assert csv_bytes(odd, period_rows=3) == csv_bytes(odd)
