"""Tests of hipsim.motion.readers: any trajectory file read by its suffix, and the README's worked examples."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from trajectory_files import assert_same_trajectory, canonical, iso_rows

from hipsim import TrajectoryError
from hipsim.motion.csv_table import load_trajectory_csv
from hipsim.motion.readers import read_trajectory
from hipsim.motion.trajectories import iso14242_angles, iso14242_load


def test_read_trajectory_chooses_the_reader_by_suffix(tmp_path):
    t, deg, load = iso_rows(20)
    path = canonical(tmp_path / "x.csv", t, deg, load)
    assert_same_trajectory(read_trajectory(path), load_trajectory_csv(path))
    with pytest.raises(TrajectoryError, match="the side \\(left or right hip\\) applies to OpenSim .mot/.sto files"):
        read_trajectory(path, side="left")


# --------------------------------------------------------------------------- the README's worked examples


EXAMPLES = Path(__file__).resolve().parents[2] / "docs" / "examples"


README_MAPPING = "time=Cycle [%]:%,flexion=Hip Flexion [deg],adduction=Hip Adduction [deg],rotation=Hip Int. Rotation [deg],load=F res [%BW]"


def test_the_readme_lab_export_is_the_built_in_cycle():
    path = EXAMPLES / "gait_lab_export.csv"
    traj = load_trajectory_csv(path, columns=README_MAPPING, period=1.0, body_weight=75 * 9.80665)
    assert traj.periodic and len(traj) == 50 and traj.t[1] == pytest.approx(0.02)
    q, _, _ = iso14242_angles(traj.t)
    assert np.abs(traj.q - q).max() <= 1e-7  # six decimals of a degree
    np.testing.assert_allclose(traj.Fe, iso14242_load(traj.t), rtol=0, atol=1e-3)  # four decimals of % body weight
    with pytest.raises(TrajectoryError) as info:  # read without a mapping: the error suggests the README's
        load_trajectory_csv(path)
    assert f"e.g. {README_MAPPING}:%BW" in str(info.value)


def test_the_readme_opensim_file_is_the_built_in_cycle():
    traj = read_trajectory(EXAMPLES / "iso_hip_right.mot", load_column="hip_force_N")
    assert traj.periodic and len(traj) == 100
    q, _, _ = iso14242_angles(traj.t)
    assert np.abs(traj.q - q).max() <= 1e-9  # eight decimals of a degree
    np.testing.assert_allclose(traj.Fe, iso14242_load(traj.t), rtol=0, atol=1e-7)
