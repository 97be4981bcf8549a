"""The analytic model (spec §3–4) against the Pinocchio closed-chain model (spec §6).

The two share only the parameter set: the analytic side is closed-form
vector algebra, the Pinocchio side a URDF tree closed by point constraints and
solved with RNEA. In the slender-lever configuration of spec §7.4 they describe
the same physics and must agree to 1e-8 of each column's peak. With the
published lever inertia the spec's lever (no spin about its axis) differs
from the universal joint's; the difference is reported and bounded, and the
analytic model's ``lever_spin=True`` option removes it.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
from support import SmoothMotion

import hipsim.analytic.inverse_kinematics as analytic_kinematics
import hipsim.analytic.virtual_work as analytic_dynamics
from hipsim import load_parameters, slender_levers
from hipsim.analysis.crosscheck import compare_models
from hipsim.closed_chain.build import load_model
from hipsim.closed_chain.constraints import platform_joint_positions
from hipsim.closed_chain.dynamics import trajectory_dynamics
from hipsim.motion.trajectories import iso14242

MOTION = ("L", "Ld", "Ldd")
TORQUES = ("total", "platforms", "levers", "sliders", "screws", "friction")
FRICTION = dict(
    screw_coulomb=0.05,
    screw_viscous=2e-4,
    guide_coulomb=20.0,
    guide_viscous=30.0,
    ujoint_coulomb=0.3,
    ujoint_viscous=0.05,
    sjoint_coulomb=0.2,
    sjoint_viscous=0.04,
)


def trajectories():
    return {"iso": iso14242(rate=1000.0), "random": SmoothMotion(seed=7)(np.linspace(0.0, 2.0, 2001))}


def column_errors(analytic, pinocchio, names) -> dict[str, float]:
    """Largest difference of each column (module, platform) over that column's peak, per quantity."""
    errors = {}
    for name in names:
        a, p = getattr(analytic, name), getattr(pinocchio, name)
        assert a.shape == p.shape, name
        peak = np.abs(a).max(axis=0)
        assert np.all(peak > 0), f"{name} has an all-zero column: nothing to compare"
        errors[name] = float((np.abs(a - p).max(axis=0) / peak).max())
    return errors


def both_models(params, traj, lever_spin=False):
    kin = analytic_kinematics.kinematics(params, traj)
    torques = analytic_dynamics.inverse_dynamics(params, kin, traj.Fe, lever_spin=lever_spin)
    pin_kin, pin_dynamics = trajectory_dynamics(load_model(params), traj)
    return kin, torques, pin_kin, pin_dynamics.torques


@pytest.fixture(scope="module")
def published():
    return load_parameters()


@pytest.mark.parametrize("name", ["iso", "random"])
def test_slender_levers_agree_exactly(published, name):
    params = slender_levers(published)
    kin, torques, pin_kin, pin_torques = both_models(params, trajectories()[name])
    errors = column_errors(kin, pin_kin, MOTION) | column_errors(torques, pin_torques, TORQUES)
    assert max(errors.values()) <= 1e-8, errors


@pytest.mark.parametrize("name", ["iso", "random"])
def test_published_lever_inertia_difference_is_the_spin(published, name, capsys):
    """The spec's spin-free lever misses the universal joint's spin: small, bounded, and only in τ_l."""
    traj = trajectories()[name]
    kin, torques, pin_kin, pin_torques = both_models(published, traj)
    errors = column_errors(torques, pin_torques, TORQUES)
    with capsys.disabled():
        print(
            f"\n[{name}] published I_l, analytic (no lever spin) vs Pinocchio, max |diff| / column peak: "
            + ", ".join(f"{k} {v:.2e}" for k, v in errors.items())
        )
    for part in ("platforms", "sliders", "screws", "friction"):
        assert errors[part] <= 1e-8, part
    # I_xx − I_yy = 56.5 kg·mm² against I ≈ 26 000 kg·mm²: a real but tiny effect.
    assert 1e-7 <= errors["levers"] <= 1e-3
    assert errors["total"] <= 1e-4
    # Give the analytic lever the universal joint's spin and the two agree again.
    spun = analytic_dynamics.inverse_dynamics(published, kin, traj.Fe, lever_spin=True)
    assert max(column_errors(spun, pin_torques, TORQUES).values()) <= 1e-8


