"""The built machine's compiled loop compiles once: numba compiles anew for each memory layout and read-only flag of
an argument, and each signature of the loop is seconds of CPU (hipsim.control.machine_loop copies its inputs)."""

from __future__ import annotations

import numpy as np

import hipsim
from hipsim.closed_chain.plant import PinocchioPlant
from hipsim.control import machine_kernel
from hipsim.control.feedback import SensorFeedback
from hipsim.control.machine_loop import ModelPD, controlled_machine, model_feedforward, run_machine
from hipsim.machine.chains import ChainGeometry
from hipsim.motion.trajectories import iso14242_at


def test_either_platform_with_or_without_a_feedforward_runs_on_one_compiled_loop():
    model = hipsim.load_parameters()
    built = model.replace(geometry=ChainGeometry.zeros().replace(lever=np.full((2, 3), 0.2e-3)))
    duration = 0.003  # three servo periods: the loop's types, not its numbers, are the point

    def run(control: int, feedforward: np.ndarray | None) -> None:
        plant = PinocchioPlant(controlled_machine(built, control))
        run_machine(plant, ModelPD(model, control), SensorFeedback(control, noise=0.0), iso14242_at, duration,
                    feedforward=feedforward)  # fmt: skip

    given = model_feedforward(model, 2, iso14242_at, 1000.0, duration)
    assert not given.flags.writeable or not given.flags.c_contiguous  # a layout of its own, unlike zeros
    run(2, given)
    compiled = len(machine_kernel.machine_loop.signatures)
    run(2, None)
    run(1, model_feedforward(model, 1, iso14242_at, 1000.0, duration))  # platform 1: the parameters' read-only seat
    assert len(machine_kernel.machine_loop.signatures) == compiled >= 1
