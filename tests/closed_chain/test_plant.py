"""The closed-chain Pinocchio plant (spec §6, §8): forward dynamics consistent with the
inverse dynamics, agreement with the reduced plant, closure drift, energy."""

import numpy as np
import pinocchio as pin
import pytest
from scipy.integrate import simpson
from support import given

import hipsim
from hipsim.closed_chain.build import load_model
from hipsim.closed_chain.dynamics import trajectory_dynamics
from hipsim.closed_chain.friction import friction_forces
from hipsim.closed_chain.plant import PinocchioPlant
from hipsim.control.controllers import AugmentedPD, WorkspacePD
from hipsim.control.simulation import ReducedPlant, apply_mismatch, simulate
from hipsim.motion.trajectories import iso14242_at

DURATION = 0.2  # [s]
SERVO = 1000.0  # [Hz], the default servo rate (RK4 step 0.5 ms, the default too)


@pytest.fixture(scope="module")
def params():
    return hipsim.load_parameters()


@pytest.fixture(scope="module")
def plant(params):
    return PinocchioPlant(params)


class Recorder:
    """A plant wrapper that keeps the full state at every servo instant (simulate reads the angles there)."""

    def __init__(self, plant):
        self.plant, self.params, self.name, self.states = plant, plant.params, plant.name, []

    def initial_state(self, desired):
        return self.plant.initial_state(desired)

    def derivative(self, t, x, tau, Fe):
        return self.plant.derivative(t, x, tau, Fe)

    def angles(self, x):
        self.states.append(x.copy())
        return self.plant.angles(x)


class OpenLoop:
    """Closed-chain (Pinocchio) inverse-dynamics torques of the ISO cycle, taken mid-period to offset the hold's delay."""

    def __init__(self, params, servo_rate, duration):
        n = int(round(duration * servo_rate))
        desired = iso14242_at((np.arange(n) + 0.5) / servo_rate)
        self.tau = trajectory_dynamics(load_model(params), desired)[1].torques.total
        self.rate = servo_rate

    def __call__(self, t, state, desired):
        return self.tau[int(round(t * self.rate))]


def _closed_states(chain, times):
    desired = iso14242_at(times)
    kin, torques = trajectory_dynamics(chain, desired)
    return desired, kin, torques


@pytest.mark.parametrize(
    "changes",
    [
        {},  # default friction: the closed-form path
        {"guide_coulomb": 10.0, "guide_viscous": 50.0, "screw_coulomb": 0.02, "screw_viscous": 1e-4},
        {"guide_coulomb": 10.0, "ujoint_coulomb": 0.01, "sjoint_viscous": 0.05},  # U/S friction: the numpy path
        {"thrust_bearing_axial_only": True, "guide_coulomb": 10.0},  # the bearing about the platform's axis only
        {"thrust_bearing_axial_only": True, "ujoint_coulomb": 0.01},
    ],
)
def test_generalised_forces_use_the_inverse_dynamics_friction_law(params, changes):
    rough = params.replace(**changes)
    plant = PinocchioPlant(rough)
    assert plant.closed_form_friction == (not any(k.startswith(("ujoint", "sjoint")) for k in changes))
    desired, kin, torques = _closed_states(plant.chain, [0.13, 0.5, 0.77])
    for k in range(3):
        x = np.concatenate([kin.q[k], kin.v[k]])
        expected = -friction_forces(plant.chain, kin.q[k], kin.v[k], desired.Fe[k])
        expected[plant.chain.actuated_v] += 2 * np.pi / rough.lead * torques.torques.total[k]
        forces = plant.generalised_forces(x, torques.torques.total[k], desired.Fe[k])
        np.testing.assert_allclose(forces, expected, rtol=0, atol=1e-12 * np.abs(expected).max())


