"""hipsim.rig.identification.consistency's conditions by hand: the bounds, the rigid-body (triangle) condition on
an inertia, and which constraints a solution sits on.

An inertia I is a rigid body's when Σ = ½·tr(I)·𝟙 − I ⪰ 0: for a diagonal I = diag(a, b, c), Σ = ½·diag(b + c − a,
a + c − b, a + b − c), so diag(1, 1, 3) breaks it (1 + 1 < 3) and diag(1, 1, 2) lies on its limit.
"""

from __future__ import annotations

import numpy as np
import pytest

import hipsim
from hipsim.rig.identification.consistency import (
    _SIGMA,
    PRIOR_SPREAD,
    _active,
    _matrix,
    _project_psd,
    _vector,
    consistent,
    violations,
)
from hipsim.rig.identification.quantities import BLOCKS, BOUNDED, QUANTITIES, standard_values

INDEX = {q.label: k for k, q in enumerate(QUANTITIES)}
NOMINAL = np.array([q.nominal for q in QUANTITIES])
#: The published machine, its friction coefficients of 0 (on their bounds) at their typical sizes.
THETA = standard_values(hipsim.load_parameters())
THETA = np.where((THETA == 0) & np.isin(np.arange(len(THETA)), BOUNDED), NOMINAL, THETA)
RIGID = "platform inertia of a rigid body (principal moments within the triangle inequalities)"
LIMIT = "platform inertia on the rigid-body limit (one principal moment equals the sum of the other two)"


def with_platform(diagonal, off=(0.0, 0.0, 0.0)):
    theta = THETA.copy()
    theta[BLOCKS["platform"]] = [*diagonal, *off]
    return theta


def test_the_constants():
    assert PRIOR_SPREAD == 0.1


def test_sigma_is_half_the_trace_less_the_inertia():
    inertia = np.array([[2.0, 0.3, -0.2], [0.3, 3.0, 0.1], [-0.2, 0.1, 4.0]])
    vector = [inertia[a, b] for a, b in ((0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2))]
    np.testing.assert_allclose(_matrix(_SIGMA @ vector), 0.5 * np.trace(inertia) * np.eye(3) - inertia, atol=1e-15)
    np.testing.assert_allclose(_vector(_matrix(_SIGMA @ vector)), _SIGMA @ vector, atol=1e-15)
    # The vector's length is the matrix's Frobenius norm.
    assert np.linalg.norm(_vector(inertia)) == pytest.approx(np.linalg.norm(inertia), rel=1e-15)


def test_the_projection_on_the_semidefinite_cone():
    np.testing.assert_allclose(_project_psd(_vector(np.diag([-1.0, 2.0, 3.0]))), _vector(np.diag([0.0, 2.0, 3.0])))
    psd = _vector(np.array([[2.0, 1.0, 0.0], [1.0, 2.0, 0.0], [0.0, 0.0, 1.0]]))
    np.testing.assert_allclose(_project_psd(psd), psd, atol=1e-15)


def test_violations_by_hand():
    assert violations(THETA) == []
    theta = THETA.copy()
    theta[INDEX["m_L"]], theta[INDEX["μ_t"]] = -1.0, -0.01
    assert violations(theta) == ["m_L ≥ 0", "μ_t ≥ 0"]
    # Products of inertia take any sign.
    assert violations(with_platform((1.0, 1.0, 1.0), (-0.1, 0.1, -0.1))) == []
    assert violations(with_platform((1.0, 1.0, 3.0))) == [RIGID]
    assert violations(with_platform((1.0, 1.0, 2.0))) == []  # on the limit
    # A tolerance relative to the largest principal moment: 1e-12 of it either side of the limit.
    assert violations(with_platform((1.0, 1.0, 2.0 + 1e-13))) == []
    assert violations(with_platform((1.0, 1.0, 2.0 + 1e-9))) == [RIGID]
    assert violations(with_platform((1.0, 1.0, 2.0 + 1e-9)), tolerance=1e-6) == []


def test_active_constraints_by_hand():
    movable = list(range(len(QUANTITIES)))
    assert _active(THETA, movable, NOMINAL) == ()
    theta = THETA.copy()
    theta[INDEX["m_L"]] = 1e-9 * NOMINAL[INDEX["m_L"]]  # at the bound (within 1e-9 of its size)
    theta[INDEX["m_l"]] = 2e-9 * NOMINAL[INDEX["m_l"]]  # just off it
    assert _active(theta, movable, NOMINAL) == ("m_L ≥ 0",)
    # A parameter that could not move is not said to sit on its bound.
    assert _active(theta, [k for k in movable if k != INDEX["m_L"]], NOMINAL) == ()
    assert _active(with_platform((1.0, 1.0, 2.0)), movable, NOMINAL) == (LIMIT,)
    assert _active(with_platform((1.0, 1.0, 2.0 - 1e-8)), movable, NOMINAL) == ()


