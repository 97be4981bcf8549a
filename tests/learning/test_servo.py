"""The simulated cycle runners' reference (hipsim.learning.servo.reference_motion): the motion a command gives the
model's controlled platform. The runners themselves run whole servo loops: tests/cli/test_learn.py runs them through
``hipsim simulate --learn``."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from stations_synthetic import deviated

from hipsim.learning import LearningLaw
from hipsim.learning.servo import reference_motion
from hipsim.learning.step import first_command
from hipsim.machine.parameters import load_parameters
from hipsim.motion.trajectories import iso14242


@pytest.fixture(scope="module")
def desired():
    return iso14242(rate=100.0)


def test_the_models_own_command_gives_back_the_desired_motion_and_its_derivatives(desired):
    model = load_parameters()
    reference = reference_motion(model, first_command(model, desired, LearningLaw("2")), desired.Fe, 1.0)
    assert reference.periodic and reference.name == "learned reference"
    assert np.array_equal(reference.Fe, desired.Fe) and np.array_equal(reference.t, desired.t)
    assert reference.q == pytest.approx(desired.q, abs=1e-10)
    # the carriages' periodic derivatives through the model's Jacobians: the gait's own rates and accelerations
    assert reference.qd == pytest.approx(desired.qd, abs=1e-9 * np.abs(desired.qd).max())
    assert reference.qdd == pytest.approx(desired.qdd, abs=1e-8 * np.abs(desired.qdd).max())


def test_the_reference_is_the_platform_the_models_geometry_controls(desired):
    drawing = load_parameters()
    geometry = deviated(seed=3, size_mm=0.3)
    on_1 = drawing.replace(geometry=dataclasses.replace(geometry, control=1))
    command = first_command(on_1, desired, LearningLaw("1"))  # exact for platform 1 only
    assert reference_motion(on_1, command, desired.Fe, 1.0).q == pytest.approx(desired.q, abs=1e-9)
    on_2 = drawing.replace(geometry=dataclasses.replace(geometry, control=2))
    other = reference_motion(on_2, command, desired.Fe, 1.0).q  # the same carriages move platform 2 elsewhere
    assert np.abs(other - desired.q).max() > 1e-4
