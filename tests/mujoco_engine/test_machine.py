"""The MuJoCo machine with the intermediate chain's stack-up (hipsim.machine.chains): the URDF's spline slide and
shaft end converted (two bodies at a placeholder mass), the seat closure a seventh ``connect``; its inverse dynamics
against the analytic and Pinocchio models, and its plant driven by them."""

import numpy as np
import pytest
from stations_synthetic import deviated

import hipsim
from hipsim.analytic.engine import AnalyticModel
from hipsim.closed_chain.engine import PinocchioModel
from hipsim.exceptions import MissingDependencyError
from hipsim.motion.trajectories import iso14242_at

try:
    from hipsim.mujoco_engine import MujocoModel
    from hipsim.mujoco_engine.machine import PLACEHOLDER_MASS
    from hipsim.mujoco_engine.model import load_model
    from hipsim.mujoco_engine.plant import MujocoPlant
    from hipsim.mujoco_engine.trajectory import trajectory_dynamics
except (ImportError, MissingDependencyError):  # pragma: no cover - MuJoCo is in the test extra
    pytest.skip("MuJoCo is not installed", allow_module_level=True)

PARAMS = hipsim.load_parameters()
CHAINS = deviated(seed=3)
STACKED = PARAMS.replace(geometry=CHAINS.replace(spline=np.array([1e-3, 2e-3, -1e-3])))
CYCLE = iso14242_at(np.arange(20) / 20.0)
SERVO, STEP, PERIODS = 1000.0, 0.5e-3, 40


@pytest.fixture(scope="module")
def machine():
    return load_model(STACKED)


def test_the_stacked_machine_has_three_free_coordinates(machine):
    model = machine.model
    assert model.nv == 24 and model.neq == 7 and machine.stackup_dof is not None
    assert sorted(model.body_mass[sorted(machine.placeholders)]) == [PLACEHOLDER_MASS] * 2
    kin, _ = trajectory_dynamics(machine, CYCLE.slice(slice(0, 3)))
    for q in kin.q:
        machine.place(q)
        residual, J = machine.closure_rows()
        assert np.abs(residual).max() < 1e-12 and np.linalg.matrix_rank(J) == 21  # 24 − 21: mobility 3


def test_mujoco_is_the_analytic_model_with_the_stack_up(machine):
    """Each part to 1e-9 of its column's peak (measured ~3e-13, the 1 mg placeholders taken out of M·a + bias).

    (Pinocchio ≡ analytic: tests/closed_chain/test_dynamics_stackup.py.)"""
    run = MujocoModel(STACKED, machine=machine).run(CYCLE)
    reference = AnalyticModel(STACKED, lever_spin=True).run(CYCLE)
    np.testing.assert_allclose(run.L, reference.L, rtol=0, atol=1e-12)
    for name in ("total", "platforms", "levers", "sliders", "screws", "friction"):
        expected, got = getattr(reference.torques, name), getattr(run.torques, name)
        np.testing.assert_allclose(got, expected, rtol=0, atol=1e-9 * np.abs(expected).max(), err_msg=name)


def test_inverse_then_forward_reproduces_the_motion_of_both_platforms(machine):
    plant = MujocoPlant(STACKED, machine=machine)
    instants = np.arange(PERIODS + 1) / SERVO
    torques = MujocoModel(STACKED, machine=machine).run(iso14242_at(instants[:-1] + 0.5 / SERVO)).torques.total
    kin, _ = trajectory_dynamics(machine, iso14242_at(instants))
    x = np.concatenate([kin.q[0], kin.v[0]])
    substeps = int(round(1 / SERVO / STEP))
    for k in range(PERIODS):
        loads = iso14242_at(instants[k] + np.arange(2 * substeps + 1) * STEP / 2).Fe
        x = plant.advance(instants[k], x, torques[k], loads, STEP, substeps)
    platforms = machine.platform_dof
    drift = np.degrees(np.abs(x[platforms] - kin.q[-1][platforms])).max()
    # Measured 1e-5° (the Pinocchio plant's 1.1e-5°) where the stack-up moves m_1 by 1.2°.
    assert drift < 1e-4


def test_with_m1_controlled_mujoco_pinocchio_and_analytic_agree_on_the_stacked_machine():
    """control = 1: m_1 held at the trajectory, m_2 and the stack-up follow (the analytic model by implicit
    differentiation of the stack-up's fixed point, the trees by their seventh closure)."""
    params = STACKED.replace(geometry=CHAINS.replace(spline=STACKED.chains.spline_seat, control=1))
    short = CYCLE.slice(slice(0, 20, 4))
    run, reference = MujocoModel(params).run(short), PinocchioModel(params).run(short)
    np.testing.assert_allclose(run.L, reference.L, rtol=0, atol=1e-12)
    # Measured 1.1e-12 of the peak torque.
    np.testing.assert_allclose(
        run.torques.total, reference.torques.total, rtol=0, atol=1e-9 * np.abs(reference.torques.total).max()
    )
    analytic = AnalyticModel(params, lever_spin=True).run(short)
    np.testing.assert_allclose(analytic.L, reference.L, rtol=0, atol=1e-11)
    for name in ("total", "platforms", "levers", "sliders", "screws", "friction"):
        expected, got = getattr(analytic.torques, name), getattr(reference.torques, name)
        np.testing.assert_allclose(got, expected, rtol=0, atol=1e-9 * np.abs(expected).max(), err_msg=name)
