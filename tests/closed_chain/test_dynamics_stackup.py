"""The intermediate chain's stack-up in the Pinocchio closed-chain model: m_1's spherical joint on the spline's slide,
the shaft's end held on m_2's seat (hipsim.machine.chains). Checked by its mobility, by the stack-up's lift computed
by hand, against the analytic model (control = 2), by the power balance with the load's work, and against today's
model when the seat is zero."""

import numpy as np
import pinocchio as pin
import pytest
from scipy.spatial.transform import Rotation
from stations_synthetic import deviated
from support import given

import hipsim
from hipsim.analytic.engine import AnalyticModel
from hipsim.closed_chain.build import load_model
from hipsim.closed_chain.constraints import constraint_rank
from hipsim.closed_chain.dynamics import trajectory_dynamics
from hipsim.closed_chain.engine import PinocchioModel
from hipsim.motion.trajectories import iso14242_at

PARAMS = hipsim.load_parameters()
CHAINS = deviated(seed=3)  # the chains built to ±0.3 mm
SEAT = np.array([1e-3, 2e-3, -1e-3])  # [m]: lifts m_1 by up to ~0.5 mm along the ISO cycle
STACKED = PARAMS.replace(geometry=CHAINS.replace(spline=SEAT))
#: 20 samples over the ISO cycle.
CYCLE = iso14242_at(np.arange(20) / 20.0)


@pytest.fixture(scope="module")
def chain():
    return load_model(STACKED)


@pytest.fixture(scope="module")
def run(chain):
    return trajectory_dynamics(chain, CYCLE)


def test_three_free_coordinates_and_m1_lifted_as_the_seat_says(chain, run):
    kin, _ = run
    layout = given(chain.layout)
    assert chain.model.nv == 24 and chain.n_closures == 7
    assert np.all(kin.residual < 1e-12)
    for k in (0, 7, 13):
        assert constraint_rank(chain, kin.q[k]) == 21  # 24 coordinates, 21 independent closure rows: mobility 3
    # m_1's centre: ẑᵀ(R_2 − I)·e above where it is built, R_2 from m_2's joint angles (rz, ry, rx) by SciPy.
    data = chain.model.createData()
    for q in kin.q[::5]:
        alpha, beta, gamma = q[layout.platform_v[1]]
        R2 = Rotation.from_euler("ZYX", [gamma, beta, alpha]).as_matrix()
        pin.forwardKinematics(chain.model, data, q)
        o1 = data.oMi[chain.model.getJointId("platform_1_rx")].translation
        np.testing.assert_allclose(o1, STACKED.chains.centres[0] + [0, 0, (R2 @ SEAT - SEAT)[2]], rtol=0, atol=1e-13)
        assert abs(q[layout.stackup_v[0]] - (R2 @ SEAT - SEAT)[2]) < 1e-13


def test_pinocchio_is_the_analytic_model_with_the_stack_up(run):
    """Every part, each to 1e-9 of its column's peak (measured ~3e-12): the same physics, lever spin included."""
    kin, dynamics = run
    analytic = AnalyticModel(STACKED, lever_spin=True).run(CYCLE)
    np.testing.assert_allclose(kin.L, analytic.L, rtol=0, atol=1e-12)
    lift = np.abs(
        analytic.torques.platforms
        - AnalyticModel(PARAMS.replace(geometry=CHAINS), lever_spin=True).run(CYCLE).torques.platforms
    )
    for name in ("total", "platforms", "levers", "sliders", "screws", "friction"):
        expected, got = getattr(analytic.torques, name), getattr(dynamics.torques, name)
        np.testing.assert_allclose(got, expected, rtol=0, atol=1e-9 * np.abs(expected).max(), err_msg=name)
    assert lift.max() > 1e-3 * np.abs(analytic.torques.platforms).max()  # the stack-up's own share is seen


def test_a_zero_seat_is_todays_model_bit_for_bit():
    zero = PARAMS.replace(geometry=CHAINS.replace(spline=np.zeros(3)))
    short = CYCLE.slice(slice(0, 4))
    today, again = PinocchioModel(PARAMS.replace(geometry=CHAINS)).run(short), PinocchioModel(zero).run(short)
    assert again.L.shape == today.L.shape
    np.testing.assert_array_equal(again.torques.total, today.torques.total)
    np.testing.assert_array_equal(given(again.joint_forces).Fo, given(today.joint_forces).Fo)


def test_power_balance_with_the_loads_work():
    """Σ τ·θ̇ = dE/dt + friction power + F_e·ż_1, E from Pinocchio's body energies (its kinetic energy has the armature)."""
    rough = STACKED.replace(guide_coulomb=20.0, screw_viscous=2e-4, sjoint_viscous=0.02)
    chain = load_model(rough)
    rate = 4000.0
    trajectory = iso14242_at(0.1 + np.arange(60) / rate)
    kin, dynamics = trajectory_dynamics(chain, trajectory)
    data, model = chain.model.createData(), chain.model
    energy = np.array(
        [
            pin.computeKineticEnergy(model, data, q, v) + pin.computePotentialEnergy(model, data, q)
            for q, v in zip(kin.q, kin.v)
        ]
    )
    torques = dynamics.torques
    power = np.sum(torques.total * torques.motor_speed, axis=1) - torques.friction_power
    load = trajectory.Fe * kin.v[:, given(chain.layout).stackup_v[0]]
    # dE/dt by fourth-order central differences (measured residual 2.5e-8 W of 17 W; second order leaves 4e-5 W).
    rate_of_energy = (energy[:-4] - 8 * energy[1:-3] + 8 * energy[3:-1] - energy[4:]) * rate / 12
    residual = power[2:-2] - rate_of_energy - load[2:-2]
    assert np.abs(residual).max() < 1e-8 * np.abs(power).max()
    assert np.abs(load).max() > 1e-2 * np.abs(power).max()  # the load's work is not small: leaving it out would show
