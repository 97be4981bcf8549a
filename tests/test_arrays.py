"""hipsim.arrays by hand: read-only copies that keep integer and boolean types, shape checks naming class and field."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pytest

from hipsim.arrays import check_shapes, readonly
from hipsim.exceptions import ArgumentError


def test_a_readonly_copy_leaves_the_callers_array_alone():
    mine = np.zeros(2)
    frozen = readonly(mine)
    with pytest.raises(ValueError, match="read-only"):
        frozen[0] = 1.0
    mine[0] = 5.0  # still writable, and not shared
    assert frozen[0] == 0.0


def test_integers_and_booleans_keep_their_type_others_become_floats():
    assert readonly([1, 2]).dtype.kind == "i"
    assert readonly([True, False]).dtype.kind == "b"
    assert readonly(np.array([3], dtype=np.uint8)).dtype.kind == "u"
    assert readonly([1.5, 2]).dtype == float
    assert readonly(np.array(["1.5"], dtype=object)).dtype == float


@dataclass(frozen=True)
class Samples:
    t: np.ndarray
    x: np.ndarray

    def __post_init__(self):
        check_shapes(self, {"t": ("N",), "x": ("N", 3)})


def test_shapes_are_checked_against_the_first_fields_count():
    ok = Samples(np.array([0.0, 0.1, 0.2]), np.zeros((3, 3)))
    assert ok.t.shape == (3,) and not ok.x.flags.writeable and not ok.t.flags.writeable
    with pytest.raises(ArgumentError, match=r"^Samples\.x: expected shape \(3, 3\), got shape \(2, 3\)$"):
        Samples(np.array([0.0, 0.1, 0.2]), np.zeros((2, 3)))
    with pytest.raises(ArgumentError, match=r"Samples\.x: expected shape \(3, 3\), got shape \(3, 2\)"):
        Samples(np.array([0.0, 0.1, 0.2]), np.zeros((3, 2)))


def test_a_given_count_overrides_the_first_field():
    sample = Samples(np.array([0.0, 0.1]), np.zeros((2, 3)))
    with pytest.raises(ArgumentError, match=r"Samples\.t: expected shape \(4,\)"):
        check_shapes(sample, {"t": ("N",)}, samples=4)
