"""The one column-scaled condition number (hipsim.rig.identification.regressor.column_condition), by hand."""

from __future__ import annotations

import math

import numpy as np
import pytest

from hipsim.rig.identification.regressor import column_condition


def test_the_condition_number_of_unit_columns_by_hand():
    # Columns u = (1, 0) and v = (3/5, 4/5) after scaling: AᵀA = [[1, 3/5], [3/5, 1]], eigenvalues 1 ± 3/5,
    # singular values √1.6 and √0.4, condition number √(1.6/0.4) = 2. Scaling a column first changes nothing.
    A = np.array([[1.0, 3.0], [0.0, 4.0]])
    assert column_condition(A) == pytest.approx(2.0, rel=1e-14)
    assert column_condition(A * np.array([1e-3, 1e4])) == pytest.approx(2.0, rel=1e-12)
    assert column_condition(np.eye(3)) == pytest.approx(1.0, rel=1e-15)


def test_what_cannot_be_told_apart_is_infinite_or_near_it():
    assert column_condition(np.array([[1.0, 0.0], [2.0, 0.0]])) == math.inf  # a zero column
    # Dependent columns: σ_min is round-off (4e-17 here), so the number is ~1e16 rather than infinite.
    assert column_condition(np.array([[1.0, 2.0], [2.0, 4.0]])) > 1e15
    assert column_condition(np.zeros((0, 2))) == math.inf  # no rows
