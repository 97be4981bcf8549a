"""The analytic per-chain plant: the inverse dynamics run forwards, on a machine with the intermediate chain's stack-up."""

import numpy as np
import pytest
from stations_synthetic import deviated

import hipsim
from hipsim.analytic.chain_dynamics import chain_forward_dynamics, chain_inverse_dynamics, chain_motion
from hipsim.analytic.stations import platform_attitude
from hipsim.control.chain_plant import ChainPlant
from hipsim.exceptions import ArgumentError

DRAWING = hipsim.load_parameters()
CHAINS = deviated(seed=3).replace(spline=np.array([1e-3, 2e-3, -1e-3]))


@pytest.mark.parametrize("control", [1, 2])
def test_inverse_then_forward_gives_the_accelerations_back(control):
    """τ from the inverse dynamics along the ISO cycle; the forward dynamics at (L, L̇, τ) return its L̈ to 1e-12."""
    machine = DRAWING.replace(geometry=CHAINS.replace(control=control), sjoint_viscous=0.02, ujoint_coulomb=0.05)
    cycle = hipsim.iso14242(rate=20)
    motion = chain_motion(machine, cycle)
    tau = chain_inverse_dynamics(machine, motion, cycle.Fe, lever_spin=True).total
    for k in (3, 11):
        Ldd = chain_forward_dynamics(machine, motion.L[k], motion.Ld[k], tau[k], cycle.Fe[k], cycle.q[k], True)
        assert np.abs(Ldd - motion.Ldd[k]).max() < 1e-12 * np.abs(motion.Ldd[k]).max()
    # Torques that are not the motion's give other accelerations: the check can fail.
    other = chain_forward_dynamics(machine, motion.L[3], motion.Ld[3], tau[3] + 0.1, cycle.Fe[3], cycle.q[3], True)
    assert np.abs(other - motion.Ldd[3]).max() > 1e-3


def test_the_plant_reads_both_platforms_as_the_stations_do():
    machine = DRAWING.replace(geometry=CHAINS.replace(control=1))
    desired = hipsim.iso14242(rate=100).slice(slice(7, 8))
    plant = ChainPlant(machine)
    x = plant.initial_state(desired)
    L, _, q, _ = plant.readings(x)
    assert q[0] == pytest.approx(desired.q[0], abs=1e-12)  # the controlled m_1 at the desired motion
    assert q[1] == pytest.approx(platform_attitude(machine, L[None], 2, q0=desired.q[0])[0], abs=1e-12)
    assert plant.angles(x)[0] == pytest.approx(desired.q[0], abs=1e-12)
    with pytest.raises(ArgumentError, match="per-chain"):
        ChainPlant(DRAWING)
