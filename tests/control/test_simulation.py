"""Closed-loop simulation (spec §8): forward dynamics, controllers, energy."""

import math
import os

import numpy as np
import pytest
from fake_clock import FakeClock
from support import given

import hipsim
from hipsim.analytic.inverse_kinematics import angular_velocity_map, kinematics, slider_jacobian
from hipsim.analytic.virtual_work import inverse_dynamics, mechanical_energy
from hipsim.closed_chain.plant import PinocchioPlant
from hipsim.control.controllers import AugmentedPD, Sample, WorkspacePD
from hipsim.control.simulation import ReducedPlant, apply_mismatch, parse_mismatch, simulate
from hipsim.exceptions import ArgumentError, HipsimError, PoseError
from hipsim.motion.trajectories import Trajectory, iso14242_at


@pytest.fixture(scope="module")
def params():
    return hipsim.load_parameters()


class OpenLoop:
    """Feeds inverse-dynamics torques of the desired motion, taken mid-period to offset the hold's delay."""

    def __init__(self, params, servo_rate, duration, lever_spin):
        n = int(round(duration * servo_rate))
        desired = iso14242_at((np.arange(n) + 0.5) / servo_rate)
        self.tau = inverse_dynamics(params, kinematics(params, desired), desired.Fe, lever_spin=lever_spin).total
        self.rate = servo_rate

    def __call__(self, t, state, desired):
        return self.tau[int(round(t * self.rate))]


def test_reduced_model_is_affine_in_acceleration(params):
    plant = ReducedPlant(params)
    rng = np.random.default_rng(0)
    q, qd, qdd = np.radians([10.0, 3.0, -5.0]), rng.normal(size=3), rng.normal(size=3) * 20
    M, h = plant.mass_and_bias(q, qd, 1500.0)
    sample = Trajectory(np.array([0.0]), q[None], qd[None], qdd[None], np.array([1500.0]))
    tau = inverse_dynamics(params, kinematics(params, sample), sample.Fe, lever_spin=True).total[0]
    np.testing.assert_allclose(M @ qdd + h, tau, rtol=1e-12, atol=1e-12)


def test_generalised_mass_matrix_is_symmetric_positive_definite(params):
    """Mapped to the orientation coordinates, (2π/p)·Tᵀ·Jᵀ·M is the kinetic-energy Hessian: symmetric, positive."""
    plant = ReducedPlant(params)
    for q in np.radians([[0.0, 0.0, 0.0], [20.0, -4.0, 2.0], [-15.0, 6.0, -9.0]]):
        M, _ = plant.mass_and_bias(q, np.zeros(3), 0.0)
        J = slider_jacobian(params, q[None])[0]
        T = angular_velocity_map(q[None])[0]
        M_q = 2 * math.pi / params.lead * T.T @ J.T @ M
        np.testing.assert_allclose(M_q, M_q.T, rtol=1e-10, atol=1e-10 * np.abs(M_q).max())
        assert np.linalg.eigvalsh(0.5 * (M_q + M_q.T)).min() > 0


@pytest.mark.parametrize("lever_spin", [False, True])
def test_inverse_then_forward_reproduces_the_motion(params, lever_spin):
    """ISO inverse-dynamics torques fed open-loop from the exact initial state: drift ≤ 0.01° over 0.2 s."""
    sim = simulate(ReducedPlant(params, lever_spin), OpenLoop(params, 1000.0, 0.2, lever_spin), iso14242_at, 0.2)
    drift = np.degrees(np.abs(sim.err)).max()
    assert drift < 0.01
    # and it is the physics, not luck: torques of the wrong model drift far more.
    wrong = OpenLoop(apply_mismatch(params, masses=0.2), 1000.0, 0.2, lever_spin)
    assert (
        np.degrees(np.abs(simulate(ReducedPlant(params, lever_spin), wrong, iso14242_at, 0.2).err)).max() > 20 * drift
    )


