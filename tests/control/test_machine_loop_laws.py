"""The loop on the machine as built (hipsim.control.machine_loop) on runs of a few servo periods of the reduced plant:
the same arithmetic as simulate() on the drawing, the feed-forward row by row, the limit, and each refusal's words."""

import dataclasses
import math
import os
from types import SimpleNamespace
from typing import Any

import numpy as np
import pytest
from fake_clock import FakeClock
from stations_synthetic import deviated
from support import RAMP_Q0 as Q0
from support import turn

import hipsim
from hipsim.analytic.chain_dynamics import chain_inverse_dynamics, chain_motion
from hipsim.control.controllers import WorkspacePD, feedforward_torques
from hipsim.control.feedback import EncoderFeedback, Feedback, SensorFeedback
from hipsim.control.machine_loop import ModelPD, check_plant, controlled_machine, model_feedforward, run_machine
from hipsim.control.simulation import ReducedPlant, simulate
from hipsim.exceptions import ArgumentError, ParameterError, PoseError
from hipsim.motion.trajectories import Trajectory


@pytest.fixture(scope="module")
def drawing():
    return hipsim.load_parameters()


_desired = turn  # the motion of tests/support.py


def test_controlled_machine(drawing):
    assert controlled_machine(drawing, 1) is drawing  # the drawing: its platforms turn alike
    built = drawing.replace(geometry=deviated(seed=5))
    assert built.geometry is not None
    assert controlled_machine(built, built.geometry.control) is built
    other = 3 - built.geometry.control
    turned = controlled_machine(built, other).geometry
    assert turned is not None and turned.control == other


def test_model_pd(drawing):
    for control in (0, 3, True):
        with pytest.raises(ArgumentError, match="^control: expected 1 \\(m_1\\) or 2 \\(m_2\\)"):
            ModelPD(drawing, control)
    pd = ModelPD(drawing, 1, kp=[1.0, 2.0, 3.0], kd=5.0)
    assert (pd.model, pd.control, pd.kp.tolist(), pd.kd.tolist()) == (drawing, 1, [1.0, 2.0, 3.0], [5.0] * 3)
    default = ModelPD(drawing, 2)
    assert default.kp.tolist() == drawing.control.kp.tolist() and default.kd.tolist() == drawing.control.kd.tolist()
    q, qd = Q0, np.array([0.1, 0.0, -0.1])
    expected = WorkspacePD(drawing, kp=[1.0, 2.0, 3.0], kd=5.0)._kernel_params  # the drawing's law, another route
    from hipsim.analytic import kernel

    tau = kernel.workspace_pd(expected, q, qd, q + 0.01, np.zeros(3), np.array([1.0, 2.0, 3.0]), np.full(3, 5.0))
    assert pd.torques(q, qd, q + 0.01, np.zeros(3)) == pytest.approx(tau, rel=1e-12)


def test_the_model_s_feedforward_at_each_period_s_middle(drawing):
    ff = model_feedforward(drawing, 2, _desired, 100.0, 0.03)
    assert ff == pytest.approx(feedforward_torques(drawing, _desired(np.array([0.005, 0.015, 0.025]))), rel=1e-12)
    built = drawing.replace(geometry=deviated(seed=5))
    machine = controlled_machine(built, 1)
    desired = _desired(np.array([0.005, 0.015]))
    expected = chain_inverse_dynamics(machine, chain_motion(machine, desired), desired.Fe).total
    assert model_feedforward(built, 1, _desired, 100.0, 0.02) == pytest.approx(expected, rel=1e-12)


