"""One computation's Pinocchio Data, read through strided NumPy views, and the block-triangular order of K.

The closure solver reads Pinocchio's results (the joint placements
``data.oMi``, the joint Jacobians ``data.J``) through NumPy views that
Pinocchio keeps current in its Data, not through per-closure property reads,
which cost a Python call and a copy each; the closures' frames, gaps and
Jacobian are compiled arithmetic on them
(:mod:`~hipsim.closed_chain.closure_kernel`), writing into arrays the
:class:`Workspace` keeps. Pinocchio's own ``RigidConstraintModel.calc`` and
``getConstraintsJacobian`` serve the public helpers of
:mod:`~hipsim.closed_chain.constraints` and the tests that hold the compiled
route equal to them.

K = [P₁; J_c] (see :mod:`~hipsim.closed_chain.closure`) is block lower
triangular in a suitable order of rows and columns (:func:`k_order`), which
the compiled velocity solve exploits.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from . import closure_kernel

__all__ = ["Workspace", "block_triangular_order", "k_order"]


class Workspace:
    """Pinocchio data and the constraint datas of one computation (not shared between threads).

    The solver reads Pinocchio's results through NumPy views that Pinocchio
    keeps current in its Data (the joint Jacobians ``data.J``,
    the joint placements ``data.oMi``): a property read costs a Python call
    and a copy, some 0.5 µs, and a sample would need dozens. The views live
    as long as this workspace's Data, which they point into.

    Args:
        chain: the :class:`~hipsim.closed_chain.build.ClosedChainModel` (its
            tree and constraint models; the workspace keeps no reference to it).
    """

    def __init__(self, chain):
        self.model = chain.model
        self.data = chain.model.createData()
        self.cms = chain.constraint_models
        self.cds = pin.StdVec_RigidConstraintData()
        for cm in self.cms:
            self.cds.append(cm.createData())
        # Python lists of references into the vectors: indexing a StdVec per access is slow.
        self.cd_list = list(self.cds)
        self.pairs = list(zip(self.cms, self.cd_list))
        n, nv = len(self.cd_list), chain.model.nv
        # The joints supporting each closure frame, frame 1 then frame 2, as 0/1 over the velocity indices:
        # the columns of the world Jacobians that move that frame's body.
        self.support_masks = np.zeros((2 * n, nv))
        for c, cm in enumerate(self.cms):
            for end, joint in enumerate((cm.joint1_id, cm.joint2_id)):
                for k in self.model.supports[joint][1:]:  # the universe (0) has no velocity
                    self.support_masks[2 * c + end, self.model.joints[k].idx_v] = 1.0
        # Each closure's two joints, and its frames' placements in them (closure_kernel.closure_frames).
        self.closure_joints = np.array([[cm.joint1_id, cm.joint2_id] for cm in self.cms])
        self.closure_placements = np.array(
            [[cm.joint1_placement.homogeneous, cm.joint2_placement.homogeneous] for cm in self.cms]
        )
        self.joint_rotations, self.joint_origins = _joint_placement_views(self.model, self.data)
        self.J = self.data.J
        self.tips = np.empty((n, 4, 4))  # frame 1's world placement per closure, at the last place()
        self.p2 = np.empty((n, 3))  # frame 2's world origin per closure [m], at the last place()
        self.gaps = np.empty(3 * n)  # the closure gaps [m] at the last place()
        self.J_c = np.empty((3 * n, nv))
        # closure_kernel.closure_frames' arguments, in its order (None without live views of data.oMi).
        self.frame_args = (
            None
            if self.joint_rotations is None
            else (
                self.joint_rotations,
                self.joint_origins,
                self.closure_joints,
                self.closure_placements,
                self.tips,
                self.p2,
                self.gaps,
            )
        )

    def place(self, q: np.ndarray, jacobians: bool = True) -> float:
        """Forward kinematics, joint Jacobians (unless not asked for) and the closures' frames and gaps at q; returns |gaps|² [m²]."""
        if jacobians:
            pin.computeJointJacobians(self.model, self.data, q)
        else:
            pin.forwardKinematics(self.model, self.data, q)
        return closure_kernel.closure_frames(*self.frame_arguments())

    def frame_arguments(self) -> tuple:
        """closure_kernel.closure_frames' arguments at the placed q: the views of ``data.oMi``, or copies of it without them."""
        if self.frame_args is not None:  # set exactly when the live views are
            return self.frame_args
        rotations, origins = _joint_placement_copies(self.data)
        return (rotations, origins, self.closure_joints, self.closure_placements, self.tips, self.p2, self.gaps)

    def residual(self) -> np.ndarray:
        """The closure gaps d = R₁ᵀ(p₂ − p₁) of every closure, stacked, in [m] (after :meth:`place`; overwritten by the next).

        Pinocchio's relative placement c1Mc2's translation, whose derivative is
        −J_c (J_c differentiates p₁ − p₂): a Newton step on the gaps is q + K⁻¹·[0; d].
        """
        return self.gaps

    def jacobian(self) -> np.ndarray:
        """The stacked closure Jacobian J_c (after :meth:`place` with the Jacobians; overwritten by the next call)."""
        closure_kernel.closure_jacobian(self.J, self.support_masks, self.tips, self.p2, self.J_c)
        return self.J_c

    def tip_frames(self) -> np.ndarray:
        """Frame 1's homogeneous placement of every closure (its axes and origin in the world), (n, 4, 4) (after :meth:`place`; overwritten by the next)."""
        return self.tips

    def calc_constraints(self) -> None:
        """Pinocchio's own closure computations (``RigidConstraintModel.calc``) at the placed q: the reference the views are checked against."""
        for cm, cd in self.pairs:
            cm.calc(self.model, self.data, cd)

    def pinocchio_jacobian(self) -> np.ndarray:
        """Pinocchio's stacked closure Jacobian (``getConstraintsJacobian``) at the placed q (after :meth:`place` with the Jacobians)."""
        self.calc_constraints()
        return pin.getConstraintsJacobian(self.model, self.data, self.cms, self.cds)


