"""Pinocchio's batched RNEA (``pin.rneaInParallel``) of the hip's tree and of each body group's tree.

The tree's torques are computed for a whole chunk of samples at once, one
call a chunk instead of one a sample. RNEA is linear in the bodies' inertias
for a fixed motion, so the trees that keep one body group's inertias each
(:func:`group_trees`) give the torques' parts, which add up to the whole tree's.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import pinocchio as pin

__all__ = ["BatchedRNEA", "group_trees"]

#: Threads of Pinocchio's batched RNEA (``pin.rneaInParallel``): one. It is used for its batching
#: (one call a chunk instead of one a sample); a second thread would save ~1 µs a sample on an idle
#: machine but compete with the loop's other process or thread wherever one runs (sweeps, servers).
_RNEA_THREADS = 1


class BatchedRNEA:
    """Pinocchio's batched RNEA (``pin.rneaInParallel``) of one tree, and where its joints sit in the hip model's velocity vector.

    Each holds its own ``pin.ModelPool`` (the tree's Data): not shared between threads.

    Args:
        model: the tree; None for a group without bodies (massless levers, say), whose torques are zero.
        columns: the hip model's velocity index of each of the tree's joints, in the tree's order.
    """

    def __init__(self, model, columns: np.ndarray):
        self.pool = pin.ModelPool(model, _RNEA_THREADS) if model is not None else None
        self.columns = columns

    def __call__(self, q: np.ndarray, v: np.ndarray, a: np.ndarray, out: np.ndarray) -> None:
        """Write the tree's torques at samples (rows of) q, v, a into ``out``'s columns, (m, nv); the other columns are zeroed."""
        if self.pool is None:
            out[:] = 0.0
        elif len(self.columns) == out.shape[1]:  # the hip model's whole tree
            pin.rneaInParallel(_RNEA_THREADS, self.pool, q.T, v.T, a.T, out.T)
        else:
            columns = self.columns
            tau = np.empty((len(q), len(columns)))
            pin.rneaInParallel(_RNEA_THREADS, self.pool, q[:, columns].T, v[:, columns].T, a[:, columns].T, tau.T)
            out[:] = 0.0
            out[:, columns] = tau


def group_trees(model, groups: np.ndarray) -> list[tuple[Any, np.ndarray]]:
    """Per body group (platforms, levers, carriages): a tree with only that group's inertias, and its joints' velocity indices.

    RNEA is linear in the bodies' inertias for a given motion, so the tree
    with only one group's inertias (and no armature: the screws' term is added
    apart) gives that group's part of the torques. A group's torques depend
    only on the joints that support its bodies, so its tree keeps just those
    (``pin.buildReducedModel`` locks the others, whose bodies carry no
    inertia there): 6 joints for the platforms, 15 for the levers, 3 for the
    carriages, against 21 for each. Built once per loaded model (by its
    :class:`~hipsim.closed_chain.solver.ClosedChainSolver`).

    Args:
        model: the hip's tree (``pin.Model``).
        groups: (10·(njoints−1), groups) dynamic parameters of each group's bodies (``HipLayout.groups``).
    """
    trees = []
    for g in range(groups.shape[1]):
        members = [k for k in range(1, model.njoints) if np.any(groups[10 * (k - 1) : 10 * k, g] != 0.0)]
        if not members:
            trees.append((None, np.zeros(0, dtype=int)))
            continue
        member = model.copy()
        member.armature = np.zeros(model.nv)
        for k in range(1, model.njoints):
            if k not in members:
                member.inertias[k] = pin.Inertia.Zero()
        kept = {int(j) for k in members for j in model.supports[k]}
        locked = [k for k in range(1, model.njoints) if k not in kept]
        reduced = pin.buildReducedModel(member, locked, pin.neutral(model)) if locked else member
        trees.append((reduced, np.array([model.joints[model.getJointId(name)].idx_v for name in reduced.names[1:]])))
    return trees