def test_initial_state_is_closed_and_forward_inverts_inverse_dynamics(params, plant):
    desired, kin, torques = _closed_states(plant.chain, [0.0, 0.13, 0.5, 0.77])
    x0 = plant.initial_state(desired)
    np.testing.assert_array_equal(x0, np.concatenate([kin.q[0], kin.v[0]]))
    gap, rate = plant.closure_residual(x0)
    assert gap < 1e-12 and rate < 1e-12
    angles, rates = plant.angles(x0)
    np.testing.assert_allclose(angles, desired.q[0], atol=1e-15)
    np.testing.assert_allclose(rates, desired.qd[0], atol=1e-15)
    for k in range(4):
        x = np.concatenate([kin.q[k], kin.v[k]])
        dx = plant.derivative(desired.t[k], x, torques.torques.total[k], desired.Fe[k])
        np.testing.assert_array_equal(dx[: plant.nq], kin.v[k])
        # Measured ≤ 1e-10 m/s² (rad/s²) against |a| = 2..15: Baumgarte (K_p = 100/s²) acting on the ≤ 1e-12 m gaps
        # the kinematics leaves, and rounding.
        np.testing.assert_allclose(dx[plant.nq :], kin.a[k], rtol=0, atol=1e-9 * np.abs(kin.a[k]).max())


def test_angle_signs_are_applied_as_in_the_analytic_model(params):
    flipped = params.replace(angle_signs=np.array([-1.0, 1.0, -1.0]))
    plant = PinocchioPlant(flipped)
    desired = iso14242_at([0.1])
    x = plant.initial_state(desired)
    np.testing.assert_allclose(
        x[given(plant.chain.layout).platform_v[0]], flipped.angle_signs * desired.q[0], atol=1e-15
    )
    angles, rates = plant.angles(x)
    np.testing.assert_allclose(angles, desired.q[0], atol=1e-15)
    np.testing.assert_allclose(rates, desired.qd[0], atol=1e-15)
    # and closed-loop the two plants still agree (measured 1.7e-12°).
    pd = WorkspacePD(flipped)
    reduced = simulate(ReducedPlant(flipped, lever_spin=True), pd, iso14242_at, 0.05)
    pinocchio = simulate(plant, pd, iso14242_at, 0.05)
    assert np.degrees(np.abs(reduced.q - pinocchio.q)).max() < 2e-11


def test_plant_does_not_change_the_callers_constraints(params):
    chain = load_model(params)
    PinocchioPlant(params, baumgarte=(1e4, 200.0), chain=chain)
    assert all(
        cm.m_baumgarte_parameters.Kp == 0.0 and cm.m_baumgarte_parameters.Kd == 0.0 for cm in chain.constraint_models
    )
    with pytest.raises(ValueError, match="mu"):
        PinocchioPlant(params, mu=0.0, chain=chain)
    with pytest.raises(ValueError, match="same params"):
        PinocchioPlant(params.replace(lever_mass=1.0), chain=chain)


def test_inverse_then_forward_reproduces_the_motion(params, plant):
    """ISO closed-chain inverse-dynamics torques fed open-loop from the exact initial state: drift ≤ 0.01° over 0.2 s."""
    sim = simulate(plant, OpenLoop(params, SERVO, DURATION), iso14242_at, DURATION)
    drift = np.degrees(np.abs(sim.err)).max()
    # Measured: 3.3e-5° (the zero-order hold of torques sampled mid-period; the plant itself adds ~1e-11°).
    assert drift < 0.01
    # and it is the physics, not luck: the torques of a 20 % heavier machine drift far more (measured 2.8°).
    wrong = OpenLoop(apply_mismatch(params, masses=0.2), SERVO, DURATION)
    assert np.degrees(np.abs(simulate(plant, wrong, iso14242_at, DURATION).err)).max() > 100 * drift


@pytest.fixture(scope="module")
def runs(params, plant):
    """The same controllers on both plants over 0.2 s; the Pinocchio runs keep their full states."""
    out = {}
    controllers = {
        "workspace PD": WorkspacePD(params),
        "augmented PD": AugmentedPD(params, iso14242_at, SERVO, DURATION),
    }
    for name, controller in controllers.items():
        reduced = simulate(ReducedPlant(params, lever_spin=True), controller, iso14242_at, DURATION)
        recorder = Recorder(plant)
        pinocchio = simulate(recorder, controller, iso14242_at, DURATION)
        out[name] = (reduced, pinocchio, np.array(recorder.states))
    return out


