"""The plant and the model apart (issue 44): per-chain plants under a controller that knows its model, and what it sees."""

import math

import numpy as np
import pytest
from stations_synthetic import deviated, reference_carriages

import hipsim
from hipsim.analytic import kernel as reduced_kernel
from hipsim.analytic.stations import platform_attitude
from hipsim.closed_chain.plant import PinocchioPlant
from hipsim.control import chain_kernel
from hipsim.control.controllers import AugmentedPD
from hipsim.control.feedback import EncoderFeedback, SensorFeedback, encoder_reading
from hipsim.control.machine_loop import ModelPD, check_plant, controlled_machine, model_feedforward, run_machine
from hipsim.control.simulation import simulate
from hipsim.control.tracking import MachineRun, error_columns
from hipsim.exceptions import ArgumentError, ParameterError
from hipsim.motion.trajectories import Trajectory, iso14242_at
from hipsim.stations.summary import error_columns as station_error_columns

DURATION = 0.1  # s: 100 servo periods


@pytest.fixture(scope="module")
def drawing():
    return hipsim.load_parameters()


@pytest.fixture(scope="module")
def built(drawing):
    """A machine whose 48 chain values deviate within ±0.3 mm: the hidden true machine."""
    return drawing.replace(geometry=deviated(seed=5))


@pytest.fixture(scope="module")
def plant(built):
    return PinocchioPlant(built)


def _run(plant, model, feedback, augmented=True, compiled=None):
    c = feedback.control
    ff = model_feedforward(model, c, iso14242_at, model.control.servo_rate, DURATION) if augmented else None
    return run_machine(plant, ModelPD(model, c), feedback, iso14242_at, DURATION, feedforward=ff, compiled=compiled)


def test_encoders_round_to_their_step():
    L = np.array([0.5626314, 0.5626315001, -0.0000004])
    assert encoder_reading(L, 1e-6) == pytest.approx([0.562631, 0.562632, 0.0], abs=1e-15)
    assert np.array_equal(encoder_reading(L, 0.0), L)


def test_sensor_drift_and_noise():
    t = np.arange(20000) / 1000.0
    drift = SensorFeedback(2, noise=0.0, drift=math.radians(0.6) / 60.0)  # 0.6°/min: 0.01° after 1 s
    drift.start(t, np.zeros(3))
    q = np.zeros((2, 3))
    _, seen, _ = drift.measure(1000, 1.0, np.zeros(3), np.zeros(3), q, q)
    assert np.degrees(seen) == pytest.approx([0.01] * 3, rel=1e-12)
    noisy, again = (
        SensorFeedback(1, noise=math.radians(0.05), seed=3),
        SensorFeedback(1, noise=math.radians(0.05), seed=3),
    )
    for sensor in (noisy, again):
        sensor.start(t, np.zeros(3))
    offsets = np.array([noisy.measure(k, t[k], np.zeros(3), np.zeros(3), q, q)[1] for k in range(t.size)])
    assert np.degrees(offsets.std(axis=0)) == pytest.approx([0.05] * 3, rel=0.03)
    assert np.array_equal(offsets[7], again.measure(7, t[7], np.zeros(3), np.zeros(3), q, q)[1])
    with pytest.raises(ArgumentError, match="noise"):
        SensorFeedback(2, noise=-1e-3)
    with pytest.raises(ArgumentError, match="control"):
        SensorFeedback(3)


@pytest.mark.parametrize("j", [1, 2])
def test_chain_kernel_against_the_hand_reference(drawing, built, j):
    """Carriages from SciPy's rotations (tests/stations_synthetic.py); attitude round trip; rates by finite differences."""
    q = np.radians([12.0, -4.0, 7.0])
    arrays = chain_kernel.platform_arrays(built, j)
    L = chain_kernel.carriages(*arrays, q)
    assert L == pytest.approx(reference_carriages(built, built.geometry, j, q[None])[0], abs=1e-13)
    assert chain_kernel.attitude(*arrays, L, q + 0.02) == pytest.approx(q, abs=1e-13)
    qd, h = np.array([0.3, -0.2, 0.5]), 1e-6
    Ld = (
        reference_carriages(built, built.geometry, j, (q + h * qd)[None])[0]
        - reference_carriages(built, built.geometry, j, (q - h * qd)[None])[0]
    ) / (2 * h)
    assert chain_kernel.rates(*arrays, q, Ld) == pytest.approx(qd, rel=1e-7)


