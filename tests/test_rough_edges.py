"""Messages that name the fix: a negative length, a left-side OpenSim file, currents without a torque constant,
a Latin-1 line in a parameter file, a comma-separated .mot (issue 30's rough edges outside identification)."""

import numpy as np
import pytest

import hipsim
from hipsim.cli.main import main
from hipsim.exceptions import ParameterError, TrajectoryError
from hipsim.machine.parameters import default_parameters_path
from hipsim.motion.opensim import load_opensim
from hipsim.rig.logs.reader import read_rig_log


def test_a_negative_length_is_named_before_the_missing_keys(tmp_path, capsys):
    path = tmp_path / "negative_length.toml"
    path.write_text("[lever]\nlength_mm = -328.0\n")
    with pytest.raises(ParameterError, match=r"key 'lever.length_mm': must be positive, got -328.0$"):
        hipsim.load_parameters(path)
    assert main(["params", "--params", str(path)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "lever.length_mm" in err and "gravity" not in err
    # A file that only leaves keys out still names the first, and says how many.
    path.write_text("[lever]\nlength_mm = 328.0\n")
    with pytest.raises(ParameterError, match=r"environment.gravity_m_s2': missing .* \(and \d+ more keys"):
        hipsim.load_parameters(path)


def test_a_latin1_line_in_a_parameter_file_is_named(tmp_path):
    text = default_parameters_path().read_text(encoding="utf-8")
    lines = text.split("\n")
    at = next(k for k, line in enumerate(lines) if line.startswith("[lever]"))
    before, after = "\n".join(lines[:at]) + "\n", "\n" + "\n".join(lines[at:])
    path = tmp_path / "latin.toml"  # UTF-8 but for one comment line written by a Latin-1 editor
    path.write_bytes(
        before.encode("utf-8") + "# Hebelmasse gemessen (Prüfstand 2)".encode("latin-1") + after.encode("utf-8")
    )
    with pytest.raises(ParameterError, match=rf"latin.toml: line {at + 1}: not UTF-8 text \(byte 0xfc\)"):
        hipsim.load_parameters(path)


def _mot(path, labels, rows, separator="\t"):
    header = ["Coordinates", "version=1", f"nRows={len(rows)}", f"nColumns={len(labels)}", "inDegrees=yes", "endheader"]
    body = [separator.join(labels)] + [separator.join(f"{v:.6f}" for v in row) for row in rows]
    path.write_text("\n".join(header + body) + "\n")
    return path


def _coordinates():
    t = np.arange(100) / 100
    return np.column_stack([t, 20 * np.cos(2 * np.pi * t), 5 * np.sin(2 * np.pi * t), -8 + 5 * np.cos(2 * np.pi * t)])


def test_a_left_side_file_names_side_left(tmp_path, capsys):
    path = _mot(tmp_path / "left.mot", ["time", "hip_flexion_l", "hip_adduction_l", "hip_rotation_l"], _coordinates())
    with pytest.raises(TrajectoryError, match=r"the other hip's are there: read them with --side left"):
        load_opensim(path)
    assert main(["torques", "--trajectory", str(path), "--out", str(tmp_path / "t.csv")]) == 2
    assert "--side left" in capsys.readouterr().err
    assert main(["torques", "--trajectory", str(path), "--side", "left", "--out", str(tmp_path / "t.csv")]) == 0
    capsys.readouterr()


def test_a_comma_separated_mot_is_named_so(tmp_path, capsys):
    labels = ["time", "hip_flexion_r", "hip_adduction_r", "hip_rotation_r", "knee_angle_r", "ankle_angle_r"]
    rows = np.column_stack([_coordinates(), np.zeros((100, 2))])
    path = _mot(tmp_path / "commas.mot", labels, rows, separator=",")
    with pytest.raises(
        TrajectoryError,
        match=r"line 7: the labels are separated by commas \(6 of them\): a .mot/.sto file is tab- or space-separated",
    ):
        load_opensim(path)
    assert main(["torques", "--trajectory", str(path), "--out", str(tmp_path / "t.csv")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "comma" in err and "header says" not in err


def test_currents_without_a_torque_constant_name_the_option(tmp_path):
    path = tmp_path / "currents.csv"
    path.write_text(
        "t_s,Fe_N,current_1_A,current_2_A,current_3_A,alpha_deg,beta_deg,gamma_deg\n"
        + "\n".join(f"{k / 1000},500,1,2,3,1,2,3" for k in range(100))
        + "\n"
    )
    with pytest.raises(TrajectoryError, match=r"no torque constant .*--torque-constant"):
        read_rig_log(path)


@pytest.mark.parametrize("command", ["identify", "compare"])
def test_a_missing_log_is_one_line_even_without_the_plausibility_check(tmp_path, capsys, command):
    out = tmp_path / ("x.toml" if command == "identify" else "cmp")
    status = main([command, "--log", str(tmp_path / "nothere.csv"), "--no-plausibility-check", "--out", str(out)])
    err = capsys.readouterr().err
    assert status == 2 and err.count("\n") == 1 and "nothere.csv: no such log file" in err
    assert not out.exists()