def _joint_placement_copies(data) -> tuple[np.ndarray, np.ndarray]:
    """The joints' world rotations (njoints, 3, 3) and origins (njoints, 3) [m], copied out of ``data.oMi``."""
    return np.array([M.rotation for M in data.oMi]), np.array([M.translation for M in data.oMi])


def _joint_placement_views(model, data) -> tuple[np.ndarray | None, np.ndarray | None]:
    """The joints' world rotations (njoints, 3, 3) and origins (njoints, 3) [m] as NumPy views into ``data.oMi``, or (None, None).

    Pinocchio keeps ``data.oMi`` as one contiguous std::vector of SE3 (the
    rotation's nine entries column by column, then the translation), and its
    bindings hand out each element's rotation and translation as views into
    it. Two strided arrays over the first element's views then cover every
    joint and stay current as Pinocchio updates the placements: the compiled
    solver reads them with no Python call per joint. The layout is checked
    (addresses, and the values after a forward kinematics); where it is not
    the expected one, (None, None) and the solver copies (slower, same result).
    """
    from numpy.lib.stride_tricks import as_strided

    def address(array: np.ndarray) -> int:
        return array.__array_interface__["data"][0]

    rotation, translation = data.oMi[0].rotation, data.oMi[0].translation
    if model.njoints < 2 or rotation.strides != (8, 24) or translation.strides != (8,):
        return None, None
    stride = address(data.oMi[1].rotation) - address(rotation)
    if any(
        address(data.oMi[j].rotation) != address(rotation) + j * stride
        or address(data.oMi[j].translation) != address(rotation) + j * stride + 72
        for j in range(model.njoints)
    ):
        return None, None
    rotations = as_strided(rotation, shape=(model.njoints, 3, 3), strides=(stride, 8, 24), writeable=False)
    origins = as_strided(translation, shape=(model.njoints, 3), strides=(stride, 8), writeable=False)
    pin.forwardKinematics(model, data, pin.randomConfiguration(model, -np.ones(model.nq), np.ones(model.nq)))
    copies = _joint_placement_copies(data)
    if not (np.array_equal(rotations, copies[0]) and np.array_equal(origins, copies[1])):
        return None, None
    return rotations, origins


def block_triangular_order(pattern: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Row and column orders that make square matrices of this sparsity block lower triangular, and where the blocks start.

    The block triangular form of Dulmage and Mendelsohn: a perfect matching of
    rows to columns (a diagonal without structural zeros), then the strongly
    connected components of the graph "row i involves the column matched to
    row k", in an order where each comes after those it involves.

    Args:
        pattern: (n, n) booleans, True where the matrices may be nonzero.

    Returns:
        rows, columns: the orders, (n,) each; starts: each block's first index and n at the end.
        One block (the original order) where no perfect matching exists.
    """
    from scipy.sparse import csr_matrix
    from scipy.sparse.csgraph import connected_components, maximum_bipartite_matching

    n = len(pattern)
    match = maximum_bipartite_matching(csr_matrix(pattern), perm_type="column")  # the column matched to each row
    if (match < 0).any():
        return np.arange(n), np.arange(n), np.array([0, n])
    involves = pattern[:, match]
    count, component = connected_components(csr_matrix(involves), directed=True, connection="strong")
    needs = [set(component[involves[component == c].any(axis=0)]) - {c} for c in range(count)]
    order: list[int] = []
    while len(order) < count:  # the components' graph has no cycles: each pass places at least one
        order += [c for c in range(count) if c not in order and needs[c] <= set(order)]
    rows = np.concatenate([np.flatnonzero(component == c) for c in order])
    starts = np.cumsum([0] + [int(np.sum(component == c)) for c in order])
    return rows, match[rows], starts


def k_order(ws: Workspace, platform1: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The block order of K's block B for :func:`~hipsim.closed_chain.closure_kernel.velocity`: J_c's rows, the velocity indices of B's columns, the blocks' starts.

    Closure c's three rows of J_c can only be nonzero in the columns of the
    joints that support its two frames (``support_masks``). For the hip the
    blocks are each platform-1 lever's slider and universal joint (3×3, three
    of them), then platform 2's levers and spherical joint together (9×9).
    """
    others = np.setdiff1d(np.arange(ws.model.nv), platform1)
    reach = ws.support_masks[0::2] + ws.support_masks[1::2] > 0  # (closures, nv)
    rows, columns, starts = block_triangular_order(np.repeat(reach[:, others], 3, axis=0))
    return rows, others[columns], starts
