"""hipsim.wear.points by hand: the cup grid's cells and areas, the unit and cup checks at their tolerance, tangents."""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

from hipsim.exceptions import ArgumentError
from hipsim.wear.points import UNIT_TOLERANCE, cup_grid, cup_points, tangent_basis


def test_a_two_by_four_grid_by_hand():
    grid = cup_grid(2, 4, radius_mm=14.0)
    assert grid.shape == (2, 4) and len(grid) == 8
    assert grid.theta is not None and grid.phi is not None and grid.area_mm2 is not None
    assert_allclose(grid.theta, [math.pi / 8, 3 * math.pi / 8])  # cell centres of [0°, 90°] in two bands
    assert_allclose(grid.phi, [math.pi / 4, 3 * math.pi / 4, 5 * math.pi / 4, 7 * math.pi / 4])
    s, c = math.sin(math.pi / 8), math.cos(math.pi / 8)
    r = math.sqrt(0.5)
    assert_allclose(grid.w[0], [s * r, s * r, c])  # θ first: row 0 is (θ₀, φ₀)
    assert_allclose(grid.w[4], [c * r, c * r, s])  # row 4 is (θ₁, φ₀)
    # Each cell r²·sinθ·dθ·dφ with dθ·dφ = (π/4)(π/2) = 1.23370: 196·0.38268·1.23370 and 196·0.92388·1.23370 mm².
    assert_allclose(grid.area_mm2[:4], 92.535, rtol=1e-4)
    assert_allclose(grid.area_mm2[4:], 223.40, rtol=1e-4)


def test_a_fine_grids_area_is_the_hemisphere():
    grid = cup_grid()  # the defaults: 90 × 180 cells of a 28 mm head
    assert grid.shape == (90, 180) and grid.area_mm2 is not None
    assert_allclose(grid.area_mm2.sum(), 2 * math.pi * 14.0**2, rtol=1e-4)  # midpoint rule: error ~ dθ²/24


@pytest.mark.parametrize("n_theta", [0, 1001, 2.0, True])
def test_grid_sizes_outside_one_to_the_most_are_refused(n_theta):
    with pytest.raises(ArgumentError, match="n_theta: expected a whole number of cells from 1 to 1000"):
        cup_grid(n_theta, 4)


def test_points_within_the_unit_tolerance_are_normalised():
    near = 1 + 0.9 * UNIT_TOLERANCE
    points = cup_points(np.array([[0.0, 0.0, near], [near, 0.0, 0.0], [0.0, 0.6, 0.8]]))
    assert_allclose(points.w, np.array([[0, 0, 1], [1, 0, 0], [0, 0.6, 0.8]]), rtol=1e-15)
    assert points.area_mm2 is None and points.shape is None


def test_points_off_the_sphere_or_below_the_cup_name_their_row():
    with pytest.raises(ArgumentError, match=r"points, row 2: .*\|w\| = 1\.0011"):
        cup_points(np.array([[0.0, 0.0, 1.0], [0.0, 0.0, 1 + 1.1 * UNIT_TOLERANCE]]))
    below = math.sqrt(1 - 0.0011**2)
    with pytest.raises(ArgumentError, match=r"cup\.csv, row 1: .*z ≥ 0"):
        cup_points(np.array([[below, 0.0, -0.0011]]), source="cup.csv")
    cup_points(np.array([[math.sqrt(1 - 0.0009**2), 0.0, -0.0009]]))  # just inside the tolerance: the rim
    with pytest.raises(ArgumentError, match="row 1: expected finite"):
        cup_points(np.array([[math.nan, 0.0, 1.0]]))


def test_each_points_tangent_is_from_its_own_least_axis():
    """w = z: |w| least along x (the first of a tie), t1 = x; w = x: least along y, t1 = y; t2 = w × t1."""
    t1, t2 = tangent_basis(np.array([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0]]))
    assert t1.tolist() == [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]
    assert t2.tolist() == [[0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]


def test_tangents_are_orthonormal_and_right_handed():
    w = np.array([[0.0, 0.0, 1.0], [0.6, 0.0, 0.8], [0.48, 0.6, 0.64]])
    t1, t2 = tangent_basis(w)
    assert_allclose(np.einsum("ij,ij->i", t1, w), 0.0, atol=1e-15)
    assert_allclose(np.linalg.norm(t1, axis=1), 1.0)
    assert_allclose(np.cross(t1, t2), w, atol=1e-15)
    assert_allclose(t1[0], [1.0, 0.0, 0.0])  # at the pole, from x (the first axis least along w)


@pytest.mark.parametrize("xyz", [np.array([0.0, 0.0, 1.0]), np.zeros((2, 2)), np.zeros((0, 3)), np.zeros((1, 4))])
def test_points_not_as_rows_of_three_are_refused(xyz):
    with pytest.raises(
        ArgumentError, match=rf"^cup\.csv: expected points as rows of x, y, z, got shape \({xyz.shape[0]}"
    ):
        cup_points(xyz, source="cup.csv")


def test_each_refusal_shows_the_row_as_given():
    """The offending row's x, y, z as given; a NaN in the second row (the first is fine) names row 2."""
    with pytest.raises(ArgumentError, match=r"^points, row 2: expected finite x, y, z, got \(0\.0, nan, 1\.0\)$"):
        cup_points(np.array([[0.0, 0.0, 1.0], [0.0, math.nan, 1.0]]))
    with pytest.raises(
        ArgumentError, match=r"^points, row 1: expected a point on the unit sphere .*got \(0\.0, 0\.0, 2\.0\)$"
    ):
        cup_points(np.array([[0.0, 0.0, 2.0]]))
    with pytest.raises(
        ArgumentError, match=r"^points, row 1: expected a point of the cup \(z ≥ 0\), got \(0\.0, 0\.6, -0\.8\)$"
    ):
        cup_points(np.array([[0.0, 0.6, -0.8]]))


def test_the_unit_and_cup_tolerances_are_inclusive():
    """|w| = 1 ± 1e-3 and z = −1e-3 exactly are still taken (binary fractions, so the bounds are exact)."""
    on = 1.0 + 2.0**-10  # within 1e-3 (0.000977)
    assert cup_points(np.array([[0.0, 0.0, on]])).w.tolist() == [[0.0, 0.0, 1.0]]
    z = -(2.0**-10)
    cup_points(np.array([[math.sqrt(1 - z * z), 0.0, z]]))
    assert UNIT_TOLERANCE == 1e-3
    edge = np.array([[0.999999499999875, 0.0, -1e-3]])  # |w| = 1 exactly in floats: z is −1e-3 itself
    assert np.linalg.norm(edge) == 1.0 and cup_points(edge).w[0, 2] == -1e-3


def test_grids_of_one_and_of_the_most_cells_are_taken_and_n_phi_is_named():
    one = cup_grid(1, 1, radius_mm=1.0)
    assert one.shape == (1, 1) and one.w.shape == (1, 3) and one.area_mm2 is not None
    assert one.area_mm2[0] == pytest.approx(math.sin(math.pi / 4) * (math.pi / 2) * 2 * math.pi)
    assert cup_grid(1000, 1, radius_mm=1.0).shape == (1000, 1)
    with pytest.raises(ArgumentError, match=r"^n_phi: expected a whole number of cells from 1 to 2000, got 2001$"):
        cup_grid(1, 2001)
    with pytest.raises(ArgumentError, match=r"^n_theta: expected a whole number of cells from 1 to 1000, got 0$"):
        cup_grid(0, 1)
