"""Every model on a per-chain machine: analytic (virtual work, each platform through its own Jacobian) ≡ Pinocchio ≡ MuJoCo."""

import numpy as np
import pytest

import hipsim
from hipsim.analysis.crosscheck import TOLERANCE, compare_models
from hipsim.analytic import kernel
from hipsim.analytic.chain_dynamics import chain_mechanical_energy, chain_motion
from hipsim.analytic.engine import AnalyticModel
from hipsim.analytic.inverse_kinematics import kinematics
from hipsim.analytic.stations import carriages_for_platform, platform_attitude
from hipsim.cli.main import main
from hipsim.closed_chain.engine import PinocchioModel
from hipsim.exceptions import ParameterError
from hipsim.machine.chains import ChainGeometry
from hipsim.machine.parameters import slender_levers
from hipsim.machine.toml_writer import parameter_toml

PARAMS = hipsim.load_parameters()
#: A machine built to ~0.3 mm (every deviation drawn at 0.3 mm), with the hip and thrust bearing friction on.
GEOMETRY = ChainGeometry.from_vector(np.random.default_rng(7).normal(0.0, 0.3e-3, 48))
TORQUE_PARTS = ("total", "platforms", "levers", "sliders", "screws", "friction", "motor_speed")


@pytest.fixture(scope="module")
def cycle():
    """A fifth of the built-in cycle at 1 kHz: through the heel-strike load peak, short enough for Pinocchio."""
    return hipsim.iso14242(rate=1000).slice(slice(0, 200))


def relative(a, b):
    return np.abs(np.asarray(a) - np.asarray(b)).max() / np.abs(np.asarray(b)).max()


def test_zero_deviations_through_the_per_chain_path_give_the_drawing(cycle):
    drawing = AnalyticModel(PARAMS).run(cycle)
    zero = AnalyticModel(PARAMS.replace(geometry=ChainGeometry.zeros())).run(cycle)
    for name in TORQUE_PARTS:
        assert relative(getattr(zero.torques, name), getattr(drawing.torques, name)) < 1e-13, name
    assert relative(zero.L, drawing.L) < 1e-15 and relative(zero.Ldd, drawing.Ldd) < 1e-13
    assert np.abs(zero.cond_inv - drawing.cond_inv).max() < 1e-13


def test_power_balance_on_a_per_chain_machine():
    """Σ τ·θ̇ = dE/dt + friction power, E from the bodies' motion alone (no wrench, no Jacobian transpose)."""
    params = PARAMS.replace(geometry=GEOMETRY, sjoint_viscous=0.02, ujoint_coulomb=0.05)
    trajectory = hipsim.iso14242(rate=4000)
    run = AnalyticModel(params).run(trajectory)
    kinetic, potential = chain_mechanical_energy(params, chain_motion(params, trajectory))
    power = np.sum(run.torques.total * run.torques.motor_speed, axis=1) - run.torques.friction_power
    dE = np.gradient(kinetic + potential, trajectory.t[1] - trajectory.t[0])
    # Central differences at 4 kHz: an O(dt²) error of ~1e-6 of the peak power.
    assert np.abs(power - dE)[2:-2].max() < 1e-5 * np.abs(power).max()


@pytest.mark.parametrize("control", [2, 1])
def test_the_trajectory_is_the_controlled_platforms_and_the_other_follows(cycle, control):
    params = PARAMS.replace(geometry=GEOMETRY.replace(control=control))
    motion = chain_motion(params, cycle)
    signs = params.angle_signs
    np.testing.assert_allclose(motion.controlled.q, cycle.q * signs, rtol=0, atol=0)
    # The carriages are the controlled platform's inverse kinematics; the follower is the forward kinematics of them.
    np.testing.assert_allclose(motion.L, carriages_for_platform(params, cycle.q, control), rtol=0, atol=0)
    follower = platform_attitude(params, motion.L, 3 - control, t=cycle.t, q0=cycle.q[0])
    np.testing.assert_allclose(motion.platforms[2 - control].q, follower * signs, rtol=0, atol=1e-12)
    error = np.degrees(np.abs(follower - cycle.q).max())
    assert 0.01 < error < 3.0  # ~0.3 mm over lever arms of a few hundred mm


