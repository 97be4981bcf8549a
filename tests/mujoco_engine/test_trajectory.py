"""The MuJoCo model's chain closed along a trajectory (hipsim/mujoco_engine/trajectory.py): the closed samples hold the
trajectory's angles, the sliders' rates are the kinematics', and a pose out of reach is refused naming its sample.

Skipped when ``mujoco`` is not installed or too old (the ``test`` extra installs it).
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

pytest.importorskip("mujoco")

import hipsim
from hipsim.exceptions import MissingDependencyError, PoseError

try:
    import hipsim.mujoco_engine
except MissingDependencyError as error:  # installed, but a release the engine refuses
    pytest.skip(str(error), allow_module_level=True)

from hipsim.motion.trajectories import iso14242_at
from hipsim.mujoco_engine import load_model
from hipsim.mujoco_engine.trajectory import kinematics, trajectory_dynamics


@pytest.fixture(scope="module")
def machine():
    return load_model(hipsim.load_parameters())


def test_closed_samples_hold_the_angles_and_the_slider_rates(machine):
    traj = iso14242_at(np.array([0.0, 0.1, 0.25]))
    kin = kinematics(machine, traj)
    assert np.all(kin.residual <= 1e-13)  # the tolerance asked (default)
    signs = machine.params.angle_signs
    for j in (0, 1):  # both platforms at the trajectory's angles, signs applied
        np.testing.assert_array_equal(kin.q[:, machine.platform_dof[j]], traj.q * signs)
        np.testing.assert_allclose(kin.v[:, machine.platform_dof[j]], traj.qd * signs, rtol=0, atol=1e-12)
    np.testing.assert_array_equal(kin.Ld[:, 0], kin.v[:, machine.slider_dof])
    np.testing.assert_array_equal(kin.Ldd[:, 1], kin.a[:, machine.slider_dof])
    assert np.all((kin.cond_inv > 0) & (kin.cond_inv <= 1))
    # The one-pass inverse dynamics closes the chain the same way.
    same, _ = trajectory_dynamics(machine, traj)
    np.testing.assert_array_equal(same.q, kin.q)


def test_a_pose_out_of_reach_is_refused_at_its_sample(machine):
    traj = iso14242_at(np.array([0.0, 0.1, 0.2]))
    q = traj.q.copy()
    q[2, 0] = 3.0  # α = 172°: no chain reaches it (measured: the gap stays at 0.063 m)
    with pytest.raises(PoseError) as refused:
        kinematics(machine, dataclasses.replace(traj, q=q))
    assert refused.value.index == 2 and refused.value.time == pytest.approx(0.2)
    assert "t = 0.2 s" in str(refused.value) and "out of the levers' reach" in refused.value.reason
