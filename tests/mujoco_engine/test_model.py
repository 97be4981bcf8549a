"""The MuJoCo engine (hipsim/mujoco_engine/model.py): its inverse dynamics against the analytic and Pinocchio
models, friction off, default and everywhere, and a different machine detected.

Skipped when ``mujoco`` is not installed or too old (the ``test`` extra installs it).
"""

from __future__ import annotations

import numpy as np
import pytest

mujoco = pytest.importorskip("mujoco")

import hipsim  # noqa: E402
from hipsim.exceptions import MissingDependencyError  # noqa: E402

try:
    import hipsim.mujoco_engine
except MissingDependencyError as error:  # installed, but a release the engine refuses
    pytest.skip(str(error), allow_module_level=True)

from support import ALL_FRICTION  # noqa: E402

from hipsim.analysis.crosscheck import compare_mujoco  # noqa: E402
from hipsim.mujoco_engine import MujocoModel  # noqa: E402


@pytest.fixture(scope="module")
def params():
    return hipsim.load_parameters()


@pytest.mark.parametrize(
    "changes",
    [
        {"hip_mu": 0.0, "thrust_mu": 0.0},  # friction off
        {},  # the default friction: hip joints and thrust bearings
        ALL_FRICTION,  # every friction coefficient, the levers' U and S joints included
    ],
    ids=["friction off", "default friction", "all friction"],
)
def test_inverse_dynamics_agree_with_the_analytic_and_pinocchio_models(params, changes):
    """ISO cycle, published (non-axisymmetric) lever inertia, lever spin on: every column within 1e-8 of its peak."""
    rough = params.replace(**changes)
    comparisons = compare_mujoco(rough, hipsim.iso14242(rate=1000))
    for comparison in comparisons:
        assert comparison.ok, (comparison.name, max(comparison.rows, key=lambda row: row[2]))
        assert comparison.worst < 1e-12  # measured 6e-14 (analytic) and 1.5e-13 (Pinocchio, slider positions)
        names = [name for name, _, _ in comparison.rows]
        assert {"tau_1_Nmm", "tau_f_3_Nmm", "L_23_mm", "cond_inv"} <= set(names)
    assert {"Fa_11_N", "Fo_2_N"} <= {name for name, _, _ in comparisons[1].rows}


def test_friction_is_in_the_torques_and_the_parts_add_up(params):
    traj = hipsim.iso14242(rate=250)
    rough = MujocoModel(params.replace(**ALL_FRICTION)).run(traj)
    smooth = hipsim.analyse(params.replace(hip_mu=0.0, thrust_mu=0.0), traj, model="mujoco")
    assert rough.model == smooth.model == "mujoco"
    assert np.abs(smooth.torques.friction).max() == 0.0
    assert np.abs(rough.torques.friction).max() > 0.05  # N·m: the comparison above is not of zeros
    for result in (rough, smooth):
        t = result.torques
        parts = t.platforms + t.levers + t.sliders + t.screws + t.friction
        np.testing.assert_allclose(parts, t.total, rtol=0, atol=1e-12 * np.abs(t.total).max())


def test_the_axial_only_thrust_bearing_agrees_with_the_other_engines(params):
    """The bearing option reaches MuJoCo's friction forces through the same law: all three engines agree with it on."""
    axial = params.replace(thrust_bearing_axial_only=True)
    traj = hipsim.iso14242(rate=200)
    for comparison in compare_mujoco(axial, traj):
        assert comparison.ok, (comparison.name, max(comparison.rows, key=lambda row: row[2]))
    publication = hipsim.analyse(params, traj, model="mujoco").torques.friction
    assert (
        np.abs(hipsim.analyse(axial, traj, model="mujoco").torques.friction - publication).max()
        > 0.2 * np.abs(publication).max()
    )


def test_a_different_machine_is_detected(params):
    """The agreement is not automatic: MuJoCo with a 10 % heavier lever disagrees with the analytic model."""
    traj = hipsim.iso14242(rate=100)
    heavier = MujocoModel(params.replace(lever_mass=params.lever_mass * 1.1)).run(traj).columns()
    reference = hipsim.analyse(params, traj, lever_spin=True).columns()
    difference = (
        np.abs(heavier["tau_l_1_Nmm"] - reference["tau_l_1_Nmm"]).max() / np.abs(reference["tau_l_1_Nmm"]).max()
    )
    assert difference > 0.05
