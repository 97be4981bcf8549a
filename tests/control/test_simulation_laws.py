"""The servo loop of hipsim.control.simulation on stand-in plants whose motion is known in closed form: the zero-order
hold, the RK4 stages and their loads, the torque limit and its count, the settings at their edges, and the records."""

import math

import numpy as np
import pytest
from support import RAMP_Q0 as Q0
from support import RAMP_QD0 as QD0
from support import ramp

import hipsim
from hipsim.analytic.inverse_kinematics import kinematics
from hipsim.control.controllers import AugmentedPD, Sample, WorkspacePD
from hipsim.control.simulation import ReducedPlant, Simulation, apply_mismatch, parse_mismatch, servo_settings, simulate
from hipsim.exceptions import ArgumentError, PoseError
from hipsim.machine.parameter_set import FRICTION_COEFFICIENTS, ControlSettings
from hipsim.motion.trajectories import Trajectory
from hipsim.physics.transmission import angle_from_travel


@pytest.fixture(scope="module")
def params():
    return hipsim.load_parameters()


_desired = ramp  # the motion of tests/support.py


class DoubleIntegrator:
    """q̈ = c·τ + k·F_e(t), q̇ and q from the desired state: exact under RK4 (a cubic in t), whatever the step."""

    name = "double integrator"
    c, k = 1e-2, 1e-5

    def __init__(self, params):
        self.params = params
        self.calls = []

    def initial_state(self, desired):
        return np.concatenate([desired.q[0], desired.qd[0]])

    def derivative(self, t, x, tau, Fe):
        self.calls.append((t, Fe))
        return np.concatenate([x[3:], self.c * np.asarray(tau) + self.k * Fe])

    def angles(self, x):
        return x[:3], x[3:]


def _exact(t, t0, q0, qd0, tau):
    """q and q̇ at t from (q0, q̇0) at t0 under the held torque, the load 1000 + 500·t."""
    c, k, s = DoubleIntegrator.c, DoubleIntegrator.k, t - t0
    acc = c * tau + k * (1000.0 + 500.0 * t0)  # the load's value at t0, then its slope 500·k
    qd = qd0 + acc * s + k * 500.0 * s**2 / 2
    q = q0 + qd0 * s + acc * s**2 / 2 + k * 500.0 * s**3 / 6
    return q, qd


class Steps:
    """A controller of your own: torques by the period, and what it was shown."""

    def __init__(self, torques):
        self.torques, self.seen = torques, []

    def __call__(self, t, state, desired):
        self.seen.append((t, state, desired))
        return self.torques[len(self.seen) - 1]


def test_the_loop_holds_each_period_s_torque_over_rk4_steps_and_their_loads(params):
    """100 Hz, a step of 4 ms asked for: 3 steps of 10/3 ms a period; the motion exact to round-off."""
    torques = np.array([[1.0, -2.0, 0.5], [0.0, 3.0, -1.0], [2.0, 2.0, 2.0], [-1.0, 0.0, 0.0]])
    plant, controller = DoubleIntegrator(params), Steps(torques)
    sim = simulate(plant, controller, _desired, 0.04, servo_rate=100.0, step=0.004, controller_name="steps")
    assert sim.step == pytest.approx(0.01 / 3, rel=1e-15)
    assert sim.t.tolist() == pytest.approx([0.0, 0.01, 0.02, 0.03], abs=1e-15)
    q, qd = Q0.copy(), QD0.copy()
    for k in range(4):
        assert sim.q[k] == pytest.approx(q, abs=1e-14) and sim.qd[k] == pytest.approx(qd, abs=1e-14)
        q, qd = _exact(0.01 * (k + 1), 0.01 * k, q, qd, torques[k])
    # Three steps of four stages each per period, at the step's start, middle (twice) and end, each with its load.
    assert len(plant.calls) == 4 * 3 * 4
    h = 0.01 / 3
    stages = np.array([[s * h, s * h + h / 2, s * h + h / 2, (s + 1) * h] for s in range(12)]).ravel()
    assert [c[0] for c in plant.calls] == pytest.approx(stages, abs=1e-15)
    assert [c[1] for c in plant.calls] == pytest.approx(1000.0 + 500.0 * stages, rel=1e-14)
    # What the controller saw: the period's time, the state (copies), the desired state with its load.
    t, state, desired = controller.seen[2]
    assert t == pytest.approx(0.02, abs=1e-15)
    assert state.q == pytest.approx(sim.q[2], abs=0) and state.qd == pytest.approx(sim.qd[2], abs=0)
    assert desired.q == pytest.approx(Q0, abs=0) and desired.qd == pytest.approx(QD0, abs=0)
    assert desired.qdd.tolist() == [0.0, 0.0, 0.0] and desired.Fe == pytest.approx(1010.0, rel=1e-15)
    assert isinstance(desired.Fe, float)
    # The records: torques as asked, none limited, the names, the motor speeds of the motion.
    assert sim.tau.tolist() == torques.tolist() and sim.tau_requested.tolist() == torques.tolist()
    assert not sim.saturated.any()
    assert (sim.plant, sim.controller) == ("double integrator", "steps")
    actual = Trajectory(sim.t, sim.q, sim.qd, np.zeros((4, 3)), sim.desired.Fe)
    speed = angle_from_travel(kinematics(params, actual).Ld[:, 0], params.lead)
    assert sim.motor_speed == pytest.approx(speed, rel=1e-12)
    assert sim.desired.Fe.tolist() == pytest.approx([1000.0, 1005.0, 1010.0, 1015.0])


