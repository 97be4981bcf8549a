"""The loop closures at given configurations, with Pinocchio's own closure computations: residuals, Jacobian, rank, joint positions.

Conventions: J_c is the derivative of R₁ᵀ(p₁ − p₂) with frame 1 the lever tip
and frame 2 the platform joint (``RigidConstraintModel``, LOCAL).
"""

from __future__ import annotations

import numpy as np

from ..exceptions import ArgumentError
from .build import ClosedChainModel, require_layout
from .workspace import Workspace

__all__ = ["closure_residuals", "configurations", "constraint_jacobian", "constraint_rank", "platform_joint_positions"]


def configurations(chain: ClosedChainModel, q) -> tuple[np.ndarray, bool]:
    """Configurations q as rows (nq,) or (N, nq), and whether one was given alone.

    Raises:
        ArgumentError: rows of another size than the model's nq.
    """
    q = np.asarray(q, dtype=float)
    single = q.ndim == 1
    q = np.atleast_2d(q)
    if q.shape[1] != chain.model.nq:
        raise ArgumentError("q", q, f"configurations of size nq = {chain.model.nq}")
    return q, single


def closure_residuals(chain: ClosedChainModel, q) -> np.ndarray:
    """How far each closure is from closed: p₂ − p₁ in world axes.

    Args:
        chain: the model.
        q: a configuration (nq,) or configurations (N, nq).

    Returns:
        Shape (n_closures, 3) or (N, n_closures, 3), in [m].
    """
    q, single = configurations(chain, q)
    ws = Workspace(chain)
    out = np.empty((len(q), chain.n_closures, 3))
    for k, qk in enumerate(q):
        ws.place(qk)
        ws.calc_constraints()
        out[k] = [cd.oMc2.translation - cd.oMc1.translation for cd in ws.cd_list]
    return out[0] if single else out


def constraint_jacobian(chain: ClosedChainModel, q) -> np.ndarray:
    """The closure Jacobian J_c (legacy LOCAL convention: d/dt of R₁ᵀ(p₁ − p₂)).

    Args:
        chain: the model.
        q: a configuration (nq,).

    Returns:
        Shape (3·n_closures, nv) for point closures, in [m/rad] or [1].
    """
    ws = Workspace(chain)
    ws.place(np.asarray(q, dtype=float))
    return ws.pinocchio_jacobian()


def constraint_rank(chain: ClosedChainModel, q, rtol: float = 1e-9) -> int:
    """Rank of the closure Jacobian J_c at q (singular values above rtol · the largest).

    Args:
        chain: the model.
        q: a configuration (nq,).
        rtol: relative threshold on the singular values.

    Returns:
        The rank; nv − rank is the mobility at q (3 for the hip simulator).
    """
    sigma = np.linalg.svd(constraint_jacobian(chain, q), compute_uv=False)
    return int(np.sum(sigma > rtol * sigma[0]))


def platform_joint_positions(chain: ClosedChainModel, q) -> np.ndarray:
    """World positions of the platforms' spherical joints a_ji (frames platform_j_joint_i).

    Args:
        chain: the hip model.
        q: a configuration (nq,) or configurations (N, nq).

    Returns:
        Shape (2, 3, 3) or (N, 2, 3, 3): [platform j, joint i, xyz] in [m].
    """
    layout = require_layout(chain)
    q, single = configurations(chain, q)
    ws = Workspace(chain)
    out = np.empty((len(q), 2, 3, 3))
    for k, qk in enumerate(q):
        ws.place(qk)
        ws.calc_constraints()
        for j in range(2):
            for i in range(3):
                out[k, j, i] = ws.cd_list[layout.closure[j, i]].oMc2.translation
    return out[0] if single else out
