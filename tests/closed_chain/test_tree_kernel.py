"""The tree's compiled kinematics and inertia (hipsim.closed_chain.tree_kernel) and the Newton–Euler bias forces
the plant's solver evaluates with them, against Pinocchio at random states of the hip's tree and of another tree."""

import numpy as np
import pinocchio as pin
import pytest
from support import given

import hipsim
from hipsim.closed_chain import plant_kernel
from hipsim.closed_chain.build import load_model
from hipsim.closed_chain.plant_kernel import tree_constants
from hipsim.closed_chain.tree_kernel import forward_kinematics, mass_matrix, tree_geometry


@pytest.fixture(scope="module")
def hip():
    return load_model(hipsim.load_parameters()).model


def _manipulator():
    """Pinocchio's sample arm (revolute joints about other axes, rotated placements), with an armature."""
    model = pin.buildSampleModelManipulator()
    model.armature = np.linspace(0.1, 0.6, model.nv)
    return model


def _compiled(model, q, v):
    """M, J, the placements and h = C(q, v)·v + g(q) through the compiled route."""
    placements, motions = given(tree_geometry(model))
    bodies, joints = tree_constants(model)
    nj, nv = model.njoints, model.nv
    R, o, J, M = np.empty((nj, 3, 3)), np.empty((nj, 3)), np.empty((6, nv)), np.empty((nv, nv))
    forward_kinematics(placements, motions, joints, q, R, o, J)
    mass_matrix(J, R, o, bodies, joints, np.array(model.armature), np.empty((nj, 13)), M)
    twists, rates, wrenches, h = np.empty((nj, 6)), np.empty((nj, 6)), np.empty((nj, 6)), np.empty(nv)
    plant_kernel._motions(J, joints, v, twists, rates)
    plant_kernel._nonlinear_effects(J, R, o, bodies, joints, tuple(model.gravity.linear), twists, rates, wrenches, h)
    return M, J, R, o, h


@pytest.mark.parametrize("which", ["hip", "manipulator"])
def test_kinematics_inertia_and_bias_forces_are_pinocchios(hip, which):
    model = hip if which == "hip" else _manipulator()
    data = model.createData()
    rng = np.random.default_rng(11)
    for _ in range(4):
        q, v = rng.uniform(-1.5, 1.5, model.nq), rng.normal(0.0, 2.0, model.nv)
        M, J, R, o, h = _compiled(model, q, v)
        expected = pin.crba(model, data, q, pin.Convention.WORLD)
        expected = np.triu(expected) + np.triu(expected, 1).T
        np.testing.assert_allclose(M, expected, rtol=0, atol=1e-12 * np.abs(expected).max())
        np.testing.assert_allclose(J, pin.computeJointJacobians(model, data, q), rtol=0, atol=1e-12)
        for j in range(1, model.njoints):
            np.testing.assert_allclose(R[j], data.oMi[j].rotation, rtol=0, atol=1e-14)
            np.testing.assert_allclose(o[j], data.oMi[j].translation, rtol=0, atol=1e-14)
        bias = pin.nonLinearEffects(model, data, q, v)
        np.testing.assert_allclose(h, bias, rtol=0, atol=1e-12 * np.abs(bias).max())
    # The armature is on the diagonal, and large enough that the comparison above would see it missing.
    armature = model.armature.copy()
    model.armature = np.zeros(model.nv)
    bare = _compiled(model, q, v)[0]
    model.armature = armature
    np.testing.assert_allclose(M - bare, np.diag(armature), rtol=0, atol=1e-12 * np.abs(M).max())
    assert armature.max() > 1e-2 * np.abs(M).max()


def test_trees_with_other_joints_are_refused():
    """A free-flyer or a spherical joint is not one revolute or prismatic coordinate: no compiled tree (the plant falls back)."""
    assert tree_geometry(pin.buildSampleModelHumanoid()) is None
    model = pin.Model()
    model.addJoint(0, pin.JointModelSpherical(), pin.SE3.Identity(), "ball")
    assert tree_geometry(model) is None
    helical = pin.Model()
    helical.addJoint(0, pin.JointModelHZ(0.01), pin.SE3.Identity(), "screw")  # turns and slides: neither
    assert tree_geometry(helical) is None
