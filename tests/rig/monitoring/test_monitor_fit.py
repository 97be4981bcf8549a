"""The monitor's estimate and chart against a wear test made by the analytic model with a known hip friction curve."""

from __future__ import annotations

import numpy as np
import pytest
from monitor_synthetic import write_snapshot, write_test

import hipsim
from hipsim.rig.monitoring.monitor_fit import MonitorSetup, estimate
from hipsim.rig.monitoring.monitor_run import monitor
from hipsim.rig.monitoring.snapshots import find_snapshots

STEP_AT = 2_100_000  # between the snapshots at 2,000,000 and 2,250,000
BASELINE = (500_000, 1_000_000)
#: Snapshots every 250,000 cycles put three in the baseline: the chart's minimum set to them (the default needs five).
BASELINE_MIN = 3


@pytest.fixture(scope="module")
def params():
    return hipsim.load_parameters()


def _load_term(params, mu):
    f = params.friction
    return (f.hip_radius * mu + f.thrust_radius * f.thrust_mu) * 1e3


def _run(tmp_path_factory, params, step):
    folder = tmp_path_factory.mktemp(f"test_step_{step}")
    truth = write_test(folder, params, step_at=STEP_AT, step=step)
    return truth, monitor(params, folder, baseline=BASELINE, alarm_rise=0.01, baseline_min=BASELINE_MIN)


@pytest.fixture(scope="module")
def stepped(tmp_path_factory, params):
    return _run(tmp_path_factory, params, 0.035)


def test_every_estimate_within_2_percent_and_the_change_within_0_002(stepped, params):
    truth, table = stepped
    cycles = list(table["cycle"])
    true_a = np.array([_load_term(params, truth[c]) for c in cycles])
    estimate_a = np.asarray(table["load_friction_mm"])
    assert np.all(np.abs(estimate_a / true_a - 1) < 0.02)
    baseline_mu = np.mean([truth[c] for c in cycles if BASELINE[0] <= c <= BASELINE[1]])
    true_change = np.array([truth[c] - baseline_mu for c in cycles])
    assert np.all(np.abs(np.asarray(table["hip_mu_change"]) - true_change) < 0.002)
    # The standard deviations are honest: errors within a few of them.
    assert np.all(np.abs(estimate_a - true_a) < 5 * np.asarray(table["load_friction_mm_std"]) + 0.01 * true_a)


def test_alarm_at_the_first_snapshot_after_the_step_and_none_before(stepped):
    _, table = stepped
    cycles, alarm, phase = list(table["cycle"]), list(table["alarm"]), list(table["phase"])
    assert all(a == 0 for c, a in zip(cycles, alarm) if c < STEP_AT)
    first = min(c for c in cycles if c >= STEP_AT)
    assert alarm[cycles.index(first)] == 1
    assert all(a == 1 for c, a in zip(cycles, alarm) if c >= STEP_AT)
    # Running-in is shown, never flagged, though its friction is well above the baseline.
    assert phase[0] == "running-in" and alarm[0] == 0 and table["hip_mu_change"][0] > 0.01


def test_a_step_below_the_threshold_is_a_notice_not_an_alarm(tmp_path_factory, params):
    # The mean up by 0.005 (+ the slow rise): up to twice that in one station, still below a threshold of 0.02.
    folder = tmp_path_factory.mktemp("small_step")
    write_test(folder, params, step_at=STEP_AT, step=0.005)
    table = monitor(params, folder, baseline=BASELINE, alarm_rise=0.02, baseline_min=BASELINE_MIN)
    assert not any(table["alarm"])
    assert table["hip_mu_change"].iloc[-1] > 0.005  # the step is seen, it is just below what matters
    assert table["flag"].iloc[-1].startswith("notice: the two stations' mean rises")


def test_no_chart_without_a_complete_baseline(tmp_path, params):
    truth = write_test(tmp_path, params, last=250_000)
    table = monitor(params, tmp_path)
    assert len(table) == len(truth) and not any(table["alarm"]) and np.all(np.isnan(table["hip_mu_change"]))


def test_per_station_estimates_when_the_loads_differ(tmp_path, params):
    rng = np.random.default_rng(3)
    write_snapshot(tmp_path / "s.csv", params, 0.1, 0, rng, station_loads=(0.9, 1.1), station_mu=(0.09, 0.13))
    row = estimate(MonitorSetup(params), find_snapshots(tmp_path)[0][0])
    assert row["stations"] == "separated"
    for p, mu in ((1, 0.09), (2, 0.13)):
        assert abs(row[f"load_friction_{p}_mm"] - _load_term(params, mu)) < 3 * row[f"load_friction_{p}_mm_std"]
        assert row[f"load_friction_{p}_mm"] == pytest.approx(_load_term(params, mu), rel=0.05)


def test_per_station_refused_when_the_loads_vary_alike(tmp_path, params):
    rng = np.random.default_rng(4)
    write_snapshot(tmp_path / "s.csv", params, 0.1, 0, rng)
    path = tmp_path / "s.csv"
    lines = path.read_text().splitlines()
    header = lines[0].split(",")
    k = header.index("Fe_N")
    out = [lines[0] + ",Fe_1_N,Fe_2_N"] + [
        line + f",{float(line.split(',')[k]) / 2:.10g},{float(line.split(',')[k]) / 2:.10g}" for line in lines[1:]
    ]
    path.write_text("\n".join(out) + "\n")
    row = estimate(MonitorSetup(params), find_snapshots(tmp_path)[0][0])
    assert row["stations"].startswith("not separable") and np.isnan(row["load_friction_1_mm"])
    assert row["load_friction_mm"] == pytest.approx(_load_term(params, 0.1), rel=0.02)
