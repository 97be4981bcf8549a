"""A closed-loop run on the machine as built (hipsim.control.tracking): its summary and its columns, by hand on a
run of four samples whose every number is chosen."""

import math

import numpy as np
import pytest

from hipsim.control.tracking import ANGLES, MachineRun, attitude_columns, error_columns
from hipsim.exceptions import HipsimError
from hipsim.motion.trajectories import Trajectory

N = 4
T = np.array([0.0, 0.002, 0.004, 0.006])  # s: a 2 ms servo period, so the run spans 8 ms


def _run(control=2, n=N, t=T):
    """Errors (desired − true, in degrees) chosen per platform and angle; torques, speeds and flags by hand."""
    desired_q = np.radians(np.array([[1.0, 2.0, 3.0]] * n))
    errors = np.zeros((n, 2, 3))
    errors[:, 0, 0] = [1.0, -3.0, 2.0, 0.0][:n]  # m_1's α: the largest magnitude is the negative one
    errors[:, 1, 1] = [0.5, 0.5, -0.5, 4.0][:n]  # m_2's β: its peak the last sample
    errors[:, 1, 2] = [2.0, 0.0, 0.0, 0.0][:n]  # m_2's γ: its peak the first sample
    attitudes = desired_q[:, None, :] - np.radians(errors)
    desired = Trajectory(t, desired_q, np.zeros((n, 3)), np.zeros((n, 3)), np.array([300.0, 400.0, 500.0, 600.0])[:n])
    carriages = np.array([[0.5, 0.6, 0.7]] * n) + np.arange(n)[:, None] * 1e-3
    tau = np.array([[0.1, -0.2, 0.0], [-0.3, 0.2, 0.0], [0.2, 0.2, 0.0], [0.0, -0.2, 0.0]])[:n]  # N·m
    speed = np.array([[1.0, 0.0, -2.0], [-3.0, 0.0, 1.0], [0.0, 0.0, 0.0], [2.0, 0.0, 0.0]])[:n]  # rad/s
    measured = attitudes[:, control - 1] + np.radians(0.01)
    saturated = np.array([True, False, True, True])[:n]
    return MachineRun(
        t=t,
        desired=desired,
        carriages=carriages,
        attitudes=attitudes,
        rates=2 * attitudes,
        measured=measured,
        tau=tau,
        tau_requested=2 * tau,
        saturated=saturated,
        motor_speed=speed,
        plant="pinocchio",
        controller="augmented-pd",
        feedback="encoders",
        control=control,
        step=5e-4,
    )


def test_errors_are_desired_minus_true_per_platform():
    run = _run()
    assert np.degrees(run.errors[1, 0]) == pytest.approx([-3.0, 0.0, 0.0], abs=1e-12)
    assert np.degrees(run.errors[3, 1]) == pytest.approx([0.0, 4.0, 0.0], abs=1e-12)


def test_each_platform_and_angle_has_its_rms_and_its_signed_peak_by_magnitude():
    s = _run().summary()
    a = s.error(1, "alpha")
    # RMS over the four samples (not three): √((1 + 9 + 4 + 0)/4); the peak the −3° of t = 2 ms, not the +2°.
    assert a.rms_deg == pytest.approx(math.sqrt(14 / 4), rel=1e-12)
    assert (a.peak_deg, a.peak_at_s) == pytest.approx((-3.0, 0.002), rel=1e-12)
    assert (a.platform, a.angle, a.controlled) == (1, "alpha", False)
    b = s.error(2, "beta")
    assert b.rms_deg == pytest.approx(math.sqrt((3 * 0.25 + 16) / 4), rel=1e-12)
    assert (b.peak_deg, b.peak_at_s) == pytest.approx((4.0, 0.006), rel=1e-12)
    assert (b.platform, b.angle, b.controlled) == (2, "beta", True)
    g = s.error(2, "gamma")
    assert (g.rms_deg, g.peak_deg, g.peak_at_s) == pytest.approx((1.0, 2.0, 0.0), rel=1e-12)
    # The entries in order: platform 1's α, β, γ, then platform 2's; only the errors chosen are non-zero.
    assert [(e.platform, e.angle) for e in s.errors] == [(j, x) for j in (1, 2) for x in ANGLES]
    assert [e.rms_deg > 0 for e in s.errors] == [True, False, False, False, True, True]
    assert s.error(1, "gamma") is s.errors[2] and s.error(2, "alpha") is s.errors[3]


def test_the_controlled_platform_is_the_run_s():
    s = _run(control=1).summary()
    assert [e.controlled for e in s.errors] == [True] * 3 + [False] * 3
    assert s.control == 1


