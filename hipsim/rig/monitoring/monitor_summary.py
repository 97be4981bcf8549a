"""What a monitor's run reports (:meth:`hipsim.rig.monitoring.monitor_run.MonitorResult.summary`): the counts, the
baseline, the alarms and notices and the state at the last snapshot, the load cell, the snapshots skipped, missing
and read, and the table."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from ...records import Record, Verdict
from .findings import Finding
from .snapshots import Skipped

__all__ = ["Baseline", "LoadCell", "MonitorSummary", "SkippedFile", "SnapshotFile", "StationBaseline"]


@dataclass(frozen=True)
class StationBaseline(Record):
    """One station's baseline: its load friction term μ₀ and spread σ₀ in [mm], over so many snapshots."""

    station: int
    load_friction_mm: float
    spread_mm: float
    snapshots: int


@dataclass(frozen=True)
class Baseline(Record):
    """The baseline: its cycles FROM and TO, its snapshots, μ₀ and σ₀ in [mm], per station when the logs separate them."""

    from_: int = field(metadata={"key": "from"})
    to: int
    snapshots: int
    load_friction_mm: float
    spread_mm: float
    stations: list[StationBaseline] | None


@dataclass(frozen=True)
class LoadCell(Record):
    """What the commanded load logged beside the measured one says of the load cell.

    Attributes:
        commanded_load_logged: the logs carry the commanded load.
        three_percent: the change of μ_h a 3 % load-cell gain drift alone would read as.
        gain_change_last: the last snapshot's gain change against the baseline (None without the commanded load).
        drifted: the snapshots whose gain drifted by more than 1 %.
    """

    commanded_load_logged: bool
    three_percent: float
    gain_change_last: float | None
    drifted: list[str]


@dataclass(frozen=True)
class SnapshotFile(Record):
    """A snapshot read: its file name, size in bytes and SHA-256."""

    file: str
    bytes: int
    sha256: str


@dataclass(frozen=True)
class SkippedFile(Record):
    """A snapshot left out of the chart: its name, path, why ("unreadable", "waiting", "duplicate") in words, the line
    the reason names, and the bytes and SHA-256 looked at (null when it could not be read)."""

    file: str
    path: str
    kind: str
    reason: str
    line: int | None
    bytes: int | None
    sha256: str | None

    @classmethod
    def of(cls, skipped: Skipped) -> SkippedFile:
        """The record of a :class:`~hipsim.rig.monitoring.snapshots.Skipped`."""
        return cls(
            skipped.name, skipped.path, skipped.kind, skipped.reason, skipped.line, skipped.size, skipped.sha256 or None
        )


@dataclass(frozen=True)
class MonitorSummary(Record):
    """A monitor's run (docs/guide/monitor.md lists the keys); ``verdict`` the state's verdict
    (:meth:`~hipsim.rig.monitoring.monitor_run.MonitorResult.verdict`: ALARM, NOTICE, OK, NOT MADE); ``table`` is the
    run's table, its columns by name (the rows as written to CSV/Parquet: their columns depend on what the logs carry)."""

    verdict: Verdict
    snapshots: int
    new: int
    kept: int
    first_cycle: int | None
    last_cycle: int | None
    baseline: Baseline
    alarm_rise: float
    threshold_mm: list[float]
    worst_case_factor: float
    chart: str
    judged: str
    alarms: int
    first_alarm: Finding | None
    notices: int
    latest_notice: Finding | None
    alarm_active: bool
    notice_active: bool
    state: str
    alarm_raised_at: int | None
    alarm_at_last_snapshot: bool
    acknowledged: list[int]
    load_cell: LoadCell
    skipped: list[SkippedFile]
    waiting: list[SkippedFile]
    missing: list[int]
    incomplete: list[str]
    files: list[SnapshotFile]
    note: str
    fingerprint: str
    parameters: str
    table: dict[str, list[Any]]
