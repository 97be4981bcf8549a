"""--watch over a folder filled during the test gives the same table as a batch run afterwards; a file still being
written is not read half; the alarm command runs once when the alarm is raised."""

from __future__ import annotations

import math
import os
import threading
from functools import partial

import numpy as np
import pytest
from fake_clock import FakeClock
from monitor_synthetic import write_snapshot

import hipsim
from hipsim.cli.main import main
from hipsim.rig.monitoring import monitor_run
from hipsim.rig.monitoring.monitor_fit import MonitorSetup
from hipsim.rig.monitoring.monitor_run import MonitorResult
from hipsim.rig.monitoring.snapshots import find_snapshots
from hipsim.rig.monitoring.watch import watch

run_monitor = partial(
    monitor_run.run_monitor, baseline_min=3
)  # three baseline snapshots (every 250,000 cycles in 500,000-1,000,000): the chart's minimum set to them

BASELINE = (10, 30)
CYCLES = (0, 10, 20, 30, 40, 50, 60)
STEP_AT = 45  # μ_h 0.1 → 0.14: alarms at 50 and 60


@pytest.fixture(scope="module")
def staged(tmp_path_factory):
    """The test's snapshots, written elsewhere first (the watch sees each appear, whole or in two halves)."""
    params = hipsim.load_parameters()
    folder = tmp_path_factory.mktemp("staged")
    rng = np.random.default_rng(9)
    for cycle in CYCLES:
        write_snapshot(folder / f"snap_{cycle:03d}.csv", params, 0.14 if cycle >= STEP_AT else 0.1, cycle, rng)
    return params, folder


def _same(a: dict, b: dict) -> None:
    assert list(a) == list(b)
    for name in a:
        for x, y in zip(a[name], b[name], strict=True):
            assert x == y or (isinstance(x, float) and math.isnan(x) and math.isnan(y)), name


def test_watching_a_folder_filled_during_the_test_gives_the_batch_table(tmp_path, staged):
    """On an injected clock (tests/fake_clock.py): between two rounds the next file appears, stamped with the clock's
    time; a file is read once it has been unchanged for the settle time, whatever the machine's speed."""
    params, source = staged
    logs = tmp_path / "logs"
    logs.mkdir()
    setup = MonitorSetup(params)
    updates: list[MonitorResult] = []
    alarms: list[MonitorResult] = []
    poll, settle = 0.25, 1.0
    text = {cycle: (source / f"snap_{cycle:03d}.csv").read_text(encoding="utf-8") for cycle in CYCLES}

    def put(cycle: int, part: str):
        def step(clock):
            path = logs / f"snap_{cycle:03d}.csv"
            path.write_text(part, encoding="utf-8")
            os.utime(path, (clock.time(), clock.time()))

        return step

    steps = []
    for cycle in CYCLES:
        if cycle == 40:  # written in two goes, a round apart: the first half is never read on its own
            steps.append(put(cycle, text[cycle][: len(text[cycle]) // 2]))
        steps.append(put(cycle, text[cycle]))
    clock = FakeClock(steps=steps, done=lambda: bool(updates) and len(updates[-1].rows) == len(CYCLES))
    waiting = []

    def update(result):
        updates.append(result)
        waiting.append({s.name for s in result.skipped if s.kind == "waiting"})

    watch(
        setup,
        logs,
        BASELINE,
        0.01,
        out=tmp_path / "watched.csv",
        poll=poll,
        settle=settle,
        update=update,
        on_alarm=alarms.append,
        stop=threading.Event(),
        rounds=200,  # a bound, never reached: the clock stops the watch once the table is whole
        clock=clock,
        baseline_min=3,
    )
    assert len(updates[-1].rows) == len(CYCLES)
    # Each file waits settle / poll = 4 rounds: the watch ends 4 rounds after the last file, its last wait the stop.
    assert clock.waits == len(steps) + settle / poll + 1
    assert any("snap_040.csv" in names for names in waiting)  # the half file was seen, and waited for
    assert all(row["samples"] == 750 for result in updates for row in result.rows)  # never half a file
    first_alarm = alarms[0].summary().first_alarm if len(alarms) == 1 else None
    assert first_alarm is not None and first_alarm.cycle == 50  # raised once
    batch = run_monitor(setup, find_snapshots(logs)[0], BASELINE, 0.01, out=tmp_path / "batch.csv")
    _same(updates[-1].columns, batch.columns)
    assert (tmp_path / "watched.csv").read_bytes() == (tmp_path / "batch.csv").read_bytes()


def test_the_watch_options_are_checked(tmp_path, capsys, staged):
    params, source = staged
    status = main(
        ["monitor", "--baseline-min", "3", "--params", params.source, "--log", str(source), "--on-alarm", "true"]
    )
    assert status == 2 and "--on-alarm: runs with --watch only" in capsys.readouterr().err
    status = main(
        ["monitor", "--baseline-min", "3", "--params", params.source, "--log", str(source), "--watch", "--poll", "0"]
    )
    assert status == 2 and "--poll" in capsys.readouterr().err
