"""The controller's model in the servo loop sees its own stack-up (issue 44, point 4): m_1 controlled on a stacked model.

The compiled ``model_*`` functions against the stations' Python laws (:mod:`hipsim.analytic.stations`), against
today's functions call for call with a zero seat, and in closed loop on an exact plant of the stacked machine (:class:`hipsim.control.chain_plant.ChainPlant`).
"""

import numpy as np
import pytest
from stations_synthetic import deviated

import hipsim
from hipsim.analytic.stations import carriages_for_platform, platform_attitude, stacked_motion
from hipsim.control import chain_kernel
from hipsim.control.chain_plant import ChainPlant
from hipsim.control.feedback import EncoderFeedback
from hipsim.control.machine_loop import ModelPD, controlled_machine, model_feedforward, run_machine
from hipsim.control.simulation import ReducedPlant
from hipsim.motion.trajectories import iso14242_at
from hipsim.physics.orientation import angular_velocity_map

DRAWING = hipsim.load_parameters()
CHAINS = deviated(seed=5)  # the chains built to ±0.3 mm
SEAT = np.array([1.0e-3, 2.0e-3, -1.0e-3])
STACKED = DRAWING.replace(geometry=CHAINS.replace(spline=SEAT, control=1))
FLAT = DRAWING.replace(geometry=CHAINS.replace(control=1))
Q = np.radians([[12.0, -4.0, 7.0]])
QD = np.array([[0.3, -0.2, 0.5]])
GAINS = (np.array([1000.0, 2000.0, 3000.0]), np.array([10.0, 20.0, 30.0]))


@pytest.mark.parametrize("control", [1, 2])
def test_a_zero_seat_is_todays_functions_call_for_call(control):
    model, today = chain_kernel.model_arrays(FLAT, control), chain_kernel.platform_arrays(FLAT, control)
    L = carriages_for_platform(FLAT, Q, control)[0]
    q = chain_kernel.model_attitude(*model, L, Q[0] + 0.01)
    assert np.array_equal(q, chain_kernel.attitude(*today, L, Q[0] + 0.01))
    assert np.array_equal(chain_kernel.model_rates(*model, q, QD[0]), chain_kernel.rates(*today, q, QD[0]))
    args = (q, QD[0], Q[0] + 0.02, np.zeros(3), *GAINS)
    lead = float(FLAT.lead)
    assert np.array_equal(chain_kernel.model_pd(*model, lead, *args), chain_kernel.workspace_pd(*today, lead, *args))
    # m_2 controlled: its attitude never depends on the seat, so the stacked model is today's there too
    assert not np.any(chain_kernel.model_arrays(STACKED, 2)[-1])


def test_the_stacked_model_reads_the_encoders_as_the_stations_do():
    """m_1's attitude and rate from the carriages through m_2 and the lift: the stations' Python laws to 1e-12."""
    model = chain_kernel.model_arrays(STACKED, 1)
    L, Ld, _, _ = stacked_motion(STACKED, Q, QD, np.zeros((1, 3)))
    q = chain_kernel.model_attitude(*model, L[0], Q[0] + 0.01)
    assert q == pytest.approx(Q[0], abs=1e-13)
    assert chain_kernel.model_rates(*model, q, Ld[0]) == pytest.approx(QD[0], abs=1e-12)
    # Read without the seat, the same carriages put m_1 elsewhere: the lift is seen.
    assert np.abs(chain_kernel.attitude(*chain_kernel.platform_arrays(STACKED, 1), L[0], Q[0]) - Q[0]).max() > 1e-5


def test_the_stacked_pd_does_the_work_of_its_moment():
    """Virtual power: the PD's motor torques times the motor speeds equal its moment M times m_1's ω_1."""
    model, lead = chain_kernel.model_arrays(STACKED, 1), float(STACKED.lead)
    _, Ld, _, _ = stacked_motion(STACKED, Q, QD, np.zeros((1, 3)))
    q_desired = Q[0] + np.radians([1.0, -0.5, 0.7])
    tau = chain_kernel.model_pd(*model, lead, Q[0], QD[0], q_desired, np.zeros(3), *GAINS)
    moment = STACKED.angle_signs * (GAINS[0] * (q_desired - Q[0]) - GAINS[1] * QD[0])
    omega = angular_velocity_map(Q * STACKED.angle_signs)[0] @ (QD[0] * STACKED.angle_signs)
    motor_speed = Ld[0] * 2 * np.pi / lead
    assert tau @ motor_speed == pytest.approx(moment @ omega, rel=1e-12)
    flat = chain_kernel.workspace_pd(
        *chain_kernel.platform_arrays(STACKED, 1), lead, Q[0], QD[0], q_desired, np.zeros(3), *GAINS
    )
    assert abs(flat @ motor_speed - moment @ omega) > 1e-4 * abs(moment @ omega)  # the seat's term matters


def test_a_stacked_model_on_its_stacked_plant_tracks_as_the_drawing():
    """Noiseless encoders, the augmented PD, m_1 controlled: the stacked model reads m_1 exactly and tracks it as
    the drawing's model tracks the drawing (today's test's 1e-4°); m_2 goes where the stations say."""
    duration, rate = 0.01, DRAWING.control.servo_rate
    machine = controlled_machine(STACKED, 1)

    def run(model, plant):
        ff = model_feedforward(model, 1, iso14242_at, rate, duration)
        feedback = EncoderFeedback(model, 1, step=0.0)
        return run_machine(plant, ModelPD(model, 1), feedback, iso14242_at, duration, feedforward=ff, step=1e-3)

    stacked, drawing = run(machine, ChainPlant(machine)), run(DRAWING, ReducedPlant(DRAWING))
    assert np.degrees(np.abs(stacked.measured - stacked.attitudes[:, 0])).max() < 1e-9
    assert np.degrees(np.abs(stacked.errors[:, 0] - drawing.errors[:, 0])).max() < 1e-4
    m2 = platform_attitude(machine, stacked.carriages, 2, q0=stacked.desired.q[0], guess=stacked.desired.q)
    assert np.degrees(np.abs(m2 - stacked.attitudes[:, 1])).max() < 1e-9
    # The model without its seat reads the same carriages off by far more: what the stack-up's model fixes.
    blind = EncoderFeedback(FLAT, 1, step=0.0)
    blind.start(stacked.t, stacked.desired.q[0])
    seen = blind.measure(5, stacked.t[5], stacked.carriages[5], np.zeros(3), stacked.attitudes[5], stacked.attitudes[5])
    assert np.degrees(np.abs(seen[1] - stacked.attitudes[5, 0])).max() > 1e-3


def test_the_compiled_loop_reads_a_stacked_model_as_the_python_loop():
    """A stacked model (m_1 controlled) over a plant without the seat: the compiled loop is the Python one, bit for
    bit, and m_1's reading carries the model's lift (the plant's m_1 is off by it)."""
    from hipsim.closed_chain.plant import PinocchioPlant

    plant = PinocchioPlant(controlled_machine(FLAT, 1))
    runs = [
        run_machine(plant, ModelPD(STACKED, 1), EncoderFeedback(STACKED, 1), iso14242_at, 0.01, compiled=compiled)
        for compiled in (True, False)
    ]
    for name in ("carriages", "attitudes", "measured", "tau"):
        assert np.array_equal(getattr(runs[0], name), getattr(runs[1], name)), name
    assert np.degrees(np.abs(runs[0].errors[:, 0])).max() > 1e-3  # the model's seat is not the plant's
