"""The servo loop's controllers (hipsim.control.controllers): the gains, the PD through the Jacobian's transpose, and
the feed-forward row of each servo period (taken at the period's middle, the last one after the end)."""

import math

import numpy as np
import pytest

import hipsim
from hipsim.analytic.inverse_kinematics import slider_jacobian
from hipsim.control.controllers import AugmentedPD, Sample, WorkspacePD, feedforward_torques
from hipsim.exceptions import ArgumentError
from hipsim.motion.trajectories import Trajectory, iso14242_at


@pytest.fixture(scope="module")
def params():
    return hipsim.load_parameters()


def test_a_sample_s_defaults():
    s = Sample(np.zeros(3), np.ones(3))
    assert s.qdd is None and s.Fe == 0.0


def test_the_gains_default_to_the_parameter_file_s(params):
    pd = WorkspacePD(params)
    assert pd.kp.tolist() == params.control.kp.tolist() and pd.kd.tolist() == params.control.kd.tolist()
    assert pd.params is params
    given = WorkspacePD(params, kp=[1.0, 2.0, 3.0], kd=4)
    assert given.kp.tolist() == [1.0, 2.0, 3.0] and given.kd.tolist() == [4.0, 4.0, 4.0]
    with pytest.raises(ArgumentError, match=r"^kp: expected shape \(3,\)"):
        WorkspacePD(params, kp=[[1.0, 2.0, 3.0]])
    with pytest.raises(ArgumentError, match="^kd: expected numbers"):
        WorkspacePD(params, kd="stiff")


def test_the_pd_by_the_jacobian_s_transpose(params):
    """(2π/p)·Jᵀ·τ is the moment K_p·Δq + K_d·Δq̇, each gain on its own angle."""
    pd = WorkspacePD(params, kp=[100.0, 200.0, 300.0], kd=[10.0, 20.0, 30.0])
    state = Sample(np.radians([4.0, -1.0, 2.0]), np.array([0.2, -0.1, 0.05]))
    desired = Sample(np.radians([5.0, 1.0, -1.0]), np.array([-0.1, 0.2, 0.3]))
    tau = pd(0.0, state, desired)
    J = slider_jacobian(params, state.q[None])[0]
    moment = np.array([100.0, 200.0, 300.0]) * (desired.q - state.q) + np.array([10.0, 20.0, 30.0]) * (
        desired.qd - state.qd
    )
    assert J.T @ (2 * math.pi / params.lead * tau) == pytest.approx(moment, rel=1e-12)
    with pytest.raises(ArgumentError, match=r"^desired\.qd: expected shape \(3,\)"):
        pd(0.0, state, Sample(desired.q, np.zeros(2)))
    with pytest.raises(ArgumentError, match=r"^desired\.q: expected shape \(3,\)"):
        pd(0.0, state, Sample(np.zeros(4), desired.qd))
    with pytest.raises(ArgumentError, match=r"^state\.qd: expected shape \(3,\)"):
        pd(0.0, Sample(state.q, np.zeros(1)), desired)


def test_the_feedforward_is_the_inverse_dynamics_at_each_period_s_middle(params):
    """Four periods at 100 Hz: rows at 5, 15, 25 and 35 ms of the desired motion, friction included."""
    pd = AugmentedPD(params, iso14242_at, 100.0, 0.04, kp=1.0, kd=0.0)
    assert pd.servo_rate == 100.0 and pd.feedforward.shape == (4, 3)
    expected = feedforward_torques(params, iso14242_at(np.array([0.005, 0.015, 0.025, 0.035])))
    assert pd.feedforward == pytest.approx(expected, rel=1e-12)
    assert (pd.kp.tolist(), pd.kd.tolist()) == ([1.0] * 3, [0.0] * 3)
    # The rows by the nearest period (a time a rounding before the next period's start is that period's), the last
    # one held after the end.
    assert pd.feedforward_rows(np.array([0.0, 0.0049, 0.0051, 0.0149, 0.03, 0.04, 0.5])).tolist() == [
        0, 0, 1, 1, 3, 3, 3
    ]  # fmt: skip
    assert int(pd.feedforward_rows(0.02)) == 2
    # Applied: the feed-forward row plus the PD.
    state = Sample(np.radians([3.0, 1.0, 0.0]), np.zeros(3))
    desired = Sample(np.radians([3.5, 1.0, 0.0]), np.zeros(3))
    plain = WorkspacePD(params, kp=1.0, kd=0.0)
    assert pd(0.021, state, desired) == pytest.approx(expected[2] + plain(0.021, state, desired), rel=1e-12)


def test_the_feedforward_counts_friction(params):
    """The hip joint's friction is in the feed-forward: a model without it gives other torques."""
    desired = iso14242_at(np.array([0.1, 0.2]))
    smooth = params.replace(hip_mu=0.0, thrust_mu=0.0)
    with_friction = feedforward_torques(params, desired)
    assert with_friction.shape == (2, 3)
    assert np.abs(with_friction - feedforward_torques(smooth, desired)).max() > 1e-3  # N·m


def test_the_feedforward_feels_the_load(params):
    t = np.array([0.0, 0.001])
    q, qd, z = np.radians([[5.0, 1.0, 0.0]] * 2), np.array([[0.5, 0.2, 0.1]] * 2), np.zeros((2, 3))
    light = feedforward_torques(params, Trajectory(t, q, qd, z, np.array([100.0, 100.0])))
    heavy = feedforward_torques(params, Trajectory(t, q, qd, z, np.array([2000.0, 2000.0])))
    assert not np.allclose(light, heavy)
