"""The closure constraints' functions (hipsim.closed_chain.constraints): residuals zero at a closed configuration and
of the right shape for one or many, the mobility 3, the spherical joints' centres a rigid triangle, and configurations
of the wrong size refused naming q. Against Pinocchio's own constraint computations: closed_chain/test_workspace.py."""

import numpy as np
import pinocchio as pin
import pytest

import hipsim
from hipsim.closed_chain.build import load_model
from hipsim.closed_chain.closure import kinematics
from hipsim.closed_chain.constraints import (
    closure_residuals,
    configurations,
    constraint_rank,
    platform_joint_positions,
)
from hipsim.exceptions import ArgumentError
from hipsim.motion.trajectories import iso14242_at


@pytest.fixture(scope="module")
def chain():
    return load_model(hipsim.load_parameters())


def test_a_closed_configuration_closes_and_leaves_three_degrees_of_freedom(chain):
    q = kinematics(chain, iso14242_at(np.array([0.0, 0.3]))).q
    gaps = closure_residuals(chain, q)
    assert gaps.shape == (2, chain.n_closures, 3) and np.abs(gaps).max() < 1e-12
    assert closure_residuals(chain, q[1]).shape == (chain.n_closures, 3)
    assert chain.model.nv - constraint_rank(chain, q[0]) == 3
    # The platforms' joint centres keep their distances from one sample to the next (a rigid triangle each).
    a = platform_joint_positions(chain, q)
    sides = np.linalg.norm(a[:, :, [0, 1, 2]] - a[:, :, [1, 2, 0]], axis=-1)
    np.testing.assert_allclose(sides[0], sides[1], rtol=0, atol=1e-12)
    opened = pin.neutral(chain.model)
    assert np.abs(closure_residuals(chain, opened)).max() > 1e-3  # the neutral tree is not closed


def test_configurations_of_the_wrong_size_are_refused(chain):
    q, single = configurations(chain, np.zeros(chain.model.nq))
    assert single and q.shape == (1, chain.model.nq)
    with pytest.raises(ArgumentError, match=rf"^q: expected configurations of size nq = {chain.model.nq}"):
        configurations(chain, np.zeros((2, chain.model.nq - 1)))
