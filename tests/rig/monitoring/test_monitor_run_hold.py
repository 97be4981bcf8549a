"""Issue 47's monitor fixes on hand-made snapshot series: an alarm held until acknowledged (and the acknowledgement
recorded in the table), a baseline of five snapshots by default, a batch run that waits for files still being
written and then reads them, a skipped file's size and SHA-256, and ``--on-alarm`` run without a shell.

The estimate is the stand-in of tests/rig/monitoring/test_monitor_run_laws.py (rows of a chosen load term by cycle,
from the file's name): the series are made by hand, not by the monitor's fit.
"""

from __future__ import annotations

import importlib.util
import json
import math
import os
import shutil
from pathlib import Path
from types import SimpleNamespace
from typing import Any

import numpy as np
import pytest
from monitor_synthetic import write_identified

from hipsim.cli.main import main
from hipsim.exceptions import ArgumentError
from hipsim.records import Level
from hipsim.rig.monitoring.findings import hold
from hipsim.rig.monitoring.monitor_run import run_monitor
from hipsim.rig.monitoring.monitor_table import read_table
from hipsim.rig.monitoring.snapshots import settled


def _beside(name: str) -> Any:
    """A test module of this folder, by its path: tests/ mirrors hipsim/ and its folders are not packages."""
    spec = importlib.util.spec_from_file_location(f"{__name__}_{name}", Path(__file__).with_name(f"{name}.py"))
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


run_laws = _beside("test_monitor_run_laws")
SETUP, stepped = run_laws.SETUP, run_laws.stepped


@pytest.fixture
def stand_in(monkeypatch):
    """tests/rig/monitoring/test_monitor_run_laws.py's stand-in for the estimate (its fixture ``estimates``)."""
    return run_laws.estimates.__wrapped__(monkeypatch)


# --------------------------------------------------------------------------- the held state, by hand

CYCLES = [0, 10, 20, 30, 40]
ALARM = [0, 1, 0, 1, 0]
FLAG = ["", "alarm: …", "notice: …", "alarm: …", ""]


@pytest.mark.parametrize(
    ("acks", "state", "recorded", "raised"),
    [
        ((), ["OK", "ALARM", "ALARM", "ALARM", "ALARM"], [], 10),
        ((10,), ["OK", "OK", "NOTICE", "ALARM", "ALARM"], [(1, 10)], 30),
        # 25 covers the alarm at 10, not the one at 30; it takes effect at the first snapshot from 25 on (30).
        ((25,), ["OK", "ALARM", "ALARM", "ALARM", "ALARM"], [(3, 25)], 30),
        ((10, 30), ["OK", "OK", "NOTICE", "OK", "OK"], [(1, 10), (3, 30)], None),
        ((35,), ["OK", "ALARM", "ALARM", "ALARM", "OK"], [(4, 35)], None),
        ((9,), ["OK", "ALARM", "ALARM", "ALARM", "ALARM"], [(1, 9)], 10),  # before the alarm: covers nothing
    ],
)
def test_an_alarm_is_held_until_acknowledged(acks, state, recorded, raised):
    got, where, first = hold(CYCLES, ALARM, FLAG, acks)
    assert got == state and first == raised
    expected = np.full(5, math.nan)
    for k, cycle in recorded:
        expected[k] = cycle
    np.testing.assert_array_equal(where, expected)


def test_no_chart_no_state():
    assert hold(CYCLES, [0] * 5, [""] * 5, (), charted=False)[0] == ["NO BASELINE"] * 5


# --------------------------------------------------------------------------- through the run and its table


def spike(stand_in, at: int = 80):
    """The load term 3 mm (± 0.001), 3.5 mm at one snapshot only: an alarm there, then the EWMA's notices."""
    snapshots = stepped(stand_in, 200, 0.0)
    stand_in.a[at] += 0.5
    return snapshots