def test_model_pd_on_the_drawing_is_the_workspace_pd(drawing):
    q, qd, qe, qde = (
        np.radians([10.0, 2.0, -3.0]),
        np.array([0.1, 0.2, -0.1]),
        np.radians([11.0, 1.0, -2.0]),
        np.zeros(3),
    )
    pd = ModelPD(drawing, 2)
    expected = reduced_kernel.workspace_pd(reduced_kernel.kernel_parameters(drawing), q, qd, qe, qde, pd.kp, pd.kd)
    assert pd.torques(q, qd, qe, qde) == pytest.approx(expected, rel=1e-12)


def test_a_per_chain_plant_agrees_with_the_stations(built, plant, drawing):
    """The plant's carriages and true attitudes: the stations' forward kinematics of those carriages to 1e-9°."""
    run = _run(plant, drawing, EncoderFeedback(drawing, 2, step=0.0), augmented=False)
    for j in (1, 2):
        q = platform_attitude(built, run.carriages, j, q0=run.desired.q[0], guess=run.desired.q)
        assert np.degrees(np.abs(q - run.attitudes[:, j - 1])).max() < 1e-9
    # The drawing's model reads the built machine's encoders wrongly: m_2 is off by what the chains deviate.
    assert 1e-3 < np.degrees(np.abs(run.errors[:, 1])).max() < 1.0


@pytest.mark.parametrize("control", [2, 1])
def test_noiseless_sensor_tracks_as_on_the_drawing(drawing, built, control):
    """Sensor feedback, a model that is the machine: the controlled platform tracks as today's run on the drawing;
    the follower as the stations say for the carriages."""
    plant = PinocchioPlant(controlled_machine(built, control))
    run = _run(plant, controlled_machine(built, control), SensorFeedback(control, noise=0.0, encoder_step=0.0))
    today = simulate(
        PinocchioPlant(drawing), AugmentedPD(drawing, iso14242_at, 1000.0, DURATION), iso14242_at, DURATION
    )
    c, f = control - 1, 2 - control
    assert np.degrees(np.abs(run.errors[:, c] - today.err)).max() < 1e-4
    follower = platform_attitude(built, run.carriages, f + 1, q0=run.desired.q[0], guess=run.desired.q)
    assert np.degrees(np.abs((run.desired.q - follower) - run.errors[:, f])).max() < 1e-9
    assert np.degrees(np.abs(run.errors[:, f])).max() > 0.01  # the follower carries the machine's deviation


def test_the_drawing_as_plant_in_the_new_loop_is_todays_run(drawing):
    plant = PinocchioPlant(drawing)
    run = _run(plant, drawing, SensorFeedback(2, noise=0.0, encoder_step=0.0))
    today = simulate(plant, AugmentedPD(drawing, iso14242_at, 1000.0, DURATION), iso14242_at, DURATION)
    assert np.abs(run.errors - today.err[:, None]).max() < 1e-15
    assert np.abs(run.tau - today.tau).max() < 1e-12


@pytest.mark.parametrize("sensors", [False, True])
def test_compiled_and_python_loops_are_one_arithmetic(drawing, plant, sensors):
    def feedback():
        return SensorFeedback(2, noise=math.radians(0.05), seed=1) if sensors else EncoderFeedback(drawing, 2)

    a = _run(plant, drawing, feedback(), compiled=True)
    b = _run(plant, drawing, feedback(), compiled=False)
    for name in ("carriages", "attitudes", "measured", "tau", "motor_speed"):
        assert np.array_equal(getattr(a, name), getattr(b, name)), name