def _problem(total, alone):
    """Rows m_L + m_l + 10·μ_h = total + 0.95 and m_l = alone (χ² units); m_L kept, m_l dependent with prior 1.43."""
    m_L, m_l, mu_h = INDEX["m_L"], INDEX["m_l"], INDEX["μ_h"]
    Aw = np.zeros((2, len(QUANTITIES)))
    Aw[0, [m_L, m_l, mu_h]] = 1.0, 1.0, 10.0
    Aw[1, m_l] = 1.0
    zw = np.array([total + 10 * THETA[mu_h], alone])
    prior = np.zeros(len(QUANTITIES))
    prior[m_l] = 1.43
    return consistent(Aw, zw, THETA, [m_L], [m_l], prior, NOMINAL)


def test_a_dependent_parameter_is_held_by_its_prior_of_a_tenth_of_its_size():
    # μ_h stays at its start (0.095: the first row's 0.95). m_L, free, closes the first row; m_l balances the second
    # row (m_l = 2) against its prior, 1.43 with a spread of 10 % of its size 1.5: weight w = (1/0.1)²/1.5² = 44.4,
    # m_l = (2 + 1.43·w)/(1 + w).
    w = 100 / 1.5**2
    m_l = (2 + 1.43 * w) / (1 + w)
    theta, active = _problem(5.0, 2.0)
    assert theta[INDEX["m_l"]] == pytest.approx(m_l, rel=1e-9)
    assert theta[INDEX["m_L"]] == pytest.approx(5.0 - m_l, rel=1e-9)
    assert theta[INDEX["μ_h"]] == THETA[INDEX["μ_h"]] and active == ()


def test_a_kept_parameter_on_its_bound():
    # The first row now wants m_L + m_l = 1 with m_l near 1.43: m_L goes to its bound 0, and m_l balances three
    # terms: (m_l − 1)² + (m_l − 1.43)² + w·(m_l − 1.43)².
    w = 100 / 1.5**2
    theta, active = _problem(1.0, 1.43)
    assert theta[INDEX["m_L"]] == 0.0
    assert theta[INDEX["m_l"]] == pytest.approx((1 + (1 + w) * 1.43) / (2 + w), rel=1e-9)
    assert active == ("m_L ≥ 0",)


def test_the_tolerances_scale_with_the_inertia():
    # Σ of diag(a, a, 2a + δ) has principal values −δ/2, a, a: a violation beyond 1e-12 of the largest, |Σ| (a), and
    # at least 1e-300.
    assert violations(with_platform((10.0, 10.0, 20.0 + 1e-11))) == []  # 5e-12 within 1e-11
    assert violations(with_platform((0.1, 0.1, 0.2 + 1e-12))) == [RIGID]  # 5e-13 beyond 1e-13
    # On the limit within 1e-9 of the largest principal value of Σ: diag(10, 12, 22 − ε) has 0.5·ε, 10 − 0.5·ε and
    # 12 − 0.5·ε; ε/2 = 1.1e-8 is within 1.2e-8 (not 1e-8).
    assert _active(with_platform((10.0, 12.0, 22.0 - 2.2e-8)), [], NOMINAL) == (LIMIT,)
    assert _active(with_platform((10.0, 10.0, 20.0 - 1e-8)), [], NOMINAL) == (LIMIT,)  # 5e-9 within 1e-8


def test_an_impossible_inertia_and_a_bound_together_by_hand():
    # Rows: I_xx = 1, I_yy = 1, I_zz + m_L = 3, m_L = −1, the products of inertia 0 (kg·m², kg; χ² units). Free,
    # m_L = −1 and I = diag(1, 1, 4), which no rigid body has. Under m_L ≥ 0 and Σ ⪰ 0 (for a diagonal I, the
    # triangle inequalities): m_L = 0 (its gradient there is 2(c − 3) + 2 = 4/3 > 0 at the solution), and
    # diag(1, 1, 3) projected onto a + b ≥ c along (1, 1, −1) by 1/3: diag(4/3, 4/3, 8/3), on the limit.
    block, m_L = BLOCKS["platform"], INDEX["m_L"]
    Aw = np.zeros((7, len(QUANTITIES)))
    for row, k in enumerate(block):
        Aw[row, k] = 1.0
    Aw[2, m_L] = 1.0
    Aw[6, m_L] = 1.0
    zw = np.array([1.0, 1.0, 3.0, 0.0, 0.0, 0.0, -1.0])
    theta, active = consistent(Aw, zw, THETA, [*block, m_L], [], np.zeros(len(QUANTITIES)), NOMINAL)
    np.testing.assert_allclose(theta[block], [4 / 3, 4 / 3, 8 / 3, 0.0, 0.0, 0.0], atol=1e-7)
    assert theta[m_L] == 0.0
    assert active == ("m_L ≥ 0", LIMIT)
    others = [k for k in range(len(QUANTITIES)) if k not in (*block, m_L)]
    np.testing.assert_array_equal(theta[others], THETA[others])
