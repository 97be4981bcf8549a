"""Following a test in progress: the snapshot folder watched, each new snapshot estimated once complete, the table
and page brought up to date, a command run when an alarm is raised.

:func:`watch` polls the logs every ``poll`` seconds (a listing and a
``stat`` per file: next to no CPU while nothing changes; a file is hashed once
per size and modification time). A file changed less than ``settle`` seconds
ago is still being written and is not read (a half-written snapshot is never
estimated). When a round finds snapshots the table does not hold, they are
estimated (:func:`~hipsim.rig.monitoring.monitor_run.run_monitor`, the rows
kept in memory between rounds), the table written atomically, and ``update``
called with the result (the page); ``on_alarm`` is called once each time an
alarm becomes active at the last snapshot. A stop (``stop`` set, or Ctrl-C)
between or within rounds leaves the files of the last complete round: every
write is atomic.
"""

from __future__ import annotations

import threading
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

from ...clock import SYSTEM_CLOCK, Clock
from ...exceptions import ArgumentError, TrajectoryError
from .control_chart import MIN_BASELINE
from .monitor_fit import MonitorSetup
from .monitor_run import MonitorResult, run_monitor
from .monitor_table import COLUMNS, MONITOR_TABLE, PARTS, table_rows
from .snapshots import find_snapshots

__all__ = ["watch"]


def watch(
    setup: MonitorSetup,
    logs,
    baseline: tuple[int, int],
    alarm_rise: float,
    out: str | Path | None = None,
    restart: bool = False,
    poll: float = 30.0,
    settle: float = 10.0,
    update: Callable[[MonitorResult], None] | None = None,
    on_alarm: Callable[[MonitorResult], None] | None = None,
    stop: threading.Event | None = None,
    rounds: int | None = None,
    workers: int = 1,
    scheduler: str | None = None,
    metadata: dict[str, Any] | None = None,
    baseline_min: int = MIN_BASELINE,
    acknowledge: Sequence[int] = (),
    clock: Clock = SYSTEM_CLOCK,
) -> MonitorResult | None:
    """Watch the logs until ``stop`` is set (or ``rounds`` polls are done); the last result, None if nothing was usable.

    Args:
        setup: what the snapshots share.
        logs: the snapshot files, folders or patterns (listed again every round).
        baseline: (FROM, TO) cycles.
        alarm_rise: the engineering threshold.
        out: the table, extended each round (resumed from the file at the start), or None.
        restart: replace ``out`` at the start instead of extending it.
        poll: seconds between rounds.
        settle: a file changed less than this many seconds ago is still being written.
        update: called with each round's result when it estimated something new (write the page).
        on_alarm: called with the result once each time an alarm becomes active at the last snapshot.
        stop: set it to end the watch after the round under way.
        rounds: stop after this many rounds (None: until ``stop``).
        workers, scheduler: as :func:`~hipsim.rig.monitoring.monitor_run.run_monitor`.
        metadata: kept with the table.
        baseline_min: snapshots the baseline needs before the chart starts.
        acknowledge: cycles of alarms acknowledged (with those ``out`` records); kept from round to round.
        clock: the clock that ages the files and spaces the rounds (:mod:`hipsim.clock`; a test passes its own).
    """
    if not (poll > 0):
        raise ArgumentError("poll", poll, "seconds > 0 between looks at the logs")
    stop = stop or threading.Event()
    out = MONITOR_TABLE.check_out(out) if out is not None else None
    fingerprints = setup.fingerprints()
    resumed = MONITOR_TABLE.resume(out, COLUMNS, fingerprints, restart, PARTS) if out is not None else {}
    rows: Sequence[dict[str, Any]] = table_rows(resumed) if out is not None else []
    acks = [int(a) for a in resumed.get("acknowledged", []) if a == a] + list(acknowledge)
    cache: dict = {}
    result: MonitorResult | None = None
    known: set[tuple[str, str]] | None = None
    active = False
    done = 0
    while not stop.is_set():
        snapshots, skipped = find_snapshots(
            logs,
            setup.window,
            settle,
            setup.torque_constant,
            setup.rate,
            cache=cache,
            columns=setup.columns,
            clock=clock,
        )
        seen = {(s.name, s.sha256) for s in snapshots}
        if seen != known and snapshots:
            try:
                result = run_monitor(
                    setup,
                    snapshots,
                    baseline,
                    alarm_rise,
                    out,
                    False,
                    workers,
                    scheduler,
                    metadata=metadata,
                    skipped=skipped,
                    previous=rows,
                    baseline_min=baseline_min,
                    acknowledge=acks,
                )
            except TrajectoryError:
                pass  # nothing usable yet: wait for the next snapshot
            else:
                rows = result.rows
                acks = list(result.findings.acknowledgements())
                if update is not None:
                    update(result)
                now = result.findings.alarm_held
                if now and not active and on_alarm is not None:
                    on_alarm(result)
                active = now
            known = seen
        done += 1
        if rounds is not None and done >= rounds:
            break
        clock.wait(stop, poll)
    return result
