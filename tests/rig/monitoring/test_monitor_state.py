"""The monitor's state at the last snapshot and its verdict, by hand (hipsim/rig/monitoring/monitor_state.py)."""

from __future__ import annotations

import numpy as np
import pytest

from hipsim.records import Level, exit_status
from hipsim.rig.monitoring.monitor_state import monitor_state, monitor_verdict


@pytest.mark.parametrize(
    ("alarm", "flag", "note", "level", "status"),
    [
        ([0, 1], ["", "alarm: μ_h up"], None, Level.ALARM, 1),
        ([1, 0], ["alarm: μ_h up", "notice: μ_h up 2 %"], None, Level.NOTICE, 0),  # only the last snapshot counts
        ([1, 0], ["alarm: μ_h up", ""], None, Level.OK, 0),
        ([0, 0], ["", ""], None, Level.OK, 0),
        ([], [], None, Level.OK, 0),
        ([0], [""], "fewer than 3 snapshots in the baseline", Level.NOT_MADE, 0),
    ],
)
def test_the_state_is_the_last_snapshots(alarm, flag, note, level, status):
    state = monitor_state(np.array(alarm, dtype=int), flag, note)
    assert state.level == level and exit_status([state]) == status
    assert state.alarm_active == (level == Level.ALARM)
    assert state.notice_active == (level == Level.NOTICE)


def test_the_verdict_says_what_it_judged():
    alarm = monitor_verdict(monitor_state(np.array([1]), ["alarm: x"], None), 4_000_000, "alarm: x", None)
    assert alarm.level == Level.ALARM and alarm.judged == "an alarm is active at the last snapshot (cycle 4,000,000)"
    notice = monitor_verdict(monitor_state(np.array([0]), ["notice: y"], None), 5, "notice: y", None)
    assert notice.level == Level.NOTICE and notice.judged == "at the last snapshot (cycle 5) a notice: y"
    ok = monitor_verdict(monitor_state(np.array([0]), [""], None), 5, None, None)
    assert ok.level == Level.OK and "before the last" in ok.not_judged
    waiting = monitor_verdict(monitor_state(np.array([0]), [""], "no baseline"), 5, None, "no baseline")
    assert waiting.level == Level.NOT_MADE and exit_status([waiting]) == 0
