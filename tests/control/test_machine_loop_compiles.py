"""The built machine's compiled loop compiles once for either controlled platform: numba compiles anew for each
read-only flag of an argument, and m_1's stack-up seat comes read-only from the parameters, m_2's as zeros
(chain_kernel.model_arrays copies it). The feed-forward's layouts: test_machine_loop_laws.py."""

from __future__ import annotations

import os

import numpy as np
import pytest

import hipsim
from hipsim.closed_chain.plant import PinocchioPlant
from hipsim.control import machine_kernel
from hipsim.control.feedback import SensorFeedback
from hipsim.control.machine_loop import ModelPD, controlled_machine, run_machine
from hipsim.machine.chains import ChainGeometry
from hipsim.motion.trajectories import iso14242_at


@pytest.mark.skipif(os.environ.get("NUMBA_DISABLE_JIT") == "1", reason="counts numba's compiled signatures")
def test_either_controlled_platform_runs_on_one_compiled_loop():
    model = hipsim.load_parameters()
    built = model.replace(geometry=ChainGeometry.zeros().replace(lever=np.full((2, 3), 0.2e-3)))
    compiled = []  # the count after each run (other tests in this process may have compiled other plants)
    for control in (2, 1):
        plant = PinocchioPlant(controlled_machine(built, control))
        run_machine(plant, ModelPD(model, control), SensorFeedback(control, noise=0.0), iso14242_at, 0.003)
        compiled.append(len(machine_kernel.machine_loop.signatures))
    assert compiled[1] == compiled[0] >= 1, machine_kernel.machine_loop.signatures
