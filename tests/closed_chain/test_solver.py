"""Each closed-chain model's solver state (hipsim.closed_chain.solver): made once per thread, reused by every run, owned by its model."""

from __future__ import annotations

import dataclasses
import gc
import threading
import weakref

from hipsim.closed_chain.build import load_model


def test_a_thread_reuses_its_share_and_another_thread_gets_its_own():
    chain = load_model()
    solver = chain.solver
    mine = (solver.workspace(), solver.k_order(), solver.rneas(True), solver.rneas(False))
    assert solver.workspace() is mine[0] and solver.k_order() is mine[1]
    assert solver.rneas(True) is mine[2] and solver.rneas(False) is mine[3]
    theirs = []
    thread = threading.Thread(target=lambda: theirs.append((solver.workspace(), solver.rneas(True))))
    thread.start()
    thread.join()
    assert theirs[0][0] is not mine[0] and theirs[0][0].data is not mine[0].data
    assert all(a.pool is not b.pool for a, b in zip(theirs[0][1], mine[2]) if a.pool is not None)
    assert solver.group_trees() is solver.group_trees()  # the trees are read only: one set per model


def test_every_model_has_its_own_solver_and_frees_it_with_itself():
    chain = load_model()
    other = dataclasses.replace(chain)
    assert other.solver is not chain.solver and other.solver.chain is other
    chain.solver.workspace()
    model, solver = weakref.ref(chain), weakref.ref(chain.solver)
    enabled = gc.isenabled()
    gc.disable()
    try:
        del chain
        assert model() is None and solver() is None  # no reference cycle: freed without the collector
    finally:
        if enabled:
            gc.enable()
