"""hipsim.rig.monitoring.snapshots on tiny files written here: which files, their identities, a long log cut into
windows of whole cycles (each its lines and the SHA-256 of their bytes), the counter's checks, the reasons given.
"""

from __future__ import annotations

import hashlib
import os
import time

import numpy as np
import pytest
from support import given

from hipsim.exceptions import ArgumentError, TrajectoryError
from hipsim.rig.monitoring.monitor_summary import SkippedFile
from hipsim.rig.monitoring.snapshots import (
    COMMANDED_LOAD,
    CYCLE_COLUMN,
    STATION_LOADS,
    Skipped,
    Snapshot,
    check_counter,
    find_snapshots,
    skipped,
)

HEADER = "t_s,Fe_N,alpha_deg,beta_deg,gamma_deg,tau_1_Nmm,tau_2_Nmm,tau_3_Nmm,cycle"


def log_text(cycles) -> str:
    """A log of one sample a cycle entry (1 kHz), the counter as given."""
    rows = [f"{k / 1000:.3f},1000,1,2,3,10,20,30,{c}" for k, c in enumerate(cycles)]
    return "\n".join([HEADER, *rows]) + "\n"


def test_the_columns():
    assert (CYCLE_COLUMN, STATION_LOADS, COMMANDED_LOAD) == ("cycle", ("Fe_1_N", "Fe_2_N"), "Fe_cmd_N")


def test_files_folders_and_patterns_each_once_in_order(tmp_path):
    for name in ("b.csv", "a.csv", "c.txt"):
        (tmp_path / name).write_text("x\n")
    (tmp_path / "sub.csv").mkdir()  # a folder named like a log is no file
    a, b = str(tmp_path / "a.csv"), str(tmp_path / "b.csv")
    found, left = find_snapshots([str(tmp_path), str(tmp_path / "*.csv"), b, tmp_path / "c.txt"])
    assert [s.path for s in found] == [a, b, str(tmp_path / "c.txt")] and left == []
    digest = hashlib.sha256(b"x\n").hexdigest()
    assert found[0] == Snapshot(a, 2, digest) and found[0].name == "a.csv" and found[0].ends_with_newline
    assert find_snapshots(a)[0] == [found[0]]  # one name alone


def test_a_file_cut_mid_line_and_an_empty_one(tmp_path):
    (tmp_path / "cut.csv").write_bytes(b"a\nb")
    (tmp_path / "empty.csv").write_bytes(b"")
    cut, empty = find_snapshots(str(tmp_path))[0]
    assert (cut.size, cut.ends_with_newline) == (3, False)
    assert (empty.size, empty.sha256, empty.ends_with_newline) == (0, hashlib.sha256(b"").hexdigest(), True)


def test_an_identity_cache_spares_the_rehash(tmp_path):
    path = tmp_path / "a.csv"
    path.write_text("x\n")
    cache: dict = {}
    (first,), _ = find_snapshots(str(path), cache=cache)
    key = (str(path), 2, os.stat(path).st_mtime_ns)
    assert cache == {key: (2, first.sha256, True)}
    cache[key] = (2, "cached", True)  # what the cache says is taken as the file's
    assert find_snapshots(str(path), cache=cache)[0][0].sha256 == "cached"


def test_a_missing_name_and_bad_options(tmp_path):
    with pytest.raises(TrajectoryError) as refused:
        find_snapshots(str(tmp_path / "nothing.csv"))
    assert str(refused.value) == f"{tmp_path / 'nothing.csv'}: no such log file or folder"
    for window in (0, -1, 1.5, True):
        with pytest.raises(ArgumentError, match="^window: expected a positive whole number of cycles"):
            find_snapshots(str(tmp_path), window=window)  # type: ignore[arg-type]  # wrong types on purpose
    for settle in (-1.0, float("nan")):
        with pytest.raises(ArgumentError, match="^settle: expected seconds ≥ 0"):
            find_snapshots(str(tmp_path), settle=settle)


def test_a_file_still_being_written_waits(tmp_path):
    path = tmp_path / "new.csv"
    path.write_text("x\n")
    found, (waiting,) = find_snapshots(str(path), settle=3600.0)
    assert found == [] and waiting.kind == "waiting" and waiting.name == "new.csv"
    assert waiting.reason.startswith(f"{path}: changed ")
    assert waiting.reason.endswith(" s ago: still being written? read once unchanged for 3600 s")
    old = time.time() - 10.0
    os.utime(path, (old, old))
    assert len(find_snapshots(str(path), settle=5.0)[0]) == 1


