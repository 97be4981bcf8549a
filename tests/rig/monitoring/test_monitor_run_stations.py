"""The worst station: one station's friction rising under a shared load alarms on the mean's worst case; with
per-station loads logged, the station is charted on its own and named."""

from __future__ import annotations

import json
from functools import partial

import jsonschema
import pytest
from monitor_synthetic import write_identified, write_test

import hipsim
from hipsim.cli.documents import schema
from hipsim.cli.main import main
from hipsim.rig.monitoring import monitor_run
from hipsim.rig.monitoring.monitor_fit import MonitorSetup
from hipsim.rig.monitoring.snapshots import find_snapshots

run_monitor = partial(
    monitor_run.run_monitor, baseline_min=3
)  # three baseline snapshots (every 250,000 cycles in 500,000-1,000,000): the chart's minimum set to them

STEP_AT = 1_600_000  # between the snapshots at 1.5 and 1.75 Mc
RISE = 0.015  # station 2 alone: +0.0075 in the two stations' mean, past the 0.01 threshold in the station
BASELINE = (500_000, 1_000_000)


@pytest.fixture(scope="module")
def params():
    return hipsim.load_parameters()


def _station_2_rises(cycle, mu):
    return {"station_mu": (mu, mu + (RISE if cycle >= STEP_AT else 0.0))}


def test_one_station_rising_under_a_shared_load_alarms_at_that_snapshot_and_not_before(tmp_path, params):
    write_test(tmp_path, params, last=2_000_000, vary=_station_2_rises)
    result = run_monitor(MonitorSetup(params), find_snapshots(tmp_path)[0], BASELINE, 0.01)
    c, summary = result.columns, result.summary()
    cycles = c["cycle"]
    assert [a for cycle, a in zip(cycles, c["alarm"]) if cycle < STEP_AT] == [0] * 7
    assert c["alarm"][cycles.index(1_750_000)] == 1 and c["alarm"][-1] == 1
    # The mean moved by half the station's rise; the alarm holds twice that, and says so.
    assert summary.first_alarm is not None
    first = summary.first_alarm
    assert first.cycle == 1_750_000 and first.hip_mu_change == pytest.approx(RISE / 2 + 0.0005, abs=0.002)
    assert first.worst_case_change == pytest.approx(2 * first.hip_mu_change)
    assert "in the two stations' mean: up to +0.01" in first.text and "reference load" in first.text
    assert c["flag"][-1] == "alarm: the two stations' mean rises (up to twice in one station)"
    assert c["stations"][0] == "not logged" and summary.judged.startswith("the two stations' mean, worst case")


def test_per_station_loads_chart_each_station_and_name_the_one_that_rises(tmp_path, params, capsys):
    logs, report = tmp_path / "logs", tmp_path / "report"
    write_test(logs, params, last=2_000_000, station_loads=(0.9, 1.1), wobble=(0.8, 2.3), vary=_station_2_rises)
    status = main(
        [
            "monitor",
            "--baseline-min",
            "3",
            "--settle",
            "0",
            "--params",
            str(write_identified(tmp_path / "identified.toml")),
            "--log",
            str(logs),
            "--report",
            str(report),
            "--summary-format",
            "json",
            "--baseline",
            "500000:1000000",
        ]
    )
    summary = json.loads(capsys.readouterr().out)
    assert status == 1 and summary["judged"] == "per station"
    jsonschema.validate(summary, schema("monitor"))  # the published contract (hipsim schema monitor)
    assert summary["report"].endswith("index.html") and summary["pdf"] is None
    first = summary["first_alarm"]
    assert first["where"] == "station 2" and first["cycle"] == 1_750_000
    assert first["hip_mu_change"] == pytest.approx(RISE + 0.002, abs=0.004)  # the station's own step and drift
    assert [s["station"] for s in summary["baseline"]["stations"]] == [1, 2]
    page = (report / "index.html").read_text(encoding="utf-8")
    assert "alarm: station 2 rises" in page and "hip_mu_change_2" in page and "station 1 falls" not in page
    assert "ewma_1_mm" in json.dumps(summary) or "ewma_1_mm" in page
