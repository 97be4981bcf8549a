"""What the controller sees (hipsim.control.feedback): the encoders' rounding, the model's attitude from them, the
sensor's noise and drift, and every setting's refusal at its edge."""

import math

import numpy as np
import pytest

import hipsim
from hipsim.control import chain_kernel
from hipsim.control.feedback import (
    DEFAULT_ENCODER_STEP,
    DEFAULT_SENSOR_NOISE,
    EncoderFeedback,
    SensorFeedback,
    encoder_reading,
)
from hipsim.exceptions import ArgumentError


@pytest.fixture(scope="module")
def drawing():
    return hipsim.load_parameters()


def test_the_defaults():
    assert DEFAULT_ENCODER_STEP == 1e-6 and DEFAULT_SENSOR_NOISE == pytest.approx(math.radians(0.05), rel=1e-15)
    sensor = SensorFeedback(2)
    assert (sensor.noise, sensor.drift, sensor.seed, sensor.step) == (DEFAULT_SENSOR_NOISE, 0.0, 0, 1e-6)
    assert (sensor.name, sensor.control) == ("sensors", 2)


def test_encoders_round_half_steps_to_even_and_negative_readings_down():
    L = np.array([2.5e-3, -0.7e-3, 3.49e-3])
    assert encoder_reading(L, 1e-3) == pytest.approx([2e-3, -1e-3, 3e-3], abs=1e-15)
    exact = encoder_reading(np.array([1, 2, 3]), 0.0)  # an exact reading is a float copy
    assert exact.dtype == float and exact.tolist() == [1.0, 2.0, 3.0]


@pytest.mark.parametrize("control", [0, 3, True, -1])
def test_only_platforms_1_and_2_are_controlled(control, drawing):
    with pytest.raises(ArgumentError, match="control"):
        SensorFeedback(control)
    with pytest.raises(ArgumentError, match="control"):
        EncoderFeedback(drawing, control)


@pytest.mark.parametrize("control", [1, 2])
def test_either_platform_is_controlled(control, drawing):
    assert SensorFeedback(control).control == control
    assert EncoderFeedback(drawing, control).control == control


def test_settings_are_refused_beyond_their_edges(drawing):
    for step in (-1e-9, math.nan, math.inf):
        with pytest.raises(ArgumentError, match="^step: expected an encoder step >= 0 in m"):
            EncoderFeedback(drawing, 2, step=step)
        with pytest.raises(ArgumentError, match="^encoder_step: expected an encoder step >= 0 in m"):
            SensorFeedback(2, encoder_step=step)
    for noise in (-1e-12, math.nan, math.inf):
        with pytest.raises(ArgumentError, match="^noise: expected a standard deviation >= 0 in rad"):
            SensorFeedback(2, noise=noise)
    for drift in (math.nan, math.inf, -math.inf):
        with pytest.raises(ArgumentError, match="^drift: expected a finite drift in rad/s"):
            SensorFeedback(2, drift=drift)
    # The edges themselves are fine: exact encoders, a noiseless sensor, a negative drift.
    assert EncoderFeedback(drawing, 2, step=0.0).step == 0.0
    sensor = SensorFeedback(2, noise=0.0, drift=-1e-3, seed=7.0, encoder_step=0.0)  # type: ignore[arg-type]
    assert (sensor.noise, sensor.drift, sensor.seed, sensor.step) == (0.0, -1e-3, 7, 0.0)


def test_the_encoders_read_the_model_s_attitude_and_rates(drawing):
    """The carriages of a pose by the model's inverse kinematics, read back with a step of 1 nm, give the pose."""
    for control in (1, 2):
        arrays = chain_kernel.platform_arrays(drawing, control)
        q = np.radians([10.0, -3.0, 5.0])
        L = chain_kernel.carriages(*arrays, q)
        feedback = EncoderFeedback(drawing, control, step=1e-9)
        assert feedback.name == "encoders"
        feedback.start(np.arange(3) * 1e-3, q + 0.01)
        ready, step, offsets, last = feedback.sensing()
        assert ready is True and step == 1e-9 and offsets.tolist() == [[0.0, 0.0, 0.0]]
        assert last == pytest.approx(q + 0.01, abs=0)
        Ld = np.array([1e-3, -2e-3, 0.5e-3])
        reading, angles, rates = feedback.measure(0, 0.0, L, Ld, np.zeros((2, 3)), np.zeros((2, 3)))
        assert reading == pytest.approx(np.rint(L / 1e-9) * 1e-9, abs=1e-15)
        assert angles == pytest.approx(q, abs=1e-8)
        assert rates == pytest.approx(chain_kernel.rates(*arrays, angles, Ld), rel=1e-12)
        assert feedback.sensing()[3] is angles  # the next period starts from this attitude


