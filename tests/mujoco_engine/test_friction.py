"""MuJoCo's friction forces (hipsim/mujoco_engine/friction.py): the closed form is the general law.

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

from hipsim.motion.trajectories import iso14242_at  # noqa: E402
from hipsim.mujoco_engine import load_model  # noqa: E402
from hipsim.mujoco_engine.friction import FrictionForces, friction_forces  # noqa: E402
from hipsim.mujoco_engine.trajectory import trajectory_dynamics  # noqa: E402


@pytest.fixture(scope="module")
def params():
    return hipsim.load_parameters()


def test_closed_form_friction_is_the_general_law(params):
    """The plant's and inverse dynamics' fast friction equals mj_applyFT of the body moments, at closed states."""
    for changes in ({}, {"guide_coulomb": 15.0, "guide_viscous": 40.0, "screw_coulomb": 0.05, "screw_viscous": 2e-4}):
        rough = params.replace(**changes)
        machine = load_model(rough)
        fast = FrictionForces(machine)
        assert not fast.general
        kin, _ = trajectory_dynamics(machine, iso14242_at(np.array([0.05, 0.31, 0.62])))
        data = mujoco.MjData(machine.model)
        for q, v, Fe in zip(kin.q, kin.v, (300.0, 1700.0, 2900.0)):
            data.qpos[:], data.qvel[:] = q, v
            mujoco.mj_forward(machine.model, data)
            out = np.zeros(machine.nv)
            fast.add(data, Fe, out)
            expected = friction_forces(machine, data, Fe)
            np.testing.assert_allclose(out, expected, rtol=0, atol=1e-13 * np.abs(expected).max())
            assert np.abs(expected).max() > 1.0
