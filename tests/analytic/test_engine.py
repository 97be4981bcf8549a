"""The analytic model behind the engine protocol (hipsim.analytic.engine): on_error's values, flagged samples, and
a trajectory flagged throughout refused unless it is a piece. Its physics: analytic/test_chain_dynamics.py and
rig/test_plausibility_laws.py."""

import dataclasses

import numpy as np
import pytest

import hipsim
from hipsim.analytic.engine import AnalyticModel
from hipsim.exceptions import ArgumentError, PoseError
from hipsim.motion.trajectories import iso14242_at


def _out_of_reach(traj, rows):
    q = traj.q.copy()
    q[rows, 0] = 3.0  # α = 172°: out of every lever's reach
    return dataclasses.replace(traj, q=q)


def test_on_error_is_raise_or_flag():
    with pytest.raises(ArgumentError, match="^on_error: expected 'raise' or 'flag'"):
        AnalyticModel(hipsim.load_parameters(), on_error="ignore")


def test_flagged_samples_and_a_trajectory_flagged_throughout():
    params = hipsim.load_parameters()
    traj = iso14242_at(np.array([0.0, 0.1, 0.2]))
    flag = AnalyticModel(params, on_error="flag")
    run = flag.run(_out_of_reach(traj, [1]))
    np.testing.assert_array_equal(run.flagged, [False, True, False])
    assert np.isnan(run.torques.total[1]).all() and np.isfinite(run.torques.total[[0, 2]]).all()
    with pytest.raises(PoseError):
        AnalyticModel(params).run(_out_of_reach(traj, [1]))
    everywhere = _out_of_reach(traj, [0, 1, 2])
    with pytest.raises(PoseError, match="all 3 samples are out of reach or singular"):
        flag.run(everywhere)
    assert flag.run(everywhere, flag.piece_state(3, None)).flagged.all()  # a piece may be flagged throughout
