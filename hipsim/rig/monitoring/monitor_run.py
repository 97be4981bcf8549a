"""Following a wear test: every snapshot's estimate (in this process or on dask.distributed), the charts, the table.

:func:`run_monitor` estimates the snapshots the table does not hold yet (by
file name and SHA-256: a file that changed is estimated again), in batches: in
this process for one worker, else on a ``LocalCluster`` of worker processes or
the cluster of a scheduler's address (:func:`hipsim.analysis.cluster.run_batches`,
the path ``hipsim sweep`` takes), the same
:func:`~hipsim.rig.monitoring.monitor_fit.estimate_batch` on either path, so the
rows are the same to the last bit. A snapshot that cannot be read is skipped
and named with its reason, never averaged in and never stopping the test; the
run fails only when nothing usable remains. The charts and findings
(:mod:`~hipsim.rig.monitoring.findings`) are then drawn over all rows, old and
new, and the table written whole, atomically.

:func:`monitor` is the library's entry (``hipsim.monitor``): the table as a
pandas DataFrame when pandas is installed, else a :class:`MonitorTable`.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ...analysis.cluster import batch_size as _batch_size
from ...analysis.cluster import run_batches
from ...exceptions import ArgumentError, TrajectoryError
from ...machine.parameters import Parameters
from ...records import Verdict
from .control_chart import DEFAULT_ALARM_RISE, DEFAULT_BASELINE, EWMA_L, EWMA_LAMBDA, MIN_BASELINE, check_baseline_min
from .findings import Findings, check_acknowledged, duplicates, find, missing_cycles
from .monitor_fit import MonitorSetup, estimate_batch
from .monitor_state import MonitorState, last_change, monitor_state, monitor_verdict
from .monitor_summary import Baseline, LoadCell, MonitorSummary, SkippedFile, SnapshotFile, StationBaseline
from .monitor_table import COLUMNS, MONITOR_TABLE, PARTS, table_rows, write_table
from .reference import reference
from .snapshots import Skipped, Snapshot, find_snapshots

__all__ = ["MOST_PER_BATCH", "MonitorResult", "MonitorTable", "monitor", "run_monitor"]

#: The largest batch of snapshots a task gets.
MOST_PER_BATCH = 50


@dataclass(frozen=True)
class MonitorTable:
    """The table without pandas: columns by name (:data:`~hipsim.rig.monitoring.monitor_table.COLUMNS`), one row a snapshot."""

    columns: dict[str, list[Any]]

    def __getitem__(self, name: str) -> list[Any]:
        return self.columns[name]

    def __len__(self) -> int:
        return len(self.columns["cycle"])

    def __iter__(self):
        return iter(self.columns)

    def to_dict(self) -> dict[str, list[Any]]:
        return {name: list(values) for name, values in self.columns.items()}


@dataclass(frozen=True, eq=False)
class MonitorResult:
    """A monitor's run.

    Attributes:
        setup: what the snapshots shared.
        rows: the estimate rows, sorted by cycle.
        columns: the table by column (:data:`COLUMNS`), sorted by cycle.
        findings: the charts and what they find.
        new: snapshots estimated in this run.
        kept: rows kept from the table already there.
        skipped: snapshots left out, each with its reason (unreadable, still being written, duplicate).
        missing: first cycles of snapshots missing from the regular sequence.
        baseline: (FROM, TO) cycles.
        alarm_rise: the engineering threshold.
        fingerprints: the set-up's fingerprints.
    """

    setup: MonitorSetup
    rows: list[dict[str, Any]]
    columns: dict[str, list[Any]]
    findings: Findings
    new: int
    kept: int
    skipped: list[Skipped]
    missing: list[int]
    baseline: tuple[int, int]
    alarm_rise: float
    fingerprints: dict[str, str]
    paths: dict[str, str] = field(default_factory=dict)

    @property
    def two_stations(self) -> bool:
        return self.setup.params.heights.size == 2

    @property
    def state(self) -> MonitorState:
        """The state at the last snapshot: ALARM, NOTICE, OK or NOT MADE (:func:`monitor_state`)."""
        found = self.findings
        return monitor_state(found.alarm, found.flag, found.mean.note, found.alarm_held)

    @property
    def verdict(self) -> Verdict:
        """The verdict on the state (:func:`monitor_verdict`): the last snapshot's cycle, and the change it names
        (:func:`last_change`)."""
        found, cycles = self.findings, self.columns["last_cycle"]
        change = last_change(found.latest_notice.text if found.latest_notice else None, found.flag)
        return monitor_verdict(self.state, int(cycles[-1]) if cycles else None, change, found.mean.note)

    def summary(self) -> MonitorSummary:
        """The run's summary: counts, baseline, alarms and notices, skipped and missing snapshots, files."""
        c, found = self.columns, self.findings
        chart = found.mean
        stations = None
        if found.stations is not None:
            stations = [
                StationBaseline(p + 1, s.mean, s.spread, s.baseline_count) for p, s in enumerate(found.stations)
            ]
        gain = found.load_gain_change
        known = np.isfinite(gain)
        if found.stations is not None:
            judged = "per station"
        elif self.two_stations:
            judged = "the two stations' mean, worst case (up to twice its change in one station)"
        else:
            judged = "the station"
        return MonitorSummary(
            verdict=self.verdict,
            snapshots=len(c["cycle"]),
            new=self.new,
            kept=self.kept,
            first_cycle=int(c["cycle"][0]) if c["cycle"] else None,
            last_cycle=int(c["last_cycle"][-1]) if c["cycle"] else None,
            baseline=Baseline(
                self.baseline[0], self.baseline[1], chart.baseline_count, chart.mean, chart.spread, stations
            ),
            alarm_rise=self.alarm_rise,
            threshold_mm=list(chart.threshold),
            worst_case_factor=chart.worst,
            chart=f"two-sided EWMA (lambda {EWMA_LAMBDA:g}, L {EWMA_L:g}) with the engineering threshold",
            judged=judged,
            alarms=int(found.alarm.sum()),
            first_alarm=found.first,
            notices=sum(1 for f in found.flag if "notice" in f),
            latest_notice=found.latest_notice,
            alarm_active=self.state.alarm_active,
            notice_active=self.state.notice_active,
            state=found.state[-1] if found.state else "NO BASELINE",
            alarm_raised_at=found.raised_at,
            alarm_at_last_snapshot=bool(len(found.alarm) and found.alarm[-1]),
            acknowledged=list(found.acknowledgements()),
            load_cell=LoadCell(
                commanded_load_logged=bool(known.any()),
                three_percent=0.03 / 1.03 * chart.mean / (self.setup.params.friction.hip_radius * 1e3),
                gain_change_last=float(gain[known][-1]) if known.any() else None,
                drifted=[c["file"][k] for k in range(len(gain)) if known[k] and abs(gain[k]) > 0.01],
            ),
            skipped=[SkippedFile.of(s) for s in self.skipped if s.kind != "waiting"],
            waiting=[SkippedFile.of(s) for s in self.skipped if s.kind == "waiting"],
            missing=self.missing,
            incomplete=[c["file"][k] for k in range(len(c["cycle"])) if "incomplete" in c["note"][k]],
            files=[SnapshotFile(c["file"][k], int(c["bytes"][k]), c["sha256"][k]) for k in range(len(c["cycle"]))],
            note=chart.note,
            fingerprint=self.fingerprints["setup"],
            parameters=self.setup.params.source,
            table=self.columns,
        )