def test_an_alarm_raised_reads_alarm_at_the_last_snapshot_until_acknowledged(stand_in, tmp_path):
    snapshots = spike(stand_in)
    result = run_monitor(SETUP, snapshots, baseline=(20, 50), baseline_min=4)
    c, s = result.columns, result.summary()
    # The case: the snapshot after the alarm is only a notice; before, the last state read NOTICE (exit 0).
    assert c["alarm"][-3:] == [1, 0, 0] and c["flag"][-1].startswith("notice")
    assert c["state"][-4:] == ["OK", "ALARM", "ALARM", "ALARM"]
    assert s.alarm_active and s.alarm_raised_at == 80 and not s.alarm_at_last_snapshot
    assert s.state == "ALARM" and not s.notice_active and s.acknowledged == []
    # The verdict (records.Verdict in the summary): ALARM held; the page says where it was raised, from the result.
    from hipsim.present.monitor_page import monitor_verdict as block

    last = c["last_cycle"][-1]
    assert (
        s.verdict.level == Level.ALARM
        and s.verdict.judged == f"an alarm is active at the last snapshot (cycle {last:,})"
    )
    assert block(result).lines[0] == (
        f"An alarm raised at cycle 80 is held at the last snapshot (cycle {last:,}) until acknowledged "
        "(hipsim monitor --acknowledge 80)."
    )
    # Acknowledged: recorded at its snapshot, the state back to what the chart says.
    out = tmp_path / "t.csv"
    result = run_monitor(SETUP, snapshots, baseline=(20, 50), baseline_min=4, out=out, acknowledge=[80])
    c, s = result.columns, result.summary()
    assert c["state"][-3:] == ["OK", "NOTICE", "NOTICE"] and not s.alarm_active and s.notice_active
    notice = s.latest_notice  # the notice's whole text, not the last snapshot's short flag
    assert notice is not None and notice.text != c["flag"][-1] and s.verdict.level == Level.NOTICE
    assert s.verdict.judged == f"at the last snapshot (cycle {c['last_cycle'][-1]:,}) a {notice.text}"
    assert c["acknowledged"][8] == 80 and sum(not math.isnan(a) for a in c["acknowledged"]) == 1
    assert s.acknowledged == [80] and read_table(out)["acknowledged"][8] == 80
    # The table keeps it: a rerun without the option stays acknowledged.
    again = run_monitor(SETUP, snapshots, baseline=(20, 50), baseline_min=4, out=out).summary()
    assert not again.alarm_active and again.acknowledged == [80] and again.kept == 11


def test_an_alarm_after_the_acknowledgement_is_held_anew(stand_in):
    snapshots = spike(stand_in, 70)
    stand_in.a[100] += 0.8
    s = run_monitor(SETUP, snapshots, baseline=(20, 50), baseline_min=4, acknowledge=[70]).summary()
    assert s.table["alarm"][-1] == 1 and s.alarm_active and s.alarm_raised_at == 100


@pytest.mark.parametrize("cycle", [50, 110, -1])
def test_an_acknowledgement_of_no_alarm_is_refused_nothing_written(stand_in, tmp_path, cycle):
    out = tmp_path / "t.csv"
    with pytest.raises(ArgumentError, match=r"^acknowledge: expected .*(alarms raised at: 80|≥ 0)"):
        run_monitor(SETUP, spike(stand_in), baseline=(20, 50), baseline_min=4, out=out, acknowledge=[cycle])
    assert not out.exists()


def test_the_baseline_needs_five_snapshots_unless_told(stand_in):
    snapshots = spike(stand_in)  # four snapshots in 20-50
    s = run_monitor(SETUP, snapshots, baseline=(20, 50)).summary()
    assert "4 of the 5 snapshots" in s.note and s.state == "NO BASELINE" and not s.alarm_active
    assert run_monitor(SETUP, snapshots, baseline=(20, 60)).summary().baseline.snapshots == 5
    assert run_monitor(SETUP, snapshots, baseline=(20, 50), baseline_min=4).summary().alarm_active


# --------------------------------------------------------------------------- the command line


@pytest.fixture
def folder(tmp_path, stand_in):
    """Stand-in snapshots 0 … 100 (the estimate replaced), an hour old, and an identified parameter file."""
    logs = tmp_path / "logs"
    logs.mkdir()
    for s in spike(stand_in):
        path = logs / os.path.basename(s.path)
        path.write_text("x\n")
        os.utime(path, (0, 1e9))
    return SimpleNamespace(logs=logs, params=write_identified(tmp_path / "identified.toml"), out=tmp_path / "t.csv")


def _cli(folder, *more):
    base = ["monitor", "--params", str(folder.params), "--log", str(folder.logs), "--baseline", "20:50"]
    return main([*base, "--out", str(folder.out), "--settle", "0", *more])


def test_the_command_holds_the_alarm_until_acknowledged(folder, capsys):
    assert _cli(folder, "--baseline-min", "4") == 1
    out = capsys.readouterr().out
    assert "state: ALARM, raised at cycle 80 and held until acknowledged (--acknowledge 80)" in out
    assert _cli(folder, "--baseline-min", "4", "--acknowledge", "80") == 0
    out = capsys.readouterr().out
    assert "acknowledged: cycle 80" in out and "state: NOTICE at the last snapshot" in out
    assert "NOTICE (acknowledged 80)" not in out and "ALARM (acknowledged 80)" not in out
    assert _cli(folder, "--baseline-min", "4") == 0  # recorded in the table
    assert read_table(folder.out)["state"][-1] == "NOTICE"