def test_a_step_that_fills_the_period_is_kept(params):
    sim = simulate(DoubleIntegrator(params), Steps(np.zeros((2, 3))), _desired, 0.02, servo_rate=100.0, step=0.01)
    assert sim.step == 0.01
    sim = simulate(DoubleIntegrator(params), Steps(np.zeros((2, 3))), _desired, 0.02, servo_rate=100.0, step=0.005)
    assert sim.step == 0.005


def test_the_limit_holds_and_counts_only_torques_beyond_it(params):
    """A torque exactly at the limit is not limited; beyond it, it is clipped to ±limit and counted."""
    torques = np.array([[1.0, -1.0, 0.0], [1.5, 0.0, 0.0], [0.0, -1.0000001, 0.2]])
    sim = simulate(
        DoubleIntegrator(params), Steps(torques), _desired, 0.03, servo_rate=100.0, step=0.01, torque_limit=1.0
    )
    assert sim.saturated.tolist() == [False, True, True]
    assert sim.tau.tolist() == [[1.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, -1.0, 0.2]]
    assert sim.tau_requested.tolist() == torques.tolist()
    assert sim.summary().saturated_samples == 2


def test_the_run_starts_where_it_is_told(params):
    start = np.concatenate([Q0 + 0.01, np.zeros(3)])
    sim = simulate(DoubleIntegrator(params), Steps(np.zeros((2, 3))), _desired, 0.02, 100.0, 0.01, initial_state=start)
    assert sim.q[0] == pytest.approx(Q0 + 0.01, abs=0) and sim.qd[0].tolist() == [0.0, 0.0, 0.0]


def test_two_periods_at_least(params):
    """0.015 s at 100 Hz rounds to 2 periods (run); 0.0149 s to 1 (refused, naming the two periods' 0.02 s)."""
    assert simulate(DoubleIntegrator(params), Steps(np.zeros((2, 3))), _desired, 0.015, 100.0, 0.01).t.size == 2
    with pytest.raises(ArgumentError, match=r"^duration: expected at least two servo periods \(0\.02 s\), got 0\.0149"):
        simulate(DoubleIntegrator(params), Steps(np.zeros((2, 3))), _desired, 0.0149, 100.0, 0.01)


def test_a_state_that_is_no_longer_finite_names_its_time(params):
    class Blows(DoubleIntegrator):
        def derivative(self, t, x, tau, Fe):
            return np.full(6, np.inf) if t > 0.016 else super().derivative(t, x, tau, Fe)  # period 1's last stage

    with pytest.raises(PoseError, match="no longer finite") as error:
        simulate(Blows(params), Steps(np.zeros((4, 3))), _desired, 0.04, 100.0, 0.01)
    assert error.value.time == pytest.approx(0.02) and error.value.index == 2


def test_a_plant_that_leaves_the_workspace_is_named(params):
    class Drifts(DoubleIntegrator):
        def derivative(self, t, x, tau, Fe):
            return np.concatenate([x[3:], [200.0, 0.0, 0.0]])  # α runs away: 200 rad/s² reaches 90° in 0.13 s

    with pytest.raises(PoseError, match="s: the plant left the workspace$") as error:
        simulate(Drifts(params), Steps(np.zeros((30, 3))), _desired, 0.3, 100.0, 0.01)
    assert 0.1 < error.value.time < 0.3 and error.value.index == round(error.value.time / 0.01)


