"""hipsim.control.closed_chain_loop: the Pinocchio plant's compiled RK4 steps with each period's compiled control, in
chunks of servo periods. Against the Python loop it compiles (the plant's ``advance`` and the controller called each
period), to the last bits; a state that is not finite stops it at its period, logging nothing; chunks are the run in
one call.

The direct calls take the argument types :func:`hipsim.control.simulate` passes (recorded from its run), so they run
the specialisation the suite's warm-up compiled.
"""

from __future__ import annotations

import inspect
import math

import numpy as np
import pytest
from support import RAMP_Q0 as Q0
from support import Recorded, argument_types, ramp, recorded_calls

import hipsim
from hipsim.control import closed_chain_loop
from hipsim.control.controllers import AugmentedPD
from hipsim.control.simulation import apply_mismatch, simulate
from hipsim.exceptions import ArgumentError

NAMES = list(
    inspect.signature(getattr(closed_chain_loop.stepped_loop, "py_func", closed_chain_loop.stepped_loop)).parameters
)
LOG = ("q", "qd", "tau", "tau_requested", "saturated")


@pytest.fixture(scope="module")
def params():
    return hipsim.load_parameters()


_desired = ramp  # the motion of tests/support.py


@pytest.fixture(scope="module")
def pinocchio(params):
    from hipsim.closed_chain.plant import PinocchioPlant

    return PinocchioPlant(apply_mismatch(params, friction=0.3, masses=-0.1))


def test_three_periods_of_the_pinocchio_plant_compiled_and_in_python_agree(params, pinocchio):
    """The Pinocchio plant's compiled RK4 steps with the control of each period (closed_chain_loop) against the
    Python loop, three periods from the desired pose, with a limit that bites: the same numbers."""
    assert pinocchio.compiled_stepper() is not None
    start = pinocchio.initial_state(_desired(np.zeros(1)))
    controller = AugmentedPD(params, _desired, 1000.0, 0.003)
    free = simulate(pinocchio, controller, _desired, 0.003, 1000.0, 5e-4, compiled=False)
    limit = 0.7 * float(np.abs(free.tau).max())
    slow, fast = (
        simulate(pinocchio, controller, _desired, 0.003, 1000.0, 5e-4, limit, start, compiled=c) for c in (False, True)
    )
    assert fast.q == pytest.approx(slow.q, abs=1e-12) and fast.qd == pytest.approx(slow.qd, abs=1e-9)
    assert fast.tau == pytest.approx(slow.tau, abs=1e-9)
    assert fast.tau_requested == pytest.approx(slow.tau_requested, abs=1e-9)
    assert fast.saturated.tolist() == slow.saturated.tolist() and slow.saturated.any()
    assert np.abs(fast.tau).max() == pytest.approx(limit, rel=1e-15) and fast.plant == pinocchio.name
    assert free.q[0] == pytest.approx(Q0, abs=1e-9)
    with pytest.raises(ArgumentError) as error:
        simulate(pinocchio, controller, _desired, 0.003, 1000.0, 5e-4, initial_state=start[:-1], compiled=True)
    assert (
        str(error.value)
        == f"initial_state: expected a state of the {pinocchio.name} plant, of shape {start.shape}, got shape {start[:-1].shape}"
    )


@pytest.fixture(scope="module")
def run(params, pinocchio):
    """simulate's calls of stepped_loop on three periods of the augmented PD (period 0 alone, then 1–2), and the run."""
    controller = AugmentedPD(params, _desired, 1000.0, 0.003)
    with pytest.MonkeyPatch.context() as patch:
        calls = recorded_calls(patch, closed_chain_loop, "stepped_loop")
        sim = simulate(pinocchio, controller, _desired, 0.003, 1000.0, 5e-4, compiled=True)
    return (
        [Recorded(dict(zip(NAMES, args, strict=True)), types) for args, types in calls],
        sim,
        pinocchio.initial_state(_desired(np.zeros(1))),
    )


def _loop(recorded: Recorded, x0: np.ndarray, start: int, stop: int):
    """stepped_loop from x0 (copied) on fresh logs (NaN, and True for the flags)."""
    args = dict(recorded.args, x=x0.copy(), start=start, stop=stop)
    for name in LOG:
        args[name] = np.full_like(recorded.args[name], True if name == "saturated" else np.nan)
    assert argument_types(tuple(args.values())) == recorded.types  # simulate's own types
    return closed_chain_loop.stepped_loop(*(args[name] for name in NAMES)), args


def test_chunks_of_periods_are_the_run_in_one_call(run):
    calls, sim, x0 = run
    assert [(call.args["start"], call.args["stop"]) for call in calls] == [(0, 1), (1, 3)]
    reached, log = _loop(calls[0], x0, 0, 3)
    assert reached == 3
    for name, logged in zip(LOG, (sim.q, sim.qd, sim.tau, sim.tau_requested, sim.saturated), strict=True):
        np.testing.assert_array_equal(log[name], logged)
    np.testing.assert_array_equal(log["x"], calls[1].args["x"])  # the state simulate's last chunk reached
    assert np.abs(log["x"] - x0).max() > 1e-6


def test_a_state_not_finite_stops_the_run_at_its_period_logging_nothing(run):
    """A NaN in a coordinate the control does not read (not the controlled platform's angles or rates): period 1
    returned, no angle, torque or flag logged at it, and x as it was."""
    calls, _, x0 = run
    unread = next(i for i in range(x0.size) if i not in {*calls[0].args["angle_slots"], *calls[0].args["rate_slots"]})
    x = x0.copy()
    x[unread] = math.nan
    reached, log = _loop(calls[0], x, 1, 3)
    assert reached == 1
    for name in LOG[:4]:
        assert np.isnan(log[name]).all(), name
    assert log["saturated"].all()
    np.testing.assert_array_equal(log["x"], x)
