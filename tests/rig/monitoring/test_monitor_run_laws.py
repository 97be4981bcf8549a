"""hipsim.rig.monitoring.monitor_run and watch's bookkeeping on hand-made rows (the estimate replaced by a stand-in
that records what it is asked): which snapshots are done and which are estimated again, the batches and their sizes,
the rows' order, what is left out and why, the table written and resumed, the summary's counts; and the watch's
decisions round by round (estimate when the snapshots change, alarm once when it becomes active). One run through
the real estimate on two tiny exact logs checks the path in between.
"""

from __future__ import annotations

import math
import threading
from types import SimpleNamespace

import numpy as np
import pytest
from monitor_synthetic import EXACT_MACHINE as MACHINE
from monitor_synthetic import write_exact
from support import given

import hipsim
from hipsim.exceptions import ArgumentError, OutputError, TrajectoryError
from hipsim.rig.monitoring import monitor_run, watch
from hipsim.rig.monitoring.monitor_fit import ESTIMATE_COLUMNS, MonitorSetup
from hipsim.rig.monitoring.monitor_run import MOST_PER_BATCH, MonitorTable, monitor, run_monitor
from hipsim.rig.monitoring.monitor_summary import SkippedFile
from hipsim.rig.monitoring.monitor_table import COLUMNS, read_metadata, read_table
from hipsim.rig.monitoring.snapshots import Skipped, Snapshot

PARAMS = hipsim.load_parameters()
SETUP = MonitorSetup(PARAMS)
R_H_MM = 15.0  # the published hip radius in [mm]


def snap(cycle: int, sha: str = "s", folder: str = "/logs") -> Snapshot:
    return Snapshot(f"{folder}/snap_{cycle:07d}.csv", 100 + cycle % 7, sha)


def first_cycle(s: Snapshot) -> int:
    """A snapshot's first cycle: a window's own, else from its file's name."""
    return s.first_cycle if s.first_cycle is not None else int(s.name[5:12])


def row(s: Snapshot, a: float = 3.0, **more) -> dict:
    """An estimate row for a snapshot (its first cycle from its name): the load term ``a`` in [mm]."""
    cycle = first_cycle(s)
    values: dict[str, float | str | None] = {name: math.nan for name in ESTIMATE_COLUMNS}
    values |= {
        "cycle": cycle,
        "last_cycle": s.last_cycle if s.last_cycle is not None else cycle + 9,
        "file": s.name,
        "samples": 1000,
        "load_friction_mm": a,
        "load_friction_mm_std": 0.001,
        "stations": "not logged",
        "note": "",
        "bytes": s.size,
        "sha256": s.sha256,
        "residual_rms_Nmm": 1.0,
    }
    return values | more


@pytest.fixture
def estimates(monkeypatch):
    """The estimate replaced: rows of ``a`` by cycle (default 3 mm), a Skipped for a snapshot named in ``refuse``;
    each batch recorded with the set-up it came with."""
    record = SimpleNamespace(batches=[], a={}, refuse={}, more={})

    def estimate_batch(batch, setup):
        record.batches.append(([s.name for s in batch], setup))
        out: list[dict | Skipped] = []
        for s in batch:
            if s.name in record.refuse:
                out.append(Skipped(s.name, s.path, record.refuse[s.name], "unreadable", 4))
            else:
                cycle = first_cycle(s)
                out.append(row(s, record.a.get(cycle, 3.0), **record.more.get(cycle, {})))
        return out

    monkeypatch.setattr(monitor_run, "estimate_batch", estimate_batch)
    return record


def test_workers_must_be_a_whole_number_of_at_least_one(estimates):
    for workers in (0, -1, 1.5, True, "2", None):
        with pytest.raises(ArgumentError) as error:
            run_monitor(SETUP, [snap(0)], workers=workers)  # type: ignore[arg-type]  # wrong types on purpose
        assert str(error.value).startswith("workers: expected a whole number of worker processes, at least 1, got")
        assert error.value.value is workers
    assert run_monitor(SETUP, [snap(0)], workers=np.int64(1)).new  # type: ignore[arg-type]  # NumPy's integer is accepted == 1 and len(estimates.batches) == 1