def test_the_compiled_loop_only_for_the_built_in_parts(params):
    with pytest.raises(ArgumentError, match="^compiled: expected False, or None, unless the controller"):
        simulate(ReducedPlant(params), Steps(np.zeros((2, 3))), _desired, 0.02, 100.0, 0.01, compiled=True)
    with pytest.raises(ArgumentError, match="^compiled"):
        simulate(DoubleIntegrator(params), WorkspacePD(params), _desired, 0.02, 100.0, 0.01, compiled=True)


def test_the_python_and_compiled_loops_of_the_reduced_plant_agree(params):
    """Five periods of the reduced plant under the PD, each loop: the same numbers."""
    plant = ReducedPlant(params, lever_spin=False)
    runs = [
        simulate(
            plant, WorkspacePD(params), _desired, 0.005, 1000.0, 5e-4, initial_state=np.r_[Q0 + 0.002, QD0], compiled=c
        )
        for c in (False, True, None)
    ]
    for run in runs[1:]:
        assert run.q == pytest.approx(runs[0].q, abs=1e-12) and run.tau == pytest.approx(runs[0].tau, abs=1e-9)
    assert runs[0].plant == "reduced" and runs[0].step == 5e-4
    assert np.abs(runs[0].tau).max() > 0.1  # N·m: the PD pushes back the 0.002 rad offset


def test_a_reduced_plant_s_parts(params):
    plant = ReducedPlant(params, lever_spin=False)
    assert plant.lever_spin is False and ReducedPlant(params).lever_spin is True
    assert plant.compiled_kernel() is not None

    class Mine(ReducedPlant):
        pass

    assert Mine(params).compiled_kernel() is None
    x = np.r_[Q0, QD0]
    q, qd = plant.angles(x)
    assert q.tolist() == Q0.tolist() and qd.tolist() == QD0.tolist()
    assert plant.initial_state(_desired(np.array([0.0]))).tolist() == x.tolist()
    L, Ld, both_q, both_qd = plant.readings(x)
    motion = kinematics(params, Trajectory(np.zeros(1), Q0[None], QD0[None], np.zeros((1, 3)), np.zeros(1)))
    assert L == pytest.approx(motion.L[0, 0], abs=1e-12) and Ld == pytest.approx(motion.Ld[0, 0], abs=1e-12)
    assert both_q.tolist() == [Q0.tolist()] * 2 and both_qd.tolist() == [QD0.tolist()] * 2


def test_servo_settings_at_their_edges():
    control = ControlSettings(1000.0, 5e-4, np.ones(3), np.ones(3), 2.0)
    assert servo_settings(control, None, None, None) == (1000.0, 5e-4, 2.0)
    assert servo_settings(control, 100.0, 0.01 * (1 + 1e-10), math.inf) == (100.0, 0.01 * (1 + 1e-10), math.inf)
    with pytest.raises(
        ArgumentError, match=r"^step: expected an integration step no longer than the servo period 0\.01 s"
    ):
        servo_settings(control, 100.0, 0.01 * (1 + 2e-9), None)
    for name, args in (
        ("servo_rate", (0.0, None, None)),
        ("servo_rate", (math.nan, None, None)),
        ("torque_limit", (None, None, 0.0)),
        ("torque_limit", (None, None, math.nan)),
        ("step", (None, 0.0, None)),
        ("step", (None, math.nan, None)),
    ):
        with pytest.raises(ArgumentError, match=f"^{name}: expected a positive"):
            servo_settings(control, *args)


