"""The mjcf command's own words (hipsim.cli.mjcf): the closure gap line of a MuJoCo plant's run, its largest gap and
when, and the RMS; refusals of the time step and a folder. The model written: mujoco_engine/test_mujoco_engine.py."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

from hipsim.cli.mjcf import format_gaps, run
from hipsim.exceptions import HipsimError


def test_the_gap_line_names_the_largest_and_the_rms():
    plant = SimpleNamespace(gap_history=lambda: (np.array([0.0, 0.001, 0.002]), np.array([3e-6, 4e-6, 0.0])))
    # RMS √((9 + 16 + 0)/3)·1e-6 = 2.89e-6
    assert format_gaps("pd", plant) == (
        "pd: closure gap (MuJoCo's soft connect constraints) at the servo instants: "
        "largest 4.00e-06 m at t = 0.001 s, RMS 2.89e-06 m"
    )


@pytest.mark.parametrize("step", [0.0, -1.0, math.nan])
def test_the_time_step_must_be_positive(step, tmp_path):
    args = SimpleNamespace(params=None, overrides=[], timestep=step, out=str(tmp_path / "m.xml"), integrator="RK4")
    with pytest.raises(HipsimError, match="--timestep must be a positive number of ms"):
        run(args)
    assert not (tmp_path / "m.xml").exists()


def test_a_folder_is_no_file(tmp_path):
    args = SimpleNamespace(params=None, overrides=[], timestep=1.0, out=str(tmp_path), integrator="RK4")
    with pytest.raises(HipsimError, match="is a folder; give an .xml file name"):
        run(args)
