"""The tree's friction forces (hipsim.closed_chain.friction): viscous friction is linear in the velocities and
dissipates, friction off is zero, velocities of the wrong shape are refused naming them. Against the inverse
dynamics' and the plant's use of the law: closed_chain/test_plant.py."""

import numpy as np
import pinocchio as pin
import pytest

import hipsim
from hipsim.closed_chain.build import load_model
from hipsim.closed_chain.friction import friction_forces
from hipsim.exceptions import ArgumentError

#: Only viscous terms: the slider guides' and the spherical joints' (the numpy path with the levers' Jacobians).
VISCOUS = {"hip_mu": 0.0, "thrust_mu": 0.0, "guide_viscous": 50.0, "sjoint_viscous": 0.05}


@pytest.fixture(scope="module")
def chain():
    return load_model(hipsim.load_parameters().replace(**VISCOUS))


def test_viscous_friction_is_linear_and_dissipates(chain):
    q = pin.neutral(chain.model)
    v = np.random.default_rng(5).normal(0.0, 0.3, chain.model.nv)
    Q = friction_forces(chain, q, v, 1000.0)
    np.testing.assert_allclose(friction_forces(chain, q, 2 * v, 1000.0), 2 * Q, rtol=1e-13, atol=1e-15)
    assert v @ Q > 0  # the actuators supply what friction takes
    assert np.abs(Q[chain.actuated_v]).max() > 0  # the guides act on the sliders
    none = chain.params.replace(guide_viscous=0.0, sjoint_viscous=0.0)
    assert not np.any(friction_forces(load_model(none), q, v, 1000.0))


def test_velocities_of_the_wrong_shape_are_refused(chain):
    q = pin.neutral(chain.model)
    with pytest.raises(ArgumentError, match=r"^v: expected velocities of shape \(1, 21\), got shape \(1, 22\)"):
        friction_forces(chain, q, np.zeros(chain.model.nv + 1), 1000.0)
