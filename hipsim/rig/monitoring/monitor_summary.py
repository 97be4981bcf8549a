"""What a monitor's run reports (:meth:`hipsim.rig.monitoring.monitor_run.MonitorResult.summary`): the counts, the
baseline, the alarms and notices and the state at the last snapshot, the load cell, the snapshots skipped, missing
and read, and the table."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from ...records import Record

__all__ = ["Baseline", "LoadCell", "MonitorSummary", "SnapshotFile", "StationBaseline"]


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
class MonitorSummary(Record):
    """A monitor's run (docs/guide/monitor.md lists the keys); the findings' descriptions and the skipped snapshots
    are the JSON-ready mappings :mod:`hipsim.rig.monitoring.findings` and :mod:`~hipsim.rig.monitoring.snapshots` make.
    """

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
    first_alarm: dict[str, Any] | None
    notices: int
    latest_notice: dict[str, Any] | None
    alarm_active: bool
    notice_active: bool
    state: str
    alarm_raised_at: int | None
    alarm_at_last_snapshot: bool
    acknowledged: list[int]
    load_cell: LoadCell
    skipped: list[dict[str, Any]]
    waiting: list[dict[str, Any]]
    missing: list[int]
    incomplete: list[str]
    files: list[SnapshotFile]
    note: str
    fingerprint: str
    parameters: str
    table: dict[str, list[Any]]
