"""The torque run's typed summary over the samples kept (hipsim/results.py RunSummary), checked by numpy on the
run's own columns: a flagged sample is out of every statistic, the RMS is over the samples kept."""

from __future__ import annotations

import math
from dataclasses import replace

import jsonschema
import numpy as np
import pytest

import hipsim
from hipsim.results import RunSummary


@pytest.fixture(scope="module")
def run():
    return hipsim.analyse(hipsim.load_parameters(), hipsim.iso14242(rate=40))


def test_flagged_samples_are_out_of_the_rms_and_the_peaks(run):
    flagged = np.zeros(len(run.t), dtype=bool)
    flagged[[0, 3, 17]] = True  # three samples dropped: the RMS divides by 37, not 40
    kept = ~flagged
    s = replace(run, flagged=flagged).summary()
    assert s.samples == 40 and s.flagged_samples == 3
    tau = run.torques.total[kept, 1] * 1e3
    assert s.motors["2"].tau_rms_Nmm == pytest.approx(math.sqrt(np.sum(tau**2) / 37), rel=1e-13)
    assert s.motors["2"].tau_peak_Nmm == pytest.approx(np.abs(tau).max(), rel=1e-13)
    L = run.L[kept, 1, 0] * 1e3
    assert s.sliders["21"].stroke_mm == pytest.approx(L.max() - L.min(), rel=1e-12)
    assert s.sliders["21"].L_min_mm == pytest.approx(L.min(), rel=1e-13)
    k = int(np.argmin(np.where(kept, run.cond_inv, np.inf)))
    assert (s.cond_inv_min, s.cond_inv_min_t_s) == (run.cond_inv[k], run.t[k])


def test_each_slider_and_motor_under_its_own_name(run):
    s = run.summary()
    for j in (1, 2):
        for i in (1, 2, 3):
            assert s.sliders[f"{j}{i}"].L_max_mm == pytest.approx(run.L[:, j - 1, i - 1].max() * 1e3, rel=1e-13)
    for i in (1, 2, 3):
        parts = run.torques
        m = s.motors[str(i)]
        assert m.tau_f_max_Nmm == pytest.approx(np.abs(parts.friction[:, i - 1]).max() * 1e3, rel=1e-13)
        assert m.tau_L_max_Nmm == pytest.approx(np.abs(parts.screws[:, i - 1]).max() * 1e3, rel=1e-13)
        assert m.tau_m_max_Nmm == pytest.approx(np.abs(parts.platforms[:, i - 1]).max() * 1e3, rel=1e-13)
    document = s.to_json()
    assert list(document["motors"]["1"]) == [
        "tau_m_max_Nmm",
        "tau_l_max_Nmm",
        "tau_s_max_Nmm",
        "tau_L_max_Nmm",
        "tau_f_max_Nmm",
        "tau_peak_Nmm",
        "tau_rms_Nmm",
        "speed_peak_rpm",
    ]
    jsonschema.validate(document, RunSummary.json_schema())
