"""hipsim.rig.plausibility pinned both ways: a factor of 1000 too large and too small, a milder factor up and down.

The logs are the analytic model's torques of the synthetic tests' "true"
machine (within ~30 % of the starting one) along two ISO cycles, scaled here:
torques in N·mm times 1000 (µN·m) or over 1000 (N·m), times or over 100
(no unit's factor, beyond the error factor 30), times or over 10 (a warning,
beyond 3); the load in kN or tens of newtons.
(Radians under ``_deg`` are refused in tests/test_plausibility.py.)
"""

from __future__ import annotations

import numpy as np
import pytest
from rig_synthetic import mismatched

import hipsim
from hipsim.exceptions import TrajectoryError
from hipsim.rig import load_log
from hipsim.rig.plausibility import ERROR_FACTOR, LOAD_PEAK_N, WARNING_FACTOR, check_log

HEADER = ["t_s", "Fe_N", "alpha_deg", "beta_deg", "gamma_deg", "tau_1_Nmm", "tau_2_Nmm", "tau_3_Nmm"]


@pytest.fixture(scope="module")
def run():
    return hipsim.analyse(mismatched(hipsim.load_parameters()), hipsim.iso14242(rate=250, cycles=2))


@pytest.fixture(scope="module")
def params():
    return hipsim.load_parameters()


def write(path, run, torque=1.0, load=1.0, angle=np.degrees):
    """A log of ``run``: torques in N·mm × ``torque``, load in N × ``load``, angles through ``angle``."""
    traj = run.trajectory
    values = np.column_stack([traj.t, traj.Fe * load, angle(traj.q), run.torques.total * 1e3 * torque])
    lines = [",".join(HEADER)] + [",".join(f"{v:.9g}" for v in row) for row in values]
    path.write_text("\n".join(lines) + "\n")
    return load_log(path)


def test_the_factors():
    assert (ERROR_FACTOR, WARNING_FACTOR) == (30.0, 3.0)
    assert LOAD_PEAK_N == (300.0, 5000.0)


def test_a_right_log_passes(run, params, tmp_path):
    assert check_log(params, write(tmp_path / "ok.csv", run)) == []


@pytest.mark.parametrize(
    "torque, words",
    [
        (1e-3, ["tau_1_Nmm", "look like N·m", "their RMS is 1/1000 of the model's", "give torques in N·mm"]),
        (1e3, ["tau_1_Nmm", "look like µN·m", "their RMS is 1000 times the model's", "give torques in N·mm"]),
    ],
)
def test_a_unit_slip_of_a_thousand_both_ways(run, params, tmp_path, torque, words):
    with pytest.raises(TrajectoryError) as refused:
        check_log(params, write(tmp_path / "slip.csv", run, torque=torque))
    message = str(refused.value)
    assert "slip.csv" in message
    for word in words:
        assert word in message, (word, message)


@pytest.mark.parametrize("torque, word", [(100.0, " times the model's"), (0.01, "RMS 1/")])
def test_beyond_the_error_factor_without_a_units_factor(run, params, tmp_path, torque, word):
    # ~100 (or 1/100): no unit gives it, yet it is beyond 30: an error naming the column and what to check.
    with pytest.raises(TrajectoryError, match="check the unit \\(N·mm\\), the load's \\(N\\)") as refused:
        check_log(params, write(tmp_path / "far.csv", run, torque=torque))
    assert word in str(refused.value) and "tau_1_Nmm" in str(refused.value)
    assert "like N·m" not in str(refused.value) and "like µN·m" not in str(refused.value)


def _factor(warning: str) -> float:
    """The constant factor a warning names: "all three X times the model's" or "all three 1/X of the model's"."""
    words = warning.split("all three ", 1)[1].split(" ", 1)[0]
    return 1.0 / float(words[2:]) if words.startswith("1/") else float(words)


@pytest.mark.parametrize("torque", [10.0, 2.0, 0.5, 0.1])
def test_a_constant_factor_on_all_three_motors_is_one_warning_that_scales_with_it(run, params, tmp_path, torque):
    # Every motor off by the same factor (a belt, a gearbox, a unit): one warning naming the three columns and the
    # factor, with what it can be. The log's machine is itself off the parameters' by a factor f₁ (measured on the
    # unscaled log as the ratio at ×2 over 2): the named factor is torque·f₁ to the message's 4 digits.
    (warning,) = check_log(params, write(tmp_path / "k.csv", run, torque=torque))
    assert warning.startswith("k.csv: tau_1_Nmm, tau_2_Nmm, tau_3_Nmm: all three ")
    assert "a transmission ratio not in the parameters (a belt, a gearbox), a unit, or another machine" in warning
    (at_two,) = check_log(params, write(tmp_path / "two.csv", run, torque=2.0))
    f1 = _factor(at_two) / 2.0
    assert 1.0 < f1 < 1.3  # the mismatched machine of the tests, within 30 % of the parameters
    assert _factor(warning) == pytest.approx(torque * f1, rel=1e-3)
    assert (" times the model's" in warning) == (torque * f1 > 1.0)


def test_within_the_constant_factor_nothing_is_said(run, params, tmp_path):
    # f₁ ≈ 1.18: ×1.2 gives 1.41 and ×0.8 gives 0.94, both inside the factor 1.5 either way.
    for torque in (1.2, 0.8):
        assert check_log(params, write(tmp_path / "near.csv", run, torque=torque)) == [], torque


def test_the_load_in_kilonewtons_and_a_light_load(run, params, tmp_path):
    # Peak 3000 N in kN (3.003 after the log's low-pass): its thousandfold is a test load: refused.
    with pytest.raises(TrajectoryError, match=r"Fe_N looks like kN: its peak is 3\.0"):
        check_log(params, write(tmp_path / "kn.csv", run, load=1e-3))
    # Peak 60 N (×0.02): not a thousandth of a test load (60 kN is beyond 5000 N), but below 100 N: a warning.
    (warning,) = [w for w in check_log(params, write(tmp_path / "light.csv", run, load=0.02)) if "Fe_N" in w]
    assert "Fe_N peaks at 60.07 N, far below" in warning  # the log's 20 Hz low-pass lifts the 3000 N peak 0.1 %
    # Peak 150 N: above the warning's 100 N, nothing about the load.
    assert not [w for w in check_log(params, write(tmp_path / "small.csv", run, load=0.05)) if "Fe_N" in w]