def test_on_the_drawing_the_loop_is_simulate_s(drawing):
    """The reduced plant of the drawing, exact sensors, a feed-forward: the run simulate() makes with the same torques."""
    plant = ReducedPlant(drawing, lever_spin=False)
    ff = model_feedforward(drawing, 2, _desired, 1000.0, 0.004)
    run = run_machine(
        plant, ModelPD(drawing, 2), SensorFeedback(2, noise=0.0, encoder_step=0.0), _desired, 0.004, feedforward=ff,
        controller_name="augmented", compiled=None,
    )  # fmt: skip

    class Same(WorkspacePD):
        def __call__(self, t, state, desired):
            return ff[int(round(t * 1000))] + super().__call__(t, state, desired)

    sim = simulate(plant, Same(drawing), _desired, 0.004)
    assert run.attitudes[:, 1] == pytest.approx(sim.q, abs=1e-14) and run.attitudes[:, 0] == pytest.approx(
        sim.q, abs=1e-14
    )
    assert run.rates[:, 1] == pytest.approx(sim.qd, abs=1e-13)
    assert run.tau == pytest.approx(sim.tau, rel=1e-12) and run.measured == pytest.approx(sim.q, abs=1e-14)
    assert run.motor_speed == pytest.approx(sim.motor_speed, rel=1e-9)
    L, _, _, _ = plant.readings(np.r_[sim.q[3], sim.qd[3]])
    assert run.carriages[3] == pytest.approx(L, abs=1e-15)
    assert (run.plant, run.controller, run.feedback, run.control, run.step) == (
        "reduced",
        "augmented",
        "sensors",
        2,
        5e-4,
    )
    assert run.t.tolist() == pytest.approx([0.0, 0.001, 0.002, 0.003])
    assert run.desired.Fe.tolist() == pytest.approx([1000.0, 1000.5, 1001.0, 1001.5])


def test_the_encoders_read_through_the_model(drawing):
    """Encoders of 1 µm on the drawing: the controller sees the attitude of the rounded carriages, not the true one."""
    plant = ReducedPlant(drawing, lever_spin=False)
    run = run_machine(plant, ModelPD(drawing, 1), EncoderFeedback(drawing, 1), _desired, 0.003, servo_rate=1000.0)
    assert run.carriages == pytest.approx(np.rint(run.carriages / 1e-6) * 1e-6, abs=1e-15)
    off = np.abs(run.measured - run.attitudes[:, 0]).max()
    assert 0 < off < 1e-4  # rad: a micrometre of carriage
    assert run.feedback == "encoders" and run.controller == ""


def test_the_limit_clips_and_counts(drawing):
    plant = ReducedPlant(drawing, lever_spin=False)
    ff = np.array([[0.5, -0.5, 0.0], [2.0, 0.0, 0.0], [0.0, 0.0, -3.0]])
    run = run_machine(
        plant, ModelPD(drawing, 2, kp=0.0, kd=0.0), SensorFeedback(2, noise=0.0), _desired, 0.003,
        feedforward=ff, servo_rate=1000.0, step=1e-3, torque_limit=0.5,
    )  # fmt: skip
    assert run.tau_requested == pytest.approx(ff, abs=0)
    assert run.tau.tolist() == [[0.5, -0.5, 0.0], [0.5, 0.0, 0.0], [0.0, 0.0, -0.5]]
    assert run.saturated.tolist() == [False, True, True] and run.saturated.dtype == np.bool_ and run.step == 1e-3


def test_what_does_not_fit_is_refused(drawing):
    plant = ReducedPlant(drawing)
    pd = ModelPD(drawing, 2)
    refused: list[tuple[Feedback, dict[str, Any], float, str]] = [
        (SensorFeedback(1), {}, 0.003, "feedback: expected the controller's platform 2, got 1"),
        (
            SensorFeedback(2),
            {"feedforward": np.zeros((2, 3))},
            0.003,
            "feedforward: expected torques of shape (3, 3), one row a servo period, got (2, 3)",
        ),
        (SensorFeedback(2), {}, 0.0014, "duration: expected at least two servo periods (0.002 s), got 0.0014"),
        (
            SensorFeedback(2),
            {"compiled": True},
            0.003,
            "compiled: expected False or None, unless the plant offers compiled_stepper() (the PinocchioPlant), "
            "got True",
        ),
    ]
    for feedback, kwargs, duration, message in refused:
        with pytest.raises(ArgumentError) as error:
            run_machine(plant, pd, feedback, _desired, duration, **kwargs)
        assert str(error.value) == message
    assert run_machine(plant, pd, SensorFeedback(2), _desired, 0.0015).t.size == 2
    with pytest.raises(ArgumentError, match="^step"):
        run_machine(plant, pd, SensorFeedback(2), _desired, 0.003, step=0.002)


