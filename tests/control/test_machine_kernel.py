"""hipsim.control.machine_kernel: the loop of run_machine on the Pinocchio plant of a machine as built, compiled whole.

Against the Python loop it compiles, to the last bit (three periods, both feedbacks, a limit that bites); and by hand
on one period: the carriages read as the encoders quantise them, both platforms' attitudes and rates signed from
their slots, the sensor's true attitude plus its offset, the feed-forward row added to the model's PD, the limit
biting strictly above it; a state that is not finite or a reading without an attitude stops the run at its period.

The direct calls take the argument types run_machine passes (recorded from its runs), so they run the specialisation
compiled for it.
"""

from __future__ import annotations

import inspect
import math

import numpy as np
import pytest
from stations_synthetic import deviated
from support import RAMP_Q0 as Q0
from support import Recorded, argument_types, recorded_calls, turn

import hipsim
from hipsim.control import machine_kernel
from hipsim.control.feedback import EncoderFeedback, SensorFeedback
from hipsim.control.machine_loop import ModelPD, run_machine

NAMES = list(inspect.signature(getattr(machine_kernel.machine_loop, "py_func", machine_kernel.machine_loop)).parameters)
LOG = ("carriages", "attitudes", "rates", "speeds", "measured", "tau", "tau_requested", "saturated")
FF = np.array([[0.01, -0.02, 0.03], [0.0, 0.01, 0.0], [-0.01, 0.0, 0.02]])


@pytest.fixture(scope="module")
def drawing():
    return hipsim.load_parameters()


_desired = turn  # the motion of tests/support.py


@pytest.fixture(scope="module")
def pinocchio_plant(drawing):
    from hipsim.closed_chain.plant import PinocchioPlant

    return PinocchioPlant(drawing.replace(geometry=deviated(seed=5)))


def _feedback(drawing, sensors: bool):
    return SensorFeedback(2, noise=math.radians(0.05), seed=1) if sensors else EncoderFeedback(drawing, 2)


def _run(drawing, plant, sensors: bool, compiled, limit=None):
    return run_machine(
        plant, ModelPD(drawing, 2), _feedback(drawing, sensors), _desired, 0.003, feedforward=FF, servo_rate=1000.0,
        step=5e-4, torque_limit=limit, compiled=compiled,
    )  # fmt: skip


@pytest.mark.parametrize("sensors", [False, True])
def test_three_periods_of_the_pinocchio_plant_compiled_and_in_python_are_one_arithmetic(
    drawing, pinocchio_plant, sensors
):
    """The compiled route through machine_kernel (the plant's compiled RK4 steps, the feedback, the feed-forward and
    the limit in one call) against the Python loop, on three periods of the Pinocchio plant of a built machine: equal
    to the last bit, and the limit biting on some torques."""
    free = _run(drawing, pinocchio_plant, sensors, False)
    limit = 0.7 * float(np.abs(free.tau).max())
    for torque_limit in (None, limit):
        a, b = (
            _run(drawing, pinocchio_plant, sensors, True, torque_limit),
            _run(drawing, pinocchio_plant, sensors, False, torque_limit),
        )
        for name in ("t", "carriages", "attitudes", "measured", "tau", "tau_requested", "saturated", "motor_speed"):
            assert np.array_equal(getattr(a, name), getattr(b, name)), name
    assert np.count_nonzero(b.saturated) > 0 and np.abs(b.tau).max() == pytest.approx(limit, rel=1e-15)
    # The run starts on the desired motion (the plant's platform 2 at the desired pose), a period apart.
    assert free.t.tolist() == pytest.approx([0.0, 0.001, 0.002], abs=1e-15)
    assert free.attitudes[0, 1] == pytest.approx(Q0, abs=1e-9)


@pytest.fixture(scope="module")
def recorded(drawing, pinocchio_plant):
    """run_machine's first call of machine_loop (period 0 alone) and its run, for the encoders and the sensors."""
    calls = {}
    with pytest.MonkeyPatch.context() as patch:
        for sensors in (False, True):
            made = recorded_calls(patch, machine_kernel, "machine_loop")
            run = _run(drawing, pinocchio_plant, sensors, True)
            patch.undo()
            calls[sensors] = Recorded(dict(zip(NAMES, made[0][0], strict=True)), made[0][1]), run
    return calls, pinocchio_plant.initial_state(_desired(np.zeros(1)))


def _loop(recorded: Recorded, x0: np.ndarray, stop: int = 1, **changes):
    """machine_loop over periods 0 … stop − 1 from x0 (copied) on fresh logs (NaN, True flags), the encoders' guess
    Q0, and some arguments changed."""
    encoders, step, offsets, _ = recorded.args["sensing"]
    log = tuple(np.full_like(logged, True if logged.dtype == bool else np.nan) for logged in recorded.args["log"])
    args = dict(recorded.args, x=x0.copy(), sensing=(encoders, step, offsets, Q0.copy()), start=0, stop=stop, log=log)
    args.update(changes)
    assert argument_types(tuple(args.values())) == recorded.types  # run_machine's types
    return machine_kernel.machine_loop(*(args[name] for name in NAMES)), dict(zip(LOG, args["log"], strict=True))


