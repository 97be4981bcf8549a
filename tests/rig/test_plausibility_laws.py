"""hipsim.rig.plausibility pinned both ways: a factor of 1000 too large and too small, a milder factor up and down.

The logs are the analytic model's torques of the synthetic tests' "true"
machine (within ~30 % of the starting one) along two ISO cycles, scaled here:
torques in N·mm times 1000 (µN·m) or over 1000 (N·m), times or over 100
(no unit's factor, beyond the error factor 30), times or over 10 (a warning,
beyond 3); the load in kN or tens of newtons.
(Radians under ``_deg`` are refused in tests/rig/test_plausibility.py.)
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest
from rig_synthetic import mismatched

import hipsim
import hipsim.rig.plausibility as plausibility
from hipsim.analytic.engine import AnalyticModel
from hipsim.exceptions import TrajectoryError
from hipsim.motion.trajectories import Trajectory
from hipsim.rig import load_log
from hipsim.rig.logs.log import LogPieces, MeasuredLog
from hipsim.rig.plausibility import (
    CONSTANT_FACTOR,
    CONSTANT_SPREAD,
    ERROR_FACTOR,
    LOAD_PEAK_N,
    MODEL_SAMPLES,
    WARNING_FACTOR,
    _ratio,
    _slip,
    check_log,
    constant_factor,
    far_from_priors,
)

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
    ("torque", "words"),
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


@pytest.mark.parametrize(("torque", "word"), [(100.0, " times the model's"), (0.01, "RMS 1/")])
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


# --- Exact logs: the numbers every message quotes, by hand ---------------------------------------------------------
#
# The log's torques are the starting machine's own along one ISO cycle at 500 Hz (the model the check runs), so the
# measured RMS over the model's is exactly the factor a test applies. Logs written to a file are read without the
# low-pass (cutoff None: only the spline), so the RMS the messages quote is that of the written values.

EXACT_RATE = 500


@pytest.fixture(scope="module")
def exact(params):
    """The ISO cycle, the model's torques along it in [N·m] (N, 3) and their RMS in [N·mm] (3,)."""
    trajectory = hipsim.iso14242(rate=EXACT_RATE, cycles=1)
    tau = AnalyticModel(params, lever_spin=True).run(trajectory).torques.total  # check_log's model
    return trajectory, tau, np.sqrt(np.mean(tau**2, axis=0)) * 1e3


def measured(exact, scale=(1.0, 1.0, 1.0), name="exact.csv", load=None, edge=0):
    """A log in memory: the exact motion, the model's torques × ``scale`` per motor, the load ``load`` (None: ISO's)."""
    traj, tau, _ = exact
    Fe = traj.Fe if load is None else np.full(len(traj), float(load))
    trajectory = Trajectory(traj.t, traj.q, traj.qd, traj.qdd, Fe, name=name)
    return MeasuredLog(trajectory, tau * np.asarray(scale), None, name, "exact", (), None, edge)


def currents(path, exact, constant, written=0.15, scale=(1.0, 1.0, 1.0), angle=np.degrees, unit="deg"):
    """A log file of motor currents τ/``written`` × ``scale``, read (unfiltered) with the torque constant ``constant``."""
    traj, tau, _ = exact
    header = [
        "t_s",
        "Fe_N",
        f"alpha_{unit}",
        f"beta_{unit}",
        f"gamma_{unit}",
        "current_1_A",
        "current_2_A",
        "current_3_A",
    ]
    values = np.column_stack([traj.t, traj.Fe, angle(traj.q), tau / written * np.asarray(scale)])
    lines = [",".join(header)] + [",".join(f"{v:.12g}" for v in row) for row in values]
    path.write_text("\n".join(lines) + "\n")
    return LogPieces(path, None, constant, cutoff=None)


def test_currents_times_the_right_constant_pass(exact, params, tmp_path):
    assert check_log(params, currents(tmp_path / "a.csv", exact, 0.15)) == []