def _columns(rows: list[dict[str, Any]], found: Findings) -> dict[str, list[Any]]:
    """The table's columns from the estimate rows (sorted by cycle) and the findings over them."""
    mean = found.mean
    nan = np.full(len(rows), math.nan)
    derived: dict[str, Any] = {
        "phase": mean.phase,
        "hip_mu_change": mean.change,
        "hip_mu_change_std": mean.change_std,
        "ewma_mm": mean.ewma,
        "lcl_mm": mean.lower,
        "ucl_mm": mean.upper,
        "load_gain_change": found.load_gain_change,
        "flag": found.flag,
        "alarm": found.alarm,
        "state": found.state,
        "acknowledged": found.acknowledged,
        "note": found.notes,
    }
    for p in (1, 2):
        s = found.stations[p - 1] if found.stations is not None else None
        derived |= {
            f"hip_mu_change_{p}": s.change if s is not None else nan,
            f"hip_mu_change_{p}_std": s.change_std if s is not None else nan,
            f"ewma_{p}_mm": s.ewma if s is not None else nan,
            f"lcl_{p}_mm": s.lower if s is not None else nan,
            f"ucl_{p}_mm": s.upper if s is not None else nan,
        }
    out: dict[str, list[Any]] = {name: [] for name in COLUMNS}
    integers = ("cycle", "last_cycle", "samples", "alarm", "bytes")
    for k, row in enumerate(rows):
        for name in COLUMNS:
            value = derived[name][k] if name in derived else row[name]
            out[name].append(value if isinstance(value, str) else (int(value) if name in integers else float(value)))
    return out