def test_workspace_pd_maps_moment_through_jacobian_transpose(params):
    pd = WorkspacePD(params, kp=[100.0, 200.0, 300.0], kd=[1.0, 2.0, 3.0])
    state = Sample(np.radians([5.0, 1.0, -2.0]), np.array([0.1, 0.0, -0.2]))
    desired = Sample(np.radians([6.0, 0.0, -1.0]), np.array([0.0, 0.3, 0.1]))
    tau = pd(0.0, state, desired)
    J = slider_jacobian(params, state.q[None])[0]
    moment = [100, 200, 300] * (desired.q - state.q) + [1, 2, 3] * (desired.qd - state.qd)
    np.testing.assert_allclose(J.T @ (2 * math.pi / params.lead * tau), moment, rtol=1e-12)


def test_augmented_pd_tracks_better_than_pd(params):
    """Matched plant and controller; and the degradation when the plant's friction is 50 % higher."""
    duration = 0.3
    plant = ReducedPlant(params, lever_spin=False)
    pd = simulate(plant, WorkspacePD(params), iso14242_at, duration)
    augmented = simulate(plant, AugmentedPD(params, iso14242_at, 1000.0, duration), iso14242_at, duration)
    peak_pd = np.degrees(np.abs(pd.err)).max()
    peak_aug = np.degrees(np.abs(augmented.err)).max()
    # Measured: PD 0.3°, augmented PD 2e-5° (the feed-forward is the plant's own inverse dynamics).
    assert peak_pd > 0.05
    assert peak_aug < 1e-3 * peak_pd
    rough = ReducedPlant(apply_mismatch(params, friction=0.5), lever_spin=False)
    mismatched = simulate(rough, AugmentedPD(params, iso14242_at, 1000.0, duration), iso14242_at, duration)
    peak_mis = np.degrees(np.abs(mismatched.err)).max()
    # The unmodelled friction is left to the PD: the error grows by orders of magnitude but stays below the PD's.
    assert 100 * peak_aug < peak_mis < peak_pd


def test_energy_never_increases_with_motors_off(params):
    rough = params.replace(guide_coulomb=10.0, guide_viscous=50.0, sjoint_viscous=0.05, screw_viscous=1e-4)
    plant = ReducedPlant(rough, lever_spin=True)
    start = iso14242_at([0.3])
    desired_at = lambda t: iso14242_at(np.asarray(t) + 0.3)  # the load of the cycle from t = 0.3 s
    sim = simulate(
        plant,
        lambda t, s, d: np.zeros(3),
        desired_at,
        0.06,
        step=1e-4,
        initial_state=np.concatenate([start.q[0], start.qd[0]]),
    )
    path = Trajectory(sim.t, sim.q, sim.qd, np.zeros_like(sim.q), np.zeros_like(sim.t))
    kinetic, potential = mechanical_energy(rough, kinematics(rough, path), lever_spin=True)
    energy = kinetic + potential
    assert np.all(np.diff(energy) <= 1e-9 * np.abs(energy).max())
    assert energy[-1] < energy[0] - 1e-3  # and friction does take some


def test_torque_limit_is_counted_not_hidden(params):
    plant = ReducedPlant(params, lever_spin=False)
    sim = simulate(plant, WorkspacePD(params), iso14242_at, 0.05, torque_limit=0.2)
    assert sim.saturated.any()
    np.testing.assert_array_less(np.abs(sim.tau), 0.2 + 1e-15)
    assert np.abs(sim.tau_requested).max() > 0.2
    assert sim.summary().saturated_samples == np.count_nonzero(sim.saturated)


def test_mismatch_parsing(params):
    assert parse_mismatch("friction=+20%,masses=-10%") == {"friction": 0.2, "masses": -0.1}
    for bad in ("friction=20", "mass=-10%", "friction=+20%,"[:-1] + ";"):
        with pytest.raises(ArgumentError, match="mismatch: expected friction=") as info:
            parse_mismatch(bad)
        assert "--" not in str(info.value)  # the library does not name the command line's options
    off = apply_mismatch(params, friction=0.2, masses=-0.1)
    assert off.friction.hip_mu == pytest.approx(0.095 * 1.2)
    assert off.lever_mass == pytest.approx(1.43 * 0.9)
    np.testing.assert_allclose(off.platform_inertia, params.platform_inertia * 0.9)


