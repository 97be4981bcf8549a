"""Physical consistency of an identified machine, and the fit solved again under it.

If the identified machine is not physically consistent — a negative mass,
friction coefficient or rotor inertia, or an inertia no rigid body has (its
principal moments must satisfy the triangle inequalities, i.e.
Σ = ½·tr(I)·𝟙 − I ⪰ 0, which also makes I ⪰ 0) — the fit is solved again
under those constraints (:func:`consistent`), the dependent parameters then
free to move but held by a prior of :data:`PRIOR_SPREAD` of their size: first
as bounded least squares (SciPy's ``lsq_linear``, BVLS, exact for the bounds),
and if an inertia is still impossible, as a small convex program with the two
3×3 semidefinite constraints added, solved by ADMM (alternating direction
method of multipliers: the bounds and the semidefinite cones projected onto
exactly, the least squares solved with one factorisation). The constraints
the solution sits on are reported.
"""

from __future__ import annotations

import math

import numpy as np
import scipy.linalg
import scipy.optimize

from .quantities import AXES, BLOCKS, BOUNDED, QUANTITIES, symmetric

__all__ = ["PRIOR_SPREAD", "consistent", "violations"]

#: The starting values' spread, relative to their size, where the consistency constraints move a dependent parameter.
PRIOR_SPREAD = 0.1

#: Σ = ½·tr(I)·𝟙 − I as a linear map of (Ixx, Iyy, Izz, Ixy, Ixz, Iyz), to (Σxx, Σyy, Σzz, √2Σxy, √2Σxz, √2Σyz)
#: (the √2 makes the Euclidean norm of the vector the Frobenius norm of the matrix).
_SIGMA = np.array(
    [
        [-0.5, 0.5, 0.5, 0, 0, 0],
        [0.5, -0.5, 0.5, 0, 0, 0],
        [0.5, 0.5, -0.5, 0, 0, 0],
        [0, 0, 0, -math.sqrt(2), 0, 0],
        [0, 0, 0, 0, -math.sqrt(2), 0],
        [0, 0, 0, 0, 0, -math.sqrt(2)],
    ]
)


def _matrix(sigma: np.ndarray) -> np.ndarray:
    """The symmetric matrix of a Σ vector (xx, yy, zz, √2xy, √2xz, √2yz)."""
    r = 1.0 / math.sqrt(2)
    return symmetric([sigma[0], sigma[1], sigma[2], sigma[3] * r, sigma[4] * r, sigma[5] * r])


def _vector(matrix: np.ndarray) -> np.ndarray:
    r = math.sqrt(2)
    return np.array([matrix[0, 0], matrix[1, 1], matrix[2, 2], r * matrix[0, 1], r * matrix[0, 2], r * matrix[1, 2]])


def _project_psd(sigma: np.ndarray) -> np.ndarray:
    values, vectors = np.linalg.eigh(_matrix(sigma))
    return _vector((vectors * np.maximum(values, 0.0)) @ vectors.T)


def violations(theta: np.ndarray, tolerance: float = 1e-12) -> list[str]:
    """The physical-consistency constraints θ breaks, as text."""
    out = [f"{QUANTITIES[k].label} ≥ 0" for k in BOUNDED if theta[k] < 0]
    for body, block in BLOCKS.items():
        sigma = np.linalg.eigvalsh(_matrix(_SIGMA @ theta[block]))
        if sigma[0] < -tolerance * max(abs(sigma).max(), 1e-300):
            out.append(f"{body} inertia of a rigid body (principal moments within the triangle inequalities)")
    return out


def consistent(Aw, zw, theta0, kept, dependent, prior, nominal, max_iter: int = 20_000):
    """Weighted least squares under the consistency constraints (module docstring).

    Variables: the kept and dependent parameters, scaled by their nominal sizes
    (``Aw``, ``zw``: the weighted rows, scaled to a χ²); the others stay at θ0. First bounded least squares (SciPy's ``lsq_linear``,
    BVLS: exact for the bounds); if an inertia then breaks the rigid-body
    condition, the semidefinite constraints join in a small convex program
    solved by ADMM. Returns θ and the active constraints as text.
    """
    variables = list(kept) + list(dependent)
    scale = nominal[variables]
    constant = np.array(theta0, dtype=float)
    constant[variables] = 0.0
    A = Aw[:, variables] * scale
    b = zw - Aw @ constant
    # The dependent parameters move only where the bounds need them to: a prior of 10 % of their size
    # (the data term is a χ², its rows weighted by the inverse noise), which holds them wherever the
    # data leave them free and gives way where the data pull.
    dep = np.zeros(len(variables))
    dep[len(kept) :] = 1.0
    target = prior[variables] / scale
    pull = 1.0 / PRIOR_SPREAD
    A_reg = np.vstack([A, pull * np.diag(dep)[dep > 0]])
    b_reg = np.concatenate([b, pull * target[dep > 0]])
    position = {k: n for n, k in enumerate(variables)}
    lower = np.full(len(variables), -np.inf)
    for k in BOUNDED:
        if k in position:
            lower[position[k]] = 0.0
    x = scipy.optimize.lsq_linear(A_reg, b_reg, bounds=(lower, np.inf), method="bvls", tol=1e-14).x
    theta = constant.copy()
    theta[variables] = x * scale
    if any("inertia" in violation for violation in violations(theta)):
        theta = _semidefinite(A_reg, b_reg, x, scale, constant, variables, max_iter)
    return theta, _active(theta, [k for k in variables if k in kept or prior[k] > 0], nominal)


