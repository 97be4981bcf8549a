"""The monitor's state at the last snapshot and its verdict: ALARM, NOTICE, OK, or none before the chart can start.

A pure function of the findings (:class:`hipsim.rig.monitoring.findings.Findings`):
ALARM when an alarm raised at the last snapshot or before is held there (not acknowledged); NOTICE when it carries a flag
that is not an alarm (a significant change below the threshold); OK otherwise;
NOT MADE while the chart has no baseline (its note says why). ALARM exits 1,
the others 0 (:func:`hipsim.records.exit_status`).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ...records import Level, Record, Verdict

__all__ = ["MonitorState", "last_change", "monitor_state", "monitor_verdict"]


@dataclass(frozen=True)
class MonitorState(Record):
    """The state at the last snapshot.

    Attributes:
        level: ALARM, NOTICE, OK or NOT MADE.
        alarm_active: the last snapshot carries an alarm.
        notice_active: the last snapshot carries a flag that is not an alarm.
    """

    level: Level
    alarm_active: bool
    notice_active: bool


def monitor_state(alarm: np.ndarray, flag: Sequence[str], note: str | None, held: bool | None = None) -> MonitorState:
    """The state from the per-snapshot alarms (1 alarm, 0 none), flags ("" none) and the chart's note.

    Args:
        alarm: per snapshot 1 for an alarm, else 0, (S,).
        flag: per snapshot the flag's text ("" for none), (S,).
        note: why the chart cannot start yet (no baseline), or None/"".
        held: whether an alarm raised at or before the last snapshot is held there, not acknowledged
            (:func:`hipsim.rig.monitoring.findings.hold`); None: only the last snapshot's own alarm counts.
    """
    last = len(flag) - 1
    if held is None:
        alarm_active = bool(last >= 0 and alarm[last])
        notice_active = bool(last >= 0 and flag[last] and not alarm[last])
    else:
        alarm_active = bool(held)
        notice_active = bool(last >= 0 and "notice" in flag[last] and not held)
    if note:
        level = Level.NOT_MADE
    elif alarm_active:
        level = Level.ALARM
    elif notice_active:
        level = Level.NOTICE
    else:
        level = Level.OK
    return MonitorState(level, alarm_active, notice_active)


def last_change(latest_notice: str | None, flag: Sequence[str]) -> str | None:
    """The change a NOTICE names: the latest notice's text, else the last snapshot's flag (None: no snapshot).

    Args:
        latest_notice: the latest notice's text ("notice: μ_h up 4 % ..."), None for none.
        flag: per snapshot the flag's text ("" for none).
    """
    if latest_notice:
        return latest_notice
    return flag[-1] if len(flag) else None


def monitor_verdict(state: MonitorState, last_cycle: int | None, change: str | None, note: str | None) -> Verdict:
    """The verdict in a sentence: what the state judged (the last snapshot) and what not (the earlier ones).

    Args:
        state: the state (:func:`monitor_state`).
        last_cycle: the last snapshot's cycle.
        change: the last notice's or alarm's text ("alarm: μ_h up 12 % ..."), None for none.
        note: the chart's note when it cannot start.
    """
    not_judged = "the snapshots before the last (their alarms and notices are listed, not judged again)"
    if state.level == Level.NOT_MADE:
        return Verdict(Level.NOT_MADE, f"no baseline yet: {note}", not_judged)
    at = f"the last snapshot (cycle {last_cycle:,})" if last_cycle is not None else "the last snapshot"
    if state.level == Level.ALARM:
        return Verdict(Level.ALARM, f"an alarm is active at {at}", not_judged)
    if state.level == Level.NOTICE:
        return Verdict(Level.NOTICE, f"at {at} a {change}", not_judged)
    return Verdict(Level.OK, f"no alarm at {at}", not_judged)