def test_a_torque_constant_in_n_mm_per_a(exact, params, tmp_path):
    # 0.15 N·m/A given as 150 (N·mm/A): every current gives 1000 times the model's torque; the message names the
    # columns, the constant as given and the one meant (150/1000 = 0.15), the RMS of motor 1 and the model's.
    path = tmp_path / "ma.csv"
    _, _, rms = exact
    with pytest.raises(TrajectoryError) as refused:
        check_log(params, currents(path, exact, 150.0))
    assert str(refused.value) == (
        f"{path}: current_1_A, current_2_A, current_3_A × --torque-constant 150 N·m/A give 1000 times the model's "
        f"torque ({rms[0] * 1e3:.4g} against {rms[0]:.4g} N·mm): the torque constant looks like N·mm/A "
        "(give --torque-constant in N·m/A, 0.15), or the currents like mA"
    )
    assert refused.value.source == str(path)


def test_a_torque_constant_in_kn_m_per_a(exact, params, tmp_path):
    path = tmp_path / "ka.csv"
    _, _, rms = exact
    with pytest.raises(TrajectoryError) as refused:
        check_log(params, currents(path, exact, 0.15e-3))
    assert str(refused.value) == (
        f"{path}: current_1_A, current_2_A, current_3_A × --torque-constant 0.00015 N·m/A give 1/1000 of the "
        f"model's torque ({rms[0] * 1e-3:.4g} against {rms[0]:.4g} N·mm): the torque constant looks like kN·m/A, "
        "or the currents like kA (give --torque-constant in N·m/A, currents in A)"
    )


def test_a_torque_constant_off_by_no_units_factor(exact, params, tmp_path):
    # ×100 (15 for 0.15): beyond the error factor 30 but no unit's: check the constant and the currents' unit.
    path = tmp_path / "far.csv"
    _, _, rms = exact
    with pytest.raises(TrajectoryError) as refused:
        check_log(params, currents(path, exact, 15.0))
    assert str(refused.value) == (
        f"{path}: current_1_A, current_2_A, current_3_A × --torque-constant 15 N·m/A give 100 times the model's "
        f"torque ({rms[0] * 1e2:.4g} against {rms[0]:.4g} N·mm): check --torque-constant (N·m/A) and the currents' "
        "unit (A)"
    )


def test_one_motors_current_in_ma_and_the_constant_named_by_the_caller(exact, params, tmp_path):
    # Motor 2's current alone ×1000: one column, "gives"; the constant the caller names (0.2) is the one quoted.
    path = tmp_path / "one.csv"
    _, _, rms = exact
    log = currents(path, exact, 0.15, scale=(1.0, 1e3, 1.0))
    with pytest.raises(TrajectoryError) as refused:
        check_log(params, log, torque_constant=0.2)
    assert str(refused.value).startswith(
        f"{path}: current_2_A × --torque-constant 0.2 N·m/A gives 1000 times the model's torque "
        f"({rms[1] * 1e3:.4g} against {rms[1]:.4g} N·mm): the torque constant looks like N·mm/A "
        "(give --torque-constant in N·m/A, 0.0002)"
    )


@pytest.mark.parametrize(
    ("motor", "scale", "words"),
    [
        (2, 1e-3, "tau_3_Nmm looks like N·m: its RMS is 1/1000 of the model's ({:.4g} against {:.4g} N·mm)"),
        (0, 1e3, "tau_1_Nmm looks like µN·m: its RMS is 1000 times the model's ({:.4g} against {:.4g} N·mm)"),
    ],
)
def test_one_motors_torque_slipped_by_a_thousand(exact, params, motor, scale, words):
    # A log built from arrays has no file: the messages name it by its name.
    _, _, rms = exact
    factors = [1.0, 1.0, 1.0]
    factors[motor] = scale
    with pytest.raises(TrajectoryError) as refused:
        check_log(params, measured(exact, factors, name="arrays"))
    expected = words.format(rms[motor] * scale, rms[motor]) + "; give torques in N·mm"
    assert str(refused.value) == f"arrays: {expected}"