def test_mismatch_text_and_its_machine(params):
    assert parse_mismatch(" friction = +20.5 % , , masses=-10%") == {"friction": 0.205, "masses": -0.1}
    assert parse_mismatch("masses=3.%") == {"masses": 0.03} and parse_mismatch("") == {}
    for text in ("friction=20", "mass=10%", "friction=+2e1%", "friction=10%x"):
        with pytest.raises(ArgumentError, match="^mismatch: expected friction=\\+20% or masses=-10%"):
            parse_mismatch(text)
    with pytest.raises(ArgumentError, match="^mismatch: expected masses given once"):
        parse_mismatch("masses=1%,friction=2%,masses=1%")
    plant = apply_mismatch(params, friction=0.5, masses=-0.25)
    for name in FRICTION_COEFFICIENTS:
        assert getattr(plant.friction, name) == pytest.approx(1.5 * getattr(params.friction, name), rel=1e-15)
    assert plant.friction.hip_mu == pytest.approx(0.1425)
    for name in ("platform_mass", "platform_inertia", "lever_mass", "lever_inertia", "slider_mass", "screw_inertia"):
        assert np.asarray(getattr(plant, name)) == pytest.approx(0.75 * np.asarray(getattr(params, name)), rel=1e-15)
    assert plant.lead == params.lead
    assert apply_mismatch(params, friction=-0.999).friction.hip_mu > 0
    for f, m in ((-1.0, 0.0), (0.0, -1.0), (-1.5, 0.0)):
        with pytest.raises(ArgumentError, match="^mismatch: expected fractions above -1"):
            apply_mismatch(params, friction=f, masses=m)


def test_a_simulation_s_columns_and_summary(tmp_path):
    t = np.array([0.0, 0.001, 0.002])
    z = np.zeros((3, 3))
    desired = Trajectory(t, np.radians(np.full((3, 3), 1.0)), z, z, np.full(3, 100.0))
    q = np.radians([[1.0, 1.5, 0.0], [0.0, 1.0, 1.0], [1.0, 1.0, 3.0]])
    tau = np.array([[0.1, 0.2, 0.3], [0.0, 0.0, 0.0], [-0.4, 0.0, 0.0]])
    speed = np.array([[1.0, 2.0, 3.0], [0.0, 0.0, 0.0], [0.0, 0.0, -4.0]])
    sim = Simulation(t, desired, q, z, tau, 2 * tau, np.array([True, False, False]), speed, "reduced", "pd", 5e-4)
    assert np.degrees(sim.err) == pytest.approx(
        np.array([[0.0, -0.5, 1.0], [1.0, 0.0, 0.0], [0.0, 0.0, -2.0]]), abs=1e-12
    )
    c = sim.columns()
    angles = [name for n in ("alpha", "beta", "gamma") for name in (f"{n}_des_deg", f"{n}_deg", f"err_{n}_deg")]
    motors = [
        f"{kind}_{i}_{unit}" for kind, unit in (("tau", "Nmm"), ("tau_req", "Nmm"), ("speed", "rpm")) for i in (1, 2, 3)
    ]
    assert list(c) == ["t_s", *angles, *motors, "saturated"]
    assert c["beta_des_deg"] == pytest.approx([1.0] * 3, rel=1e-12)
    assert c["gamma_deg"] == pytest.approx([0.0, 1.0, 3.0], abs=1e-12)
    assert c["err_gamma_deg"] == pytest.approx([1.0, 0.0, -2.0], abs=1e-12)
    assert c["tau_3_Nmm"].tolist() == pytest.approx([300.0, 0.0, 0.0])
    assert c["tau_req_1_Nmm"].tolist() == pytest.approx([200.0, 0.0, -800.0])
    assert c["speed_3_rpm"] == pytest.approx(np.array([3.0, 0.0, -4.0]) * 60 / (2 * math.pi), rel=1e-12)
    assert c["saturated"].tolist() == [1.0, 0.0, 0.0]
    s = sim.summary()
    assert s.errors_deg["gamma"].peak == pytest.approx(2.0) and s.torques_Nmm["1"].peak == pytest.approx(400.0)
    assert s.duration_s == pytest.approx(0.003) and s.saturated_samples == 1
    path = sim.write_csv(tmp_path / "sim.csv")
    header = path.read_text().splitlines()[0].split(",")
    assert header == list(c)
    table = np.loadtxt(path, delimiter=",", skiprows=1)
    assert table[:, header.index("err_gamma_deg")] == pytest.approx([1.0, 0.0, -2.0], abs=1e-9)
    default = Simulation(t, desired, q, z, tau, tau, np.zeros(3, bool), speed)
    assert (default.plant, default.controller, math.isnan(default.step)) == ("", "", True)


