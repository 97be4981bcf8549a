"""hipsim.rig.identification.consistency: the fit under the physical-consistency constraints (bounds, rigid-body inertias)."""

import numpy as np
import scipy.optimize
from rig_synthetic import machines

from hipsim.rig.identification.consistency import _SIGMA, _matrix
from hipsim.rig.identification.consistency import consistent as _consistent
from hipsim.rig.identification.consistency import violations as _violations
from hipsim.rig.identification.quantities import BLOCKS as _BLOCKS
from hipsim.rig.identification.quantities import QUANTITIES, standard_values


def _problem(seed, n=len(QUANTITIES)):
    rng = np.random.default_rng(seed)
    A = rng.normal(size=(3 * n, n)) * np.array([q.nominal for q in QUANTITIES]) ** -1
    return rng, A


def test_bounds_alone_are_bounded_least_squares():
    start, _ = machines()
    prior = standard_values(start)
    nominal = np.array([abs(prior[k]) if prior[k] else q.nominal for k, q in enumerate(QUANTITIES)])
    rng, A = _problem(0)
    theta_true = prior.copy()
    theta_true[_BLOCKS["lever"][:3]] = [0.03, 0.03, 0.02]  # a lever well inside the rigid-body limits
    theta_true[[q.label for q in QUANTITIES].index("τ_c,screw")] = -0.01  # beyond its bound
    b = A @ theta_true + rng.normal(0, 1e-6, len(A))
    kept = list(range(len(QUANTITIES)))
    theta, active = _consistent(A, b, theta_true, kept, [], prior, nominal)
    assert "τ_c,screw ≥ 0" in active and not _violations(theta)
    lower = np.array(
        [
            0.0 if q.nonnegative and not any(k in block for block in _BLOCKS.values()) else -np.inf
            for k, q in enumerate(QUANTITIES)
        ]
    )
    reference = scipy.optimize.lsq_linear(A, b, bounds=(lower, np.inf), method="trf", tol=1e-14).x
    assert not _violations(reference)  # the bounds are all that is active
    np.testing.assert_allclose(theta, reference, rtol=1e-7, atol=1e-12 * nominal.max())


def test_an_impossible_inertia_is_brought_onto_the_rigid_body_limit():
    start, _ = machines()
    prior = standard_values(start)
    nominal = np.array([abs(prior[k]) if prior[k] else q.nominal for k, q in enumerate(QUANTITIES)])
    rng, A = _problem(1)
    wanted = prior.copy()
    lever = _BLOCKS["lever"]
    wanted[lever[0]] = wanted[lever[1]] + wanted[lever[2]] + 0.004  # I_xx beyond I_yy + I_zz: no rigid body
    b = A @ wanted
    kept = list(range(len(QUANTITIES)))
    theta, active = _consistent(A, b, wanted, kept, [], prior, nominal)
    assert not _violations(theta) and any("lever inertia" in text for text in active)
    assert np.linalg.eigvalsh(_matrix(_SIGMA @ theta[lever]))[0] >= -1e-15
    # Optimal: no feasible point nearby fits better (the problem is convex, so no feasible point at all).
    cost = np.sum((A @ theta - b) ** 2)
    for _ in range(200):
        trial = theta + rng.normal(size=theta.size) * nominal * 1e-3
        if not _violations(trial):
            assert np.sum((A @ trial - b) ** 2) >= cost * (1 - 1e-6)
