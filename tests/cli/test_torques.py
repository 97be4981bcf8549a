"""The torques command's own logic (hipsim.cli.torques): which cycle a time falls in, at the edges of a cycle."""

from __future__ import annotations

import pytest

from hipsim.cli.torques import _cycle_of
from hipsim.motion.trajectories import iso14242


def test_a_time_in_a_run_of_several_cycles():
    run = iso14242(rate=10.0, cycles=3)  # 0 … 2.9 s, periodic: it spans 3 s
    at = _cycle_of(2.35, run, 1.0)
    assert at is not None and at.cond_inv_min_cycle == 3 and at.cond_inv_min_t_in_cycle_s == pytest.approx(0.35)
    start = _cycle_of(2.0 - 1e-10, run, 1.0)  # a hair before 2 s, as a time printed to 6 digits: cycle 3's start
    assert start is not None and (start.cond_inv_min_cycle, start.cond_inv_min_t_in_cycle_s) == (3, 0.0)
    first = _cycle_of(0.0, run, 1.0)
    assert first is not None and first.cond_inv_min_cycle == 1


def test_one_cycle_or_no_period_has_no_cycle_to_name():
    one = iso14242(rate=10.0)  # spans exactly one period
    assert _cycle_of(0.5, one, 1.0) is None
    assert _cycle_of(0.5, iso14242(rate=10.0, cycles=3), None) is None
