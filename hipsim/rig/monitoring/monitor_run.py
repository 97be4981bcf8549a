"""Following a wear test: every snapshot's estimate (in this process or on dask.distributed), the chart over them, the table.

:func:`run_monitor` checks every input first (the parameter file, the
snapshots, the table's set-up), then estimates the snapshots the table does
not have yet, in batches: in this process for one worker, else on a
``LocalCluster`` of worker processes or the cluster of a scheduler's address,
the same :func:`~hipsim.rig.monitoring.monitor_fit.estimate_batch` on either path, so the
rows are the same to the last bit. Each worker holds one snapshot at a time
and the main process only the rows: memory does not grow with the test.
The chart (:func:`~hipsim.rig.monitoring.control_chart.chart`) is then drawn over all
rows, old and new, and the table written whole, atomically.

:func:`monitor` is the library's entry (``hipsim.monitor``): the table as a
pandas DataFrame when pandas is installed, else a :class:`MonitorTable`.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ...analysis.cluster import map_batches
from ...exceptions import ArgumentError, HipsimError
from ...machine.parameters import Parameters
from .control_chart import DEFAULT_ALARM_RISE, DEFAULT_BASELINE, Chart, chart
from .monitor_fit import MonitorSetup, estimate_batch, reference
from .monitor_table import COLUMNS, check_out, previous_rows, write_table
from .snapshots import Snapshot, find_snapshots

__all__ = ["MonitorResult", "MonitorTable", "monitor", "run_monitor", "run_snapshots"]


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
        columns: the table by column (:data:`COLUMNS`), sorted by cycle.
        chart: the control chart over the rows.
        new: snapshots estimated in this run.
        kept: rows kept from the table already there.
        baseline: (FROM, TO) cycles.
        alarm_rise: the engineering threshold.
        fingerprints: the set-up's fingerprints.
        paths: each row's file path (the rows estimated in this run; kept rows by name only).
    """

    setup: MonitorSetup
    columns: dict[str, list[Any]]
    chart: Chart
    new: int
    kept: int
    baseline: tuple[int, int]
    alarm_rise: float
    fingerprints: dict[str, str]
    paths: dict[str, str] = field(default_factory=dict)

    def summary(self) -> dict[str, Any]:
        """The run's summary, JSON-ready: counts, baseline, first alarm, the alarm at the last snapshot."""
        c, chart = self.columns, self.chart
        alarms = [k for k, a in enumerate(c["alarm"]) if a]
        first = None
        if alarms:
            k = alarms[0]
            first = {
                "cycle": int(c["cycle"][k]),
                "file": c["file"][k],
                "hip_mu_change": c["hip_mu_change"][k],
                "hip_mu_change_std": c["hip_mu_change_std"][k],
                "load_friction_mm": c["load_friction_mm"][k],
                "load_friction_change_mm": c["load_friction_mm"][k] - chart.mean,
            }
        last = len(c["cycle"]) - 1
        return {
            "snapshots": len(c["cycle"]),
            "new": self.new,
            "kept": self.kept,
            "first_cycle": int(c["cycle"][0]) if c["cycle"] else None,
            "last_cycle": int(c["last_cycle"][-1]) if c["cycle"] else None,
            "baseline": {
                "from": self.baseline[0],
                "to": self.baseline[1],
                "snapshots": chart.baseline_count,
                "load_friction_mm": chart.mean,
                "spread_mm": chart.spread,
            },
            "alarm_rise": self.alarm_rise,
            "threshold_mm": chart.threshold,
            "chart": "EWMA (lambda 0.2, L 3) with the engineering threshold",
            "alarms": len(alarms),
            "first_alarm": first,
            "alarm_active": bool(last >= 0 and c["alarm"][last]),
            "note": chart.note,
            "fingerprint": self.fingerprints["setup"],
            "parameters": self.setup.params.source,
        }


def _batch_size(count: int, workers: int) -> int:
    """About eight batches a worker, each of 1 to 50 snapshots."""
    return max(1, min(50, math.ceil(count / (8 * max(workers, 1)))))


def run_snapshots(
    setup: MonitorSetup,
    snapshots: Sequence[Snapshot],
    workers: int = 1,
    scheduler: str | None = None,
    batch_size: int | None = None,
) -> Iterator[list[tuple[str, Any]]]:
    """Estimate snapshots in batches, yielding each batch's results as it completes (("row", row) or ("error", message)).

    Args:
        setup: what the snapshots share (sent to each worker once).
        snapshots: the snapshots.
        workers: worker processes of a local cluster; 1 without ``scheduler`` runs in this process.
        scheduler: a dask scheduler's address, to run on its cluster (the files must be readable there).
        batch_size: snapshots per task (default: about eight tasks a worker, at most 50 each).
    """
    if isinstance(workers, bool) or not isinstance(workers, (int, np.integer)) or workers < 1:
        raise ArgumentError("workers", workers, "a whole number of worker processes, at least 1")
    size = batch_size or _batch_size(len(snapshots), int(workers))
    work = [list(snapshots[k : k + size]) for k in range(0, len(snapshots), size)]
    if not work:
        return
    if scheduler is None and workers == 1:
        for batch in work:
            yield estimate_batch(batch, setup)
        return
    yield from map_batches(estimate_batch, work, setup, int(workers), scheduler, "hipsim monitor")