@pytest.mark.parametrize("controller", ["workspace PD", "augmented PD"])
def test_the_two_plants_agree(runs, controller):
    reduced, pinocchio, _ = runs[controller]
    angle = np.degrees(np.abs(reduced.q - pinocchio.q)).max()
    rate = np.degrees(np.abs(reduced.qd - pinocchio.qd)).max()
    # Measured over 0.2 s (both controllers): 4.4e-12° in the angles, 1.5e-10 °/s in the rates, against
    # tracking errors of 0.42° (PD) and 1.8e-5° (augmented PD): the plants describe the same physics.
    # The residual comes from the Baumgarte corrector responding to RK4's intermediate stages, which
    # leave the closure manifold by O(h²): it scales as h⁴ (2.7e-13° at 0.25 ms, 7e-11° at 1 ms) and
    # with the corrector off the plants agree to 1.6e-13°; the proximal solver's bias (~1e-14 after
    # two iterations) and rounding in the reduced model's mass matrix are below that.
    assert angle < 3e-11
    assert rate < 1e-9


@pytest.mark.parametrize("controller", ["workspace PD", "augmented PD"])
def test_closures_stay_closed_along_a_run(plant, runs, controller):
    states = runs[controller][2]
    residuals = np.array([plant.closure_residual(x) for x in states])
    # Measured: gaps ≤ 1.2e-13 m, closure velocities ≤ 2.0e-12 m/s (Baumgarte K_p = 100/s², K_d = 20/s;
    # without it the gaps grow steadily, to 5e-11 m after 5 s).
    assert residuals[:, 0].max() < 1e-12
    assert residuals[:, 1].max() < 2e-11
    # Platform 2 follows platform 1's orientation through its three closures (measured 6e-17 rad apart).
    layout = plant.chain.layout
    np.testing.assert_allclose(states[:, layout.platform_v[1]], states[:, layout.platform_v[0]], rtol=0, atol=1e-14)


@pytest.mark.parametrize(
    "changes",
    [
        {},  # hip joint and thrust bearing only (the default friction)
        {
            "guide_coulomb": 10.0,
            "guide_viscous": 50.0,
            "sjoint_viscous": 0.05,
            "ujoint_coulomb": 0.01,
            "screw_viscous": 1e-4,
        },
    ],
)
def test_energy_never_increases_with_motors_off(params, changes):
    rough = params.replace(**changes)
    plant = PinocchioPlant(rough)
    recorder = Recorder(plant)
    start = iso14242_at([0.3])
    desired_at = lambda t: iso14242_at(np.asarray(t) + 0.3)  # the load of the cycle from t = 0.3 s
    sim = simulate(
        recorder, lambda t, s, d: np.zeros(3), desired_at, 0.06, step=1e-4, initial_state=plant.initial_state(start)
    )
    assert np.degrees(np.abs(sim.q - sim.q[0])).max() > 3.0  # the machine does fall (measured 6–7°)
    energy = np.array([sum(plant.energy(x)) for x in recorder.states])  # kinetic (armature included) + potential
    # Measured: every 1 ms step loses 0.02–0.03 J of the ~394 J.
    assert np.all(np.diff(energy) <= 1e-9 * np.abs(energy).max())
    assert energy[-1] < energy[0] - 1.0
    # What is lost is what friction dissipates: ∫ vᵀ(−Q_f) dt (Simpson on the 1 ms samples; measured 1e-9 relative).
    loads = desired_at(sim.t).Fe
    power = [x[plant.nq :] @ plant.generalised_forces(x, np.zeros(3), f) for x, f in zip(recorder.states, loads)]
    dissipated = simpson(power, x=sim.t)
    assert abs((energy[-1] - energy[0]) - dissipated) < 1e-6 * abs(dissipated)
    gaps = np.array([plant.closure_residual(x)[0] for x in recorder.states])
    assert gaps.max() < 1e-12


