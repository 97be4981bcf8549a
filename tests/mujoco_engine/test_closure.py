"""The MuJoCo model's closed chain (hipsim/mujoco_engine/closure.py): its record refuses arrays of the wrong shape
naming the field, the LAPACK inverse is the inverse or None when singular. The chain closed along a trajectory:
mujoco_engine/test_trajectory.py.

Skipped when ``mujoco`` is not installed or too old (the ``test`` extra installs it).
"""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("mujoco")

from hipsim.exceptions import ArgumentError, MissingDependencyError

try:
    from hipsim.mujoco_engine.closure import MujocoKinematics, _inverse
except MissingDependencyError as error:  # installed, but a release the engine refuses
    pytest.skip(str(error), allow_module_level=True)


def _fields(n: int, nv: int) -> dict[str, np.ndarray]:
    return {
        "t": np.zeros(n),
        "q": np.zeros((n, nv)),
        "v": np.zeros((n, nv)),
        "a": np.zeros((n, nv)),
        "L": np.zeros((n, 2, 3)),
        "Ld": np.zeros((n, 2, 3)),
        "Ldd": np.zeros((n, 2, 3)),
        "cond_inv": np.zeros(n),
        "residual": np.zeros(n),
    }


def test_the_record_refuses_a_field_of_the_wrong_shape():
    MujocoKinematics(**_fields(2, 21))
    fields = _fields(2, 21)
    fields["v"] = np.zeros((2, 20))  # not the q's nv
    with pytest.raises(ArgumentError, match=r"^MujocoKinematics\.v"):
        MujocoKinematics(**fields)
    fields = _fields(2, 21)
    fields["residual"] = np.zeros(3)  # not one per sample
    with pytest.raises(ArgumentError, match=r"^MujocoKinematics\.residual"):
        MujocoKinematics(**fields)


def test_the_inverse_or_none_when_singular():
    A = np.array([[2.0, 1.0], [0.0, 4.0]])
    inverse = _inverse(A.copy())
    assert inverse is not None
    np.testing.assert_allclose(inverse, np.array([[0.5, -0.125], [0.0, 0.25]]), rtol=0, atol=1e-16)
    assert _inverse(np.array([[1.0, 2.0], [2.0, 4.0]])) is None
