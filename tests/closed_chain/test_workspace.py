"""The closure workspace (hipsim.closed_chain.workspace): its closure frames, gaps and Jacobian against Pinocchio's
own constraint computations, its views over Pinocchio's Data against copies, and the block triangular order. The
compiled solver that reads it: closed_chain/test_closure_kernel.py."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
from support import closed_hip

from hipsim.closed_chain.workspace import Workspace, block_triangular_order


@pytest.fixture(scope="module")
def closed():
    return closed_hip()


def test_closure_frames_and_jacobian_are_pinocchios(closed):
    """The compiled closure frames, gaps and Jacobian, read through views of Pinocchio's Data, equal RigidConstraintModel.calc's and getConstraintsJacobian's.

    One workspace placed at configurations in turn, open ones among them: a
    view that went stale (Pinocchio reallocating, or handing out copies)
    would show the previous configuration's frames.
    """
    ws, layout, kin, model = closed.ws, closed.layout, closed.kin, closed.chain.model
    rng = np.random.default_rng(11)
    for k in (3, 17, 30):
        for spread in (0.0, 0.05):
            q = kin.q[k].copy()
            q[layout.leg_v] += spread * rng.normal(size=layout.leg_v.size)
            ws.place(q)
            gaps, tips, p2, J_c = ws.residual().copy(), ws.tip_frames().copy(), ws.p2.copy(), ws.jacobian()
            # The other route: Pinocchio's own constraint computations, in a fresh Data.
            reference = Workspace(closed.chain)
            pin.computeJointJacobians(model, reference.data, q)
            expected_J = reference.pinocchio_jacobian()
            np.testing.assert_allclose(
                gaps, np.concatenate([cd.c1Mc2.translation for cd in reference.cd_list]), rtol=0, atol=1e-15
            )
            np.testing.assert_allclose(tips, [cd.oMc1.homogeneous for cd in reference.cd_list], rtol=0, atol=1e-15)
            np.testing.assert_allclose(p2, [cd.oMc2.translation for cd in reference.cd_list], rtol=0, atol=1e-15)
            np.testing.assert_allclose(J_c, expected_J, rtol=0, atol=1e-14)
            assert (spread == 0.0) == (np.abs(gaps).max() < 1e-12)


def test_placement_views_follow_pinocchio_and_the_copying_route_agrees(closed):
    """The strided views over data.oMi show every joint's current placement; a workspace without them (copies) places the closures bit for bit alike."""
    ws, model, q = closed.ws, closed.chain.model, closed.kin.q[21]
    assert ws.joint_rotations is not None  # this Pinocchio's layout is the one the views assume
    copying = Workspace(closed.chain)
    copying.joint_rotations = copying.joint_origins = None
    for qk in (q, q + 0.01):
        ws.place(qk)
        copying.place(qk)
        for j in range(model.njoints):
            np.testing.assert_array_equal(ws.joint_rotations[j], ws.data.oMi[j].rotation)
            np.testing.assert_array_equal(ws.joint_origins[j], ws.data.oMi[j].translation)
        np.testing.assert_array_equal(ws.residual(), copying.residual())
        np.testing.assert_array_equal(ws.tip_frames(), copying.tip_frames())


def test_block_triangular_order_finds_the_blocks():
    """A scrambled block lower triangular pattern is put back in block form; a structurally singular one stays one block; the hip's B splits 3, 3, 3, 9."""
    rng = np.random.default_rng(8)
    sizes = [2, 3, 1, 2]
    starts = np.cumsum([0] + sizes)
    pattern = np.zeros((8, 8), bool)
    for b in range(len(sizes)):
        pattern[starts[b] : starts[b + 1], : starts[b + 1]] = rng.random((sizes[b], starts[b + 1])) < 0.6
        pattern[starts[b] : starts[b + 1], starts[b] : starts[b + 1]] = True  # each block irreducible
    row_mix, column_mix = rng.permutation(8), rng.permutation(8)
    rows, columns, found = block_triangular_order(pattern[row_mix][:, column_mix])
    ordered = pattern[row_mix][:, column_mix][rows][:, columns]
    for b in range(len(found) - 1):
        assert not ordered[found[b] : found[b + 1], found[b + 1] :].any()
    assert np.sort(np.diff(found)).tolist() == sorted(sizes)
    singular = np.ones((3, 3), bool)
    singular[:, 0] = False
    assert block_triangular_order(singular)[2].tolist() == [0, 3]
