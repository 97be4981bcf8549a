"""MuJoCo's forward dynamics as a plant (hipsim/mujoco_engine/plant.py): closed initial state, forward against
inverse dynamics, open-loop drift, closed-loop tracking against the Pinocchio plant, the closure gap, the torques.

Skipped when ``mujoco`` is not installed or too old (the ``test`` extra installs it).
"""

from __future__ import annotations

import numpy as np
import pytest

mujoco = pytest.importorskip("mujoco")

import hipsim  # noqa: E402
from hipsim.exceptions import MissingDependencyError  # noqa: E402

try:
    import hipsim.mujoco_engine
except MissingDependencyError as error:  # installed, but a release the engine refuses
    pytest.skip(str(error), allow_module_level=True)

from hipsim.closed_chain.plant import PinocchioPlant  # noqa: E402
from hipsim.control.controllers import AugmentedPD, WorkspacePD  # noqa: E402
from hipsim.control.simulation import apply_mismatch, simulate  # noqa: E402
from hipsim.motion.trajectories import iso14242_at  # noqa: E402
from hipsim.mujoco_engine import MujocoModel, MujocoPlant  # noqa: E402
from hipsim.mujoco_engine.trajectory import trajectory_dynamics  # noqa: E402

DURATION = 0.2  # [s] of closed-loop and open-loop runs
SERVO = 1000.0  # [Hz], with the parameter file's RK4 step of 0.5 ms
#: Before MuJoCo 3.7 the RK4 step leaves closure gaps of ~1e-6 m (measured 3.3.1-3.6.0), from 3.7 on ~1e-8 m.
RECENT = tuple(int(part) for part in mujoco.__version__.split(".")[:2]) >= (3, 7)


@pytest.fixture(scope="module")
def params():
    return hipsim.load_parameters()


class OpenLoop:
    """MuJoCo inverse-dynamics torques of the ISO cycle, taken mid-period to offset the hold's delay."""

    def __init__(self, params, duration):
        n = int(round(duration * SERVO))
        self.tau = MujocoModel(params).run(iso14242_at((np.arange(n) + 0.5) / SERVO)).torques.total

    def __call__(self, t, state, desired):
        return self.tau[int(round(t * SERVO))]


@pytest.fixture(scope="module")
def plant(params):
    return MujocoPlant(params)


def test_initial_state_is_closed_and_leaves_the_callback_alone(params, plant):
    desired = iso14242_at(np.array([0.13]))
    x = plant.initial_state(desired)
    gap, rate = plant.closure_residual(x)
    assert gap < 1e-12 and rate < 1e-12
    angles, rates = plant.angles(x)
    np.testing.assert_allclose(angles, desired.q[0], atol=1e-15)
    np.testing.assert_allclose(rates, desired.qd[0], atol=1e-14)
    assert mujoco.get_mjcb_passive() is None
    plant.advance(0.13, x, np.zeros(3), np.full(5, 1000.0), 0.5e-3, 2)
    assert mujoco.get_mjcb_passive() is None  # installed only while stepping


def test_forward_dynamics_at_a_rigid_state_is_the_inverse_dynamics_but_soft(params, plant):
    """At a closed state under the inverse-dynamics torques MuJoCo's acceleration is the rigid one, except for the
    closures' softness: impedance 0.9999 leaves 1e-4 of the constraint-space acceleration unenforced."""
    if not RECENT:
        pytest.skip(
            f"MuJoCo {mujoco.__version__}: before 3.7 the closures are much softer at a rigid state "
            "(measured up to 1.05 of |a| with 3.3.1, 3.3e-3 with 3.6.0)"
        )
    traj = iso14242_at(np.array([0.0, 0.13, 0.5, 0.77]))
    kin, torques = trajectory_dynamics(plant.machine, traj)
    for k in range(4):
        x = np.concatenate([kin.q[k], kin.v[k]])
        dx = plant.derivative(traj.t[k], x, torques.torques.total[k], traj.Fe[k])
        np.testing.assert_array_equal(dx[: plant.nq], kin.v[k])
        # Measured 2e-4 to 9e-4 of the largest |a| (a of 2..15 m/s², rad/s²).
        relative = np.abs(dx[plant.nq :] - kin.a[k]).max() / np.abs(kin.a[k]).max()
        assert relative < 2e-3
    # and the softness is what it is: a stiffer-than-allowed impedance is not available, a softer one is worse.
    soft = MujocoPlant(params, solimp=(0.99, 0.99, 0.001, 0.5, 2.0), machine=None)
    dx = soft.derivative(traj.t[1], np.concatenate([kin.q[1], kin.v[1]]), torques.torques.total[1], traj.Fe[1])
    assert np.abs(dx[soft.nq :] - kin.a[1]).max() / np.abs(kin.a[1]).max() > 10 * 2e-4