def test_motors_saturation_and_the_run_s_span():
    s = _run().summary()
    m1, m2, m3 = s.motors
    assert (m1.motor, m2.motor, m3.motor) == (1, 2, 3)
    assert (m1.torque_peak_Nmm, m1.torque_rms_Nmm) == pytest.approx((300.0, 1e3 * math.sqrt(0.14 / 4)), rel=1e-12)
    assert (m2.torque_peak_Nmm, m2.torque_rms_Nmm) == pytest.approx((200.0, 200.0), rel=1e-12)
    assert (m3.torque_peak_Nmm, m3.torque_rms_Nmm) == (0.0, 0.0)
    rpm = 60 / (2 * math.pi)
    assert [m.speed_peak_rpm for m in s.motors] == pytest.approx([3 * rpm, 0.0, 2 * rpm], rel=1e-12)
    assert s.saturated_samples == 3
    # Four periods of 2 ms: 8 ms (the samples' count times the period, not the span of the stamps).
    assert (s.duration_s, s.step_s) == pytest.approx((0.008, 5e-4), rel=1e-12)
    assert (s.plant, s.controller, s.feedback) == ("pinocchio", "augmented-pd", "encoders")


def test_the_summary_as_json():
    s = _run().summary()
    doc = s.to_json()
    assert list(doc) == [
        "plant",
        "controller",
        "feedback",
        "control",
        "duration_s",
        "step_s",
        "errors",
        "motors",
        "saturated_samples",
    ]
    assert doc["errors"][3] == {
        "platform": 2,
        "angle": "alpha",
        "controlled": True,
        "rms_deg": 0.0,
        "peak_deg": 0.0,
        "peak_at_s": 0.0,
    }
    assert doc["motors"][2] == {
        "motor": 3,
        "torque_peak_Nmm": 0.0,
        "torque_rms_Nmm": 0.0,
        "speed_peak_rpm": s.motors[2].speed_peak_rpm,
    }
    assert (doc["control"], doc["saturated_samples"], doc["step_s"]) == (2, 3, 5e-4)
    doc["errors"][0]["rms_deg"] = -1.0  # a copy: the record is not changed through its JSON
    assert s.errors[0].rms_deg > 0


def test_the_columns_in_the_file_s_units():
    run = _run()
    c = run.columns()
    assert c["t_s"] is run.t
    assert [c[f"L_1{i}_mm"][2] for i in (1, 2, 3)] == pytest.approx([502.0, 602.0, 702.0], rel=1e-12)
    assert attitude_columns() == [f"{a}_{j}_deg" for j in (1, 2) for a in ("alpha", "beta", "gamma")]
    assert error_columns() == [f"err_{a}_{j}_deg" for j in (1, 2) for a in ("alpha", "beta", "gamma")]
    assert c["alpha_1_deg"][1] == pytest.approx(1.0 + 3.0, rel=1e-12)
    assert c["beta_2_deg"][3] == pytest.approx(2.0 - 4.0, rel=1e-12)
    assert c["err_alpha_1_deg"][1] == pytest.approx(-3.0, rel=1e-12)
    assert c["err_beta_2_deg"][3] == pytest.approx(4.0, rel=1e-12)
    assert c["err_gamma_2_deg"][0] == pytest.approx(2.0, rel=1e-12)
    # The unnumbered columns are the controlled platform's (m_2 here): its β error, not m_1's.
    assert c["beta_des_deg"] == pytest.approx([2.0] * N, rel=1e-12)
    assert c["err_beta_deg"] == pytest.approx([0.5, 0.5, -0.5, 4.0], rel=1e-12)
    assert c["beta_deg"][3] == pytest.approx(-2.0, rel=1e-12)
    assert c["alpha_meas_deg"] == pytest.approx([1.01] * N, rel=1e-12)
    assert c["gamma_deg"][0] == pytest.approx(1.0, rel=1e-12)
    assert c["err_alpha_deg"][1] == 0.0
    assert c["tau_1_Nmm"][1] == pytest.approx(-300.0) and c["tau_req_1_Nmm"][1] == pytest.approx(-600.0)
    assert c["tau_2_Nmm"][0] == pytest.approx(-200.0) and c["tau_req_3_Nmm"][0] == 0.0
    assert c["speed_3_rpm"][0] == pytest.approx(-2 * 60 / (2 * math.pi), rel=1e-12)
    assert c["speed_1_rpm"][1] == pytest.approx(-3 * 60 / (2 * math.pi), rel=1e-12)
    assert c["saturated"].tolist() == [1.0, 0.0, 1.0, 1.0]
    assert c["Fe_N"].tolist() == [300.0, 400.0, 500.0, 600.0]
    one = _run(control=1).columns()
    assert one["err_alpha_deg"] == pytest.approx([1.0, -3.0, 2.0, 0.0], rel=1e-12)


def test_the_columns_written_and_read_back(tmp_path):
    run = _run()
    path = run.write(tmp_path / "run.csv")
    assert path == tmp_path / "run.csv"
    header = path.read_text().splitlines()[0].split(",")
    table = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    assert header == list(run.columns())
    assert table[:, header.index("err_alpha_1_deg")] == pytest.approx([1.0, -3.0, 2.0, 0.0], rel=1e-9)


def test_a_run_whose_arrays_disagree_is_refused():
    run = _run()
    with pytest.raises(HipsimError, match="attitudes"):
        MachineRun(
            run.t, run.desired, run.carriages, run.attitudes[:3], run.rates, run.measured, run.tau,
            run.tau_requested, run.saturated, run.motor_speed, "p", "c", "f", 2,
        )  # fmt: skip