def test_the_reduced_plant_checks_what_it_is_given(params):
    plant = ReducedPlant(params)
    with pytest.raises(ArgumentError, match=r"^loads: expected shape \(5,\)"):
        plant.advance(0.0, np.r_[Q0, QD0], np.zeros(3), np.zeros(4), 1e-4, 2)
    with pytest.raises(ArgumentError, match=r"^qd: expected shape \(3,\)"):
        plant.mass_and_bias(Q0, np.zeros(2), 0.0)
    M, h = plant.mass_and_bias(Q0, QD0, 1000)
    assert M.shape == (3, 3) and h.shape == (3,)
    # One step of the compiled advance is the Python RK4 through the derivative, to round-off.
    x, tau, loads = np.r_[Q0, QD0], np.array([0.1, -0.1, 0.2]), np.array([1000.0, 1001.0, 1002.0, 1003.0, 1004.0])
    compiled = plant.advance(0.0, x, tau, loads, 1e-4, 2)

    class Mine(ReducedPlant):
        def derivative(self, t, x, tau, Fe):
            return super().derivative(t, x, tau, Fe)

    assert Mine(params).advance(0.0, x, tau, loads, 1e-4, 2) == pytest.approx(compiled, rel=1e-12, abs=1e-15)
    assert Sample(Q0, QD0).Fe == 0.0


class Slotted:
    """The double integrator with its angles where a plant of its own keeps them: q = signs·x[angles], q̇ = signs·x[rates].

    Eight state values (two spare, left alone), steps itself (``advance``, RK4 written here), so the compiled loop
    controls each period around it as it does the Pinocchio plant's.
    """

    name = "slotted"
    ANGLES, RATES, SIGNS = np.array([1, 3, 2]), np.array([5, 7, 6]), np.array([1.0, -1.0, 1.0])

    def __init__(self, params, blow_at=math.inf):
        self.params, self.blow_at = params, blow_at

    @property
    def angle_slots(self):
        return self.ANGLES, self.RATES, self.SIGNS

    def initial_state(self, desired):
        x = np.array([7.0, 0, 0, 0, -7.0, 0, 0, 0])
        x[self.ANGLES], x[self.RATES] = self.SIGNS * desired.q[0], self.SIGNS * desired.qd[0]
        return x

    def angles(self, x):
        return self.SIGNS * x[self.ANGLES], self.SIGNS * x[self.RATES]

    def derivative(self, t, x, tau, Fe):
        dx = np.zeros_like(x)
        dx[self.ANGLES] = x[self.RATES]
        dx[self.RATES] = self.SIGNS * (DoubleIntegrator.c * tau + DoubleIntegrator.k * Fe)
        return dx

    def advance(self, t, x, tau, loads, h, substeps):
        if t >= self.blow_at:
            return np.full_like(x, np.nan)
        for s in range(substeps):
            k1 = self.derivative(t, x, tau, loads[2 * s])
            k2 = self.derivative(t, x + h / 2 * k1, tau, loads[2 * s + 1])
            k3 = self.derivative(t, x + h / 2 * k2, tau, loads[2 * s + 1])
            k4 = self.derivative(t, x + h * k3, tau, loads[2 * s + 2])
            x = x + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
        return x


@pytest.mark.parametrize("augmented", [False, True])
def test_the_compiled_control_around_a_plant_that_steps_itself_is_the_python_loop(params, augmented):
    """Four periods at 1 kHz, two RK4 steps each, from a pose 0.002 rad off: the compiled control (each period's
    PD or augmented PD around the plant's own ``advance``, reading the state at its slots with their signs) gives the
    Python loop's numbers, with and without a limit that bites on some torques."""
    plant = Slotted(params)
    controller = AugmentedPD(params, _desired, 1000.0, 0.004) if augmented else WorkspacePD(params)
    start = plant.initial_state(_desired(np.zeros(1)))
    start[Slotted.ANGLES] += Slotted.SIGNS * np.array([0.002, -0.001, 0.003])
    free = simulate(plant, controller, _desired, 0.004, 1000.0, 5e-4, initial_state=start, compiled=False)
    assert free.q[0] == pytest.approx(Q0 + [0.002, -0.001, 0.003], abs=1e-15) and free.qd[0] == pytest.approx(QD0)
    limit = 0.6 * float(np.abs(free.tau).max())
    for torque_limit in (None, limit):
        slow, fast, default = (
            simulate(plant, controller, _desired, 0.004, 1000.0, 5e-4, torque_limit, start, compiled=c)
            for c in (False, True, None)
        )
        for run in (fast, default):
            assert run.q == pytest.approx(slow.q, abs=1e-13) and run.qd == pytest.approx(slow.qd, abs=1e-12)
            assert run.tau == pytest.approx(slow.tau, abs=1e-12)
            assert run.tau_requested == pytest.approx(slow.tau_requested, abs=1e-12)
            assert run.saturated.tolist() == slow.saturated.tolist()
        if torque_limit is not None:
            assert 0 < np.count_nonzero(slow.saturated) and np.abs(slow.tau).max() == pytest.approx(limit, rel=1e-15)
    assert np.abs(free.tau).max() > 0.02  # N·m: the controller pushes back the offset
    assert not free.saturated.any()


