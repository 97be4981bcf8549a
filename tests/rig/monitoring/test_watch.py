"""--watch over a folder filled during the test gives the same table as a batch run afterwards; a file still being
written is not read half; the alarm command runs once when the alarm is raised."""

from __future__ import annotations

import math
import shutil
import threading
import time

import numpy as np
import pytest
from monitor_synthetic import write_snapshot

import hipsim
from hipsim.cli.main import main
from hipsim.rig.monitoring.monitor_fit import MonitorSetup
from hipsim.rig.monitoring.monitor_run import run_monitor
from hipsim.rig.monitoring.snapshots import find_snapshots
from hipsim.rig.monitoring.watch import watch

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
    params, source = staged
    logs = tmp_path / "logs"
    logs.mkdir()
    setup = MonitorSetup(params)
    updates, alarms, stop = [], [], threading.Event()
    thread = threading.Thread(
        target=watch,
        args=(setup, logs, BASELINE, 0.01),
        kwargs={
            "out": tmp_path / "watched.csv",
            "poll": 0.05,
            "settle": 1.0,
            "update": updates.append,
            "on_alarm": alarms.append,
            "stop": stop,
        },
    )
    thread.start()
    try:
        for cycle in CYCLES:
            name = f"snap_{cycle:03d}.csv"
            if cycle == 40:  # written in two goes: the first half must never be read on its own
                text = (source / name).read_text(encoding="utf-8")
                (logs / name).write_text(text[: len(text) // 2], encoding="utf-8")
                time.sleep(0.1)
                (logs / name).write_text(text, encoding="utf-8")
            else:
                shutil.copy(source / name, logs / name)
            time.sleep(0.1)
        deadline = time.monotonic() + 60
        while time.monotonic() < deadline and not (updates and len(updates[-1].rows) == len(CYCLES)):
            time.sleep(0.05)
    finally:
        stop.set()
        thread.join(timeout=30)
    assert not thread.is_alive()
    assert len(updates[-1].rows) == len(CYCLES)
    assert all(row["samples"] == 750 for result in updates for row in result.rows)  # never half a file
    assert len(alarms) == 1 and alarms[0].summary().first_alarm["cycle"] == 50  # raised once
    batch = run_monitor(setup, find_snapshots(logs)[0], BASELINE, 0.01, out=tmp_path / "batch.csv")
    _same(updates[-1].columns, batch.columns)
    assert (tmp_path / "watched.csv").read_bytes() == (tmp_path / "batch.csv").read_bytes()


def test_the_watch_options_are_checked(tmp_path, capsys, staged):
    params, source = staged
    status = main(["monitor", "--params", params.source, "--log", str(source), "--on-alarm", "true"])
    assert status == 2 and "--on-alarm: runs with --watch only" in capsys.readouterr().err
    status = main(["monitor", "--params", params.source, "--log", str(source), "--watch", "--poll", "0"])
    assert status == 2 and "--poll" in capsys.readouterr().err