def test_a_desired_motion_out_of_the_model_s_reach_is_named(drawing):
    def far(t):
        d = _desired(t)
        q = d.q.copy()
        q[2:] = np.radians([0.0, 0.0, 80.0])
        return Trajectory(d.t, q, d.qd, d.qdd, d.Fe, name="far")

    with pytest.raises(PoseError) as error:
        run_machine(ReducedPlant(drawing), ModelPD(drawing, 2), SensorFeedback(2), far, 0.004)
    assert (error.value.time, error.value.index) == (pytest.approx(0.002), 2)
    assert str(error.value) == (
        "far, t = 0.002 s: pose out of reach of the model's platform 2: a lever cannot span the gap from its U-joint "
        "to its platform joint"
    )


def test_a_state_no_longer_finite_or_an_unreadable_attitude_is_named(drawing):
    class Blows(ReducedPlant):
        def derivative(self, t, x, tau, Fe):
            return np.full(6, np.nan) if t > 0.0016 else super().derivative(t, x, tau, Fe)

    with pytest.raises(PoseError, match="no longer finite") as error:
        run_machine(Blows(drawing), ModelPD(drawing, 2), SensorFeedback(2, noise=0.0), _desired, 0.004)
    assert (error.value.time, error.value.index) == (pytest.approx(0.002), 2)

    class Lost(EncoderFeedback):
        def measure(self, k, t, L, Ld, q, qd):
            reading, angles, rates = super().measure(k, t, L, Ld, q, qd)
            return (reading + 1.0, angles * math.nan, rates) if k == 1 else (reading, angles, rates)

    with pytest.raises(
        PoseError, match=r"finds no attitude of platform 2 for what the encoders read \(\d+\.\d{4}, "
    ) as error:
        run_machine(ReducedPlant(drawing), ModelPD(drawing, 2), Lost(drawing, 2), _desired, 0.004)
    assert (error.value.time, error.value.index) == (pytest.approx(0.001), 1)


def _stand_in(model, source="plant.toml", **chains):
    """A plant machine that is the model's but for the chain values given (what check_plant reads of it)."""
    return SimpleNamespace(
        angle_signs=model.angle_signs, chains=dataclasses.replace(model.chains, **chains), source=source
    )


@pytest.mark.parametrize(
    ("field", "index", "where", "what"),
    [
        ("screw_points", (1, 0, 2), "chain 21", "U-joint centre"),
        ("platform_points", (0, 2, 0), "chain 13", "platform joint"),
        ("lever_lengths", (1, 2), "chain 23", "lever length"),
        ("centres", (1, 1), "platform 2", "rotation centre"),
    ],
)
def test_each_part_of_the_built_machine_is_checked_at_its_limit(drawing, monkeypatch, field, index, where, what):
    """Each part off by 50 mm (MAX_DEVIATION) passes; by 50.4 mm it is refused, naming part, chain or platform, and
    the deviation in mm; the largest deviation is the one named (a smaller one elsewhere first)."""
    reached = []
    monkeypatch.setattr(
        "hipsim.analytic.stations.platform_attitude", lambda plant, L, control, **kw: reached.append((plant, control))
    )
    desired = _desired(np.arange(3) / 1000.0)
    base = getattr(drawing.chains, field)

    def off(mm):
        values = np.array(base, dtype=float)
        values[index] += mm * 1e-3
        first = (0,) * values.ndim  # a smaller deviation at the first entry: not the one named
        if first != index:
            values[first] += 20e-3
        return values

    # The centres' x and y are 0 on the drawing: 50 mm there is exactly MAX_DEVIATION (not refused).
    at_limit = _stand_in(drawing, **{field: off(50.0 if field == "centres" else 50.0 - 1e-9)})
    check_plant(drawing, at_limit, desired, 2)
    assert reached == [(at_limit, 2)]
    with pytest.raises(ParameterError) as error:
        check_plant(drawing, _stand_in(drawing, **{field: off(50.4)}), desired, 2)
    assert str(error.value) == (
        f"plant.toml: not the model's machine as built: the {what} of {where} is 50.4 mm off the model's "
        "(a built machine deviates by at most 50 mm; give the plant and the model of one design)"
    )
    assert len(reached) == 1


