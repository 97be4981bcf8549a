"""hipsim.control.servo_kernel by hand: one servo period is the state logged, the controller's torque clipped to the
limit and held over the plant's RK4 steps; the limit bites strictly above it and lets NaN through; a run stops at the
first state that is not finite; chunks of periods are the run in one call.

Every call takes the argument types :func:`hipsim.control.simulate` passes (recorded from a three-period run), so the
specialisation the suite's warm-up compiled is the one these tests run: no compilation of their own.
"""

from __future__ import annotations

import inspect
import math

import numpy as np
import pytest
from support import Recorded, argument_types, recorded_calls

import hipsim
from hipsim.analytic import kernel as reduced_kernel
from hipsim.control import servo_kernel
from hipsim.control.controllers import AugmentedPD, Sample, WorkspacePD
from hipsim.control.simulation import ReducedPlant, simulate
from hipsim.motion.trajectories import iso14242_at

NAMES = list(inspect.signature(getattr(servo_kernel.servo_loop, "py_func", servo_kernel.servo_loop)).parameters)
PERIOD_NAMES = list(
    inspect.signature(getattr(servo_kernel.control_period, "py_func", servo_kernel.control_period)).parameters
)
LOG = ("q", "qd", "tau", "tau_requested", "saturated")


@pytest.fixture(scope="module")
def params():
    return hipsim.load_parameters()


@pytest.fixture(scope="module")
def run(params):
    """simulate's three periods of an augmented PD on the reduced plant: its calls of servo_loop and the run."""
    controller = AugmentedPD(params, iso14242_at, params.control.servo_rate, 0.003)
    with pytest.MonkeyPatch.context() as patch:
        calls = recorded_calls(patch, servo_kernel, "servo_loop")
        sim = simulate(ReducedPlant(params), controller, iso14242_at, 0.003)
    return [Recorded(dict(zip(NAMES, args, strict=True)), types) for args, types in calls], sim, controller


def _read_only(values, dtype=float) -> np.ndarray:
    array = np.ascontiguousarray(values, dtype=dtype)
    array.flags.writeable = False
    return array


def _loop(recorded: Recorded, x0: np.ndarray, start: int, stop: int, **changes):
    """servo_loop from x0 (copied) on fresh logs (NaN, and True for the flags), with some arguments changed."""
    args = dict(recorded.args, x=x0.copy(), start=start, stop=stop, **changes)
    for name in LOG:
        args[name] = np.full_like(recorded.args[name], True if name == "saturated" else np.nan)
    assert argument_types(tuple(args.values())) == recorded.types  # simulate's own types
    reached = servo_kernel.servo_loop(*(args[name] for name in NAMES))
    return reached, args


def _start(sim) -> np.ndarray:
    return np.concatenate([sim.q[0], sim.qd[0]])


def test_a_period_logs_the_state_then_holds_the_clipped_torque_over_rk4_steps_by_hand(params, run):
    """Period 1 by hand, from the state the run reached there: the augmented PD's torque at the logged state and
    period 1's desired state and feed-forward row, clipped to a limit that bites, then the classic RK4 steps (h, the
    loads at every half step from period 1's first, 2·substeps in) of the plant's derivative under that torque."""
    calls, sim, controller = run
    recorded, x1 = calls[0].args, np.concatenate([sim.q[1], sim.qd[1]])
    t1 = float(sim.t[1])
    desired = Sample(recorded["desired_q"][1], recorded["desired_qd"][1])
    wanted = controller(t1, Sample(x1[:3], x1[3:]), desired)
    limit = 0.5 * float(np.abs(wanted).max())
    reached, log = _loop(calls[0], x1, 1, 2, limit=limit)
    assert reached == 2 and t1 == pytest.approx(1.0 / params.control.servo_rate, rel=1e-15)
    assert log["q"][1].tolist() == x1[:3].tolist() and log["qd"][1].tolist() == x1[3:].tolist()
    np.testing.assert_allclose(log["tau_requested"][1], wanted, rtol=0, atol=1e-12)
    held = np.clip(wanted, -limit, limit)
    assert np.abs(held - wanted).max() > 0.1 * limit  # the limit bites
    np.testing.assert_allclose(log["tau"][1], held, rtol=0, atol=1e-12)
    assert bool(log["saturated"][1]) and np.isnan(log["q"][[0, 2]]).all()  # period 1 only

    plant, h, substeps = ReducedPlant(params), recorded["h"], recorded["substeps"]
    loads = recorded["loads"][2 * substeps :]
    x = x1.copy()
    for s in range(substeps):
        k1 = plant.derivative(t1, x, held, loads[2 * s])
        k2 = plant.derivative(t1, x + h / 2 * k1, held, loads[2 * s + 1])
        k3 = plant.derivative(t1, x + h / 2 * k2, held, loads[2 * s + 1])
        k4 = plant.derivative(t1, x + h * k3, held, loads[2 * s + 2])
        x = x + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
    assert substeps >= 2 and loads[0] != loads[1] != loads[2]  # a wrong load index would show
    np.testing.assert_allclose(log["x"], x, rtol=0, atol=1e-13)
    assert np.abs(log["x"] - x1).max() > 1e-6  # and the state moved