def test_the_two_plants_agree_with_the_axial_only_thrust_bearing(params):
    """friction.thrust_bearing_axial_only in both plants: they still agree (and the option changes the motion)."""
    axial = params.replace(thrust_bearing_axial_only=True)
    pd = WorkspacePD(axial)
    reduced = simulate(ReducedPlant(axial, lever_spin=True), pd, iso14242_at, 0.05)
    pinocchio = simulate(PinocchioPlant(axial), pd, iso14242_at, 0.05)
    # Measured: 1.5e-11° in the angles, 5.3e-9 °/s in the rates. Ten times the default friction's
    # figures, all of it from t = 0.038 s, where the platform's spin about its axis crosses zero and the
    # bearing's ŝ(ω·z) turns over within 0.3 ms (slope 1/ε): RK4's 0.5 ms step does not resolve that
    # turn, and the two plants' rounding-level differences land on it differently.
    assert np.degrees(np.abs(reduced.q - pinocchio.q)).max() < 3e-11
    assert np.degrees(np.abs(reduced.qd - pinocchio.qd)).max() < 2e-8
    publication = simulate(ReducedPlant(params, lever_spin=True), pd, iso14242_at, 0.05)
    assert np.degrees(np.abs(publication.q - reduced.q)).max() > 1e-4  # measured 0.024°


def test_kinetic_energy_includes_the_screw_rotors(plant):
    q = plant.initial_state(iso14242_at([0.2]))[: plant.nq]
    v = np.zeros(plant.nv)
    v[plant.chain.actuated_v[0]] = 0.1
    kinetic, _ = plant.energy(np.concatenate([q, v]))
    M = pin.crba(plant.model, plant.model.createData(), q)
    assert kinetic == pytest.approx(0.5 * 0.1**2 * M[v != 0, v != 0][0], rel=1e-12)
    assert M[v != 0, v != 0][0] > plant.model.armature[plant.chain.actuated_v[0]] > 0


def test_advance_takes_the_steps_simulate_takes_through_the_derivative(params):
    """The plant's own RK4 (fewer Python crossings) against simulate's RK4 through derivative()."""
    plant, pd = PinocchioPlant(params), WorkspacePD(params)
    own = simulate(plant, pd, iso14242_at, 0.03)
    through = simulate(Recorder(PinocchioPlant(params)), pd, iso14242_at, 0.03)
    np.testing.assert_allclose(own.q, through.q, rtol=0, atol=1e-13)
    np.testing.assert_allclose(own.tau, through.tau, rtol=0, atol=1e-10)
    assert np.abs(own.q - own.desired.q).max() > 1e-7  # the motion is not trivially the desired one


@pytest.mark.parametrize("route", ["compiled", "kernel"])
@pytest.mark.parametrize("changes", [{}, {"guide_coulomb": 10.0, "ujoint_coulomb": 0.01, "sjoint_viscous": 0.05}])
def test_the_compiled_route_solves_what_constraint_dynamics_solves(params, changes, route):
    """The compiled closure solver (after the compiled tree or pin.crba) against pin.constraintDynamics (converged: 20 proximal iterations), on and off the closures.

    Off them (gaps of 1e-6 … 1e-3 m, closure velocities likewise) the Baumgarte terms and the drift's
    frame conventions matter: the two must still agree (measured 1e-14 m/s² against |a| ≈ 16).
    """
    rough = params.replace(**changes)
    plant = PinocchioPlant(rough, baumgarte=(400.0, 40.0), route=route)
    assert plant.route == route
    desired, kin, torques = _closed_states(plant.chain, [0.13, 0.77])
    rng = np.random.default_rng(7)
    reference = pin.ProximalSettings(1e-14, 1e-14, 1e-12, 20)
    for k in range(2):
        for spread in (0.0, 1e-6, 1e-3):
            x = np.concatenate([kin.q[k], kin.v[k]]) + rng.normal(0.0, spread, 2 * plant.nv)
            forces = plant.generalised_forces(x, torques.torques.total[k], desired.Fe[k])
            expected = pin.constraintDynamics(
                plant.model, plant.data, x[: plant.nq], x[plant.nq :], forces,
                plant.constraint_models, plant.constraint_datas, reference,
            )  # fmt: skip
            a = plant.derivative(desired.t[k], x, torques.torques.total[k], desired.Fe[k])[plant.nq :]
            np.testing.assert_allclose(a, expected, rtol=0, atol=1e-12 * np.abs(expected).max())
    # The Baumgarte terms are really there: off the closures, other gains give another acceleration.
    soft = PinocchioPlant(rough, baumgarte=(0.0, 0.0), chain=plant.chain, route=route)
    assert (
        np.abs(
            soft.derivative(0.0, x, torques.torques.total[1], 0.0)
            - plant.derivative(0.0, x, torques.torques.total[1], 0.0)
        ).max()
        > 1.0
    )


