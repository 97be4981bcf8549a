"""hipsim.physics.vectors against NumPy's own vector algebra, on tuples and on components-first arrays."""

import numpy as np

from hipsim.physics import vectors

RNG = np.random.default_rng(3)


def test_tuple_algebra_on_floats():
    a, b, s = tuple(RNG.normal(size=3)), tuple(RNG.normal(size=3)), 0.7
    np.testing.assert_allclose(vectors.add(a, b), np.add(a, b), rtol=1e-15)
    np.testing.assert_allclose(vectors.sub(a, b), np.subtract(a, b), rtol=1e-15)
    np.testing.assert_allclose(vectors.scale(a, s), np.multiply(a, s), rtol=1e-15)
    assert abs(vectors.dot(a, b) - np.dot(a, b)) < 1e-15
    np.testing.assert_allclose(vectors.cross(a, b), np.cross(a, b), rtol=1e-15, atol=1e-15)
    M = RNG.normal(size=(3, 3))
    rows = tuple(tuple(row) for row in M)
    np.testing.assert_allclose(vectors.matvec(rows, a), M @ a, rtol=1e-14)
    np.testing.assert_allclose(vectors.transpose_times(rows, a), M.T @ a, rtol=1e-14)
    assert isinstance(vectors.cross(a, b), tuple)  # values, as the compiled kernels want them


def test_components_first_arrays_broadcast_per_sample_against_per_leg():
    per_sample = RNG.normal(size=(3, 50))  # a vector per sample
    per_leg = RNG.normal(size=(3, 4, 50))  # a vector per leg and sample
    expected = np.cross(per_sample.T[:, None], per_leg.transpose(2, 1, 0))  # (N, leg, xyz)
    got = vectors.cross_array(per_sample[:, None], per_leg)
    np.testing.assert_allclose(got.transpose(2, 1, 0), expected, rtol=1e-14, atol=1e-15)
    np.testing.assert_allclose(vectors.stack(vectors.cross(per_sample[:, None], per_leg)), got, rtol=0, atol=0)
    np.testing.assert_allclose(vectors.dot(per_sample[:, None], per_leg), np.einsum("an,aln->ln", per_sample, per_leg))


def test_per_leg_and_stack():
    rows = np.arange(9.0).reshape(3, 3)  # leg i's vector in row i
    out = vectors.per_leg(rows)
    assert out.shape == (3, 3, 1)
    np.testing.assert_array_equal(out[:, 1, 0], rows[1])
    stacked = vectors.stack((np.ones(4), 2.0, np.arange(4.0)))  # components broadcast
    assert stacked.shape == (3, 4)
    np.testing.assert_array_equal(stacked[1], 2.0)