def run_monitor(
    setup: MonitorSetup,
    snapshots: Sequence[Snapshot],
    baseline: tuple[int, int] = DEFAULT_BASELINE,
    alarm_rise: float = DEFAULT_ALARM_RISE,
    out: str | Path | None = None,
    restart: bool = False,
    workers: int = 1,
    scheduler: str | None = None,
    batch_size: int | None = None,
    progress: Callable[[int, int], None] | None = None,
    metadata: dict[str, Any] | None = None,
    skipped: Sequence[Skipped] = (),
    previous: Sequence[dict[str, Any]] | None = None,
    baseline_min: int = MIN_BASELINE,
    acknowledge: Sequence[int] = (),
) -> MonitorResult:
    """Estimate the snapshots ``out`` (or ``previous``) does not hold yet, chart over all, write ``out`` (when given).

    Args:
        setup: what the snapshots share.
        snapshots: the snapshots (:func:`~hipsim.rig.monitoring.snapshots.find_snapshots`).
        baseline: (FROM, TO) cycles.
        alarm_rise: the engineering threshold, a change of μ_h in one station.
        out: the table to extend and write, or None.
        restart: replace ``out`` instead of extending it.
        workers: local worker processes (1: in this process).
        scheduler: a dask scheduler's address.
        batch_size: snapshots per task (default: about eight tasks a worker, at most :data:`MOST_PER_BATCH`).
        progress: called with (snapshots done, to do) after each batch.
        metadata: more to keep with the table.
        skipped: snapshots already left out (still being written, unreadable), carried into the result.
        previous: estimate rows already made (a watch keeps them in memory), used instead of ``out``'s.
        baseline_min: snapshots the baseline needs before the chart starts.
        acknowledge: cycles of alarms acknowledged (each covers the alarms raised at or before it), added to those
            ``out`` records (a watch passes the last round's, :meth:`Findings.acknowledgements`).

    Raises:
        OutputError: ``out`` cannot be written or holds another set-up's rows.
        TrajectoryError: no usable snapshot at all (naming the first left out and why).
        ArgumentError: a new acknowledgement that covers no alarm, or lies past the last snapshot (nothing written).
    """
    if isinstance(workers, bool) or not isinstance(workers, (int, np.integer)) or workers < 1:
        raise ArgumentError("workers", workers, "a whole number of worker processes, at least 1")
    out = MONITOR_TABLE.check_out(out) if out is not None else None
    check_baseline_min(baseline_min)
    fingerprints = setup.fingerprints()
    recorded: list[int] = []
    if previous is None:
        resumed = MONITOR_TABLE.resume(out, COLUMNS, fingerprints, restart, PARTS) if out else {}
        previous = table_rows(resumed) if out else []
        recorded = [int(a) for a in resumed.get("acknowledged", []) if a == a]
    present = {(s.name, s.sha256) for s in snapshots}
    names = {s.name for s in snapshots}
    # A row whose file is there with other bytes is estimated again; rows of files no longer given are kept.
    kept = [r for r in previous if (r["file"], r["sha256"]) in present or r["file"] not in names]
    done = {(r["file"], r["sha256"]) for r in kept}
    todo = [s for s in snapshots if (s.name, s.sha256) not in done]
    rows = list(kept)
    left = list(skipped)
    size = batch_size or _batch_size(len(todo), int(workers), MOST_PER_BATCH)
    work = [list(todo[k : k + size]) for k in range(0, len(todo), size)]
    count = 0
    for results in run_batches(estimate_batch, work, setup, int(workers), scheduler, "hipsim monitor"):
        for value in results:
            (left if isinstance(value, Skipped) else rows).append(value)
        count += len(results)
        if progress is not None:
            progress(count, len(todo))
    rows.sort(key=lambda row: (int(row["cycle"]), row["file"]))
    paths = {s.name: s.path for s in snapshots}
    rows, twice = duplicates(rows, paths)
    left += twice
    if not rows:
        first = next((s for s in left if s.kind != "waiting"), left[0] if left else None)
        raise TrajectoryError(
            "no usable snapshot"
            + (f" ({len(left)} left out; the first: {first.reason})" if first is not None else ": none given"),
            source=None if first is None else first.path,
        )
    f = setup.params.friction
    two = setup.params.heights.size == 2
    found = find(rows, f.hip_radius * 1e3, two, baseline, alarm_rise, baseline_min)
    new = [a for a in acknowledge if a not in recorded]
    if new:
        cycles = [int(r["cycle"]) for r in rows]
        check_acknowledged(new, cycles, found.alarm, cycles[-1])
    if new or recorded:
        found = find(rows, f.hip_radius * 1e3, two, baseline, alarm_rise, baseline_min, [*recorded, *new])
    columns = _columns(rows, found)
    if out is not None:
        write_table(out, columns, (metadata or {}) | {"fingerprints": fingerprints, "parameters": setup.params.source})
    missing = missing_cycles([r["cycle"] for r in rows])
    return MonitorResult(
        setup, rows, columns, found, len(todo), len(kept), left, missing, baseline, alarm_rise, fingerprints, paths
    )