def _columns(rows: list[dict[str, Any]], chart_: Chart) -> dict[str, list[Any]]:
    """The table's columns from the estimate rows (sorted by cycle) and the chart over them."""
    out: dict[str, list[Any]] = {name: [] for name in COLUMNS}
    derived = {
        "phase": chart_.phase,
        "hip_mu_change": chart_.change,
        "hip_mu_change_std": chart_.change_std,
        "ewma_mm": chart_.ewma,
        "ucl_mm": chart_.limit,
        "alarm": chart_.alarm,
    }
    for k, row in enumerate(rows):
        for name in COLUMNS:
            value = derived[name][k] if name in derived else row[name]
            out[name].append(
                value
                if isinstance(value, str)
                else (int(value) if name in ("cycle", "last_cycle", "samples", "alarm") else float(value))
            )
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
) -> MonitorResult:
    """Estimate the snapshots ``out`` does not hold yet, draw the chart over all, write ``out`` (when given).

    Raises:
        OutputError: ``out`` cannot be written or holds another set-up's rows.
        HipsimError: a snapshot that cannot be read (naming it); nothing is written then.
    """
    out = check_out(out) if out is not None else None
    fingerprints = setup.fingerprints()
    kept = previous_rows(out, fingerprints, restart)
    done = {(row["file"], int(row["cycle"])) for row in kept}
    todo = [s for s in snapshots if (s.name, s.first_cycle) not in done]
    rows = list(kept)
    count = 0
    for results in run_snapshots(setup, todo, workers, scheduler, batch_size):
        for kind, value in results:
            if kind == "error":
                raise HipsimError(value)
            rows.append(value)
        count += len(results)
        if progress is not None:
            progress(count, len(todo))
    rows.sort(key=lambda row: (int(row["cycle"]), row["file"]))
    if not rows:
        raise HipsimError("no snapshots to monitor")
    f = setup.params.friction
    chart_ = chart(
        [r["cycle"] for r in rows],
        [r["load_friction_mm"] for r in rows],
        [r["load_friction_mm_std"] for r in rows],
        f.hip_radius * 1e3,
        baseline,
        alarm_rise,
    )
    columns = _columns(rows, chart_)
    if out is not None:
        write_table(out, columns, (metadata or {}) | {"fingerprints": fingerprints, "parameters": setup.params.source})
    paths = {s.name: s.path for s in snapshots}
    return MonitorResult(setup, columns, chart_, len(todo), len(kept), baseline, alarm_rise, fingerprints, paths)


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
):
    """Follow a wear test's friction from its snapshots' motor torques (the library's ``hipsim monitor``).

    Args:
        params: an identified parameter file (checked: :func:`hipsim.rig.monitoring.monitor_fit.identified_file`), or a
            :class:`~hipsim.machine.parameters.Parameters` you vouch for (lever spin on).
        logs: snapshot files, a folder (its ``*.csv``) or a glob pattern, or a list of them; each with a ``cycle`` column.
        baseline: (FROM, TO) cycles, or ``"FROM:TO"``: the reference period after running-in.
        alarm_rise: the engineering threshold, a rise of the hip friction coefficient.
        window: cut each file into windows of this many cycles (one long log); None: a snapshot a file.
        cutoff: low-pass cutoff in [Hz] (None: none).
        torque_constant: motor torque constant in [N·m/A], for logs of currents.
        out: a .csv/.parquet table to extend (resumed: only new snapshots are estimated), or None.
        restart: replace ``out`` instead of extending it.
        workers: local worker processes (dask.distributed) for more than 1.
        scheduler: a dask scheduler's address.

    Returns:
        The table (columns :data:`~hipsim.rig.monitoring.monitor_table.COLUMNS`): a pandas DataFrame when pandas is installed,
        else a :class:`MonitorTable`.
    """
    from .control_chart import parse_baseline

    if isinstance(baseline, str):
        baseline = parse_baseline(baseline)
    if isinstance(params, Parameters):
        machine, spin = reference(None, params)
    else:
        machine, spin = reference(params)
    setup = MonitorSetup(machine, lever_spin=spin, cutoff=cutoff, torque_constant=torque_constant, window=window)
    snapshots = find_snapshots(logs, window, cutoff)
    result = run_monitor(setup, snapshots, tuple(baseline), alarm_rise, out, restart, workers, scheduler)
    try:
        import pandas
    except ImportError:
        return MonitorTable(result.columns)
    return pandas.DataFrame(result.columns)
