"""Tests of hipsim.motion.headers: a header matched against a mapping, hipsim's own header checked, a mapping suggested."""

from __future__ import annotations

import numpy as np
import pytest
from trajectory_files import assert_traj_error, canonical, iso_rows, write_lines

from hipsim import TrajectoryError
from hipsim.motion.csv_table import load_trajectory_csv


def test_a_header_that_does_not_match_lists_its_columns_and_suggests_a_mapping(tmp_path):
    t, deg, load = iso_rows(20)
    rows = [";".join(repr(float(v)).replace(".", ",") for v in (t[k], *deg[k], load[k])) for k in range(20)]
    path = write_lines(tmp_path / "lab.csv", ["Time;FE;AA;IE;Fz", *rows])
    with pytest.raises(TrajectoryError) as info:
        load_trajectory_csv(path)
    assert_traj_error(info, path, line=1)
    message = str(info.value)
    assert "the header has 'Time', 'FE', 'AA', 'IE', 'Fz'" in message
    assert "e.g. time=Time,alpha=FE,beta=AA,gamma=IE,load=Fz" in message
    # And the mapping it suggests reads the file.
    traj = load_trajectory_csv(path, columns="time=Time,alpha=FE,beta=AA,gamma=IE,load=Fz")
    np.testing.assert_allclose(traj.q, np.radians(deg), rtol=0, atol=1e-15)


def test_a_mapped_column_that_is_missing_is_named_with_the_columns_found(tmp_path):
    t, deg, load = iso_rows(20)
    path = canonical(tmp_path / "x.csv", t, deg, load)
    with pytest.raises(TrajectoryError) as info:
        load_trajectory_csv(path, columns="time=t_s,alpha=alpha_deg,beta=beta_deg,gamma=Gamma")
    assert_traj_error(info, path, line=1)
    assert "no column 'Gamma' (mapped to gamma); the header has 't_s', 'alpha_deg'" in str(info.value)


@pytest.mark.parametrize(
    ("header", "suggestion"),
    [
        (["Time", "FE", "AA", "IE", "Fz"], "time=Time,alpha=FE,beta=AA,gamma=IE,load=Fz"),
        (
            ["Zeit (ms)", "FE (rad)", "AA", "IE", "Fz [kN]"],
            "time=Zeit (ms):ms,alpha=FE (rad):rad,beta=AA,gamma=IE,load=Fz [kN]:kN",
        ),
        (["frame", "x", "y"], "time=<column>,alpha=<column>,beta=<column>,gamma=<column>"),
    ],
)
def test_the_suggested_mapping_follows_the_names(header, suggestion):
    from hipsim.motion.headers import suggest_mapping

    assert suggest_mapping(header) == suggestion
