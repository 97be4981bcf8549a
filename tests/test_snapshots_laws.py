"""hipsim.rig.monitoring.snapshots on tiny files written here: which files, their identities, a long log cut into
windows of whole cycles (each its lines and the SHA-256 of their bytes), the counter's checks, the reasons given.
"""

from __future__ import annotations

import hashlib
import os
import time

import numpy as np
import pytest

from hipsim.exceptions import ArgumentError, TrajectoryError
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
            find_snapshots(str(tmp_path), window=window)
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
        part = b"".join(lines[s.lines[0] - 1 : s.lines[1] - 1])  # file lines [first, stop)
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
    assert one == Skipped("a.csv", "/logs/a.csv", "/logs/a.csv, line 7, column 'Fe_N': bad value", "unreadable", 7)
    times = skipped(snapshot, TrajectoryError("times must increase", source="a.csv", line=3, column="t_s"), "x")
    assert times.reason == (
        "a.csv, line 3, column 't_s': times must increase (time stamps too coarse for the rate? give --rate HZ to "
        "read the times from the sample index)"
    )
    assert times.kind == "x" and times.line == 3
    worded = skipped(snapshot, TrajectoryError("column 't_s' must increase", source="a.csv"))
    assert worded.reason.endswith("give --rate HZ to read the times from the sample index)") and worded.line is None
    assert not skipped(snapshot, TrajectoryError("'t_s' is missing", source="a.csv")).reason.endswith(")")
    assert one.as_dict() == {
        "file": "a.csv",
        "path": "/logs/a.csv",
        "kind": "unreadable",
        "reason": one.reason,
        "line": 7,
    }