def test_batches_in_this_process_with_progress(estimates):
    snapshots = [snap(10 * k) for k in range(20)]
    progress = []
    result = run_monitor(SETUP, snapshots, progress=lambda done, todo: progress.append((done, todo)))
    # About eight batches a worker: ⌈20/8⌉ = 3 snapshots each, in order, every one with the set-up.
    assert [len(names) for names, _ in estimates.batches] == [3, 3, 3, 3, 3, 3, 2]
    assert [n for names, _ in estimates.batches for n in names] == [s.name for s in snapshots]
    assert all(setup is SETUP for _, setup in estimates.batches)
    assert progress == [(3, 20), (6, 20), (9, 20), (12, 20), (15, 20), (18, 20), (20, 20)]
    assert (result.new, result.kept, len(result.rows)) == (20, 0, 20)
    estimates.batches.clear()
    run_monitor(SETUP, snapshots, batch_size=6)
    assert [len(names) for names, _ in estimates.batches] == [6, 6, 6, 2]


def test_the_batches_handed_to_the_workers(monkeypatch):
    calls = []

    def run_batches(function, work, setup, workers, scheduler, what):
        calls.append((function, work, setup, workers, scheduler, what))
        for batch in work:
            yield [row(s) for s in batch]

    monkeypatch.setattr(monitor_run, "run_batches", run_batches)
    snapshots = [snap(10 * k) for k in range(30)]
    run_monitor(SETUP, snapshots, workers=np.int64(2), scheduler="tcp://x:1")  # type: ignore[arg-type]  # NumPy's integer
    (function, work, setup, workers, scheduler, what), *_ = calls
    # Two workers: ⌈30/16⌉ = 2 a batch; the workers and scheduler passed on as given.
    assert function is monitor_run.estimate_batch and setup is SETUP and what == "hipsim monitor"
    assert (workers, type(workers), scheduler) == (2, int, "tcp://x:1")
    assert [len(b) for b in work] == [2] * 15 and all(isinstance(b, list) for b in work)
    calls.clear()
    run_monitor(SETUP, [snap(10 * k) for k in range(900)], workers=1)
    assert [len(b) for b in calls[0][1]] == [MOST_PER_BATCH] * 18 and MOST_PER_BATCH == 50  # ⌈900/8⌉ = 113 > 50


def test_what_is_done_is_kept_and_a_changed_file_estimated_again(estimates):
    old = [snap(0), snap(10), snap(20, sha="old"), snap(30)]
    previous = [row(s, a=9.0) for s in old]
    now = [snap(10), snap(20, sha="new"), snap(40), snap(50)]  # 0 and 30 no longer given; 20 changed
    result = run_monitor(SETUP, now, previous=previous)
    assert [n for names, _ in estimates.batches for n in names] == [
        "snap_0000020.csv",
        "snap_0000040.csv",
        "snap_0000050.csv",
    ]
    assert (result.new, result.kept) == (3, 3)
    by_cycle = {r["cycle"]: (r["sha256"], r["load_friction_mm"]) for r in result.rows}
    assert by_cycle == {0: ("s", 9.0), 10: ("s", 9.0), 20: ("new", 3.0), 30: ("s", 9.0), 40: ("s", 3.0), 50: ("s", 3.0)}
    estimates.batches.clear()
    assert run_monitor(SETUP, old, previous=previous).new == 0 and estimates.batches == []


def test_rows_by_cycle_then_file_and_duplicates_left_out(estimates):
    twin = Snapshot("/other/snap_0000010.csv", 5, "t")  # same name, same cycles, another file: one row only
    a, b = Snapshot("/logs/snap_0000020_b.csv", 1, "b"), Snapshot("/logs/snap_0000020_a.csv", 1, "a")
    result = run_monitor(SETUP, [snap(30), b, a, snap(10)])
    assert [r["file"] for r in result.rows] == ["snap_0000010.csv", "snap_0000020_a.csv", "snap_0000030.csv"]
    (dup,) = result.skipped
    assert (dup.name, dup.path, dup.kind) == ("snap_0000020_b.csv", "/logs/snap_0000020_b.csv", "duplicate")
    assert dup.reason.startswith("/logs/snap_0000020_b.csv: covers cycles 20-29, as does snap_0000020_a.csv")
    assert result.paths["snap_0000030.csv"] == "/logs/snap_0000030.csv" and twin.name == "snap_0000010.csv"
    assert result.rows[0]["cycle"] == 10 and all(isinstance(r["cycle"], int) for r in result.rows)