def test_inverse_then_forward_reproduces_the_motion(params, plant):
    """ISO MuJoCo inverse-dynamics torques fed open loop from the closed initial state: drift ≤ 1e-4° over 0.2 s."""
    sim = simulate(plant, OpenLoop(params, DURATION), iso14242_at, DURATION)
    drift = np.degrees(np.abs(sim.err)).max()
    # Measured 3.2e-5° at RK4 0.5 ms (the Pinocchio plant: 3.3e-5°, the zero-order hold of torques sampled mid-period).
    assert drift < 1e-4
    wrong = OpenLoop(apply_mismatch(params, masses=0.2), DURATION)  # a 20 % heavier machine's torques: 2.8°
    assert np.degrees(np.abs(simulate(plant, wrong, iso14242_at, DURATION).err)).max() > 1000 * drift
    # With Euler at 1 ms the same torques drift 0.12°: the integrator, not the model (see the README).
    euler = MujocoPlant(params.replace(integration_step=1e-3), integrator="Euler")
    assert 0.01 < np.degrees(np.abs(simulate(euler, OpenLoop(params, DURATION), iso14242_at, DURATION).err)).max() < 1.0


@pytest.fixture(scope="module")
def runs(params, plant):
    """Both controllers over 0.2 s on the Pinocchio plant and on the MuJoCo plant (RK4 0.5 ms, Euler 1 ms)."""
    euler = MujocoPlant(params.replace(integration_step=1e-3), integrator="Euler")
    out = {}
    for name, controller in (
        ("pd", WorkspacePD(params)),
        ("augmented-pd", AugmentedPD(params, iso14242_at, SERVO, DURATION)),
    ):
        reference = simulate(PinocchioPlant(params), controller, iso14242_at, DURATION)
        rk4 = simulate(plant, controller, iso14242_at, DURATION)
        rk4_gaps = plant.gap_history()
        slow = simulate(euler, controller, iso14242_at, DURATION)
        out[name] = (reference, rk4, rk4_gaps, slow, euler.gap_history())
    return out


@pytest.mark.parametrize("controller", ["pd", "augmented-pd"])
def test_closed_loop_tracking_is_the_pinocchio_plants(runs, controller):
    reference, rk4, _, slow, _ = runs[controller]
    peak = lambda sim: np.degrees(np.abs(sim.err)).max(axis=0)
    # RK4 at the servo settings: measured 4.3e-7° (PD) and 4.6e-7° (augmented PD) from the Pinocchio plant's angles,
    # against tracking errors of 0.42° and 1.8e-5°; the peak errors agree within 0.3 %.
    # Before MuJoCo 3.7 (gaps of 1e-6 m): 6e-6°, which moves the augmented PD's peak errors by up to 4.6e-6°.
    bound = 2e-6 if RECENT else 2e-5
    assert np.degrees(np.abs(rk4.q - reference.q)).max() < bound
    np.testing.assert_allclose(peak(rk4), peak(reference), rtol=0.03, atol=2e-7 if RECENT else 1e-5)
    # Euler at 1 ms: the PD's peak errors within 10 % (measured 2.5 %, 6.2 %, 0.8 % smaller for α, β, γ), the
    # augmented PD's 750 times larger (0.0136° vs 1.8e-5°): semi-implicit Euler's first-order error, not the model.
    if controller == "pd":
        np.testing.assert_allclose(peak(slow), peak(reference), rtol=0.1)
    else:
        assert peak(slow).max() > 100 * peak(reference).max()


@pytest.mark.parametrize("controller", ["pd", "augmented-pd"])
def test_closure_gap_along_the_run(runs, controller):
    _, rk4, (times, gaps), _, (_, euler_gaps) = runs[controller]
    np.testing.assert_allclose(times, rk4.t + 1e-3)  # one entry per servo period, at its end
    # Measured: 9.4e-9 m with RK4 0.5 ms (MuJoCo >= 3.7; 1.1e-6 m with 3.3.1-3.6), 1.7e-6 m with Euler 1 ms.
    assert gaps.max() < (3e-8 if RECENT else 5e-6)
    assert gaps.max() > 1e-10  # the closures are soft: a gap does open
    assert euler_gaps.max() < 4e-6


def test_the_plant_applies_the_torques_the_loop_asks_for(params):
    """The servo loop limits torques; the MJCF's ctrlrange (from the plant's own limit) must not clamp them again."""
    limited = MujocoPlant(params.replace(torque_limit=0.5))
    x = limited.initial_state(iso14242_at(np.array([0.2])))
    limited.derivative(0.2, x, np.array([2.0, -2.0, 1.0]), 1000.0)
    np.testing.assert_array_equal(limited.data.actuator_force, [2.0, -2.0, 1.0])  # not clamped to ±0.5 N·m
    sliders = limited.machine.slider_dof
    np.testing.assert_allclose(
        limited.data.qfrc_actuator[sliders], 2 * np.pi / params.lead * np.array([2.0, -2.0, 1.0]), rtol=1e-14
    )