def test_the_loop_refuses_what_does_not_fit(drawing, plant):
    with pytest.raises(ArgumentError, match="feedback"):
        run_machine(plant, ModelPD(drawing, 2), SensorFeedback(1), iso14242_at, DURATION)
    with pytest.raises(ArgumentError, match="controlled_machine"):
        run_machine(plant, ModelPD(drawing, 1), SensorFeedback(1), iso14242_at, DURATION)
    with pytest.raises(ArgumentError, match="feedforward"):
        run_machine(plant, ModelPD(drawing, 2), SensorFeedback(2), iso14242_at, DURATION, feedforward=np.zeros((3, 3)))


def test_a_plant_of_another_design_is_refused(drawing, built):
    desired = iso14242_at(np.arange(100) / 1000.0)
    check_plant(drawing, built, desired, 2)  # the machine as built: fine
    with pytest.raises(ParameterError, match="lever length of chain 11 is 60.0 mm off"):
        check_plant(drawing, drawing.replace(lever_length=drawing.lever_length + 0.06), desired, 2)
    with pytest.raises(ParameterError, match="angle signs"):
        check_plant(drawing, built.replace(angle_signs=np.array([1.0, -1.0, 1.0])), desired, 2)


def test_summary_by_hand(drawing):
    """Errors 0.1·k° on m_1's α at t = k ms: RMS √(Σ(0.1k)²/n), peak the last, at its time."""
    n = 5
    t = np.arange(n) / 1000.0
    desired = Trajectory(t, np.zeros((n, 3)), np.zeros((n, 3)), np.zeros((n, 3)), np.full(n, 300.0))
    attitudes = np.zeros((n, 2, 3))
    attitudes[:, 0, 0] = -np.radians(0.1 * np.arange(n))
    z = np.zeros((n, 3))
    run = MachineRun(t, desired, z, attitudes, attitudes, z, z, z, np.zeros(n, bool), z, "p", "pd", "sensors", 2, 5e-4)
    s = run.summary()
    e = s.error(1, "alpha")
    assert (e.rms_deg, e.peak_deg, e.peak_at_s, e.controlled) == pytest.approx(
        (math.sqrt(sum((0.1 * k) ** 2 for k in range(n)) / n), 0.4, 0.004, False)
    )
    assert s.error(2, "gamma").rms_deg == 0.0 and s.error(2, "gamma").controlled
    assert s.to_json()["errors"][0] == {
        "platform": 1,
        "angle": "alpha",
        "controlled": False,
        "rms_deg": e.rms_deg,
        "peak_deg": e.peak_deg,
        "peak_at_s": e.peak_at_s,
    }
    assert error_columns() == station_error_columns()  # the stations' column names
    assert run.columns()["err_alpha_1_deg"][4] == pytest.approx(0.4)


def test_the_mujoco_plant_per_chain_agrees_with_pinocchio(drawing, built, plant):
    """MuJoCo's soft closures against Pinocchio's rigid ones, the same built machine and loop: within 1e-4°."""
    pytest.importorskip("mujoco")
    from hipsim.mujoco_engine.plant import MujocoPlant

    feedback = SensorFeedback(2, noise=0.0, encoder_step=0.0)
    a = _run(MujocoPlant(built), drawing, feedback)
    b = _run(plant, drawing, SensorFeedback(2, noise=0.0, encoder_step=0.0))
    assert np.degrees(np.abs(a.attitudes - b.attitudes)).max() < 1e-4
    assert np.abs(a.carriages - b.carriages).max() < 1e-7  # m
    # Its readings on the drawing: the carriages of the drawing's inverse kinematics.
    mujoco_plant = MujocoPlant(drawing)
    x = mujoco_plant.initial_state(iso14242_at(np.zeros(1)))
    L, _, q, _ = mujoco_plant.readings(x)
    expected = chain_kernel.carriages(*chain_kernel.platform_arrays(drawing, 1), q[0])
    assert L == pytest.approx(expected, abs=1e-12)