def test_what_is_left_out_is_carried_and_nothing_usable_is_an_error(estimates):
    waiting = Skipped("w.csv", "/logs/w.csv", "still being written", "waiting")
    estimates.refuse = {"snap_0000010.csv": "/logs/snap_0000010.csv, line 4: broken"}
    result = run_monitor(SETUP, [snap(0), snap(10)], skipped=[waiting])
    assert [s.name for s in result.skipped] == ["w.csv", "snap_0000010.csv"] and len(result.rows) == 1
    summary = result.summary()
    assert summary.waiting == [SkippedFile.of(waiting)] and [s.file for s in summary.skipped] == ["snap_0000010.csv"]
    assert summary.skipped[0].line == 4
    # Nothing usable: the first left out that is not waiting is named, with its file.
    with pytest.raises(TrajectoryError) as error:
        run_monitor(SETUP, [snap(10)], skipped=[waiting])
    assert str(error.value) == (
        "/logs/snap_0000010.csv: no usable snapshot (2 left out; the first: /logs/snap_0000010.csv, line 4: broken)"
    )
    with pytest.raises(TrajectoryError) as error:
        run_monitor(SETUP, [], skipped=[waiting])
    assert str(error.value) == "/logs/w.csv: no usable snapshot (1 left out; the first: still being written)"
    with pytest.raises(TrajectoryError) as error:
        run_monitor(SETUP, [])
    assert str(error.value) == "no usable snapshot: none given" and error.value.source is None


def test_the_table_written_and_resumed(estimates, tmp_path):
    out = tmp_path / "table.csv"
    snapshots = [snap(0), snap(10)]
    first = run_monitor(SETUP, snapshots, out=out, metadata={"command": "test"})
    table = read_table(out)
    assert list(table) == list(COLUMNS) and table["cycle"] == [0, 10] and table["file"] == first.columns["file"]
    meta = given(read_metadata(out))
    assert meta["command"] == "test" and meta["fingerprints"] == SETUP.fingerprints()
    assert meta["parameters"] == PARAMS.source and first.fingerprints == SETUP.fingerprints()
    # A second run reads the table: nothing new to estimate; restart estimates all again.
    estimates.batches.clear()
    again = run_monitor(SETUP, snapshots + [snap(20)], out=out)
    assert (again.new, again.kept) == (1, 2) and [n for names, _ in estimates.batches for n in names] == [
        "snap_0000020.csv"
    ]
    assert read_table(out)["cycle"] == [0, 10, 20]
    assert run_monitor(SETUP, snapshots, out=out, restart=True).new == 2 and read_table(out)["cycle"] == [0, 10]
    # Another set-up's table is refused, not extended, naming what differs.
    with pytest.raises(OutputError, match=r"the model options \(cutoff, torque constant, tolerance, rate\) differs"):
        run_monitor(MonitorSetup(PARAMS, cutoff=None), snapshots, out=out)
    with pytest.raises(OutputError):
        run_monitor(SETUP, snapshots, out=tmp_path / "table.txt")


