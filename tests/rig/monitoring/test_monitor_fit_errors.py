"""Honest standard deviations: the sandwich covariance by hand, and z-scores of repeated noise-only snapshots.

The monitor's standard error is a Newey–West sandwich whose correlation window is the rows per independent row that
identification floors its information by (:func:`hipsim.rig.identification.regressor.rows_per_independent_row`):
the same model-error bandwidth, in one place. Measured over 120 noise-only snapshots (two seeds): z-score spreads
0.97–0.98 (load term), 0.99 (screw Coulomb), 1.01 (screw viscous), 0.93–0.98 (weight term); the filter's ratio as a
plain inflation (the old estimate) gave 0.64, and identification's floor as a plain inflation would give 0.64/√2 = 0.45 (standard errors
1.6 and 2.2 times too wide). Forty snapshots tell a spread of 1 from 0.64 by four of their own standard errors.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import hipsim
from hipsim.rig.monitoring.monitor_fit import MonitorSetup, _solve, estimate
from hipsim.rig.monitoring.snapshots import find_snapshots

SNAPSHOTS = 40


def test_the_sandwich_by_hand():
    # The mean of y = 1, −1, 1, −1 (one column of ones): x = 0, residual r = y. Window 0: S = Σr² = 4, so
    # var = S/n² · n/(n − k) = 4/16 · 4/3 = 1/3 (the plain standard error of a mean). Window 1 adds the Bartlett-weighted
    # neighbours: S = 4 + 2·(1 − 1/2)·Σ r_t·r_{t+1} = 4 − 3 = 1, var = 1/16 · 4/3 = 1/12.
    A, y, time = np.ones((4, 1)), np.array([1.0, -1.0, 1.0, -1.0]), np.arange(4)
    x, std, residual = _solve(A, y, time, 0)
    assert x[0] == pytest.approx(0.0, abs=1e-15) and std[0] == pytest.approx(math.sqrt(1 / 3))
    assert _solve(A, y, time, 1)[1][0] == pytest.approx(math.sqrt(1 / 12))
    # Rows of one sample (three motors) sum their scores before the lags: y = 1, 1 at t = 0 and −1, −1 at t = 1.
    x, std, _ = _solve(np.ones((4, 1)), np.array([1.0, 1.0, -1.0, -1.0]), np.array([0, 0, 1, 1]), 0)
    assert std[0] == pytest.approx(math.sqrt((2**2 + 2**2) / 16 * 4 / 3))


def test_dependent_columns_give_no_estimate():
    x, std, _ = _solve(np.ones((5, 2)), np.arange(5.0), np.arange(5), 2)
    assert np.all(np.isnan(x)) and np.all(np.isinf(std))


@pytest.fixture(scope="module")
def noise_only(tmp_path_factory):
    """40 snapshots of one machine (μ_h = 0.1), only the noise drawn anew: torque 3 N·mm, angles 0.003°."""
    params = hipsim.load_parameters()
    folder = tmp_path_factory.mktemp("noise")
    trajectory = hipsim.iso14242(rate=250.0, cycles=3)
    tau = hipsim.analyse(params.replace(hip_mu=0.1), trajectory, lever_spin=True).torques.total * 1e3
    rng = np.random.default_rng(2024)
    header = "t_s,cycle,Fe_N,tau_1_Nmm,tau_2_Nmm,tau_3_Nmm,alpha_deg,beta_deg,gamma_deg\n"
    for k in range(SNAPSHOTS):
        noisy = tau + rng.normal(0.0, 3.0, tau.shape)
        angles = np.degrees(trajectory.q) + rng.normal(0.0, 0.003, trajectory.q.shape)
        cycle = 1000 * k + np.floor(trajectory.t).astype(int)
        data = np.column_stack([trajectory.t, cycle, trajectory.Fe, noisy, angles])
        lines = (",".join(f"{v:.10g}" for v in row) + "\n" for row in data)
        (folder / f"s{k:03d}.csv").write_text(header + "".join(lines), encoding="utf-8")
    setup = MonitorSetup(params)
    return [estimate(setup, s) for s in find_snapshots(folder)[0]]


@pytest.mark.parametrize("name", ["load_friction_mm", "screw_coulomb_Nmm", "screw_viscous_Nmm_s_rad"])
def test_z_scores_of_noise_only_snapshots_have_spread_one(noise_only, name):
    x = np.array([row[name] for row in noise_only])
    s = np.array([row[f"{name}_std"] for row in noise_only])
    z = (x - x.mean()) / s
    assert 0.8 <= float(np.std(z, ddof=1)) <= 1.25