@pytest.mark.parametrize(
    ("more", "words"),
    [
        (("--baseline-min", "1"), ("--baseline-min", "at least 2")),
        (("--acknowledge", "-5"), ("--acknowledge", "at least 0")),
        (("--baseline-min", "4", "--acknowledge", "50"), ("acknowledge: expected the cycle of a raised alarm",)),
    ],
)
def test_bad_options_one_line_exit_2_nothing_written(folder, capsys, more, words):
    assert _cli(folder, *more) == 2
    err = capsys.readouterr().err.strip().splitlines()
    # Warnings may come first (the option table's plausible ranges); the error is one line, the last.
    assert err[-1].startswith("hipsim: error: ") and all(w in err[-1] for w in words), err[-1]
    assert not any(line.startswith("hipsim: error") for line in err[:-1])
    assert not folder.out.exists()


def test_the_default_baseline_minimum_is_said(folder, capsys):
    assert _cli(folder) == 0
    assert "baseline incomplete: 4 of the 5 snapshots it needs within cycles 20-50" in capsys.readouterr().out


# --------------------------------------------------------------------------- files still being written


def test_a_batch_run_waits_for_files_to_settle_at_most_settle_seconds(tmp_path):
    a, b = tmp_path / "a.csv", tmp_path / "b.csv"
    for path, changed in ((a, 100.0), (b, 99.0)):
        path.write_text("x\n")
        os.utime(path, (changed, changed))
    now = [100.5]
    slept = []

    def sleep(seconds):
        slept.append(seconds)
        now[0] += seconds

    # Settle 2 s: a changed 0.5 s ago, so 1.5 s more; b is older.
    assert settled([str(a), str(b)], 2.0, clock=lambda: now[0], sleep=sleep) == pytest.approx(1.5)
    assert slept == [pytest.approx(1.5)]
    # A file that changes at every look is read after settle seconds in all, not waited for without end.
    slept.clear()
    now[0] = 200.0

    def writing(seconds):
        sleep(seconds)
        os.utime(a, (now[0], now[0]))

    os.utime(a, (200.0, 200.0))
    assert settled([str(a)], 2.0, clock=lambda: now[0], sleep=writing) == pytest.approx(2.0)
    # Settled files: no wait.
    assert settled([str(b)], 2.0, clock=lambda: 500.0, sleep=sleep) == 0.0


# --------------------------------------------------------------------------- --on-alarm


def test_on_alarm_runs_without_a_shell_and_a_shell_when_asked(folder, tmp_path, monkeypatch):
    from hipsim.rig.monitoring import watch as watching

    if shutil.which("sh") is None:
        pytest.skip("no sh")
    document = {"alarm_active": True, "alarm_raised_at": 80}

    def once(*args, on_alarm=None, **options):
        summary = SimpleNamespace(to_json=lambda: document, **document)
        from hipsim.records import Level
        from hipsim.rig.monitoring.monitor_state import MonitorState

        state = MonitorState(Level.ALARM, True, False)
        result = SimpleNamespace(summary=lambda: summary, findings=SimpleNamespace(alarm_held=True), state=state)
        on_alarm(result)
        return result

    monkeypatch.setattr(watching, "watch", once)
    caught = tmp_path / "alarm.json"
    # Without a shell, '>' is an argument of cat: nothing is redirected (the surprise).
    assert _cli(folder, "--watch", "--on-alarm", f"cat > {caught}") == 1
    assert not caught.exists()
    # With one, deliberately: the summary JSON arrives on the command's standard input.
    assert _cli(folder, "--watch", "--on-alarm", f"sh -c 'cat > {caught}'") == 1
    assert json.loads(caught.read_text()) == document


def test_a_watch_holds_and_keeps_acknowledgements(folder):
    from hipsim.rig.monitoring.watch import watch

    raised: list[object] = []
    options: dict[str, Any] = {"out": folder.out, "poll": 1e-3, "settle": 0.0, "rounds": 1, "baseline_min": 4}
    held = watch(SETUP, folder.logs, (20, 50), 0.01, on_alarm=raised.append, **options)
    assert held is not None
    assert held.findings.alarm_held and len(raised) == 1 and held.summary().alarm_raised_at == 80
    seen = watch(SETUP, folder.logs, (20, 50), 0.01, acknowledge=[80], restart=True, **options)
    assert seen is not None
    assert not seen.findings.alarm_held and seen.findings.acknowledgements() == (80,)
    # A later watch of the same table: the acknowledgement read back from it.
    again = watch(SETUP, folder.logs, (20, 50), 0.01, on_alarm=raised.append, **options)
    assert again is not None
    assert not again.findings.alarm_held and again.findings.acknowledgements() == (80,) and len(raised) == 1