def test_a_long_log_in_windows_of_whole_cycles(tmp_path):
    # Cycles 10…19 (two lines each): windows of 4 cycles from the first, 10-13 and 14-17; 18-19 is not whole yet.
    cycles = np.repeat(np.arange(10, 20), 2)
    path = tmp_path / "long.csv"
    path.write_text(log_text(cycles))
    found, left = find_snapshots(str(path), window=4)
    assert left == []
    assert [(s.lines, s.first_cycle, s.last_cycle) for s in found] == [((2, 10), 10, 13), ((10, 18), 14, 17)]
    assert [s.name for s in found] == ["long.csv[10-13]", "long.csv[14-17]"]
    lines = path.read_bytes().splitlines(keepends=True)
    for s in found:
        part = b"".join(lines[given(s.lines)[0] - 1 : given(s.lines)[1] - 1])  # file lines [first, stop)
        assert (s.size, s.sha256) == (len(part), hashlib.sha256(part).hexdigest())
    # A window of 5 cycles: 10-14 and 15-19, the last whole as soon as cycle 19 is in; the last line's window.
    found, _ = find_snapshots(str(path), window=5)
    assert [(s.lines, s.first_cycle, s.last_cycle) for s in found] == [((2, 12), 10, 14), ((12, 22), 15, 19)]


def test_a_long_log_that_cannot_be_cut_is_skipped_with_its_reason(tmp_path):
    short = tmp_path / "short.csv"
    short.write_text(log_text([5, 5, 6]))
    nocycle = tmp_path / "nocycle.csv"
    nocycle.write_text(log_text([1, 2, 3]).replace(",cycle", ",count"))
    _, left = find_snapshots([str(short), str(nocycle)], window=4)
    assert [s.reason for s in left] == [  # in the order given
        f"{short}: holds no whole window of 4 cycles (cycles 5-6)",
        f"{nocycle}: no 'cycle' column: a snapshot needs the machine's cycle counter",
    ]
    assert all(s.kind == "unreadable" for s in left)


def test_the_counter_checked():
    lines = np.array([2, 3, 5, 6])
    out = check_counter(np.array([0.0, 1.0, 1.0, 7.0]), lines, "c.csv")
    assert out.dtype == np.int64 and list(out) == [0, 1, 1, 7]
    for bad, line, value in (
        ([0.0, 1.5, 2.0, 3.0], 3, "1.5"),
        ([0.0, 1.0, -1.0, 3.0], 5, "-1"),
        ([0, np.nan, 1, 2], 3, "nan"),
    ):
        with pytest.raises(TrajectoryError) as refused:
            check_counter(np.array(bad, dtype=float), lines, "c.csv")
        assert (
            str(refused.value)
            == f"c.csv, line {line}, column 'cycle': the cycle counter must be a whole number ≥ 0, got {value}"
        )
    with pytest.raises(TrajectoryError) as refused:
        check_counter(np.array([0.0, 4.0, 3.0, 5.0]), lines, "c.csv")
    assert str(refused.value) == (
        "c.csv, line 5, column 'cycle': the cycle counter decreases (4 → 3): one snapshot a file, its counter "
        "non-decreasing"
    )


def test_a_skipped_snapshot_keeps_the_errors_line_and_hints_at_coarse_times():
    snapshot = Snapshot("/logs/a.csv", 10, "ab")
    one = skipped(snapshot, TrajectoryError("bad value", source="/logs/a.csv", line=7, column="Fe_N"))
    reason = "/logs/a.csv, line 7, column 'Fe_N': bad value"
    assert one == Skipped("a.csv", "/logs/a.csv", reason, "unreadable", 7, 10, "ab")  # the file's identity kept
    times = skipped(snapshot, TrajectoryError("times must increase", source="a.csv", line=3, column="t_s"), "x")
    assert times.reason == (
        "a.csv, line 3, column 't_s': times must increase (time stamps too coarse for the rate? give --rate HZ to "
        "read the times from the sample index)"
    )
    assert times.kind == "x" and times.line == 3
    worded = skipped(snapshot, TrajectoryError("column 't_s' must increase", source="a.csv"))
    assert worded.reason.endswith("give --rate HZ to read the times from the sample index)") and worded.line is None
    assert not skipped(snapshot, TrajectoryError("'t_s' is missing", source="a.csv")).reason.endswith(")")
    assert SkippedFile.of(one).to_json() == {
        "file": "a.csv",
        "path": "/logs/a.csv",
        "kind": "unreadable",
        "reason": one.reason,
        "line": 7,
        "bytes": 10,
        "sha256": "ab",
    }


def test_windows_from_the_first_cycle_one_line_a_cycle(tmp_path):
    # Cycles 9…19, one line each, windows of 4: 9-12, 13-16; 17-19 lacks cycle 20. With 20 logged it is whole.
    path = tmp_path / "one.csv"
    path.write_text(log_text(range(9, 20)))
    found, _ = find_snapshots(str(path), window=4)
    assert [(s.lines, s.first_cycle, s.last_cycle) for s in found] == [((2, 6), 9, 12), ((6, 10), 13, 16)]
    path.write_text(log_text(range(9, 21)))
    found, _ = find_snapshots(str(path), window=4)
    assert [(s.first_cycle, s.last_cycle, s.lines) for s in found][-1] == (17, 20, (10, 14))
    # A last window of one line (cycle 17 alone) waits too.
    path.write_text(log_text(range(9, 18)))
    assert [s.last_cycle for s in find_snapshots(str(path), window=4)[0]] == [12, 16]
    path.write_text(log_text(range(9, 21)))
    # One cycle a window is a window.
    assert len(find_snapshots(str(path), window=1)[0]) == 12
    # Several files, each in its windows.
    other = tmp_path / "other.csv"
    other.write_text(log_text(range(0, 4)))
    found, _ = find_snapshots([str(path), str(other)], window=4)
    assert [s.name for s in found] == ["one.csv[9-12]", "one.csv[13-16]", "one.csv[17-20]", "other.csv[0-3]"]


