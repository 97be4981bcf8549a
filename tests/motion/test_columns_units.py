"""A load column in % body weight, named so but mapped without a unit, is refused without a body weight (it was read as newtons)."""

import numpy as np
import pytest

import hipsim
from hipsim.cli.main import main
from hipsim.exceptions import TrajectoryError
from hipsim.motion.columns import stated_unit


def lab_file(path, load_name):
    t = np.linspace(0.0, 1.0, 101)
    rows = ["Time," + ",".join(["FE", "AA", "IE", load_name])]
    for k, s in enumerate(t):
        w = 2 * np.pi * s
        rows.append(
            f"{s:.4f},{25 * np.cos(w):.6f},{5 * np.sin(w):.6f},{-10 * np.cos(w):.6f},{100 + 200 * np.sin(w / 2) ** 2:.6f}"
        )
    path.write_text("\n".join(rows) + "\n")
    return path


@pytest.mark.parametrize("name", ["Fz_%BW", "Fz [%BW]", "Fz (%BW)", "Load %BW"])
def test_a_body_weight_load_without_a_body_weight_is_an_error(name, tmp_path, capsys):
    path = lab_file(tmp_path / "lab.csv", name)
    columns = f"time=Time,alpha=FE,beta=AA,gamma=IE,load={name}"
    out = tmp_path / "t.csv"
    assert main(["torques", "--trajectory", str(path), "--columns", columns, "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--body-weight" in err and "%BW" in err and name in err, err
    assert not out.exists()
    with pytest.raises(TrajectoryError, match="body weight"):
        hipsim.load_trajectory_csv(path, columns=columns)
    # With the body weight it is read as % of it: 75 kg, 100 % at t = 0.
    assert (
        main(["torques", "--trajectory", str(path), "--columns", columns, "--body-weight", "75", "--out", str(out)])
        == 0
    )
    capsys.readouterr()
    trajectory = hipsim.load_trajectory_csv(path, columns=columns, body_weight=75 * 9.80665)
    assert trajectory.Fe[0] == pytest.approx(75 * 9.80665)


def test_an_explicit_unit_is_taken_as_given(tmp_path, capsys):
    path = lab_file(tmp_path / "lab.csv", "Fz_%BW")
    trajectory = hipsim.load_trajectory_csv(path, columns="time=Time,alpha=FE,beta=AA,gamma=IE,load=Fz_%BW:N")
    assert trajectory.Fe[0] == pytest.approx(100.0)
    with pytest.raises(TrajectoryError, match="--body-weight"):
        hipsim.load_trajectory_csv(path, columns="time=Time,alpha=FE,beta=AA,gamma=IE,load=Fz_%BW:%BW")


def test_a_load_named_in_kilonewtons_is_not_read_as_newtons(tmp_path):
    path = lab_file(tmp_path / "lab.csv", "Fz [kN]")
    with pytest.raises(TrajectoryError, match=r"load=Fz \[kN\]:kN"):
        hipsim.load_trajectory_csv(path, columns="time=Time,alpha=FE,beta=AA,gamma=IE,load=Fz [kN]")


def test_stated_units():
    assert stated_unit("Fz [%BW]", "load") == "%BW" and stated_unit("Fz_%BW", "load") == "%BW"
    assert stated_unit("Fz_% BW", "load") == "%BW" and stated_unit("Fz (kN)", "load") == "kN"
    assert stated_unit("Fz", "load") is None and stated_unit("FE [deg]", "load") is None
    assert stated_unit("FE_rad", "alpha") == "rad"
