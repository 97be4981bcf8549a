"""hipsim.closed_chain.block_inverse: a block lower triangular inverse by hand and as M·X = I (3×3 blocks in closed
form, others by Gauss–Jordan with pivoting), singular blocks refused as LAPACK refuses them, Cramer's rule by hand."""

from __future__ import annotations

import numpy as np
import pytest
from numpy.testing import assert_allclose

from hipsim.closed_chain.block_inverse import block_lower_inverse, cramer


def test_two_scalar_blocks_by_hand():
    # X₁₁ = 1/2, X₂₂ = 1/4, X₂₁ = −D₂⁻¹·M₂₁·X₁₁ = −(1/4)·3·(1/2) = −3/8.
    X = block_lower_inverse(np.array([[2.0, 0.0], [3.0, 4.0]]), np.array([0, 1, 2]))
    assert_allclose(X, [[0.5, 0.0], [-0.375, 0.25]], rtol=1e-15)


def test_a_three_and_a_two_block_matrix_times_its_inverse_is_the_identity():
    M = np.zeros((5, 5))
    M[:3, :3] = [[4.0, 1.0, 0.5], [0.0, 3.0, 1.0], [2.0, 0.0, 5.0]]  # closed form
    M[3:, 3:] = [[0.0, 2.0], [1.0, 1.0]]  # Gauss–Jordan: a zero first pivot, rows swapped
    M[3:, :3] = [[1.0, 0.0, -2.0], [0.0, 0.0, 0.0]]  # a coupling row and a zero one (skipped)
    X = block_lower_inverse(M, np.array([0, 3, 5]))
    assert_allclose(M @ X, np.eye(5), atol=1e-14)
    assert_allclose(X[:3, 3:], 0.0, atol=0.0)  # block lower triangular, like M
    assert_allclose(X[3:, 3:], [[-0.5, 1.0], [0.5, 0.0]], rtol=1e-15)  # [[0, 2], [1, 1]]⁻¹ by hand


@pytest.mark.parametrize(
    ("block", "starts"),
    [
        (np.array([[1.0, 2.0, 3.0], [2.0, 4.0, 6.0], [0.0, 1.0, 1.0]]), np.array([0, 3])),  # 3×3, rank 2
        (np.array([[1.0, 2.0], [2.0, 4.0]]), np.array([0, 2])),  # 2×2, rank 1
    ],
)
def test_a_singular_block_is_refused(block, starts):
    with pytest.raises(np.linalg.LinAlgError):
        block_lower_inverse(block, starts)


def test_cramers_rule_by_hand():
    # x + y = 3, y + z = 5, x + z = 4: x = 1, y = 2, z = 3.
    x = cramer(((1.0, 1.0, 0.0), (0.0, 1.0, 1.0), (1.0, 0.0, 1.0)), (3.0, 5.0, 4.0))
    assert_allclose(x, (1.0, 2.0, 3.0), rtol=1e-15)
    rows = ((2.0, -1.0, 0.0), (-1.0, 2.0, -1.0), (0.0, -1.0, 2.0))
    b = (1.0, 0.0, 1.0)
    assert_allclose(np.array(rows) @ np.array(cramer(rows, b)), b, rtol=1e-15)
