"""hipsim/stations/calibration_file.py: the ``[identification]`` record of a calibration written by hand (no fit), each
entry's unit and rounding, the comment header, and the file written and read back."""

from __future__ import annotations

import numpy as np
import pytest
from stations_synthetic import CENTRE_X_1, LEVER_11, LEVER_21, NAMES, hand_calibration

from hipsim.machine.parameters import load_parameters
from hipsim.rig.identification.identified_file import FileProvenance, read_identified_file
from hipsim.stations import deviations as dv
from hipsim.stations.calibration import Calibration, Confounding
from hipsim.stations.calibration_file import CALIBRATED_MARK, calibrated_toml, calibration_record, write_calibrated
from hipsim.stations.calibration_summary import HeldOutResidual
from hipsim.stations.sensitivity import Structure


def test_the_record_by_hand():
    validation = [HeldOutResidual("held.csv", [[0.5] * 3] * 2, [[1.0] * 3] * 2)]
    record = calibration_record(hand_calibration(), validation, start="start.toml")
    assert record["kind"] == "kinematic calibration" and record["start"] == "start.toml"
    assert record["logs"] == ["a.csv", "b.csv"] and record["samples"] == 300 and record["iterations"] == 4
    assert record["prior_mm"] == pytest.approx(0.5) and record["sensor_offsets"] == "per-log"
    assert record["values"] == list(NAMES)
    assert record["deviation_mm"][LEVER_11] == pytest.approx(0.2) and record["deviation_mm"][LEVER_21] == -0.05
    assert record["std_mm"][LEVER_21] == pytest.approx(0.4) and record["std_mm"][0] == pytest.approx(0.5)
    assert record["value_determined"][LEVER_11] is True and record["value_determined"][LEVER_21] is False
    assert record["estimated"] == ["lever_11", "lever_21"]
    assert record["covariance_mm2"] == [[0.01, -0.002], [-0.002, 0.16]]
    assert record["unseen"] == ["centre_x_1"] and record["combinations"] == ["lever_11 + 0.5·centre_x_1"]
    assert record["confounded_offsets"] == [] and record["confounded_values"] == []
    assert record["noise_deg"] == pytest.approx([0.01, 0.02, 0.03, 0.04, 0.05, 0.06])
    assert record["offsets_deg"][0] == [0.0] * 6 and record["offsets_deg"][1][2] == pytest.approx(0.25)
    assert record["residual_rms_deg"][1] == pytest.approx([0.02, 0.04, 0.06, 0.08, 0.1, 0.12])
    assert record["start_residual_rms_deg"][0][5] == pytest.approx(0.6)
    assert record["validation_logs"] == ["held.csv"]
    assert record["validation_rms_deg"] == [pytest.approx([0.5] * 6)]
    assert record["validation_start_rms_deg"] == [pytest.approx([1.0] * 6)]
    bare = calibration_record(hand_calibration(offsets=False))
    assert bare["sensor_offsets"] == "none" and bare["start"] == "the published machine"
    assert bare["validation_logs"] == [] and bare["validation_rms_deg"] == []


def test_the_files_header_and_the_file_read_back(tmp_path):
    trade = Confounding("gamma_1", 0.987654321, ("joint_x_11", "joint_y_12"), (1.0, -0.5))
    calibration = hand_calibration(confounded=(trade,))
    text = calibrated_toml(calibration, start="start.toml")
    lines = text.splitlines()
    lines = lines[next(k for k, line in enumerate(lines) if line.startswith(CALIBRATED_MARK)) :]
    assert lines[0] == f"{CALIBRATED_MARK} from 2 log(s), 300 samples: a.csv, b.csv"
    assert lines[1] == "# Start: start.toml; prior ±0.5 mm on every per-chain value."
    assert lines[2] == "# Sensor noise [deg] m_1 α β γ, m_2 α β γ: 0.01, 0.02, 0.03, 0.04, 0.05, 0.06"
    assert lines[3] == "# Not seen by these logs (kept at the start): centre_x_1"
    assert lines[4] == (
        "# Sensor offset gamma_1 not told apart from joint_x_11, joint_y_12 (R² 0.9877); a fixture's known-attitude "
        "rows separate them."
    )
    record = calibration_record(calibration)
    assert record["confounded_offsets"] == ["gamma_1"] and record["confounded_values"] == ["joint_x_11, joint_y_12"]
    path = write_calibrated(tmp_path / "calibrated.toml", calibration, start="start.toml")
    assert path.read_text(encoding="utf-8") == text
    found = read_identified_file(path)
    assert found is not None and found.table["kind"] == "kinematic calibration"
    assert found.logs == ("a.csv", "b.csv")
    machine = load_parameters(path)
    assert machine.geometry is not None
    assert dv.deviation(machine)[LEVER_11] == pytest.approx(2e-4)


def test_a_calibration_that_sees_everything_says_none_unseen():
    calibration = hand_calibration()
    seen = Structure(3, np.array([LEVER_11, LEVER_21, CENTRE_X_1]), np.array([], dtype=int), np.zeros((3, 0)), True)
    everything = Calibration(**{**calibration.__dict__, "structure": seen})
    assert "\n# Not seen by these logs (kept at the start): none\n" in calibrated_toml(everything)


def test_rounding_the_default_start_two_unseen_values_and_the_provenance(tmp_path):
    """A third of a micrometre kept to 12 decimals of a mm; a noise of a third of a thousandth of a degree to 9."""
    base = hand_calibration()
    theta = np.array(base.theta)
    theta[LEVER_11] = 1e-6 / 3
    noise = np.array(base.noise)
    noise[0, 0] = np.radians(1e-3 / 3)
    seen = Structure(2, np.array([LEVER_11, LEVER_21]), np.array([CENTRE_X_1, CENTRE_X_1 + 1]), np.zeros((2, 2)), True)
    calibration = Calibration(**{**base.__dict__, "theta": theta, "noise": noise, "structure": seen})
    record = calibration_record(calibration)
    assert record["deviation_mm"][LEVER_11] == round(1e-3 / 3, 12) != round(1e-3 / 3, 13)
    assert record["noise_deg"][0] == round(1e-3 / 3, 9) != round(1e-3 / 3, 10)
    provenance = FileProvenance("9.9", "2026-11-29T08:00:00Z", "hipsim calibrate --log a.csv")
    text = calibrated_toml(calibration, provenance=provenance)
    assert "# Start: the published machine; prior ±0.5 mm on every per-chain value." in text
    assert "# Not seen by these logs (kept at the start): centre_x_1, centre_y_1\n" in text
    assert "hipsim calibrate --log a.csv" in text
    path = write_calibrated(tmp_path / "c.toml", calibration, provenance=provenance)
    assert path.read_text(encoding="utf-8") == text