@pytest.mark.parametrize("control", [2, 1])
def test_analytic_equals_pinocchio_on_a_per_chain_machine(cycle, control):
    """Spec §7.4's exact configuration (slender levers), on a per-chain machine: to the cross-check's 1e-8 of each peak."""
    params = slender_levers(PARAMS).replace(geometry=GEOMETRY.replace(control=control))
    analytic = AnalyticModel(params).run(cycle)
    pinocchio = PinocchioModel(params).run(cycle)
    for name in TORQUE_PARTS:
        assert relative(getattr(pinocchio.torques, name), getattr(analytic.torques, name)) < 1e-10, name
    assert relative(pinocchio.L, analytic.L) < 1e-12 and relative(pinocchio.Ldd, analytic.Ldd) < 1e-10
    assert np.abs(pinocchio.cond_inv - analytic.cond_inv).max() < 1e-10
    assert relative(pinocchio.torques.friction_moment, analytic.torques.friction_moment) < 1e-10
    # The per-chain machine is not the drawing: its torques differ from the drawing's by far more than the agreement.
    drawing = AnalyticModel(slender_levers(PARAMS)).run(cycle)
    assert relative(analytic.torques.total, drawing.torques.total) > 1e-4


def test_hipsim_check_passes_on_a_per_chain_machine(cycle):
    params = PARAMS.replace(geometry=GEOMETRY)
    comparisons = compare_models(params, cycle)
    required = [c for c in comparisons if c.required]
    assert required and all(c.ok for c in required)
    assert max(c.worst for c in required) < TOLERANCE


def test_mujoco_equals_analytic_and_pinocchio_on_a_per_chain_machine(cycle):
    pytest.importorskip("mujoco")
    from hipsim.analysis.crosscheck import compare_mujoco

    comparisons = compare_mujoco(PARAMS.replace(geometry=GEOMETRY.replace(control=1)), cycle.slice(slice(0, 60)))
    assert len(comparisons) == 2 and all(c.ok for c in comparisons)
    assert max(c.worst for c in comparisons) < 1e-10  # today's machine agrees to ~1e-13 as well


def test_the_per_chain_urdf_moves_each_chain():
    from hipsim.closed_chain.build import load_model

    chain = load_model(PARAMS.replace(geometry=GEOMETRY))
    model = chain.model
    placement = model.jointPlacements[model.getJointId("u1_22")].translation
    h1, h2 = PARAMS.heights
    np.testing.assert_allclose(placement, [*GEOMETRY.ujoint[1, 1], h2 - h1 + GEOMETRY.slider[1, 1]], rtol=0, atol=1e-15)
    centre = model.jointPlacements[model.getJointId("platform_1_rz")].translation
    np.testing.assert_allclose(centre, [0.0, 0.0, h1] + GEOMETRY.centre[0], rtol=0, atol=1e-15)
    tip = model.frames[model.getFrameId("lever_13_tip")].placement.translation
    assert tip[2] == pytest.approx(PARAMS.lever_length + GEOMETRY.lever[0, 2], abs=1e-15)


# --- What cannot use per-chain geometry refuses it ----------------------------------------


def test_the_drawing_only_models_refuse_by_name(cycle):
    params = PARAMS.replace(geometry=GEOMETRY)
    for call in (lambda: kinematics(params, cycle), lambda: kernel.kernel_parameters(params)):
        with pytest.raises(ParameterError, match=r"geometry.*per-chain geometry is not supported") as caught:
            call()
        assert "\n" not in str(caught.value)


@pytest.fixture(scope="module")
def per_chain_file(tmp_path_factory):
    path = tmp_path_factory.mktemp("chains") / "built.toml"
    path.write_text(parameter_toml(PARAMS.replace(geometry=GEOMETRY)), encoding="utf-8")
    return path


@pytest.mark.parametrize(
    "command", [["workspace"], ["excite"], ["size"]]
)  # simulate runs it: tests/cli/test_simulate_plant.py
def test_commands_that_cannot_use_it_refuse_the_file_in_one_line(per_chain_file, tmp_path, capsys, command):
    out = [] if command == ["size"] else ["--out", str(tmp_path / "out")]
    status = main([*command, "--params", str(per_chain_file), *out])
    err = capsys.readouterr().err.strip().splitlines()
    assert status == 2
    assert len([line for line in err if line.startswith("hipsim: error")]) == 1
    assert "[geometry]" in err[-1] and "built.toml" in err[-1]
    assert not (tmp_path / "out").exists()


def test_torques_runs_on_the_file(per_chain_file, tmp_path, capsys):
    out = tmp_path / "t.csv"
    assert main(["torques", "--params", str(per_chain_file), "--rate", "200", "--out", str(out)]) == 0
    drawing = tmp_path / "d.csv"
    assert main(["torques", "--rate", "200", "--out", str(drawing)]) == 0
    a = np.genfromtxt(out, delimiter=",", names=True)
    b = np.genfromtxt(drawing, delimiter=",", names=True)
    assert not np.array_equal(a["tau_1_Nmm"], b["tau_1_Nmm"])
    np.testing.assert_allclose(a["tau_1_Nmm"], b["tau_1_Nmm"], rtol=0, atol=0.05 * np.abs(b["tau_1_Nmm"]).max())