def test_a_period_reads_the_encoders_and_both_platforms_by_hand(drawing, recorded):
    """Carriages rounded to the encoders' 1 µm, their rates as they are, each platform's angles and rates the
    plant's coordinates at its slots times the angle signs."""
    calls, x0 = recorded
    recorded_call, _ = calls[False]
    call = recorded_call.args
    sliders, platforms, nq = call["slots"]
    step = call["sensing"][1]
    reached, log = _loop(recorded_call, x0)
    assert reached == 1 and step == 1e-6
    L = x0[sliders]
    assert log["carriages"][0].tolist() == (np.rint(L / step) * step).tolist()
    assert 0 < np.abs(log["carriages"][0] - L).max() <= step / 2
    assert log["speeds"][0].tolist() == x0[nq + sliders].tolist()
    signs = call["signs"]
    for j in range(2):
        assert log["attitudes"][0, j].tolist() == (signs * x0[platforms[j]]).tolist()
        assert log["rates"][0, j].tolist() == (signs * x0[nq + platforms[j]]).tolist()
    # What the encoders' Python route (EncoderFeedback.measure: the drawing's forward kinematics from the guess Q0)
    # sees in that reading: the drawing's attitude, a few mrad off the built machine's.
    feedback = EncoderFeedback(drawing, 2)
    feedback.start(np.zeros(3), Q0)
    reading, angles, _ = feedback.measure(0, 0.0, L, x0[nq + sliders], log["attitudes"][0], log["rates"][0])
    assert log["carriages"][0].tolist() == reading.tolist() and log["measured"][0].tolist() == angles.tolist()
    assert 1e-4 < np.abs(angles - log["attitudes"][0, 1]).max() < 1e-2
    assert np.isnan(log["carriages"][1:]).all()  # period 0 only


def test_the_sensor_sees_the_true_attitude_plus_its_offset(recorded):
    calls, x0 = recorded
    sensor, _ = calls[True]
    call = sensor.args
    offsets = call["sensing"][2]
    reached, log = _loop(sensor, x0)
    assert reached == 1 and np.abs(offsets[0]).min() > 0
    assert log["measured"][0].tolist() == (log["attitudes"][0, call["control"]] + offsets[0]).tolist()
    assert call["control"] == 1  # platform 2


def test_the_feedforward_row_adds_to_the_pd_and_the_limit_bites_strictly_above_it(recorded):
    """Row 0 of the feed-forward raised by δ raises the request by δ (the PD is the state's, unchanged); a limit at
    the request's largest magnitude keeps every torque and flags none, a limit a hair below clips that one and flags."""
    calls, x0 = recorded
    call, _ = calls[True]
    _, base = _loop(call, x0)
    delta = np.array([0.25, -0.5, 1.0])
    raised = call.args["feedforward"].copy()
    raised[0] += delta
    _, more = _loop(call, x0, feedforward=raised)
    np.testing.assert_allclose(more["tau_requested"][0] - base["tau_requested"][0], delta, rtol=0, atol=1e-14)
    wanted = base["tau_requested"][0]
    top = float(np.abs(wanted).max())
    _, at = _loop(call, x0, limit=top)
    assert at["tau"][0].tolist() == wanted.tolist() and not at["saturated"][0]
    _, below = _loop(call, x0, limit=math.nextafter(top, 0.0))
    i = int(np.argmax(np.abs(wanted)))
    assert below["saturated"][0] and below["tau"][0, i] == math.copysign(math.nextafter(top, 0.0), wanted[i])


def test_a_state_not_finite_or_a_reading_without_attitude_stops_the_run_at_its_period(recorded):
    """A NaN in the state: period 0 returned, nothing logged, x kept. Encoders reading a carriage 0.2 m away, where
    the model has no attitude: period 0 returned, its readings logged and no measurement, the state still finite."""
    calls, x0 = recorded
    call, _ = calls[False]
    sliders = call.args["slots"][0]
    x = x0.copy()
    x[-1] = math.nan
    reached, log = _loop(call, x, stop=3)
    assert reached == 0 and all(np.isnan(log[name]).all() for name in LOG[:-1]) and log["saturated"].all()
    x = x0.copy()
    x[sliders[0]] += 0.2
    reached, log = _loop(call, x, stop=3)
    assert reached == 0 and np.isfinite(log["carriages"][0]).all() and np.isfinite(log["attitudes"][0]).all()
    assert np.isnan(log["measured"]).all() and np.isnan(log["tau"]).all()
