"""The compiled plant's generalised forces (hipsim.closed_chain.plant_step.generalised_forces) by hand on a small
state: the motors' push less the guides' and screws' viscous friction on the sliders, nothing on a frictionless
platform, the load on a lifted slot. The compiled RK4 against the other routes: closed_chain/test_plant.py."""

import math

import numpy as np

import hipsim
from hipsim.closed_chain.plant_step import generalised_forces
from hipsim.physics import laws

NV = 9  # one platform's three angles, three sliders, three more joints


def test_generalised_forces_by_hand():
    rough = {"hip_mu": 0.0, "thrust_mu": 0.0, "guide_coulomb": 0.0, "screw_coulomb": 0.0}
    params = hipsim.load_parameters().replace(**rough, guide_viscous=50.0, screw_viscous=1e-4)
    friction = laws.friction_record(params.friction)
    gain = 2 * math.pi / 0.004
    x = np.zeros(2 * NV)
    x[:3], x[NV : NV + 3] = [0.1, -0.2, 0.3], [0.5, 0.4, -0.3]  # the platform turns: no friction there
    x[NV + 3 : NV + 6] = [0.01, -0.02, 0.0]  # slider rates [m/s]
    platforms = np.array([[0, 1, 2, NV, NV + 1, NV + 2]])
    sliders = np.array([[3, NV + 3], [4, NV + 4], [5, NV + 5]])
    tau = np.array([0.2, -0.1, 0.05])
    buf = np.full(NV, 7.0)
    generalised_forces(buf, x, tau, 2000.0, friction, 300.0, gain, platforms, sliders, np.zeros(0, dtype=np.int64))
    rates = x[NV + 3 : NV + 6]
    expected = gain * tau - (2 * 50.0 * rates + gain * 1e-4 * gain * rates)
    np.testing.assert_allclose(buf[3:6], expected, rtol=1e-14)
    np.testing.assert_array_equal(buf[:3], 0.0)
    np.testing.assert_array_equal(buf[6:], 7.0)  # the other joints' entries are left alone
    generalised_forces(buf, x, tau, 2000.0, friction, 300.0, gain, platforms, sliders, np.array([7]))
    assert buf[7] == -2000.0 and buf[8] == 7.0