def _active(theta, movable, nominal) -> tuple[str, ...]:
    """The constraints θ sits on: bounds of the parameters that moved to them, and inertias on the rigid-body limit."""
    active = [f"{QUANTITIES[k].label} ≥ 0" for k in BOUNDED if k in movable and theta[k] <= 1e-9 * nominal[k]]
    for body, block in BLOCKS.items():
        eigen = np.linalg.eigvalsh(_matrix(_SIGMA @ theta[block]))
        if eigen[0] <= 1e-9 * eigen[-1]:
            active.append(
                f"{body} inertia on the rigid-body limit (one principal moment equals the sum of the other two)"
            )
    return tuple(active)


def _semidefinite(A, b, x0, scale, constant, variables, max_iter):
    """Least squares ‖A·x − b‖² under the bounds and the two semidefinite constraints, by ADMM (x scaled by ``scale``)."""
    H = A.T @ A
    q = A.T @ b
    # Constraint rows y = M·x + c, blocks: bounds (y ≥ 0), then each inertia's Σ vector (PSD).
    position = {k: n for n, k in enumerate(variables)}
    rows: list[np.ndarray] = []
    offsets: list[float] = []
    kinds: list[tuple[str, int | str]] = []  # ("bound", variable) or ("block", body)
    for k in BOUNDED:
        if k in position:
            row = np.zeros(len(variables))
            row[position[k]] = 1.0
            rows.append(row)
            offsets.append(0.0)
            kinds.append(("bound", k))
    for body, block in BLOCKS.items():
        G = np.zeros((6, len(variables)))
        c = _SIGMA @ constant[block]
        for column, k in enumerate(block):
            if k in position:
                G[:, position[k]] = _SIGMA[:, column] * scale[position[k]]
        size = max(np.abs(G).max(), np.abs(c).max(), 1e-300)
        rows.extend(G / size)
        offsets.extend(c / size)
        kinds.append(("block", body))
    M = np.array(rows)
    c = np.array(offsets)

    def project(v):
        out = v.copy()
        n_bounds = sum(1 for kind in kinds if kind[0] == "bound")
        out[:n_bounds] = np.maximum(out[:n_bounds], 0.0)
        for b_index in range(len(BLOCKS)):
            start = n_bounds + 6 * b_index
            out[start : start + 6] = _project_psd(out[start : start + 6])
        return out

    rho = np.trace(H) / len(variables)
    x = x0
    y = project(M @ x + c)
    u = np.zeros_like(y)
    factor = scipy.linalg.cho_factor(H + rho * M.T @ M)
    for iteration in range(max_iter):
        x = scipy.linalg.cho_solve(factor, q + rho * M.T @ (y - c - u))
        Mx = M @ x + c
        y_new = project(Mx + u)
        u += Mx - y_new
        primal = np.linalg.norm(Mx - y_new)
        dual = rho * np.linalg.norm(M.T @ (y_new - y))
        y = y_new
        if primal <= 1e-10 * max(float(np.linalg.norm(Mx)), 1.0) and dual <= 1e-10 * max(
            float(np.linalg.norm(q)), 1e-300
        ):
            break
        if iteration % 50 == 49 and (primal > 10 * dual or dual > 10 * primal):
            factor_change = 2.0 if primal > dual else 0.5
            rho *= factor_change
            u /= factor_change
            factor = scipy.linalg.cho_factor(H + rho * M.T @ M)
    theta = constant.copy()
    theta[variables] = x * scale
    # Exactly feasible: clip the bounds, and put each inertia on its cone.
    for k in BOUNDED:
        theta[k] = max(theta[k], 0.0)
    for block in BLOCKS.values():
        sigma = _SIGMA @ theta[block]
        projected = _project_psd(sigma)
        if np.linalg.norm(projected - sigma) > 0:
            inertia = np.trace(_matrix(projected)) * np.eye(3) - _matrix(projected)
            theta[block] = [inertia[a, b] for a, b in AXES.values()]
    return theta
