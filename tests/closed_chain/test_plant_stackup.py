"""The Pinocchio plant with the intermediate chain's stack-up: forward dynamics that invert the closed-chain inverse
dynamics, with the load doing work on m_1's riding centre; the route that cannot take the massless slides refused."""

import numpy as np
import pytest
from stations_synthetic import deviated
from support import given

import hipsim
from hipsim.closed_chain.build import load_model
from hipsim.closed_chain.closure import kinematics
from hipsim.closed_chain.dynamics import trajectory_dynamics
from hipsim.closed_chain.plant import PinocchioPlant
from hipsim.exceptions import ArgumentError
from hipsim.motion.trajectories import iso14242_at

PARAMS = hipsim.load_parameters()
CHAINS = deviated(seed=3)
STACKED = PARAMS.replace(geometry=CHAINS.replace(spline=np.array([1e-3, 2e-3, -1e-3])))
SERVO, STEP, PERIODS = 1000.0, 0.5e-3, 40  # [Hz], [s], 0.04 s


@pytest.fixture(scope="module")
def plant():
    return PinocchioPlant(STACKED)


def test_forward_dynamics_invert_the_inverse_dynamics(plant):
    desired = iso14242_at([0.13, 0.5, 0.77])
    kin, dynamics = trajectory_dynamics(plant.chain, desired)
    slide = given(plant.chain.layout).stackup_v[0]
    for k in range(3):
        x = np.concatenate([kin.q[k], kin.v[k]])
        forces = plant.generalised_forces(x, dynamics.torques.total[k], desired.Fe[k])
        assert forces[slide] == -desired.Fe[k]  # the load presses m_1's centre down its slide
        dx = plant.derivative(desired.t[k], x, dynamics.torques.total[k], desired.Fe[k])
        # Measured 3e-13 of the largest acceleration (Baumgarte on the ≤ 1e-12 m gaps the kinematics leave).
        np.testing.assert_allclose(dx[plant.nq :], kin.a[k], rtol=0, atol=1e-9 * np.abs(kin.a[k]).max())


def test_inverse_then_forward_reproduces_the_motion_of_both_platforms(plant):
    """Mid-period inverse-dynamics torques, held over each servo period, from the closed state: both platforms follow."""
    instants = np.arange(PERIODS + 1) / SERVO
    torques = trajectory_dynamics(plant.chain, iso14242_at(instants[:-1] + 0.5 / SERVO))[1].torques.total
    kin = trajectory_dynamics(plant.chain, iso14242_at(instants))[0]
    x = np.concatenate([kin.q[0], kin.v[0]])
    substeps = int(round(1 / SERVO / STEP))
    for k in range(PERIODS):
        loads = iso14242_at(instants[k] + np.arange(2 * substeps + 1) * STEP / 2).Fe
        x = plant.advance(instants[k], x, torques[k], loads, STEP, substeps)
    platforms = given(plant.chain.layout).platform_v
    drift = np.degrees(np.abs(x[platforms] - kin.q[-1][platforms])).max()
    # Measured: the stack-up moves m_1 by 1.2° here, the zero-order hold of the torques leaves 1.1e-5°.
    flat = load_model(PARAMS.replace(geometry=CHAINS))
    m1 = given(flat.layout).platform_v[0]
    effect = np.degrees(np.abs(kinematics(flat, iso14242_at(instants[-1:])).q[0][m1] - kin.q[-1][platforms[0]])).max()
    assert drift < 1e-3 * effect, (drift, effect)


def test_the_constraint_dynamics_route_is_refused_in_one_line():
    with pytest.raises(ArgumentError, match=r"route: expected 'compiled' or 'kernel' with a stack-up") as caught:
        PinocchioPlant(STACKED, route="constraint_dynamics")
    assert "\n" not in str(caught.value)