def test_step_longer_than_servo_period_is_refused(params):
    with pytest.raises(HipsimError, match="longer than the servo period"):
        simulate(ReducedPlant(params), WorkspacePD(params), iso14242_at, 0.01, step=2e-3)


def test_plant_and_controller_refuse_states_of_the_wrong_shape(params):
    plant, pd = ReducedPlant(params), WorkspacePD(params)
    with pytest.raises(HipsimError, match=r"state x: expected shape \(6,\)"):
        plant.derivative(0.0, np.zeros(5), np.zeros(3), 0.0)
    with pytest.raises(HipsimError, match=r"loads: expected shape \(5,\)"):
        plant.advance(0.0, np.zeros(6), np.zeros(3), np.zeros(4), 2.5e-4, 2)
    with pytest.raises(HipsimError, match=r"state.q: expected shape \(3,\)"):
        pd(0.0, Sample(np.zeros((1, 3)), np.zeros(3)), Sample(np.zeros(3), np.zeros(3)))
    with pytest.raises(HipsimError, match=r"kd: expected shape \(3,\)"):
        WorkspacePD(params, kd=[1.0, 2.0])


def test_one_gain_applies_to_every_angle(params):
    state, desired = Sample(np.radians([5.0, 1.0, -2.0]), np.zeros(3)), Sample(np.radians([6.0, 0.0, -1.0]), np.ones(3))
    np.testing.assert_array_equal(
        WorkspacePD(params, kp=150.0, kd=2)(0.0, state, desired),
        WorkspacePD(params, kp=[150.0] * 3, kd=[2.0] * 3)(0.0, state, desired),
    )


def test_a_plant_subclass_is_stepped_through_its_own_derivative(params):
    """simulate() integrates the reduced plant compiled, unless a subclass changes its derivative."""

    class Disturbed(ReducedPlant):
        def derivative(self, t, x, tau, Fe):
            return super().derivative(t, x, tau + np.array([0.5, 0.0, 0.0]), Fe)

    pd = WorkspacePD(params)
    plain = simulate(ReducedPlant(params), pd, iso14242_at, 0.02)
    disturbed = simulate(Disturbed(params), pd, iso14242_at, 0.02)
    assert np.abs(disturbed.q - plain.q).max() > 1e-6


def test_a_plant_of_your_own_needs_no_name_and_no_advance(params):
    """The Plant protocol's minimum: params, initial_state, derivative, angles."""

    class Minimal:
        def __init__(self, params):
            self.params, self._reduced = params, ReducedPlant(params)

        def initial_state(self, desired):
            return self._reduced.initial_state(desired)

        def derivative(self, t, x, tau, Fe):
            return self._reduced.derivative(t, x, tau, Fe)

        def angles(self, x):
            return x[:3], x[3:]

    pd = WorkspacePD(params)
    mine = simulate(Minimal(params), pd, iso14242_at, 0.02)  # type: ignore[arg-type]  # the least a plant needs
    reference = simulate(ReducedPlant(params), pd, iso14242_at, 0.02)
    assert mine.plant == "Minimal"
    np.testing.assert_allclose(mine.q, reference.q, rtol=0, atol=1e-14)  # simulate's own RK4 = the compiled one


def test_a_desired_motion_through_a_singularity_is_named_before_the_run(params):
    """Not blamed on the plant: the desired motion itself is checked first."""

    def crossing(t):
        motion = iso14242_at(t)
        q = np.column_stack([np.zeros_like(t), np.zeros_like(t), np.radians(-60.0 + 400.0 * t)])  # γ sweeps through −δ
        return Trajectory(motion.t, q, np.zeros_like(q), np.zeros_like(q), motion.Fe, name="sweep")

    with pytest.raises(PoseError, match=r"sweep, t = .*(singular|out of reach)"):
        simulate(ReducedPlant(params), WorkspacePD(params), crossing, 0.2)