def test_two_kinds_of_slip_name_the_first_motors(exact, params):
    # Motor 1 in µN·m and motor 3 in N·m: the message is about motor 1's slip, its column alone.
    with pytest.raises(TrajectoryError, match=r"^x: tau_1_Nmm looks like µN·m: its RMS") as refused:
        check_log(params, measured(exact, (1e3, 1.0, 1e-3), name="x"))
    assert "tau_3_Nmm" not in str(refused.value)


@pytest.mark.parametrize(("scale", "ratio"), [(10.0, "10 times"), (0.1, "1/10 of")])
def test_one_motor_off_by_ten_is_a_warning_naming_it(exact, params, scale, ratio):
    _, _, rms = exact
    (warning,) = check_log(params, measured(exact, (1.0, scale, 1.0), name="w"))
    assert warning == (
        f"w: tau_2_Nmm: {ratio} the model's with these parameters ({rms[1] * scale:.4g} against {rms[1]:.4g} N·mm): "
        "check its unit and the machine's parameters"
    )


@pytest.mark.parametrize(("scale", "ratio"), [(2.0, "2 times"), (0.5, "1/2 of")])
def test_all_three_off_by_one_factor_is_one_warning(exact, params, scale, ratio):
    (warning,) = check_log(params, measured(exact, (scale,) * 3, name="k"))
    assert warning == (
        f"k: tau_1_Nmm, tau_2_Nmm, tau_3_Nmm: all three {ratio} the model's with these parameters (a constant factor "
        f"of {scale:.3g}): a transmission ratio not in the parameters (a belt, a gearbox), a unit, or another machine; "
        "a fit on this log moves every parameter to absorb it"
    )


def test_a_factor_of_ten_on_every_motor_is_one_warning_not_three(exact, params):
    (warning,) = check_log(params, measured(exact, (10.0,) * 3, name="k"))
    assert warning.startswith("k: tau_1_Nmm, tau_2_Nmm, tau_3_Nmm: all three 10 times the model's")


def test_beyond_the_error_factor_names_the_ratio(exact, params):
    # ×40 on motor 3 alone: no unit's factor, beyond 30: the error quotes its ratio and numbers.
    _, _, rms = exact
    with pytest.raises(TrajectoryError) as refused:
        check_log(params, measured(exact, (1.0, 1.0, 40.0), name="f"))
    assert str(refused.value) == (
        f"f: tau_3_Nmm: RMS 40 times the model's ({rms[2] * 40:.4g} against {rms[2]:.4g} N·mm): check the unit (N·mm), "
        "the load's (N) and the machine's parameters (--no-plausibility-check if the log is right)"
    )


def test_a_log_of_one_usable_sample_or_of_unreachable_poses_is_not_checked(exact, params):
    # 500 samples, 249 at each edge: two usable samples are checked (a thousandfold torque refused), one is not.
    with pytest.raises(TrajectoryError):
        check_log(params, measured(exact, (1e3,) * 3, edge=249))
    traj, tau, _ = exact
    odd = Trajectory(traj.t[:499], traj.q[:499], traj.qd[:499], traj.qdd[:499], traj.Fe[:499])
    assert check_log(params, MeasuredLog(odd, tau[:499] * 1e3, None, "one", "exact", (), None, 249)) == []
    # A rotation γ of 90° the levers cannot reach: the comparison or the fit names the pose; the check says nothing.
    far = Trajectory(traj.t, np.tile(np.radians([0.0, 0.0, 90.0]), (len(traj), 1)), 0 * traj.qd, 0 * traj.qdd, traj.Fe)
    assert check_log(params, MeasuredLog(far, tau * 1e3, None, "far", "exact")) == []


@pytest.mark.parametrize("peak", [0.3, 1.0, 5.0])
def test_a_load_whose_thousandfold_is_a_test_load_is_kn(exact, params, peak):
    # 300 to 5000 N, both ends included, read as kN.
    with pytest.raises(TrajectoryError) as refused:
        check_log(params, measured(exact, load=peak, name="kn"))
    assert str(refused.value) == (
        f"kn: Fe_N looks like kN: its peak is {peak:g}, 1/1000 of a hip simulator's test loads "
        "(ISO 14242-1: 300 to 3000 N); give the load in N"
    )