def test_a_long_log_is_read_with_the_callers_torque_constant(tmp_path):
    # Currents need the torque constant. (The rate, for coarse time stamps: tests/rig/monitoring/test_snapshots_files.py.)
    text = log_text(range(0, 8)).replace("tau_1_Nmm,tau_2_Nmm,tau_3_Nmm", "current_1_A,current_2_A,current_3_A")
    path = tmp_path / "currents.csv"
    path.write_text(text)
    assert len(find_snapshots(str(path), window=4, torque_constant=0.1)[0]) == 2
    (refused,) = find_snapshots(str(path), window=4)[1]
    assert "no torque constant in N·m/A was given" in refused.reason


def test_a_long_logs_counter_is_checked_naming_its_line(tmp_path):
    path = tmp_path / "down.csv"
    path.write_text(log_text([0, 1, 2, 1, 3]))
    (refused,) = find_snapshots(str(path), window=2)[1]
    assert refused.reason == (
        f"{path}, line 5, column 'cycle': the cycle counter decreases (2 → 1): one snapshot a file, its counter "
        "non-decreasing"
    )
    assert refused.line == 5 and refused.name == "down.csv" and refused.path == str(path)
    short = tmp_path / "short.csv"
    short.write_text(log_text([4, 5, 6]))
    assert (
        find_snapshots(str(short), window=4)[1][0].reason == f"{short}: holds no whole window of 4 cycles (cycles 4-6)"
    )


def test_a_waiting_file_does_not_stop_the_others(tmp_path):
    old, new = tmp_path / "a.csv", tmp_path / "b.csv"
    old.write_text("x\n")
    new.write_text("y\n")
    past = time.time() - 100.0
    os.utime(old, (past, past))
    found, (waiting,) = find_snapshots([str(new), str(old)], settle=50.0)
    assert [s.path for s in found] == [str(old)] and waiting.path == str(new)
    age = float(waiting.reason.split("changed ")[1].split(" s ago")[0])
    assert 0.0 <= age < 1.0  # just written


def test_a_file_gone_between_listing_and_reading(tmp_path, monkeypatch):
    import hipsim.rig.monitoring.snapshots as snapshots

    for name in ("a.csv", "b.csv"):
        (tmp_path / name).write_text("x\n")
    real = snapshots._identity

    def gone(path, cache):
        if path.endswith("a.csv"):
            raise FileNotFoundError(2, "No such file or directory")
        return real(path, cache)

    monkeypatch.setattr(snapshots, "_identity", gone)
    found, left = find_snapshots(str(tmp_path))
    a = str(tmp_path / "a.csv")
    assert left == [Skipped("a.csv", a, f"{a}: cannot read (No such file or directory)")]
    assert [s.name for s in found] == ["b.csv"]


def test_two_folders_and_two_patterns(tmp_path):
    for folder in ("x", "y"):
        (tmp_path / folder).mkdir()
        (tmp_path / folder / f"{folder}.csv").write_text("x\n")
    both = [str(tmp_path / "x"), str(tmp_path / "y")]
    assert [s.name for s in find_snapshots(both)[0]] == ["x.csv", "y.csv"]
    patterns = [str(tmp_path / "x" / "*.csv"), str(tmp_path / "y" / "*.csv")]
    assert [s.name for s in find_snapshots(patterns)[0]] == ["x.csv", "y.csv"]


def test_line_ends_of_short_files(tmp_path):
    (tmp_path / "a.csv").write_bytes(b"ab\n")
    (tmp_path / "b.csv").write_bytes(b"a")
    a, b = find_snapshots(str(tmp_path))[0]
    assert (a.ends_with_newline, b.ends_with_newline) == (True, False)


def test_the_options_refused_name_their_values(tmp_path):
    with pytest.raises(ArgumentError) as refused:
        find_snapshots(str(tmp_path), window=0)
    assert refused.value.value == 0
    with pytest.raises(ArgumentError) as refused:
        find_snapshots(str(tmp_path), settle=-1.0)
    assert refused.value.value == -1.0
    # A time column refused by its column alone gets the --rate hint too.
    hinted = skipped(Snapshot("a.csv", 1, ""), TrajectoryError("bad time", source="a.csv", line=2, column="t_s"))
    assert hinted.reason.endswith("give --rate HZ to read the times from the sample index)")