def test_mismatch_given_twice_is_refused():
    with pytest.raises(HipsimError, match="friction given once"):
        parse_mismatch("friction=+20%,friction=-10%")


def test_the_step_used_is_recorded(params):
    sim = simulate(ReducedPlant(params), WorkspacePD(params), iso14242_at, 0.01, step=0.3e-3)
    assert sim.step == pytest.approx(0.25e-3, rel=1e-12)


def test_a_slow_first_step_is_announced_as_compiling_not_timed(params, capsys, monkeypatch):
    """The first servo step of a process compiles the numba kernels (some 15 s on a machine's first run):
    it is announced as compiling instead of being timed by the progress bar. On an injected clock: the first
    step takes 1.5 s of it, past the note's 1 s, whatever the machine's speed."""
    import hipsim.clock

    clock = FakeClock()
    monkeypatch.setattr(hipsim.clock, "SYSTEM_CLOCK", clock)  # the clock of simulate's compile note

    class SlowFirstCall(WorkspacePD):
        calls = 0

        def __call__(self, t, state, desired):
            SlowFirstCall.calls += 1
            if SlowFirstCall.calls == 1:
                clock.advance(1.5)  # as long as a compilation, as far as the note can tell
            return super().__call__(t, state, desired)

    controller = SlowFirstCall(params)
    controller(0.0, Sample(np.zeros(3), np.zeros(3)), Sample(np.zeros(3), np.zeros(3)))  # compile the real law first
    simulate(ReducedPlant(params), WorkspacePD(params), iso14242_at, 0.002)  # and the compiled loop the last run takes
    SlowFirstCall.calls = 0
    notes: list[str] = []
    sim = simulate(
        ReducedPlant(params), controller, iso14242_at, 0.02, progress=True, controller_name="slow", notify=notes.append
    )
    assert notes == ["reduced plant, slow: compiling (first run only) ..."]
    assert len(sim.t) == 20 and SlowFirstCall.calls == 20  # every step ran once, the first one included
    simulate(
        ReducedPlant(params),
        WorkspacePD(params),
        iso14242_at,
        0.02,
        progress=True,
        controller_name="fast",
        notify=notes.append,
    )
    assert len(notes) == 1 and all(t.cancelled for t in clock.timers)  # compiled now: nothing to announce


def _mismatched_plant(kind: str, params):
    """A plant whose friction and masses the controller does not know, and how long to run it [s]."""
    plant_params = apply_mismatch(params, friction=0.3, masses=-0.1)
    return (
        (ReducedPlant(plant_params, lever_spin=True), 0.15)
        if kind == "reduced"
        else (PinocchioPlant(plant_params), 0.05)
    )


@pytest.mark.parametrize("plant_kind", ["reduced", "pinocchio"])
@pytest.mark.parametrize("controller_kind", ["pd", "augmented"])
@pytest.mark.parametrize("limited", [False, True])
def test_compiled_loop_is_the_python_loop(params, plant_kind, controller_kind, limited):
    """The compiled servo loop (the whole loop for the reduced plant, each period's control around the
    Pinocchio plant's own steps) against the Python one, on a plant the controller does not know."""
    plant, duration = _mismatched_plant(plant_kind, params)
    controller = WorkspacePD(params) if controller_kind == "pd" else AugmentedPD(params, iso14242_at, 1000.0, duration)
    free = simulate(plant, controller, iso14242_at, duration, compiled=False)
    limit = 0.8 * np.abs(free.tau).max() if limited else None  # bites on the peaks only
    fast, slow = (
        simulate(plant, controller, iso14242_at, duration, torque_limit=limit, compiled=flag) for flag in (True, False)
    )
    np.testing.assert_allclose(fast.q, slow.q, rtol=0, atol=1e-12)
    np.testing.assert_allclose(fast.qd, slow.qd, rtol=0, atol=1e-9)
    np.testing.assert_allclose(fast.tau_requested, slow.tau_requested, rtol=0, atol=1e-9)
    np.testing.assert_array_equal(fast.saturated, slow.saturated)
    if limited:
        assert 0 < np.count_nonzero(fast.saturated) < len(fast.t)
        np.testing.assert_array_less(np.abs(fast.tau), given(limit) * (1 + 1e-15))
        assert np.abs(fast.q - free.q).max() > 1e-9  # and the limit changed the motion
    else:
        assert not fast.saturated.any()
        np.testing.assert_allclose(fast.q, free.q, rtol=0, atol=1e-12)


