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


NOT_JUDGED = "the snapshots before the last (their alarms and notices are listed, not judged again)"


@pytest.mark.parametrize(
    ("flag", "held", "level", "alarm_active", "notice_active"),
    [
        (["", "alarm: up"], True, Level.ALARM, True, False),  # held: the alarm counts, not the notice
        (["", "notice: up 2 %"], True, Level.ALARM, True, False),
        (["", "notice: up 2 %"], False, Level.NOTICE, False, True),
        (["notice: up 2 %", ""], False, Level.OK, False, False),  # only the last snapshot's notice
        (["", "alarm: up"], False, Level.OK, False, False),  # acknowledged: not held, and not a notice
        (["", ""], False, Level.OK, False, False),
        ([], False, Level.OK, False, False),
        (["notice: up 2 %"], False, Level.NOTICE, False, True),  # one snapshot is enough
    ],
)
def test_a_held_alarm_and_the_last_snapshot_s_notice(flag, held, level, alarm_active, notice_active):
    state = monitor_state(np.zeros(len(flag), dtype=int), flag, None, held=held)
    assert (state.level, state.alarm_active, state.notice_active) == (level, alarm_active, notice_active)
    assert isinstance(state.alarm_active, bool) and isinstance(state.notice_active, bool)


def test_the_last_snapshot_alone_and_its_own_alarm():
    one = monitor_state(np.array([0]), ["notice: x"], None)
    assert (one.level, one.alarm_active, one.notice_active) == (Level.NOTICE, False, True)
    alarm = monitor_state(np.array([1]), ["alarm: x"], "")  # an empty note is no note
    assert (alarm.level, alarm.alarm_active, alarm.notice_active) == (Level.ALARM, True, False)
    assert isinstance(alarm.alarm_active, bool) and isinstance(one.notice_active, bool)
    waiting = monitor_state(np.array([1]), ["alarm: x"], "no baseline")
    assert (waiting.level, waiting.alarm_active) == (Level.NOT_MADE, True)


def test_each_verdict_whole():
    def verdict(level_flag, last_cycle, change, note=None):
        alarm, flag = level_flag
        return monitor_verdict(monitor_state(np.array([alarm]), [flag], note), last_cycle, change, note)

    cases = [
        (verdict((1, "alarm: x"), None, "alarm: x"), Level.ALARM, "an alarm is active at the last snapshot"),
        (verdict((0, "notice: y"), None, "notice: y"), Level.NOTICE, "at the last snapshot a notice: y"),
        (verdict((0, ""), 1234, None), Level.OK, "no alarm at the last snapshot (cycle 1,234)"),
        (verdict((0, ""), None, None), Level.OK, "no alarm at the last snapshot"),
        (
            verdict((0, ""), 5, None, "fewer than 3 snapshots"),
            Level.NOT_MADE,
            "no baseline yet: fewer than 3 snapshots",
        ),
    ]
    for made, level, judged in cases:
        assert (made.level, made.judged, made.not_judged) == (level, judged, NOT_JUDGED)
        assert dict(made.numbers) == {}


def test_the_change_a_notice_names():
    from hipsim.rig.monitoring.monitor_state import last_change

    assert last_change("notice: up 4 %", ["notice: up 4 %", "alarm: up 12 %"]) == "notice: up 4 %"  # the notice first
    assert last_change(None, ["", "alarm: up 12 %"]) == "alarm: up 12 %"  # else the last snapshot's flag
    assert last_change("", ["a", "b"]) == "b"  # an empty notice is none: the last flag
    assert last_change(None, ["a", "b", "c"]) == "c"  # the last, not the second
    assert last_change(None, []) is None  # no snapshot