@pytest.mark.parametrize("peak", [0.299, 5.001, 99.9])
def test_a_light_load_that_is_no_kn_is_a_warning(exact, params, peak):
    warnings = check_log(params, measured(exact, load=peak, name="light"))
    assert (
        f"light: Fe_N peaks at {peak:g} N, far below a hip simulator's test loads (ISO 14242-1: 300 to 3000 N): "
        "is it in N?"
    ) in warnings


def test_a_load_of_a_hundred_newtons_is_not_light(exact, params):
    assert not [w for w in check_log(params, measured(exact, load=100.0)) if "Fe_N" in w]


def test_radians_under_deg_name_the_widest_angle(exact, params, tmp_path):
    # The ISO cycle's flexion spans the most: written as radians under _deg its range is a few "degrees".
    traj, _, _ = exact
    span = float(np.ptp(traj.q[:, 0]))
    assert span == float(np.ptp(traj.q, axis=0).max())
    path = tmp_path / "rad.csv"
    with pytest.raises(TrajectoryError) as refused:
        check_log(params, currents(path, exact, 0.15, angle=lambda q: q))
    assert str(refused.value) == (
        f"{path}: alpha_deg looks like radians: its range is {span:.3g}°, 1/57 of a gait cycle's "
        f"({np.degrees(span):.3g}° if read as radians); label the angle columns _rad"
    )
    # Labelled _rad, the same values are right.
    assert check_log(params, currents(tmp_path / "ok.csv", exact, 0.15, angle=lambda q: q, unit="rad")) == []


# --- far_from_priors: several base parameters far from their priors, all one way ------------------------------------


def estimates(*shifts, determined=None):
    """Base parameters b1, b2, … moved by ``shifts`` prior standard deviations (all determined unless said)."""
    flags = determined or [True] * len(shifts)
    return [SimpleNamespace(name=f"b{k + 1}", shift=s, determined=d) for k, (s, d) in enumerate(zip(shifts, flags))]


def test_two_far_up_are_one_warning_naming_them_farthest_first():
    assert far_from_priors(estimates(4.0, 1.0, 5.0, 0.0)) == [
        "2 of 4 base parameters moved more than 3 prior standard deviations, all up (b3 +5, b1 +4): one cause scales "
        "the logged torques; a transmission ratio not in the parameters (a belt, a gearbox), a unit, or another "
        "machine's logs; check it before using the identified file"
    ]


def test_three_far_down():
    (warning,) = far_from_priors(estimates(-4.0, -3.5, -12.0))
    assert warning.startswith("3 of 3 base parameters moved more than 3 prior standard deviations, all down ")
    assert "(b3 -12, b1 -4, b2 -3.5)" in warning


@pytest.mark.parametrize(
    ("shifts", "determined"),
    [
        ((4.0, -5.0, 0.0), None),  # two far, opposite ways: the machine's own spread
        ((4.0, 1.0, 2.0), None),  # one far
        ((3.0, 4.0, 0.0), None),  # 3 exactly is not beyond 3: one far
        ((-3.0, -4.0, 0.0), None),
        ((4.0, 5.0, 0.0), [True, False, True]),  # one of the two far is not determined by the logs
        ((), None),
    ],
)
def test_no_warning(shifts, determined):
    assert far_from_priors(estimates(*shifts, determined=determined)) == []


# --- The factor windows by hand ---------------------------------------------------------------------------------


def test_a_units_factor_is_within_two_of_a_thousand_either_way():
    for factor in (500.0, 1000.0, 2000.0):
        assert _slip(factor) == 1e3, factor
    for factor in (5e-4, 1e-3, 2e-3):
        assert _slip(factor) == 1e-3, factor
    for factor in (499.0, 2001.0, 4.99e-4, 2.01e-3, 1.0, 100.0):
        assert _slip(factor) is None, factor


def test_ratios_in_words():
    assert (_ratio(1.0), _ratio(1.5), _ratio(1000.0)) == ("1 times", "1.5 times", "1000 times")
    assert (_ratio(0.5), _ratio(1e-3)) == ("1/2 of", "1/1000 of")


