"""Two-sided: a load-cell gain drift reads as a change of the load term either way; a fall is flagged as a rise is,
the flag's sentence names the load-cell alternative, and the commanded load, when logged, shows the drift.

A load cell reading (1 + g) times the true load gives a/(1 + g) for the load term a = r_h·μ_h + r_t·μ_t: a gain
drift g reads as Δμ_h = −g/(1 + g)·a/r_h, ∓0.0060 for ±3 % at μ_h = 0.1 on the published machine.
"""

from __future__ import annotations

import shutil
from functools import partial

import numpy as np
import pytest
from monitor_synthetic import write_snapshot
from support import given

import hipsim
from hipsim.rig.monitoring import monitor_run
from hipsim.rig.monitoring.monitor_fit import MonitorSetup
from hipsim.rig.monitoring.snapshots import find_snapshots

run_monitor = partial(
    monitor_run.run_monitor, baseline_min=3
)  # three baseline snapshots (every 250,000 cycles in 500,000-1,000,000): the chart's minimum set to them

DRIFT_AT = 1_600_000
BASELINE = (500_000, 1_000_000)
LATER = (1_750_000, 2_000_000)


@pytest.fixture(scope="module")
def params():
    return hipsim.load_parameters()


@pytest.fixture(scope="module")
def before(tmp_path_factory, params):
    """The test up to the drift: a steady specimen (μ_h = 0.1, no running-in), the commanded load logged."""
    folder = tmp_path_factory.mktemp("before")
    rng = np.random.default_rng(5)
    for cycle in range(0, 1_500_001, 250_000):
        write_snapshot(folder / f"snap_{cycle:08d}.csv", params, 0.1, cycle, rng, commanded=True)
    return folder


def _drifted(tmp_path, params, before, gain):
    shutil.copytree(before, tmp_path / "logs")
    rng = np.random.default_rng(11)
    for cycle in LATER:
        write_snapshot(
            tmp_path / "logs" / f"snap_{cycle:08d}.csv", params, 0.1, cycle, rng, load_gain=gain, commanded=True
        )
    return run_monitor(MonitorSetup(params), find_snapshots(tmp_path / "logs")[0], BASELINE, 0.02)


def test_the_expected_reading_of_a_gain_drift(params):
    f = params.friction
    a = f.hip_radius * 0.1 + f.thrust_radius * f.thrust_mu
    assert 0.03 / 1.03 * a / f.hip_radius == pytest.approx(0.0060, abs=0.0002)


@pytest.mark.parametrize(("gain", "verb", "drift"), [(1.03, "falls", "+3.0 %"), (0.97, "rises", "-3.0 %")])
def test_a_load_cell_drift_is_flagged_either_way_with_its_alternative(tmp_path, params, before, gain, verb, drift):
    result = _drifted(tmp_path, params, before, gain)
    c, summary = result.columns, result.summary()
    expected = -(gain - 1) / gain * result.findings.mean.mean / (params.friction.hip_radius * 1e3)
    assert c["hip_mu_change"][-1] == pytest.approx(expected, abs=0.0012)  # ∓0.0050
    # Significant, and its worst case (twice the mean's change, 0.010) below the 0.02 threshold: a notice.
    assert c["flag"][-1] == f"notice: the two stations' mean {verb}" + " (up to twice in one station)"
    assert not any(c["alarm"]) and summary.notice_active
    text = given(summary.latest_notice).text
    assert "cannot tell friction from a load-cell gain drift" in text
    g = float(text.split("and a drift of ")[1].split(" %")[0]) / 100
    assert g == pytest.approx(gain - 1, abs=0.008)  # the drift that alone explains the change
    assert f"the commanded load logged with it says the measured load drifted by {drift}" in text
    # The commanded load, logged, shows the drift itself.
    assert c["load_gain_change"][-1] == pytest.approx(gain - 1, abs=1e-3)
    assert f"load cell: measured over commanded load {drift} since the baseline" in c["note"][-1]
    assert summary.load_cell.drifted == ["snap_01750000.csv", "snap_02000000.csv"]
    assert all(abs(v) < 1e-3 for v in c["load_gain_change"][:-2])
