"""The loop on the machine as built (hipsim.control.machine_loop) on runs of a few servo periods of the reduced plant:
the same arithmetic as simulate() on the drawing, the feed-forward row by row, the limit, and each refusal's words."""

import dataclasses
import math
from types import SimpleNamespace

import numpy as np
import pytest
from stations_synthetic import deviated

import hipsim
from hipsim.analytic.chain_dynamics import chain_inverse_dynamics, chain_motion
from hipsim.control.controllers import WorkspacePD, feedforward_torques
from hipsim.control.feedback import EncoderFeedback, SensorFeedback
from hipsim.control.machine_loop import ModelPD, check_plant, controlled_machine, model_feedforward, run_machine
from hipsim.control.simulation import ReducedPlant, simulate
from hipsim.exceptions import ArgumentError, ParameterError, PoseError
from hipsim.motion.trajectories import Trajectory

Q0 = np.radians([4.0, 1.0, -2.0])


@pytest.fixture(scope="module")
def drawing():
    return hipsim.load_parameters()


def _desired(t):
    """A slow turn from Q0 under a load that rises: 1000 + 500·t N."""
    t = np.asarray(t, dtype=float)
    rate = np.array([0.2, -0.1, 0.05])
    q = Q0 + t[:, None] * rate
    return Trajectory(t, q, np.tile(rate, (t.size, 1)), np.zeros((t.size, 3)), 1000.0 + 500.0 * t, name="turn")


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
    assert run.saturated.tolist() == [False, True, True] and run.step == 1e-3


def test_what_does_not_fit_is_refused(drawing):
    plant = ReducedPlant(drawing)
    pd = ModelPD(drawing, 2)
    with pytest.raises(ArgumentError, match="^feedback: expected the controller's platform 2, got 1"):
        run_machine(plant, pd, SensorFeedback(1), _desired, 0.003)
    with pytest.raises(
        ArgumentError, match=r"^feedforward: expected torques of shape \(3, 3\), one row a servo period"
    ):
        run_machine(plant, pd, SensorFeedback(2), _desired, 0.003, feedforward=np.zeros((2, 3)))
    with pytest.raises(ArgumentError, match=r"^duration: expected at least two servo periods \(0\.002 s\)"):
        run_machine(plant, pd, SensorFeedback(2), _desired, 0.0014)
    assert run_machine(plant, pd, SensorFeedback(2), _desired, 0.0015).t.size == 2
    with pytest.raises(
        ArgumentError, match="^compiled: expected False or None, unless the plant offers compiled_stepper"
    ):
        run_machine(plant, pd, SensorFeedback(2), _desired, 0.003, compiled=True)
    with pytest.raises(ArgumentError, match="^step"):
        run_machine(plant, pd, SensorFeedback(2), _desired, 0.003, step=0.002)


def test_a_desired_motion_out_of_the_model_s_reach_is_named(drawing):
    def far(t):
        d = _desired(t)
        q = d.q.copy()
        q[2:] = np.radians([0.0, 0.0, 80.0])
        return Trajectory(d.t, q, d.qd, d.qdd, d.Fe, name="far")

    with pytest.raises(PoseError, match="pose out of reach of the model's platform 2") as error:
        run_machine(ReducedPlant(drawing), ModelPD(drawing, 2), SensorFeedback(2), far, 0.004)
    assert (error.value.time, error.value.index) == (pytest.approx(0.002), 2)
    assert "far" in str(error.value)


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