def test_a_plant_of_another_convention_or_out_of_reach_is_refused_whole(drawing, monkeypatch):
    desired = _desired(np.arange(3) / 1000.0)
    other = SimpleNamespace(angle_signs=np.array([1.0, -1.0, 1.0]), chains=drawing.chains, source="plant.toml")
    with pytest.raises(ParameterError) as error:
        check_plant(drawing, other, desired, 1)  # type: ignore[arg-type]
    signs = drawing.angle_signs.tolist()
    assert str(error.value) == (
        f"plant.toml, key 'angles': the plant's angle signs [1.0, -1.0, 1.0] are not the model's {signs}: "
        "one machine has one convention"
    )

    def lost(plant, L, control, t, q0, guess):
        assert control == 1 and t.tolist() == desired.t.tolist()
        assert q0.tolist() == desired.q[0].tolist() and guess is desired.q
        raise PoseError("no attitude", 0.002, 2)

    monkeypatch.setattr("hipsim.analytic.stations.platform_attitude", lost)
    with pytest.raises(ParameterError) as error:
        check_plant(drawing, _stand_in(drawing), desired, 1)
    assert str(error.value).startswith(
        "plant.toml: the plant's platform 1 cannot follow the carriages the model commands: "
    )
    assert str(error.value).endswith("no attitude")


@pytest.fixture(scope="module")
def pinocchio_plant(drawing):
    from hipsim.closed_chain.plant import PinocchioPlant

    return PinocchioPlant(drawing.replace(geometry=deviated(seed=5)))


def test_the_loop_s_refusals_whole(drawing):
    """Each refusal names its setting and value: the platform, the gains, a plant built for the other platform, the
    encoders' readings in mm where the model finds no attitude."""
    for make, message in (
        (lambda: ModelPD(drawing, 3), "control: expected 1 (m_1) or 2 (m_2), got 3"),
        (lambda: ModelPD(drawing, 2, kp=np.ones(2)), "kp: expected shape (3,), got shape (2,)"),
        (lambda: ModelPD(drawing, 2, kd=np.ones(4)), "kd: expected shape (3,), got shape (4,)"),
    ):
        with pytest.raises(ArgumentError) as error:
            make()
        assert str(error.value) == message
    built = drawing.replace(geometry=deviated(seed=5))
    assert built.geometry is not None
    other = 3 - built.geometry.control
    stand_in = SimpleNamespace(params=built)  # what the check reads of a plant
    with pytest.raises(ArgumentError) as error:
        run_machine(stand_in, ModelPD(drawing, other), SensorFeedback(other), _desired, 0.003)
    assert str(error.value) == (
        f"plant: expected a plant built from controlled_machine(params, {other}), whose first state holds the "
        f"controlled platform at the desired motion, got 'a plant whose [geometry] control is {built.geometry.control}'"
    )
    seen = []

    class Lost(EncoderFeedback):
        def measure(self, k, t, L, Ld, q, qd):
            reading, angles, rates = super().measure(k, t, L, Ld, q, qd)
            seen.append(reading)
            return (reading, angles * math.nan, rates) if k == 1 else (reading, angles, rates)

    with pytest.raises(PoseError) as lost:
        run_machine(ReducedPlant(drawing), ModelPD(drawing, 2), Lost(drawing, 2), _desired, 0.004, servo_rate=500.0)
    mm = ", ".join(f"{v * 1000:.4f}" for v in seen[1])
    assert f"finds no attitude of platform 2 for what the encoders read ({mm} mm)" in str(lost.value)
    assert (lost.value.time, lost.value.index) == (pytest.approx(0.002), 1)  # 500 Hz: period 1 at 2 ms


