"""The closure solver's per-model state, one share per thread: workspace, K's block order, batched RNEAs.

Pinocchio's Data is not shared between threads, and making it again for every
run would cost some 0.3 ms a run (K's block order alone ~0.7 ms of SciPy
graph work). So each :class:`~hipsim.closed_chain.build.ClosedChainModel`
owns one :class:`ClosedChainSolver`, which makes each thread's share the
first time that thread asks for it and keeps it for the thread's later runs
on the same model; two threads on one model never touch each other's Data.
"""

from __future__ import annotations

import threading
import weakref
from typing import Any

import numpy as np

from .rnea import BatchedRNEA, group_trees
from .workspace import Workspace, k_order

__all__ = ["ClosedChainSolver"]


class _ThreadShare:
    """What the solver of one model needs in one thread: its workspace, and (once asked for) K's block order and its batched RNEAs."""

    def __init__(self, workspace: Workspace):
        self.workspace = workspace
        self.rneas: dict[bool, list[BatchedRNEA]] = {}
        self.k_order: dict[int, tuple[np.ndarray, np.ndarray, np.ndarray]] = {}


class ClosedChainSolver:
    """Per model, the closure solver's state that threads do not share (made once per thread, then reused by every run).

    Args:
        chain: the :class:`~hipsim.closed_chain.build.ClosedChainModel` that owns this solver
            (held weakly: the model holds its solver).
    """

    def __init__(self, chain):
        self._chain = weakref.ref(chain)
        self._threads = threading.local()
        self._group_trees: list[tuple[Any, np.ndarray]] | None = None  # shared: the trees are only read

    @property
    def chain(self):
        """The model this solver belongs to."""
        return self._chain()

    def _share(self) -> _ThreadShare:
        """This thread's share, made on its first call (a run reuses the last run's: some 0.3 ms saved each)."""
        share = getattr(self._threads, "share", None)
        if share is None:
            share = self._threads.share = _ThreadShare(Workspace(self.chain))
        return share

    def workspace(self) -> Workspace:
        """This thread's workspace (Pinocchio Data and constraint Datas, with their views)."""
        return self._share().workspace

    def k_order(self, platform: int = 0) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """K's block order (:func:`~hipsim.closed_chain.workspace.k_order`) with P₁ on platform ``platform``'s coordinates
        (0: m_1, the drawing's; 1: m_2, the controlled platform of a per-chain machine): ~0.7 ms of SciPy graph work, once."""
        share = self._share()
        if platform not in share.k_order:
            share.k_order[platform] = k_order(share.workspace, self.chain.layout.platform_v[platform])
        return share.k_order[platform]

    def rneas(self, parts: bool) -> list[BatchedRNEA]:
        """This thread's batched RNEAs: the body groups' (parts), or the whole tree's, armature included."""
        share = self._share()
        if parts not in share.rneas:
            chain = self.chain
            trees = self.group_trees() if parts else [(chain.model, np.arange(chain.model.nv))]
            share.rneas[parts] = [BatchedRNEA(model, columns) for model, columns in trees]
        return share.rneas[parts]

    def group_trees(self) -> list[tuple[Any, np.ndarray]]:
        """The body groups' trees (:func:`~hipsim.closed_chain.rnea.group_trees`), built once per model."""
        if self._group_trees is None:
            chain = self.chain
            self._group_trees = group_trees(chain.model, chain.layout.groups)
        return self._group_trees