@pytest.mark.parametrize("route", ["compiled", "kernel"])
def test_both_routes_run_the_same_closed_loop(params, plant, route):
    """The workspace PD on the plant's compiled routes and on constraintDynamics: the same tracking error and torques to the integrator's tolerance."""
    pd = WorkspacePD(params)
    on_route = PinocchioPlant(params, route=route, chain=plant.chain)
    # The compiled route runs the whole servo loop compiled; the kernel route steps through advance().
    assert (on_route.compiled_stepper() is not None) == (route == "compiled")
    fast = simulate(on_route, pd, iso14242_at, 0.05)
    slow = simulate(PinocchioPlant(params, route="constraint_dynamics", chain=plant.chain), pd, iso14242_at, 0.05)
    # Measured: 1e-17 rad and 1e-15 N·m apart, against the ~1e-11° by which RK4 at 0.5 ms and the reduced plant differ.
    np.testing.assert_allclose(fast.err, slow.err, rtol=0, atol=1e-13)
    np.testing.assert_allclose(fast.tau, slow.tau, rtol=0, atol=1e-9)
    assert np.degrees(np.abs(fast.err)).max() > 0.01  # a real tracking error, not a trivially exact one
    with pytest.raises(hipsim.ArgumentError, match="route"):
        PinocchioPlant(params, route="lcaba", chain=plant.chain)


def test_advance_names_a_state_or_torques_of_the_wrong_size(params, plant):
    x = plant.initial_state(iso14242_at(np.array([0.0])))
    with pytest.raises(hipsim.ArgumentError, match="state"):
        plant.advance(0.0, x[:-1], np.zeros(3), np.full(3, 100.0), 5e-4, 1)
    with pytest.raises(hipsim.ArgumentError, match="tau"):
        plant.advance(0.0, x, np.zeros(2), np.full(3, 100.0), 5e-4, 1)


def test_a_read_only_tau_steps_as_a_writable_one_on_the_steps_compiled_once(params, plant):
    """numba compiles a kernel anew for a read-only array (seconds of CPU for the plant's steps): advance copies tau."""
    from hipsim.closed_chain.plant_step import advance as compiled_advance

    x = plant.initial_state(iso14242_at(np.array([0.0])))
    tau, loads = np.array([0.1, -0.2, 0.3]), np.full(3, 100.0)
    writable = plant.advance(0.0, x, tau, loads, 5e-4, 1)
    compiled = len(compiled_advance.signatures)
    tau.flags.writeable = False
    read_only = plant.advance(0.0, x, tau, loads, 5e-4, 1)
    assert len(compiled_advance.signatures) == compiled >= 1
    np.testing.assert_array_equal(read_only, writable)


def test_compiled_control_names_an_initial_state_of_the_wrong_size(params, plant):
    with pytest.raises(hipsim.ArgumentError, match="initial_state"):
        simulate(plant, WorkspacePD(params), iso14242_at, 0.01, initial_state=np.zeros(6))


def test_the_compiled_loop_keeps_the_closures_closed(params, plant, monkeypatch):
    """The whole servo loop compiled (the default route): the closures along it, read between its chunks of periods."""
    from hipsim.control import closed_chain_loop, simulation

    residuals, loop = [], closed_chain_loop.stepped_loop

    def watched(stepper, x, *args):
        reached = loop(stepper, x, *args)
        residuals.append(plant.closure_residual(x))
        return reached

    monkeypatch.setattr(simulation, "_CHUNK", 20)
    monkeypatch.setattr(closed_chain_loop, "stepped_loop", watched)
    sim = simulate(plant, WorkspacePD(params), iso14242_at, DURATION)
    gaps = np.array(residuals)
    assert len(gaps) >= DURATION * SERVO / 20  # the loop really ran in chunks, compiled
    # Measured over 2 s: gaps ≤ 1.2e-13 m, closure velocities ≤ 2.0e-12 m/s, as along the other routes.
    assert gaps[:, 0].max() < 1e-12
    assert gaps[:, 1].max() < 2e-11
    assert np.degrees(np.abs(sim.err)).max() > 0.01