def test_every_friction_agrees(published):
    """All friction coefficients non-zero (U and S joints see the lever's spin, so the analytic side uses it)."""
    params = published.replace(**FRICTION)
    for traj in trajectories().values():
        kin, torques, pin_kin, pin_torques = both_models(params, traj, lever_spin=True)
        errors = column_errors(torques, pin_torques, TORQUES)
        assert max(errors.values()) <= 1e-8, errors


@pytest.mark.parametrize("name", ["iso", "random"])
def test_axial_only_thrust_bearing_agrees(published, name):
    """friction.thrust_bearing_axial_only: both models honour it, and with slender levers agree to 1e-8 of each peak."""
    traj = trajectories()[name]
    axial = slender_levers(published.replace(thrust_bearing_axial_only=True))
    kin, torques, pin_kin, pin_torques = both_models(axial, traj)
    errors = column_errors(kin, pin_kin, MOTION) | column_errors(torques, pin_torques, TORQUES)
    assert max(errors.values()) <= 1e-8, errors
    # Not both ignoring it: the publication's bearing gives a friction part a fifth of its peak or more away.
    publication = analytic_dynamics.inverse_dynamics(slender_levers(published), kin, traj.Fe)
    assert np.abs(publication.friction - torques.friction).max() > 0.2 * np.abs(publication.friction).max()


def test_axial_only_thrust_bearing_with_every_friction_agrees(published):
    params = published.replace(**FRICTION, thrust_bearing_axial_only=True)
    kin, torques, pin_kin, pin_torques = both_models(params, trajectories()["random"], lever_spin=True)
    errors = column_errors(torques, pin_torques, TORQUES)
    assert max(errors.values()) <= 1e-8, errors


def test_check_passes_with_the_axial_only_thrust_bearing(published):
    """hipsim check's comparisons, with the option on: every required one within 1e-8 of the column peak."""
    comparisons = compare_models(published.replace(thrust_bearing_axial_only=True), iso14242(rate=1000.0))
    assert [c.name for c in comparisons if c.required] == ["exact", "published+spin"]
    for comparison in comparisons:
        if comparison.required:
            assert comparison.ok, (comparison.name, comparison.worst)


def test_frames_sit_on_the_analytic_points(published):
    traj = trajectories()["random"]
    kin = analytic_kinematics.kinematics(published, traj)
    chain = load_model(published)
    pin_kin, _ = trajectory_dynamics(chain, traj)
    every = slice(None, None, 50)
    np.testing.assert_allclose(platform_joint_positions(chain, pin_kin.q[every]), kin.a[every], rtol=0, atol=1e-12)
    # The lever frames follow spec §7.1 on both sides (z along e_ji, x along e × u1).
    frames = analytic_kinematics.lever_frames(published, kin)[every]
    model = chain.model
    data = model.createData()
    for n, q in enumerate(pin_kin.q[every]):
        pin.forwardKinematics(model, data, q)
        for j in (1, 2):
            for i in (1, 2, 3):
                joint = model.getJointId(f"u2_{j}{i}")
                np.testing.assert_allclose(data.oMi[joint].rotation, frames[n, i - 1], atol=1e-12)
                np.testing.assert_allclose(data.oMi[joint].translation, kin.b[every][n, j - 1, i - 1], atol=1e-12)


@pytest.mark.parametrize("name", ["iso", "random"])
def test_closure_jacobian_is_the_analytic_jacobian(published, name):
    """The Pinocchio model's own J (from its velocity closure) and singularity measure equal the analytic ones."""
    traj = trajectories()[name]
    kin, _, pin_kin, _ = both_models(published, traj)
    np.testing.assert_allclose(pin_kin.J, kin.J, rtol=0, atol=1e-11 * np.abs(kin.J).max())
    np.testing.assert_allclose(pin_kin.cond_inv, kin.cond_inv, rtol=0, atol=1e-11)  # an SVD of each: round-off