def test_an_unreadable_attitude_keeps_the_last_one(drawing):
    feedback = EncoderFeedback(drawing, 2, step=0.0)
    q0 = np.radians([5.0, 1.0, -2.0])
    feedback.start(np.zeros(2), q0)
    _, angles, _ = feedback.measure(0, 0.0, np.full(3, 10.0), np.zeros(3), np.zeros((2, 3)), np.zeros((2, 3)))
    assert not np.all(np.isfinite(angles))
    assert feedback.sensing()[3] == pytest.approx(q0, abs=0)


def test_the_sensor_reads_its_platform_with_noise_and_drift():
    t = np.array([0.0, 0.5, 1.0])
    q = np.array([[0.1, 0.2, 0.3], [0.4, 0.5, 0.6]])
    qd = np.array([[1.0, 2.0, 3.0], [4.0, 5.0, 6.0]])
    L = np.array([2.4e-6, 1.2e-6, -0.4e-6])
    for control in (1, 2):
        sensor = SensorFeedback(control, noise=0.0, drift=0.02, encoder_step=1e-6)
        sensor.start(t, np.zeros(3))
        reading, seen, rates = sensor.measure(2, 1.0, L, np.zeros(3), q, qd)
        assert reading == pytest.approx([2e-6, 1e-6, 0.0], abs=1e-15)
        assert seen == pytest.approx(q[control - 1] + 0.02, rel=1e-12)
        assert rates.tolist() == qd[control - 1].tolist() and rates is not qd[control - 1]
        ready, step, offsets, last = sensor.sensing()
        assert (ready, step, last.tolist()) == (False, 1e-6, [0.0, 0.0, 0.0])
        assert offsets == pytest.approx(np.outer(t, [0.02] * 3), abs=1e-15)
    # White noise: the seed's standard normal numbers times the noise, plus the drift.
    sensor = SensorFeedback(1, noise=0.3, drift=0.02, seed=4)
    sensor.start(t, np.zeros(3))
    white = np.random.default_rng(4).standard_normal((3, 3))
    assert sensor.sensing()[2] == pytest.approx(0.3 * white + np.outer(t, [0.02] * 3), rel=1e-12)


def test_refusals_name_the_setting_and_its_value_whole(drawing):
    for make, message in (
        (lambda: SensorFeedback(3), "control: expected 1 (m_1) or 2 (m_2), got 3"),
        (lambda: SensorFeedback(True), "control: expected 1 (m_1) or 2 (m_2), got True"),
        (lambda: EncoderFeedback(drawing, 0), "control: expected 1 (m_1) or 2 (m_2), got 0"),
        (lambda: EncoderFeedback(drawing, 2, step=-1e-9), "step: expected an encoder step >= 0 in m, got -1e-09"),
        (lambda: SensorFeedback(2, noise=-0.5), "noise: expected a standard deviation >= 0 in rad, got -0.5"),
        (lambda: SensorFeedback(2, drift=math.inf), "drift: expected a finite drift in rad/s, got inf"),
        (lambda: SensorFeedback(2, encoder_step=-2.0), "encoder_step: expected an encoder step >= 0 in m, got -2.0"),
    ):
        with pytest.raises(ArgumentError) as error:
            make()
        assert str(error.value) == message


def test_the_defaults_are_the_documented_instruments(drawing):
    """Encoders of 1 µm, a sensor of 0.05° white noise, no drift, seed 0; nothing read before a run starts."""
    sensor = SensorFeedback(1)
    assert (sensor.noise, sensor.drift, sensor.seed, sensor.step) == (math.radians(0.05), 0.0, 0, 1e-6)
    assert sensor.control == 1 and sensor.name == "sensors" and sensor.sensing()[2].shape == (0, 3)
    encoders = EncoderFeedback(drawing, 1)
    assert encoders.step == 1e-6 and encoders.sensing()[3].tolist() == [0.0, 0.0, 0.0]
    # A noiseless sensor's offsets are the drift alone, (n, 3), whatever the seed.
    quiet = SensorFeedback(2, noise=0.0, drift=0.5, seed=9)
    quiet.start(np.array([0.0, 2.0]), np.zeros(3))
    assert quiet.sensing()[2].tolist() == [[0.0, 0.0, 0.0], [1.0, 1.0, 1.0]]