def test_a_plant_that_steps_itself_is_named_where_it_goes_unstable(params):
    for compiled in (True, False):
        with pytest.raises(PoseError, match="no longer finite") as error:
            simulate(
                Slotted(params, blow_at=0.0015), WorkspacePD(params), _desired, 0.004, 1000.0, 5e-4, compiled=compiled
            )
        assert error.value.time == pytest.approx(0.003, abs=1e-15) and error.value.index == 3


def test_a_state_without_the_plant_s_slots_is_refused(params):
    """The compiled control reads the state at the slots unchecked: a state too short or not flat is refused first."""
    for state in (np.zeros(7), np.zeros((1, 8))):
        with pytest.raises(ArgumentError) as error:
            simulate(
                Slotted(params), WorkspacePD(params), _desired, 0.002, 1000.0, 5e-4, initial_state=state, compiled=True
            )
        assert str(error.value) == (
            "initial_state: expected a state of the slotted plant, holding its angles at [1 3 2] and rates at [5 7 6], "
            f"got shape {state.shape}"
        )
    run = simulate(Slotted(params), WorkspacePD(params), _desired, 0.002, 1000.0, 5e-4, initial_state=np.zeros(8))
    assert run.q[0].tolist() == [0.0, 0.0, 0.0]


def test_refusals_name_option_value_and_unit_whole(params):
    control = ControlSettings(1000.0, 5e-4, np.ones(3), np.ones(3), 2.0)
    assert servo_settings(control, 0.5, 2.0, None) == (0.5, 2.0, 2.0)  # a rate between 0 and 1 Hz: a 2 s period
    for args, message in (
        ((0.0, None, None), "servo_rate: expected a positive rate in Hz, got 0.0"),
        ((-0.5, None, None), "servo_rate: expected a positive rate in Hz, got -0.5"),
        ((None, None, 0.0), "torque_limit: expected a positive torque in N·m (inf for none), got 0.0"),
        ((None, -1e-4, None), "step: expected a positive integration step in s, got -0.0001"),
        ((0.5, 2.1, None), "step: expected an integration step no longer than the servo period 2 s, got 2.1"),
    ):
        with pytest.raises(ArgumentError) as error:
            servo_settings(control, *args)
        assert str(error.value) == message
    with pytest.raises(ArgumentError) as error:
        simulate(DoubleIntegrator(params), WorkspacePD(params), _desired, 0.02, 100.0, 0.01, compiled=True)
    assert str(error.value) == (
        "compiled: expected False, or None, unless the controller is a WorkspacePD or AugmentedPD and the plant a "
        "ReducedPlant or one with angle_slots (the PinocchioPlant), got True"
    )
    with pytest.raises(ArgumentError) as error:
        simulate(DoubleIntegrator(params), Steps(np.zeros((2, 3))), _desired, 0.0149, 100.0, 0.01)
    assert str(error.value) == "duration: expected at least two servo periods (0.02 s), got 0.0149"
    for text, message in (
        ("friction=20", "mismatch: expected friction=+20% or masses=-10%, got 'friction=20'"),
        ("masses=1%,masses=2%", "mismatch: expected masses given once, got 'masses=1%,masses=2%'"),
    ):
        with pytest.raises(ArgumentError) as error:
            parse_mismatch(text)
        assert str(error.value) == message
    with pytest.raises(ArgumentError) as error:
        apply_mismatch(params, friction=0.1, masses=-1.0)
    assert str(error.value) == (
        "mismatch: expected fractions above -1 (a mismatch of -100 % or less leaves nothing), "
        "got {'friction': 0.1, 'masses': -1.0}"
    )
