"""hipsim.analysis.runs.analyse: the published machine on one ISO 14242-1 cycle at 1 kHz by default, each model by
name (the analytic model with the levers' spin and Pinocchio's closed chain agree to round-off), an unknown one refused."""

from __future__ import annotations

import numpy as np
import pytest

import hipsim
from hipsim.analysis.runs import MODELS, analyse
from hipsim.exceptions import ArgumentError
from hipsim.machine.parameters import file_values


def test_the_defaults_are_the_published_machine_on_one_iso_cycle():
    run = analyse()
    assert run.model == "analytic" and run.t.shape == (1000,)  # 1 s at 1 kHz, the closing sample left out
    assert np.array_equal(run.trajectory.q, hipsim.iso14242().q)
    assert file_values(run.params) == file_values(hipsim.load_parameters())


def test_two_models_of_one_physics_agree_to_round_off():
    motion = hipsim.iso14242(rate=50)
    analytic = analyse(None, motion, "analytic", lever_spin=True)
    closed = analyse(None, motion, "pinocchio")
    assert analytic.trajectory is motion and closed.model == "pinocchio"
    np.testing.assert_allclose(analytic.L, closed.L, rtol=0, atol=1e-12)  # [m]
    np.testing.assert_allclose(analytic.torques.total, closed.torques.total, rtol=0, atol=1e-12)  # [N·m], peak 0.43
    # Without the levers' spin the analytic model leaves out a term of order 1e-6 N·m: the flag reaches the model.
    spinless = analyse(None, motion, "analytic")
    assert 1e-8 < np.abs(spinless.torques.total - closed.torques.total).max() < 1e-5


def test_an_unknown_model_is_refused_naming_the_models():
    assert MODELS == ("analytic", "pinocchio", "mujoco")
    with pytest.raises(ArgumentError, match="model: expected one of analytic, pinocchio, mujoco, got 'bogus'"):
        analyse(model="bogus")