def test_the_limit_bites_strictly_above_it_and_lets_nan_through(run):
    """Zero gains leave the feed-forward row alone: row 1 above the limit of 1 N·m (clipped, flagged), row 0 at it
    exactly (kept, not flagged), row 2 NaN (passed through as np.clip does, not flagged); the rows as ``rows`` picks."""
    calls, sim, _ = run
    table = _read_only([[0.5, -1.0, 1.0], [1.5, 0.0, -3.0], [math.nan, 0.25, 0.0]])
    zero, rows = _read_only(np.zeros(3)), _read_only([1, 0, 2], np.int64)
    changes = dict(kp=zero, kd=zero, feedforward=table, rows=rows, limit=1.0)
    reached, log = _loop(calls[0], _start(sim), 0, 3, **changes)
    assert reached == 3
    np.testing.assert_array_equal(log["tau_requested"], table[[1, 0, 2]])
    np.testing.assert_array_equal(log["tau"], [[1.0, 0.0, -1.0], [0.5, -1.0, 1.0], [math.nan, 0.25, 0.0]])
    assert log["saturated"].tolist() == [True, False, False]
    assert np.isfinite(log["q"][:3]).all() and not np.isfinite(log["x"]).any()  # the NaN torque reached the state
    reached, log = _loop(calls[0], _start(sim), 0, 3, **changes, with_feedforward=False)  # the workspace PD
    assert reached == 3 and not log["tau_requested"].any() and log["saturated"].tolist() == [False] * 3


def test_a_state_not_finite_stops_the_run_at_its_period(run):
    """From a state with one NaN rate at period 1: its angles logged, nothing else, period 1 returned, x kept."""
    calls, sim, _ = run
    x = _start(sim)
    x[4] = math.nan
    reached, log = _loop(calls[0], x, 1, 3)
    assert reached == 1
    assert log["q"][1].tolist() == x[:3].tolist() and math.isnan(log["qd"][1, 1])
    assert np.isnan(log["tau"]).all() and np.isnan(log["tau_requested"]).all() and log["saturated"].all()
    np.testing.assert_array_equal(log["x"], x)


def test_chunks_of_periods_are_the_run_in_one_call(run):
    """simulate's run came in chunks (period 0 alone, then 1–2): one call over 0–2 gives it to the last bit."""
    calls, sim, _ = run
    assert [(call.args["start"], call.args["stop"]) for call in calls] == [(0, 1), (1, 3)]
    reached, log = _loop(calls[0], _start(sim), 0, 3)
    assert reached == 3
    for name, logged in zip(LOG, (sim.q, sim.qd, sim.tau, sim.tau_requested, sim.saturated), strict=True):
        np.testing.assert_array_equal(log[name], logged)
    np.testing.assert_array_equal(log["x"], calls[1].args["x"])  # the state simulate's last chunk reached


def test_control_period_reads_the_signed_slots_of_a_plant_state(params, run):
    """A plant stepped outside (the Pinocchio plant's own routes): q[k] = signs·x[angle slots], q̇[k] the same at the
    rate slots, then the workspace PD at them (the controller's law); a state with a NaN anywhere logs nothing."""
    calls, _, _ = run
    recorded = calls[0].args
    controller = WorkspacePD(params)
    x = np.array([0.3, 0.05, -0.02, 9.0, 0.04, 0.5, -0.1, 0.2, 7.0, 0.01])
    angles, rates, signs = np.array([1, 6, 2]), np.array([4, 9, 7]), np.array([1.0, -1.0, 1.0])
    q, qd = np.full((3, 3), np.nan), np.full((3, 3), np.nan)
    tau, tau_requested, saturated = np.full((3, 3), np.nan), np.full((3, 3), np.nan), np.zeros(3, dtype=bool)
    args = dict(
        x=x,
        angle_slots=angles,
        rate_slots=rates,
        signs=signs,
        control=reduced_kernel.plain_parameters(controller._kernel_params),
        k=1,
        **{name: recorded[name] for name in PERIOD_NAMES[6:14]},
        q=q,
        qd=qd,
        tau=tau,
        tau_requested=tau_requested,
        saturated=saturated,
    )
    args.update(kp=_read_only(controller.kp), kd=_read_only(controller.kd), with_feedforward=False, limit=math.inf)
    assert servo_kernel.control_period(*(args[name] for name in PERIOD_NAMES))
    assert q[1].tolist() == [0.05, 0.1, -0.02] and qd[1].tolist() == [0.04, -0.01, 0.2]
    assert np.isnan(q[[0, 2]]).all()  # row k only
    desired = Sample(recorded["desired_q"][1], recorded["desired_qd"][1])
    np.testing.assert_allclose(tau_requested[1], controller(0.0, Sample(q[1], qd[1]), desired), rtol=1e-14, atol=0)
    np.testing.assert_array_equal(tau[1], tau_requested[1])
    x[3] = math.inf  # a coordinate the control does not read
    args["k"] = 2
    assert not servo_kernel.control_period(*(args[name] for name in PERIOD_NAMES))
    assert np.isnan(q[2]).all() and np.isnan(tau_requested[2]).all()
