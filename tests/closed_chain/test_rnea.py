"""hipsim.closed_chain.rnea on a two-link pendulum built here: the batched RNEA is Pinocchio's RNEA sample by sample
(and a point mass's m·l²·q̈ + m·g·l·sin q by hand), a massless tree gives zeros, and the body groups' trees (each with
only its joints) add up to the whole tree's torques."""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
from numpy.testing import assert_allclose

from hipsim.closed_chain.rnea import BatchedRNEA, group_trees

G = 9.81


def pendulum(masses=(2.0, 1.5), length=0.5) -> pin.Model:
    """Two joints about x, each link a point mass ``length`` below its joint along −z."""
    model = pin.Model()
    model.gravity.linear = np.array([0.0, 0.0, -G])
    parent = 0
    for k, mass in enumerate(masses):
        placement = pin.SE3(np.eye(3), np.array([0.0, 0.0, -length if k else 0.0]))
        parent = model.addJoint(parent, pin.JointModelRX(), placement, f"joint{k + 1}")
        frame = model.addJointFrame(parent)  # frames, as a URDF's model has them: buildReducedModel needs them
        inertia = pin.Inertia(mass, np.array([0.0, 0.0, -length]), np.zeros((3, 3)))
        model.appendBodyToJoint(parent, inertia, pin.SE3.Identity())
        model.addBodyFrame(f"link{k + 1}", parent, pin.SE3.Identity(), frame)
    return model


def samples(n=4, nv=2, seed=3):
    rng = np.random.default_rng(seed)
    return (rng.uniform(-1, 1, (n, nv)) for _ in range(3))


def test_one_point_mass_by_hand():
    model = pendulum(masses=(2.0,), length=0.5)
    q, v, a = np.array([[0.3]]), np.array([[0.0]]), np.array([[1.2]])
    out = np.empty((1, 1))
    BatchedRNEA(model, np.array([0]))(q, v, a, out)
    # τ = m·l²·q̈ + m·g·l·sin q, the mass hanging below the axis.
    assert_allclose(out[0, 0], 2.0 * 0.25 * 1.2 + 2.0 * G * 0.5 * math.sin(0.3), rtol=1e-12)


def test_the_batch_is_rnea_sample_by_sample():
    model = pendulum()
    q, v, a = samples()
    out = np.full((4, 2), np.nan)
    BatchedRNEA(model, np.array([0, 1]))(q, v, a, out)
    data = model.createData()
    for k in range(4):
        assert_allclose(out[k], pin.rnea(model, data, q[k], v[k], a[k]), rtol=1e-12, atol=1e-12)


def test_a_tree_without_bodies_gives_zeros():
    q, v, a = samples(3)
    out = np.full((3, 2), np.nan)
    BatchedRNEA(None, np.zeros(0, dtype=int))(q, v, a, out)
    assert np.array_equal(out, np.zeros((3, 2)))


def test_the_groups_trees_add_up_to_the_whole_tree():
    model = pendulum()
    # Dynamic parameters per body (10 a body: m, m·c, inertia), one column a group: link 1 alone, link 2 alone.
    groups = np.zeros((20, 2))
    groups[:10, 0] = model.inertias[1].toDynamicParameters()
    groups[10:, 1] = model.inertias[2].toDynamicParameters()
    trees = group_trees(model, groups)
    assert [list(columns) for _, columns in trees] == [[0], [0, 1]]  # link 1 hangs from joint 1 only
    q, v, a = samples()
    whole = np.empty((4, 2))
    BatchedRNEA(model, np.array([0, 1]))(q, v, a, whole)
    total = np.zeros((4, 2))
    for tree, columns in trees:
        part = np.full((4, 2), np.nan)
        BatchedRNEA(tree, columns)(q, v, a, part)
        total += part
    assert_allclose(total, whole, rtol=1e-12, atol=1e-12)
    empty = group_trees(model, np.zeros((20, 1)))
    assert empty[0][0] is None and empty[0][1].size == 0