@pytest.mark.parametrize("plant_kind", ["reduced", "pinocchio"])
def test_compiled_loop_stops_where_the_python_loop_does(params, plant_kind):
    """An unstable loop is named at the same servo instant by both loops."""
    plant = ReducedPlant(params) if plant_kind == "reduced" else PinocchioPlant(params)
    wild = WorkspacePD(params, kp=-5e4, kd=0.0)  # positive feedback: the platform runs away
    times = []
    for flag in (True, False):
        with pytest.raises(PoseError) as info:
            simulate(plant, wild, iso14242_at, 0.5, compiled=flag)
        times.append(info.value.time)
    assert times[0] == times[1]


def test_compiled_loop_is_refused_for_a_controller_of_your_own(params):
    with pytest.raises(ArgumentError, match="compiled"):
        simulate(ReducedPlant(params), lambda t, s, d: np.zeros(3), iso14242_at, 0.01, compiled=True)


@pytest.mark.skipif(os.environ.get("NUMBA_DISABLE_JIT") == "1", reason="counts numba's compiled signatures")
@pytest.mark.parametrize("plant_kind", ["reduced", "pinocchio"])
def test_gains_given_or_read_from_the_file_compile_the_loop_once(params, plant_kind):
    """Writable gains (given) and read-only ones (the parameter file's) reach the compiled loop as one
    array type: numba compiles each loop once, not once per kind of array (seconds of a first run)."""
    from hipsim.control import closed_chain_loop, servo_kernel

    loop = servo_kernel.servo_loop if plant_kind == "reduced" else closed_chain_loop.stepped_loop
    plant = ReducedPlant(params) if plant_kind == "reduced" else PinocchioPlant(params)
    given = np.array([400.0, 400.0, 400.0])
    assert not WorkspacePD(params).kp.flags.writeable and WorkspacePD(params, kp=given).kp.flags.writeable
    controllers = (
        WorkspacePD(params),
        WorkspacePD(params, kp=given, kd=given / 80),
        AugmentedPD(params, iso14242_at, 1000.0, 0.004),
    )
    for controller in controllers:
        simulate(plant, controller, iso14242_at, 0.004)
    assert len(loop.signatures) == 1, loop.signatures


def test_servo_settings_default_to_the_parameters_and_hold_the_step_to_one_period():
    from hipsim.control.simulation import servo_settings
    from hipsim.exceptions import ArgumentError

    control = hipsim.load_parameters().control
    assert servo_settings(control, None, None, None) == (
        control.servo_rate,
        control.integration_step,
        control.torque_limit,
    )
    assert servo_settings(control, 1000.0, 1e-3, 2.0) == (1000.0, 1e-3, 2.0)  # a step of exactly one period
    with pytest.raises(ArgumentError, match="no longer than the servo period 0.001 s"):
        servo_settings(control, 1000.0, 1.001e-3, 2.0)
    for bad in ({"servo_rate": 0.0}, {"step": 0.0}, {"torque_limit": 0.0}):
        arguments = {"servo_rate": 1000.0, "step": 5e-4, "torque_limit": 2.0} | bad
        with pytest.raises(ArgumentError, match=next(iter(bad))):
            servo_settings(control, arguments["servo_rate"], arguments["step"], arguments["torque_limit"])
