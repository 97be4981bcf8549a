"""A monitor's run summary as a record (hipsim/rig/monitoring/monitor_summary.py): built by hand, its JSON (the
baseline's ``from``, stations per baseline) and its schema."""

from __future__ import annotations

import jsonschema

from hipsim.records import Level, Verdict
from hipsim.rig.monitoring.monitor_summary import (
    Baseline,
    LoadCell,
    MonitorSummary,
    SkippedFile,
    SnapshotFile,
    StationBaseline,
)
from hipsim.rig.monitoring.snapshots import Skipped


def test_the_json_of_a_monitor_run():
    baseline = Baseline(0, 500_000, 3, 1.25, 0.05, [StationBaseline(1, 1.2, 0.04, 3), StationBaseline(2, 1.3, 0.06, 3)])
    verdict = Verdict(Level.NOTICE, "at the last snapshot (cycle 750,000) a notice: x", "earlier snapshots")
    summary = MonitorSummary(
        verdict=verdict, snapshots=4, new=1, kept=3, first_cycle=0, last_cycle=750_000, baseline=baseline, alarm_rise=0.1,
        threshold_mm=[0.2], worst_case_factor=1.5, chart="ewma", judged="the last snapshot", alarms=0,
        first_alarm=None, notices=1, latest_notice=None, alarm_active=False, notice_active=True,
        state="NOTICE", alarm_raised_at=None, alarm_at_last_snapshot=False, acknowledged=[],
        load_cell=LoadCell(True, 0.03, 0.001, []), skipped=[], waiting=[], missing=[250_000], incomplete=[],
        files=[SnapshotFile("s1.csv", 120, "ab" * 32)], note="", fingerprint="f", parameters="published",
        table={"cycle": [0, 250_000]},
    )  # fmt: skip
    doc = summary.to_json()
    assert list(doc)[0] == "verdict" and doc["verdict"] == {
        "level": "NOTICE",
        "judged": "at the last snapshot (cycle 750,000) a notice: x",
        "not_judged": "earlier snapshots",
        "numbers": {},
    }
    assert doc["baseline"]["from"] == 0 and "from_" not in doc["baseline"] and doc["baseline"]["to"] == 500_000
    assert doc["baseline"]["stations"][1] == {"station": 2, "load_friction_mm": 1.3, "spread_mm": 0.06, "snapshots": 3}
    assert doc["load_cell"] == {
        "commanded_load_logged": True,
        "three_percent": 0.03,
        "gain_change_last": 0.001,
        "drifted": [],
    }
    assert doc["files"] == [{"file": "s1.csv", "bytes": 120, "sha256": "ab" * 32}]
    jsonschema.validate(doc, MonitorSummary.json_schema())
    one = Baseline(0, 10, 2, 1.0, 0.1, None).to_json()
    assert one["stations"] is None and list(one)[0] == "from"


def test_a_skipped_snapshots_record_field_by_field():
    """Each field of the snapshot left out goes to its own key; an empty SHA-256 (the file not read) is null."""
    read = SkippedFile.of(Skipped("b.csv", "/logs/b.csv", "line 4: bad value", "duplicate", 4, 120, "cd"))
    assert read == SkippedFile("b.csv", "/logs/b.csv", "duplicate", "line 4: bad value", 4, 120, "cd")
    unread = SkippedFile.of(Skipped("c.csv", "/logs/c.csv", "cannot read", "unreadable", None, None, ""))
    assert unread.to_json() == {
        "file": "c.csv",
        "path": "/logs/c.csv",
        "kind": "unreadable",
        "reason": "cannot read",
        "line": None,
        "bytes": None,
        "sha256": None,
    }
