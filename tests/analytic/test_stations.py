"""The stations' carriages and motion (hipsim.analytic.stations): the motion's rates are the carriages' time
derivatives, and a platform other than 1 or 2 or angles of another shape are refused naming them. The per-chain and
stacked machines: analytic/test_chain_dynamics.py, machine/test_chains.py."""

import numpy as np
import pytest
from support import central_difference

import hipsim
from hipsim.analytic.stations import carriages_for_platform, platform_jacobian, platform_motion
from hipsim.exceptions import ArgumentError
from hipsim.motion.trajectories import iso14242_at


@pytest.mark.parametrize("platform", [1, 2])
def test_the_motions_rates_are_the_carriages_derivatives(platform):
    params = hipsim.load_parameters()
    t, h = np.array([0.1, 0.45]), 1e-5
    traj = iso14242_at(t)
    L, Ld, Ldd = platform_motion(params, traj.q, traj.qd, traj.qdd, platform)
    carriages = lambda s: carriages_for_platform(params, iso14242_at(s).q, platform)
    np.testing.assert_allclose(L, carriages(t), rtol=0, atol=1e-12)
    np.testing.assert_allclose(Ld, central_difference(carriages, t, h), rtol=0, atol=1e-8)

    def rates(s):
        m = iso14242_at(s)
        return platform_motion(params, m.q, m.qd, m.qdd, platform)[1]

    np.testing.assert_allclose(Ldd, central_difference(rates, t, h), rtol=0, atol=1e-6)
    assert np.abs(Ld).max() > 1e-3  # m/s: not a comparison of zeros


def test_a_bad_platform_or_angles_are_refused():
    params = hipsim.load_parameters()
    q = np.zeros((2, 3))
    for platform in (0, 3, True):
        with pytest.raises(ArgumentError, match=r"^platform: expected 1 \(m_1\) or 2 \(m_2\)"):
            carriages_for_platform(params, q, platform)
    with pytest.raises(ArgumentError, match=r"^q: expected an array of shape \(N, 3\)"):
        platform_jacobian(params, np.zeros(3), 1)
