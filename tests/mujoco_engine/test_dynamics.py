"""The MuJoCo model's rigid inverse dynamics (hipsim/mujoco_engine/dynamics.py): along a closed motion it is the
one-pass route's, a scalar load is the load at every sample, and a heavier load asks more of the motors. Against the
analytic and Pinocchio models: mujoco_engine/test_model.py.

Skipped when ``mujoco`` is not installed or too old (the ``test`` extra installs it).
"""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("mujoco")

import hipsim
from hipsim.exceptions import MissingDependencyError

try:
    from hipsim.mujoco_engine import load_model
    from hipsim.mujoco_engine.dynamics import inverse_dynamics
    from hipsim.mujoco_engine.trajectory import kinematics, trajectory_dynamics
except MissingDependencyError as error:  # installed, but a release the engine refuses
    pytest.skip(str(error), allow_module_level=True)

from hipsim.motion.trajectories import iso14242_at


def test_inverse_dynamics_along_a_closed_motion_is_the_one_pass_routes():
    machine = load_model(hipsim.load_parameters())
    traj = iso14242_at(np.array([0.05, 0.3, 0.6]))
    kin = kinematics(machine, traj)
    two = inverse_dynamics(machine, kin, traj.Fe)
    _, one = trajectory_dynamics(machine, traj)
    total = one.torques.total
    np.testing.assert_allclose(two.torques.total, total, rtol=0, atol=1e-12 * np.abs(total).max())
    np.testing.assert_allclose(two.F_act, one.F_act, rtol=0, atol=1e-12 * np.abs(one.F_act).max())
    assert two.lambdas.shape == (3, 2, 3, 3)
    scalar = inverse_dynamics(machine, kin, 2000.0).torques.total
    np.testing.assert_array_equal(scalar, inverse_dynamics(machine, kin, np.full(3, 2000.0)).torques.total)
    heavier = inverse_dynamics(machine, kin, 3000.0).torques.total
    assert np.abs(heavier - scalar).max() > 0.01  # N·m: the load reaches the motors