def _blowing_up(t):
    """The slow turn under a load of 1e300 N from 5 ms on: the plant's state overflows within the period it starts in."""
    d = _desired(t)
    return Trajectory(d.t, d.q, d.qd, d.qdd, np.where(d.t > 0.005, 1e300, d.Fe), name="turn")


@pytest.mark.parametrize("compiled", [True, False])
@pytest.mark.parametrize("sensors", [False, True])
def test_an_unstable_run_of_the_pinocchio_plant_is_named_at_its_period(drawing, pinocchio_plant, compiled, sensors):
    """At 500 Hz (a period of 2 ms, four steps of 0.5 ms) the load first overflows in period 2 (4-6 ms): its last
    steps; the state is first not finite at the start of period 3, t = 6 ms, on the compiled route (machine_kernel)
    as in the Python loop."""
    feedback = SensorFeedback(2, noise=0.0) if sensors else EncoderFeedback(drawing, 2)
    with np.errstate(all="ignore"), pytest.raises(PoseError) as error:
        run_machine(
            pinocchio_plant, ModelPD(drawing, 2), feedback, _blowing_up, 0.012, servo_rate=500.0, step=5e-4,
            compiled=compiled,
        )  # fmt: skip
    assert (error.value.time, error.value.index) == (pytest.approx(0.006, abs=1e-15), 3)
    assert str(error.value) == (
        "t = 0.006 s: the plant's state is no longer finite: the loop went unstable or the machine left its workspace "
        "(check the gains control.kp_Nm_rad and kd_Nm_s_rad, the integration step and the masses)"
    )


@pytest.mark.parametrize("compiled", [True, False])
def test_encoders_the_model_cannot_read_are_named_on_both_routes(drawing, pinocchio_plant, compiled):
    """Encoders of 1 m read the carriages (about 0.6 m) as 1 m each, where the model's platform 2 has no attitude:
    the first period is refused, naming the readings in mm, on the compiled route as in the Python loop."""
    with pytest.raises(PoseError) as error:
        run_machine(
            pinocchio_plant, ModelPD(drawing, 2), EncoderFeedback(drawing, 2, step=1.0), _desired, 0.006,
            servo_rate=500.0, compiled=compiled,
        )  # fmt: skip
    assert (error.value.time, error.value.index) == (0.0, 0)
    assert str(error.value) == (
        "t = 0 s: the model's forward kinematics finds no attitude of platform 2 for what the encoders read "
        "(1000.0000, 1000.0000, 1000.0000 mm)"
    )


class _Bar:
    """tqdm as the servo loop opens it: what it was given and how far it went."""

    opened: list[dict] = []

    def __init__(self, **kwargs):
        self.kwargs = {**kwargs, "updates": 0}
        _Bar.opened.append(self.kwargs)

    def __enter__(self):
        return self

    def __exit__(self, *args):
        return False

    def update(self, count):
        self.kwargs["updates"] += count