def monitor(
    params: Parameters | str | Path,
    logs,
    baseline: tuple[int, int] | str = DEFAULT_BASELINE,
    alarm_rise: float = DEFAULT_ALARM_RISE,
    window: int | None = None,
    cutoff: float | None = 20.0,
    torque_constant: float | None = None,
    out: str | Path | None = None,
    restart: bool = False,
    workers: int = 1,
    scheduler: str | None = None,
    rate: float | None = None,
    settle: float = 0.0,
    baseline_min: int = MIN_BASELINE,
    acknowledge: Sequence[int] = (),
    columns: str | None = None,
):
    """Follow a wear test's friction from its snapshots' motor torques (the library's ``hipsim monitor``).

    Args:
        params: an identified parameter file (checked), or a :class:`~hipsim.machine.parameters.Parameters` you
            vouch for (lever spin on).
        logs: snapshot files (CSV, TDMS, HDF5), a folder (its ``*.csv``, ``*.tdms``, ``*.h5``, ``*.hdf5``) or a glob
            pattern, or a list of them; each with a ``cycle`` column.
        baseline: (FROM, TO) cycles, or ``"FROM:TO"``: the reference period after running-in.
        alarm_rise: the engineering threshold, a change of the hip friction coefficient in one station.
        window: cut each file into windows of this many cycles (one long log); None: a snapshot a file.
        cutoff: low-pass cutoff in [Hz] (None: none).
        torque_constant: motor torque constant in [N·m/A], for logs of currents.
        out: a .csv/.parquet table to extend (resumed: only new snapshots are estimated), or None.
        restart: replace ``out`` instead of extending it.
        workers: local worker processes (dask.distributed) for more than 1.
        scheduler: a dask scheduler's address.
        rate: sample rate in [Hz] to read the times from the sample index (time stamps too coarse), or None.
        settle: a file changed less than this many seconds ago is still being written: waited for (at most this long
            in all), then read.
        baseline_min: snapshots the baseline needs before the chart starts (default 5).
        acknowledge: cycles of alarms acknowledged (recorded in ``out``): an alarm is held until one covers it.
        columns: a TDMS or HDF5 snapshot's column map (``NAME=GROUP/CHANNEL,…``, :mod:`hipsim.channels`), or None.

    Returns:
        The table (columns :data:`~hipsim.rig.monitoring.monitor_table.COLUMNS`): a pandas DataFrame when pandas is
        installed, else a :class:`MonitorTable`.
    """
    from .control_chart import parse_baseline

    if isinstance(baseline, str):
        baseline = parse_baseline(baseline)
    machine, spin = reference(None, params) if isinstance(params, Parameters) else reference(params)
    setup = MonitorSetup(
        machine,
        lever_spin=spin,
        cutoff=cutoff,
        torque_constant=torque_constant,
        window=window,
        rate=rate,
        columns=columns,
    )
    snapshots, skipped = find_snapshots(logs, window, settle, torque_constant, rate, wait=True, columns=columns)
    result = run_monitor(
        setup,
        snapshots,
        (baseline[0], baseline[1]),
        alarm_rise,
        out,
        restart,
        workers,
        scheduler,
        skipped=skipped,
        baseline_min=baseline_min,
        acknowledge=acknowledge,
    )
    try:
        import pandas
    except ImportError:
        return MonitorTable(result.columns)
    return pandas.DataFrame(result.columns)
