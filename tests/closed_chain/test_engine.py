"""The Pinocchio model behind the engine protocol (hipsim.closed_chain.engine): pieces handed out in time order only,
the total without its parts equal to the total with them. Against the analytic model: analytic/test_chain_dynamics.py."""

import numpy as np
import pytest

import hipsim
from hipsim.closed_chain.closure import Continuation
from hipsim.closed_chain.engine import PinocchioModel
from hipsim.exceptions import ArgumentError
from hipsim.motion.trajectories import iso14242_at


@pytest.fixture(scope="module")
def engine():
    return PinocchioModel(hipsim.load_parameters())


def test_pieces_are_handed_out_in_time_order_only(engine):
    first = engine.piece_state(0, None)
    assert isinstance(first, Continuation) and first.samples == 0
    engine.run(iso14242_at(np.array([0.0, 0.01, 0.02])), first)
    assert first.samples == 3 and engine.piece_state(3, first) is first
    for offset, previous in ((2, first), (4, first), (3, None)):
        with pytest.raises(ArgumentError, match="^start: expected pieces of a Pinocchio run in time order, from 0"):
            engine.piece_state(offset, previous)


def test_the_total_without_its_parts_is_the_total(engine):
    traj = iso14242_at(np.array([0.1, 0.2]))
    whole = engine.run(traj)
    total = PinocchioModel(engine.params, chain=engine.chain, parts=False).run(traj)
    assert whole.model == total.model == "pinocchio"
    np.testing.assert_allclose(total.torques.total, whole.torques.total, rtol=1e-12, atol=1e-12)
    assert np.isnan(total.torques.friction).all() and not np.isnan(whole.torques.friction).any()