@pytest.mark.parametrize("compiled", [None, True, False])
def test_the_route_taken_its_progress_bar_and_its_compile_note(drawing, pinocchio_plant, monkeypatch, compiled):
    """compiled None or True takes machine_kernel (its two calls: the first period alone, then the rest), False the
    Python loop; the bar is described by plant, controller and feedback, shown only when asked for, and a first
    period that takes 1.5 s is announced through ``notify``."""
    import hipsim.clock
    from hipsim.control import machine_kernel

    clock = FakeClock()
    monkeypatch.setattr(hipsim.clock, "SYSTEM_CLOCK", clock)  # the clock of the compile note
    monkeypatch.setattr("hipsim.control.simulation.tqdm", _Bar)
    _Bar.opened = []
    calls = []
    kernel = machine_kernel.machine_loop

    def slow_kernel(*args):
        calls.append(args[8:10])  # start, stop
        clock.advance(1.5 if len(calls) == 1 else 0.0)  # as long as a compilation, as far as the note can tell
        return kernel(*args)

    class Slow(EncoderFeedback):  # the Python loop's first period: as slow
        def measure(self, k, t, L, Ld, q, qd):
            clock.advance(1.5 if k == 0 else 0.0)
            return super().measure(k, t, L, Ld, q, qd)

    monkeypatch.setattr(machine_kernel, "machine_loop", slow_kernel)
    notes: list[str] = []
    feedback = (Slow if compiled is False else EncoderFeedback)(drawing, 2)
    run = run_machine(
        pinocchio_plant, ModelPD(drawing, 2), feedback, _desired, 0.003, servo_rate=1000.0, step=5e-4,
        progress=True, notify=notes.append, controller_name="slow", compiled=compiled,
    )  # fmt: skip
    # What the run records of itself, on either route (a period of 1 ms: two steps of 0.5 ms).
    assert (run.plant, run.controller, run.feedback, run.control, run.step) == (
        "pinocchio",
        "slow",
        "encoders",
        2,
        5e-4,
    )
    assert run.desired.Fe.tolist() == pytest.approx([1000.0, 1000.5, 1001.0], abs=1e-12)
    assert calls == ([] if compiled is False else [(0, 1), (1, 3)])
    assert notes == ["pinocchio plant, slow, encoders: compiling (first run only) ..."]
    assert [(b["desc"], b["disable"], b["total"], b["updates"]) for b in _Bar.opened] == [
        ("pinocchio plant, slow, encoders", False, 3, 2)
    ]
    run_machine(pinocchio_plant, ModelPD(drawing, 2), EncoderFeedback(drawing, 2), _desired, 0.002, compiled=compiled)
    assert _Bar.opened[-1]["desc"] == "pinocchio plant, controller, encoders" and _Bar.opened[-1]["disable"]


@pytest.mark.skipif(os.environ.get("NUMBA_DISABLE_JIT") == "1", reason="counts numba's compiled signatures")
def test_a_feedforward_of_any_layout_compiles_the_loop_once(drawing, pinocchio_plant):
    """model_feedforward's read-only Fortran view, a user's C array and none at all reach the compiled loop as one
    array type (a second type would compile machine_kernel.machine_loop again: seconds), with the same torques."""
    from hipsim.control import machine_kernel

    n = 3  # servo periods at 1 kHz over 3 ms
    given = np.array([[0.01, -0.02, 0.03], [0.0, 0.01, 0.0], [-0.01, 0.0, 0.02]])[:n]
    fortran = np.asfortranarray(given)
    fortran.flags.writeable = False
    runs, compiled = [], []  # the count after each run (other tests in this process may have compiled other plants)
    for ff in (None, given, fortran):
        pd, encoders = ModelPD(drawing, 2), EncoderFeedback(drawing, 2)
        runs.append(run_machine(pinocchio_plant, pd, encoders, _desired, 0.003, feedforward=ff))
        compiled.append(len(machine_kernel.machine_loop.signatures))
    assert compiled[1:] == compiled[:1] * 2, machine_kernel.machine_loop.signatures
    assert np.array_equal(runs[1].tau_requested, runs[2].tau_requested)
    # The same state at period 0: the rows differ by the feed-forward alone there.
    assert np.allclose(runs[1].tau_requested[0] - runs[0].tau_requested[0], given[0], rtol=0, atol=1e-12)