def test_the_constant_factor_by_hand():
    assert (CONSTANT_FACTOR, CONSTANT_SPREAD) == (1.5, 0.15)
    # The median of the finite, positive factors, when all lie within 15 % of it and it is 1.5 or beyond either way.
    assert constant_factor(np.array([2.0, 2.2, 1.9])) == 2.0
    assert constant_factor(np.array([2.0, 2.0, np.nan])) == 2.0  # an idle motor left out: two are enough
    assert constant_factor(np.array([2.0, 2.0, 0.0])) == 2.0  # nor is a motor whose log is all zeros
    assert constant_factor(np.array([2.0, 2.0, -2.0])) == 2.0
    assert constant_factor(np.array([2.0, np.nan, np.nan])) is None  # one motor says nothing of a common factor
    assert constant_factor(np.array([2.0, 2.0, 2.4])) is None  # 20 % apart
    # 1.5 and 1/1.5 are beyond the window (1/1.5, 1.5) of the model's own error: named.
    assert constant_factor(np.array([1.5, 1.5, 1.5])) == 1.5
    assert constant_factor(np.array([1 / 1.5] * 3)) == 1 / 1.5
    assert constant_factor(np.array([1.49, 1.49, 1.49])) is None


def test_the_factor_named_is_the_units_and_an_unknown_constant_is_not_quoted(exact, params, tmp_path):
    # Currents 1.2 times what 0.15 N·m/A needs, read with 150: 1200 times the model's, named as the unit's 1000.
    path = tmp_path / "ma.csv"
    _, _, rms = exact
    log = currents(path, exact, 150.0, scale=(1.2, 1.2, 1.2))
    with pytest.raises(TrajectoryError, match=r"give 1000 times the model's torque \(") as refused:
        check_log(params, log)
    assert f"({rms[0] * 1.2e3:.4g} against {rms[0]:.4g} N·mm)" in str(refused.value)
    # A caller that says the constant is 0 (unknown): no constant quoted, none suggested.
    with pytest.raises(TrajectoryError) as refused:
        check_log(params, log, torque_constant=0.0)
    assert ": current_1_A, current_2_A, current_3_A × --torque-constant give 1000 times the model's torque (" in str(
        refused.value
    )
    assert str(refused.value).endswith(
        ": the torque constant looks like N·mm/A (give --torque-constant in N·m/A), or the currents like mA"
    )


def test_radians_under_deg_name_the_widest_angle_wherever_it_is(exact, params, tmp_path):
    # The flexion's values written under beta_deg (and the abduction's under alpha_deg): beta_deg is named.
    traj, _, _ = exact
    span = float(np.ptp(traj.q[:, 0]))
    path = tmp_path / "beta.csv"
    with pytest.raises(TrajectoryError) as refused:
        check_log(params, currents(path, exact, 0.15, angle=lambda q: q[:, [1, 0, 2]]))
    assert f": beta_deg looks like radians: its range is {span:.3g}°" in str(refused.value)


# --- The torque check's logic on a stand-in model whose RMS torques are given exactly ---------------------------------


class StandIn:
    """An AnalyticModel stand-in: torques constant at ``MODEL`` (N·m, per motor); records (lever_spin, samples)."""

    MODEL = np.ones(3)
    calls: list = []

    def __init__(self, params, lever_spin=False):
        self.lever_spin = lever_spin

    def run(self, trajectory):
        StandIn.calls.append((self.lever_spin, len(trajectory)))
        return SimpleNamespace(torques=SimpleNamespace(total=np.tile(StandIn.MODEL, (len(trajectory), 1))))


@pytest.fixture
def stand_in(monkeypatch):
    monkeypatch.setattr(plausibility, "AnalyticModel", StandIn)
    StandIn.MODEL, StandIn.calls = np.ones(3), []
    return StandIn


def constant(logged, n=2, name="c"):
    """A log of ``n`` samples at rest under 1000 N whose torques are constant at ``logged`` (N·m, per motor)."""
    t = np.arange(n) / 1000.0
    still = np.zeros((n, 3))
    trajectory = Trajectory(t, still, still, still, np.full(n, 1000.0), name=name)
    return MeasuredLog(trajectory, np.tile(np.asarray(logged, dtype=float), (n, 1)), None, name, "exact")


