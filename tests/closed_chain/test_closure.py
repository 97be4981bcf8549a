"""The chain closed along a trajectory (hipsim.closed_chain.closure): the closed samples hold the trajectory's angles
and close, a run in pieces through a Continuation gives the one-piece run bit for bit, and a pose out of reach is
refused at its sample. The compiled arithmetic inside: closed_chain/test_closure_kernel.py."""

import dataclasses

import numpy as np
import pytest

import hipsim
from hipsim.closed_chain.build import load_model
from hipsim.closed_chain.closure import Continuation, close_chain, kinematics
from hipsim.exceptions import PoseError
from hipsim.motion.trajectories import iso14242_at


@pytest.fixture(scope="module")
def chain():
    return load_model(hipsim.load_parameters())


def test_closed_samples_and_a_run_in_pieces(chain):
    traj = iso14242_at(np.linspace(0.0, 0.05, 6))
    kin = kinematics(chain, traj)
    np.testing.assert_array_equal(kin.angles, traj.q * chain.params.angle_signs)
    assert np.all(kin.residual <= 1e-12)
    state = Continuation()
    pieces = [
        close_chain(chain, traj.slice(slice(a, b)), 1e-12, 50, continuation=state)[0] for a, b in ((0, 3), (3, 6))
    ]
    assert state.samples == 6
    np.testing.assert_array_equal(np.concatenate([piece.q for piece in pieces]), kin.q)


def test_a_pose_out_of_reach_is_refused_at_its_sample(chain):
    traj = iso14242_at(np.array([0.0, 0.1, 0.2]))
    q = traj.q.copy()
    q[1, 0] = 3.0  # α = 172°: out of every lever's reach
    with pytest.raises(PoseError) as refused:
        kinematics(chain, dataclasses.replace(traj, q=q))
    assert refused.value.index == 1 and refused.value.time == pytest.approx(0.1)