def stepped(estimates, step_from: int, step_mm: float, gain=None):
    """Snapshots every 10 cycles up to 100, baseline 20-50 (four snapshots: the runs set ``baseline_min=4``), the load
    term 3 mm (± 0.001) up by ``step_mm`` from a cycle."""
    for cycle in range(0, 101, 10):
        estimates.a[cycle] = 3.0 + 0.001 * (-1) ** (cycle // 10) + (step_mm if cycle >= step_from else 0.0)
        if gain is not None:
            estimates.more[cycle] = {"load_gain": gain(cycle)}
    return [snap(c) for c in range(0, 101, 10)]


def test_the_columns_from_the_rows_and_the_charts(estimates):
    result = run_monitor(SETUP, stepped(estimates, 80, 0.5), baseline=(20, 50), baseline_min=4, alarm_rise=0.01)
    c, mean = result.columns, result.findings.mean
    assert list(c) == list(COLUMNS) and len(c["cycle"]) == 11
    for name in ("cycle", "last_cycle", "samples", "alarm", "bytes"):
        assert all(type(v) is int for v in c[name]), name
    for name in ("load_friction_mm", "hip_mu_change", "ewma_mm", "ucl_mm", "load_gain", "hip_mu_change_1"):
        assert all(type(v) is float for v in c[name]), name
    assert c["file"][0] == "snap_0000000.csv" and c["stations"][0] == "not logged" and c["sha256"][0] == "s"
    assert c["phase"] == ["running-in", "running-in"] + ["baseline"] * 4 + ["monitoring"] * 5
    assert c["load_friction_mm"] == [estimates.a[k] for k in range(0, 101, 10)]
    # The change of μ_h: (a - μ₀)/r_h, μ₀ the baseline's mean (3 mm, its ±0.001 cancelling over four snapshots).
    assert c["hip_mu_change"][-1] == pytest.approx((3.5 + 0.001 - 3.0) / R_H_MM, abs=1e-12)
    for name, values in (
        ("hip_mu_change_std", mean.change_std),
        ("ewma_mm", mean.ewma),
        ("lcl_mm", mean.lower),
        ("ucl_mm", mean.upper),
    ):
        np.testing.assert_array_equal(c[name], values, err_msg=name)
    assert c["alarm"] == [0] * 8 + [1] * 3 and c["flag"][-1].startswith("alarm: the two stations' mean rises")
    for p in (1, 2):  # no station's chart: NaN
        assert all(
            math.isnan(c[f"{name}_{p}{unit}"][0])
            for name, unit in (
                ("hip_mu_change", ""),
                ("hip_mu_change", "_std"),
                ("ewma", "_mm"),
                ("lcl", "_mm"),
                ("ucl", "_mm"),
            )
        )
    assert c["note"] == [""] * 11 and all(math.isnan(v) for v in c["load_gain_change"])


def test_the_stations_columns_from_their_charts(estimates):
    snapshots = stepped(estimates, 200, 0.0)
    for cycle in estimates.a:
        estimates.more[cycle] = {
            "stations": "separated",
            "load_friction_1_mm": 2.9 + 0.001 * (cycle % 20 == 0),
            "load_friction_1_mm_std": 0.001,
            "load_friction_2_mm": 3.1,
            "load_friction_2_mm_std": 0.001,
        }
    result = run_monitor(SETUP, snapshots, baseline=(20, 50), baseline_min=4)
    c, (one, two) = result.columns, given(result.findings.stations)
    for p, s in ((1, one), (2, two)):
        for name, values in (
            (f"hip_mu_change_{p}", s.change),
            (f"hip_mu_change_{p}_std", s.change_std),
            (f"ewma_{p}_mm", s.ewma),
            (f"lcl_{p}_mm", s.lower),
            (f"ucl_{p}_mm", s.upper),
        ):
            np.testing.assert_array_equal(c[name], values, err_msg=name)
    summary = result.summary()
    assert summary.judged == "per station"
    assert summary.baseline.stations is not None
    assert [s.station for s in summary.baseline.stations] == [1, 2]
    assert summary.baseline.stations[1].load_friction_mm == pytest.approx(3.1)
    assert summary.baseline.stations[0].snapshots == 4 and summary.baseline.stations[0].spread_mm >= 0


def test_the_summary_s_counts(estimates):
    # An alarm at 80, 90, 100 after a step of 0.5 mm (0.033 of μ_h); the load cell 3 % low at 70, 2 % high at 90,
    # its commanded load not logged at 100 (the last change known is 90's).
    drift = {70: 0.97, 90: 1.02, 100: math.nan}
    gains = stepped(estimates, 80, 0.5, gain=lambda cycle: drift.get(cycle, 1.0))
    result = run_monitor(SETUP, gains, baseline=(20, 50), baseline_min=4, alarm_rise=0.01)
    s = result.summary()
    assert (s.snapshots, s.new, s.kept, s.first_cycle, s.last_cycle) == (11, 11, 0, 0, 109)
    assert s.baseline.from_ == 20 and s.baseline.to == 50 and s.baseline.snapshots == 4
    assert s.baseline.load_friction_mm == pytest.approx(3.0, abs=1e-12) and s.baseline.stations is None
    assert s.baseline.spread_mm == result.findings.mean.spread > 0
    assert s.alarm_rise == 0.01 and s.threshold_mm == list(result.findings.mean.threshold)
    assert s.chart == "two-sided EWMA (lambda 0.2, L 3) with the engineering threshold"
    assert s.judged == "the two stations' mean, worst case (up to twice its change in one station)"
    assert (s.alarms, s.alarm_active, s.notice_active, s.notices) == (3, True, False, 0)
    assert s.first_alarm is not None
    assert s.first_alarm.file == "snap_0000080.csv" and s.latest_notice is None
    assert s.worst_case_factor == 2.0
    cell = s.load_cell
    assert cell.commanded_load_logged and cell.gain_change_last == pytest.approx(0.02, abs=1e-12)
    assert cell.three_percent == pytest.approx(0.03 / 1.03 * 3.0 / R_H_MM, rel=1e-12)
    assert cell.drifted == ["snap_0000070.csv", "snap_0000090.csv"]
    assert s.missing == [] and s.incomplete == [] and s.note == ""
    assert s.files[0].to_json() == {"file": "snap_0000000.csv", "bytes": 100, "sha256": "s"} and len(s.files) == 11
    assert s.fingerprint == SETUP.fingerprints()["setup"] and s.parameters == PARAMS.source
    assert s.table is result.columns and s.skipped == [] and s.waiting == []
    assert result.two_stations and result.baseline == (20, 50) and result.alarm_rise == 0.01


def test_the_summary_s_notice_gaps_and_short_snapshots(estimates):
    # A step of 0.1 mm (μ_h + 0.0067): seen, under the threshold of 0.01 in the worst station (twice 0.0067 is above
    # it, so the worst case is a notice, not an alarm); snapshot 60 missing; 100 short.
    snapshots = [s for s in stepped(estimates, 80, 0.1) if s.name != "snap_0000060.csv"]
    estimates.more[100] = {"samples": 400, "note": "cut"}
    s = run_monitor(SETUP, snapshots, baseline=(20, 50), baseline_min=4, alarm_rise=0.02).summary()
    assert s.missing == [60] and s.incomplete == ["snap_0000100.csv"]
    assert s.alarms == 0 and s.notice_active and not s.alarm_active
    assert s.notices == sum("notice" in f for f in s.table["flag"]) >= 1
    assert s.latest_notice is not None
    assert s.latest_notice.file == "snap_0000100.csv" and s.first_alarm is None
    assert not s.load_cell.commanded_load_logged and s.load_cell.gain_change_last is None
    assert s.load_cell.drifted == []
    # No baseline yet: no chart, said so.
    s = run_monitor(SETUP, [snap(0)], baseline=(20, 50), baseline_min=4).summary()
    assert s.note != "" and s.alarms == 0 and not s.alarm_active and not s.notice_active


def test_monitor_takes_its_options_and_gives_a_table(estimates, tmp_path):
    for cycle in (0, 10):
        (tmp_path / f"snap_{cycle:07d}.csv").write_text("x\n")
    table = monitor(PARAMS, tmp_path, baseline="0:10", window=None, cutoff=None, torque_constant=0.2, rate=500.0)
    assert list(table["cycle"]) == [0, 10] and list(table.columns) == list(COLUMNS)
    assert [names for names, _ in estimates.batches] == [["snap_0000000.csv"], ["snap_0000010.csv"]]
    setup = estimates.batches[0][1]
    assert (setup.params, setup.lever_spin, setup.cutoff, setup.torque_constant, setup.rate, setup.window) == (
        PARAMS,
        True,
        None,
        0.2,
        500.0,
        None,
    )
    assert list(table["phase"]) == ["baseline", "baseline"]
    # Files just written: a batch run waits for them to settle (0.3 s here), then reads them, never skips them.
    import os
    import time

    for path in tmp_path.glob("*.csv"):
        os.utime(path)  # changed just now
    start = time.monotonic()
    assert list(monitor(PARAMS, tmp_path, settle=0.3)["cycle"]) == [0, 10]
    assert time.monotonic() - start >= 0.25
    out = tmp_path / "out" / "t.csv"
    out.parent.mkdir()
    monitor(PARAMS, tmp_path, baseline=(0, 10), out=out)
    assert read_table(out)["cycle"] == [0, 10]
    estimates.batches.clear()
    monitor(PARAMS, tmp_path, baseline=(0, 10), out=out)  # resumed: nothing new
    assert estimates.batches == []
    monitor(PARAMS, tmp_path, baseline=(0, 10), out=out, restart=True)
    assert len(estimates.batches) == 2


def test_monitor_without_pandas_gives_its_own_table(estimates, tmp_path, monkeypatch):
    import builtins

    (tmp_path / "snap_0000000.csv").write_text("x\n")
    real = builtins.__import__

    def no_pandas(name, *args, **kwargs):
        if name == "pandas":
            raise ImportError(name)
        return real(name, *args, **kwargs)

    monkeypatch.setattr(builtins, "__import__", no_pandas)
    table = monitor(PARAMS, tmp_path)
    assert isinstance(table, MonitorTable) and len(table) == 1 and list(table) == list(COLUMNS)
    assert table["cycle"] == [0] and table.to_dict()["file"] == ["snap_0000000.csv"]


def test_the_real_estimate_in_between(tmp_path):
    for cycle in (0, 10):
        write_exact(tmp_path / f"snap_{cycle:07d}.csv", first_cycle=cycle)
    from hipsim.rig.monitoring.snapshots import find_snapshots

    snapshots, _ = find_snapshots(str(tmp_path))
    result = run_monitor(MonitorSetup(MACHINE, cutoff=None), snapshots, baseline=(0, 10))
    f = MACHINE.friction
    a = (f.hip_radius * f.hip_mu + f.thrust_radius * f.thrust_mu) * 1e3
    assert result.columns["load_friction_mm"] == pytest.approx([a, a], rel=2e-4)
    assert result.columns["cycle"] == [0, 10] and result.new == 2


# ------------------------------------------------------------------------------------------------------------ watch


class Rounds(threading.Event):
    """A stop whose wait between rounds runs the next of ``between`` (the world changing while the watch sleeps)."""

    def __init__(self, between):
        super().__init__()
        self.between, self.waits = list(between), []

    def wait(self, timeout=None):
        self.waits.append(timeout)
        if self.between:
            self.between.pop(0)()
        return self.is_set()


@pytest.fixture
def world(monkeypatch):
    """The watch's snapshots and results replaced: ``world.snapshots`` is what each round finds, ``world.alarm`` the
    last snapshot's alarm of the next result, ``world.fail`` makes the next run find nothing usable."""
    w = SimpleNamespace(snapshots=[], skipped=[], alarm=0, fail=False, runs=[], finds=[])

    def find_snapshots(logs, window, settle, torque_constant, rate, cache, clock, columns=None):
        w.finds.append((logs, window, settle, torque_constant, rate, cache))
        return list(w.snapshots), list(w.skipped)

    def run(
        setup,
        snapshots,
        baseline,
        alarm_rise,
        out,
        restart,
        workers,
        scheduler,
        metadata,
        skipped,
        previous,
        baseline_min=5,
        acknowledge=(),
    ):
        w.runs.append(SimpleNamespace(**locals()))
        if w.fail:
            raise TrajectoryError("no usable snapshot")
        rows = [{"file": s.name} for s in snapshots]
        findings = SimpleNamespace(
            alarm=np.array([0] * (len(rows) - 1) + [w.alarm]),
            alarm_held=bool(w.alarm),
            acknowledgements=lambda: tuple(acknowledge),
        )
        return SimpleNamespace(rows=rows, findings=findings)

    monkeypatch.setattr(watch, "find_snapshots", find_snapshots)
    monkeypatch.setattr(watch, "run_monitor", run)
    return w


def test_the_poll_must_be_positive():
    for poll in (0.0, -1.0, math.nan):
        with pytest.raises(ArgumentError, match="^poll: expected seconds > 0 between looks at the logs") as error:
            watch.watch(SETUP, "x", (0, 1), 0.01, poll=poll)
        assert error.value.name == "poll" and error.value.value is poll


def test_a_round_estimates_only_when_the_snapshots_change(world):
    updates: list = []
    alarms: list = []

    def add(*snapshots):
        return lambda: world.snapshots.extend(snapshots)

    def alarm(value):
        return lambda: setattr(world, "alarm", value)

    # Round 1: nothing yet. 2: one snapshot. 3: the same. 4: another, alarm. 5: another, still alarm.
    # 6: another, alarm gone. 7: another, alarm again.
    world.skipped = [Skipped("w.csv", "/logs/w.csv", "still being written", "waiting")]
    stop = Rounds(
        [
            add(snap(0)),
            lambda: None,
            lambda: (add(snap(10))(), alarm(1)()),
            add(snap(20)),
            lambda: (add(snap(30))(), alarm(0)()),
            lambda: (add(snap(40))(), alarm(1)()),
        ]
    )
    setup = MonitorSetup(PARAMS, window=3, torque_constant=0.1, rate=200.0)
    last = watch.watch(
        setup,
        ["logs"],
        (0, 10),
        0.02,
        poll=0.5,
        settle=2.0,
        update=updates.append,
        on_alarm=alarms.append,
        stop=stop,
        rounds=7,
        workers=1,
        scheduler="tcp://s:1",
        metadata={"m": 1},
    )
    assert [len(r.snapshots) for r in world.runs] == [1, 2, 3, 4, 5]  # rounds 2, 4, 5, 6, 7
    assert len(updates) == 5 and [len(r.rows) for r in alarms] == [2, 5]
    assert last is updates[-1] and stop.waits == [0.5] * 6  # no wait after the last round
    assert world.finds[0][:5] == (["logs"], 3, 2.0, 0.1, 200.0)
    assert isinstance(world.finds[0][5], dict) and all(f[5] is world.finds[0][5] for f in world.finds)  # one cache
    first, second = world.runs[0], world.runs[1]
    assert (first.baseline, first.alarm_rise, first.out, first.restart, first.workers, first.scheduler) == (
        (0, 10),
        0.02,
        None,
        False,
        1,
        "tcp://s:1",
    )
    assert first.metadata == {"m": 1} and list(first.previous) == [] and second.previous == updates[0].rows
    assert first.setup is setup and first.skipped == world.skipped


def add_and_succeed(world, snapshot: Snapshot) -> None:
    """The world's next round: a new snapshot, and the run that finds it usable."""
    world.snapshots.append(snapshot)
    world.fail = False


def test_nothing_usable_waits_for_the_next_change(world):
    world.snapshots, world.fail = [snap(0)], True
    stop = Rounds([lambda: None, lambda: add_and_succeed(world, snap(10))])
    updates: list = []
    assert watch.watch(SETUP, "logs", (0, 1), 0.01, poll=1.0, update=updates.append, stop=stop, rounds=2) is None
    assert len(world.runs) == 1 and updates == []  # the same snapshots are not tried again
    stop = Rounds([lambda: add_and_succeed(world, snap(10))])
    result = watch.watch(SETUP, "logs", (0, 1), 0.01, poll=1.0, update=updates.append, stop=stop, rounds=2)
    assert len(given(result).rows) == 2 and updates == [result]


def test_a_stop_ends_the_watch_and_no_snapshot_runs_nothing(world):
    stop = Rounds([])
    stop.set()
    assert watch.watch(SETUP, "logs", (0, 1), 0.01, stop=stop) is None and world.finds == []
    stop = Rounds([lambda: None, lambda: stop.set()])
    assert watch.watch(SETUP, "logs", (0, 1), 0.01, stop=stop) is None  # rounds: until stopped
    assert len(world.finds) == 2 and world.runs == []


def test_the_watch_resumes_the_table(world, tmp_path, estimates):
    out = tmp_path / "t.csv"
    run_monitor(SETUP, [snap(0)], out=out)  # the real run (estimate replaced) writes a table to resume
    world.snapshots = [snap(0), snap(10)]
    watch.watch(SETUP, "logs", (0, 1), 0.01, out=out, stop=Rounds([]), rounds=1)
    (run,) = world.runs
    assert run.out == out and [r["file"] for r in run.previous] == ["snap_0000000.csv"]
    assert run.previous[0]["cycle"] == 0 and type(run.previous[0]["cycle"]) is int
    world.runs.clear()
    watch.watch(SETUP, "logs", (0, 1), 0.01, out=out, restart=True, stop=Rounds([]), rounds=1)
    assert list(world.runs[0].previous) == []
    with pytest.raises(OutputError):
        watch.watch(SETUP, "logs", (0, 1), 0.01, out=tmp_path / "t.txt", stop=Rounds([]), rounds=1)


def test_without_a_stop_it_watches_its_rounds(world):
    world.snapshots = [snap(0)]
    result = watch.watch(SETUP, "logs", (0, 1), 0.01, poll=1e-3, rounds=2)
    assert len(world.finds) == 2 and len(world.runs) == 1 and given(result).rows == [{"file": "snap_0000000.csv"}]
    assert world.finds[0][2] == 10.0  # the settle's default: ten seconds
    assert (world.runs[0].workers, world.runs[0].scheduler, world.runs[0].metadata) == (1, None, None)


def test_an_alarm_at_the_first_result_is_raised(world):
    world.snapshots, world.alarm = [snap(0)], 1
    alarms: list = []
    watch.watch(SETUP, "logs", (0, 1), 0.01, on_alarm=alarms.append, stop=Rounds([]), rounds=2)
    assert len(alarms) == 1 and len(world.runs) == 1


def test_the_watch_refuses_another_set_up_s_table(world, tmp_path, estimates):
    out = tmp_path / "t.csv"
    run_monitor(SETUP, [snap(0)], out=out)
    with pytest.raises(OutputError, match=r"the model options \(cutoff, torque constant, tolerance, rate\) differs"):
        watch.watch(MonitorSetup(PARAMS, cutoff=None), "logs", (0, 1), 0.01, out=out, stop=Rounds([]), rounds=1)


def test_the_alarm_and_notice_at_the_last_snapshot_alone(estimates):
    # The step at the last snapshot only: the alarm is active there, not before.
    s = run_monitor(SETUP, stepped(estimates, 100, 0.5), baseline=(20, 50), baseline_min=4, alarm_rise=0.01).summary()
    assert s.table["alarm"][-2:] == [0, 1] and s.alarm_active and s.alarms == 1
    assert not s.notice_active
    # Below the threshold (0.1 mm: 0.0067 of μ_h, twice that still under 0.02): a notice, active at the last only.
    s = run_monitor(SETUP, stepped(estimates, 100, 0.1), baseline=(20, 50), baseline_min=4, alarm_rise=0.02).summary()
    assert s.table["flag"][-2] == "" and s.table["flag"][-1].startswith("notice")
    assert s.notice_active and not s.alarm_active and s.notices == 1


def test_monitor_from_an_identified_file_and_windows_of_a_long_log(estimates, tmp_path):
    from monitor_synthetic import write_identified

    params = write_identified(tmp_path / "identified.toml")
    text = params.read_text().replace("lever spin on", "lever spin off")
    params.write_text(text)
    logs = tmp_path / "logs"
    logs.mkdir()
    # Stamps rounded down to 30 ms at 50 Hz: the long log's scan reads its times from the rate too.
    write_exact(logs / "long.csv", first_cycle=100, cycles=3, stamp_step=0.03)
    table = monitor(params, logs, baseline=(100, 102), window=1, rate=50.0)
    assert list(table["cycle"]) == [100, 101, 102]
    assert list(table["file"]) == ["long.csv[100-100]", "long.csv[101-101]", "long.csv[102-102]"]
    setup = estimates.batches[0][1]
    assert setup.window == 1 and setup.lever_spin is False and setup.params.source == str(params)
    assert setup.rate == 50.0 and setup.cutoff == 20.0 and setup.torque_constant is None


def test_monitor_hands_its_workers_and_scheduler_on(monkeypatch, tmp_path):
    calls = []

    def run_batches(function, work, setup, workers, scheduler, what):
        calls.append((workers, scheduler))
        for batch in work:
            yield [row(s) for s in batch]

    monkeypatch.setattr(monitor_run, "run_batches", run_batches)
    (tmp_path / "snap_0000000.csv").write_text("x\n")
    monitor(PARAMS, tmp_path, workers=3, scheduler="tcp://s:1")
    assert calls == [(3, "tcp://s:1")]


def test_windows_of_a_long_log_of_currents(estimates, tmp_path):
    # The long log's scan reads currents through the torque constant given.
    write_exact(tmp_path / "amps.csv", first_cycle=0, cycles=3, torque_constant=0.5)
    table = monitor(PARAMS, tmp_path, baseline=(0, 2), window=1, torque_constant=0.5)
    assert list(table["file"]) == ["amps.csv[0-0]", "amps.csv[1-1]", "amps.csv[2-2]"]