@pytest.mark.parametrize(
    ("factor", "outcome"),
    [
        (30.0, "error"),  # on the error factor: an error (within it means strictly inside)
        (1 / 30, "error"),
        (29.9, "warning"),
        (0.05, "warning"),  # 1/20: inside 1/30, beyond 1/3
        (3.0, "warning"),  # on the warning factor: a warning
        (1 / 3, "warning"),
        (2.99, "none"),
        (0.5, "none"),
    ],
)
def test_the_error_and_warning_windows_and_their_ends(stand_in, params, factor, outcome):
    log = constant([1.0, factor, 1.0])
    assert np.sqrt(np.mean(log.tau**2, axis=0))[1] == factor  # the RMS of two equal samples is their value, to the bit
    if outcome == "error":
        with pytest.raises(TrajectoryError, match=r"^c: tau_2_Nmm: RMS "):
            check_log(params, log)
        return
    warnings = check_log(params, log)
    assert len(warnings) == (outcome == "warning")
    if warnings:
        assert warnings[0].startswith("c: tau_2_Nmm: ")


def test_a_motor_the_model_says_is_idle_is_not_compared(stand_in, params):
    # Motor 1 idle (0 N·m in the model) with 1 N·m logged: not compared; motor 2 at 10 times is still said.
    stand_in.MODEL = np.array([0.0, 1.0, 1.0])
    (warning,) = check_log(params, constant([1.0, 10.0, 1.0]))
    assert warning.startswith("c: tau_2_Nmm: 10 times the model's")
    # 1e-6 N·m is idle too, and left out of the constant factor: the other two name theirs.
    stand_in.MODEL = np.array([1.0, 1.0, 1e-6])
    (warning,) = check_log(params, constant([2.0, 2.0, 1.0]))
    assert "all three 2 times the model's" in warning


@pytest.mark.parametrize(("n", "samples"), [(4000, 4000), (4001, 2001), (9000, 3000)])
def test_the_model_runs_on_at_most_model_samples(stand_in, params, n, samples):
    assert MODEL_SAMPLES == 4000
    check_log(params, constant([1.0, 1.0, 1.0], n=n))
    assert stand_in.calls == [(True, samples)]  # every k-th sample, k = ⌈n/4000⌉; the lever spin by default


def test_the_model_has_the_lever_spin_the_caller_names(stand_in, params):
    check_log(params, constant([1.0, 1.0, 1.0]), lever_spin=False)
    check_log(params, constant([1.0, 1.0, 1.0]), lever_spin=True)
    assert [spin for spin, _ in stand_in.calls] == [False, True]


def test_a_log_read_in_pieces_is_checked_on_its_first(exact, params, tmp_path):
    # Torques in N·mm for the first 100 samples, then in µN·m: read whole the log is refused (its RMS is 600 to
    # 1000 times the model's, within a factor 2 of 1000); read in pieces of 100 samples, the check takes the first piece's samples
    # only (its window reaches further, for the spline), which are right.
    traj, tau, _ = exact
    scale = np.where(np.arange(len(traj)) < 100, 1.0, 1e3)[:, None]
    header = ["t_s", "Fe_N", "alpha_deg", "beta_deg", "gamma_deg", "tau_1_Nmm", "tau_2_Nmm", "tau_3_Nmm"]
    values = np.column_stack([traj.t, traj.Fe, np.degrees(traj.q), tau * 1e3 * scale])
    path = tmp_path / "pieces.csv"
    path.write_text("\n".join([",".join(header)] + [",".join(f"{v:.12g}" for v in row) for row in values]) + "\n")
    with pytest.raises(TrajectoryError, match="look like µN·m"):
        check_log(params, LogPieces(path, None, None, cutoff=None))
    pieces = LogPieces(path, None, None, cutoff=None, piece=100)
    assert pieces.piece == 100 and len(pieces) == 500
    assert check_log(params, pieces) == []
