"""Drive catalogues (issue 14): motors, screws and gearboxes read in SI, and bad catalogues refused in one line naming file, line and column."""

import re

import numpy as np
import pytest
from drive_support import RPM, write
from support import given

from hipsim.exceptions import CatalogueError
from hipsim.machine.drive_catalogues import load_gearbox_catalogue, load_motor_catalogue, load_screw_catalogue

MOTORS = """\
# a comment line, then the header
name,s1_speed_rpm,s1_torque_Nm,peak_speed_rpm,peak_torque_Nmm,rotor_inertia_kgcm2,torque_constant_Nm_A,thermal_time_constant_min,dc_bus_energy_J
small,0;3000,0.32;0.30,0;3000;6000,950;950;450,0.051,0.3,12,8
big,,1.27,0 3000,3820 3820,0.26,,,
"""


def test_motor_catalogue_in_si(tmp_path):
    (small, amplifier), (big, none) = load_motor_catalogue(write(tmp_path, MOTORS))
    assert small.name == "small" and big.name == "big"
    np.testing.assert_allclose(given(small.continuous).speed, [0.0, 3000 * RPM])
    np.testing.assert_allclose(given(small.peak).torque, [0.95, 0.95, 0.45])  # N·mm column → N·m
    assert small.rotor_inertia == pytest.approx(0.051e-4) and small.thermal_time_constant == pytest.approx(720.0)
    assert small.top_speed == pytest.approx(6000 * RPM)
    assert given(amplifier).dc_bus_energy == 8.0 and none is None
    assert given(big.continuous).flat and given(big.continuous).at(5000.0) == pytest.approx(
        1.27
    )  # one torque: flat at every speed
    assert big.rotor_inertia == pytest.approx(0.26e-4) and big.torque_constant is None


def test_screw_and_gearbox_catalogues(tmp_path):
    screws = load_screw_catalogue(
        write(tmp_path, "name,lead_mm,dynamic_load_rating_N,end_fixing\nA,5,7700,Fixed-Supported\nB,20,,\n", "s.csv")
    )
    assert (
        screws[0].lead == pytest.approx(0.005)
        and screws[0].end_fixing == "fixed-supported"
        and screws[1].dynamic_load_rating is None
    )
    (belt,) = load_gearbox_catalogue(write(tmp_path, "name,ratio,efficiency,inertia_kgmm2\nbelt,2,0.95,4\n", "g.csv"))
    assert belt.ratio == 2.0 and belt.efficiency == 0.95 and belt.inertia == pytest.approx(4e-6)


@pytest.mark.parametrize(
    ("text", "line", "column", "message"),
    [
        ("name,s1_torque_Nm\nA,1\n", 1, None, "missing column 'peak_torque_Nm' or 'peak_torque_Nmm'"),
        ("name,s1_torque_Nm,peak_torque_Nm,colour\nA,1,2,red\n", 1, "colour", "unknown column"),
        (
            "name,s1_torque_Nm,peak_torque_Nm,peak_speed_rpm\nA,1,2 2 1,0;3000;2000\n",
            2,
            "peak_speed_rpm",
            "speeds must rise strictly",
        ),
        ("name,s1_torque_Nm,peak_torque_Nm\nA,1,2\nB,-1,2\n", 3, "s1_torque_Nm", "must not be negative"),
        (
            "name,s1_torque_Nm,peak_torque_Nm,rotor_inertia_kgcm2\nA,1,2,-0.1\n",
            2,
            "rotor_inertia_kgcm2",
            "must be positive",
        ),
        ("name,s1_torque_Nm,peak_torque_Nm\nA,1,two\n", 2, "peak_torque_Nm", "'two' is not a number"),
        ("name,s1_torque_Nm,peak_torque_Nm\nA,1,nan\n", 2, "peak_torque_Nm", "finite"),
        ("name,s1_torque_Nm,peak_torque_Nm\nA,1\n", 2, None, "2 cells for 3 columns"),
        ("name,s1_torque_Nm,peak_torque_Nm\nA,1,\n", 2, "peak_torque_Nm", "required"),
        ("name,s1_torque_Nm,peak_torque_Nm\nA,1,2\nA,1,3\n", 3, "name", "already used on line 2"),
        ("name,s1_torque_Nm,s1_torque_Nmm,peak_torque_Nm\nA,1,1,2\n", 1, "s1_torque_Nmm", "two columns"),
        (
            "name,s1_torque_Nm,peak_torque_Nm,peak_speed_rpm\nA,1,2;3,0;1000;2000\n",
            2,
            "peak_torque_Nm",
            "2 torques for 3 speeds",
        ),
        ("# only a comment\n", None, None, "no entries"),
    ],
)
def test_bad_motor_catalogues_name_file_line_and_column(tmp_path, text, line, column, message):
    path = write(tmp_path, text)
    with pytest.raises(CatalogueError) as error:
        load_motor_catalogue(path)
    text = str(error.value)
    assert "\n" not in text and text.startswith(str(path))
    assert message in text
    assert error.value.line == line and error.value.column == column
    if line is not None:
        assert f"line {line}" in text
    if column is not None:
        assert f"column '{column}'" in text


@pytest.mark.parametrize(
    ("loader", "text", "column", "message"),
    [
        (load_screw_catalogue, "name,lead_mm,end_fixing\nA,10,clamped\n", "end_fixing", "fixed-free"),
        (load_screw_catalogue, "name,lead_mm,preload_N\nA,10,-5\n", "preload_N", "must not be negative"),
        (load_screw_catalogue, "name,dynamic_load_rating_N\nA,900\n", None, "missing column 'lead_mm'"),
        (load_gearbox_catalogue, "name,ratio,efficiency\nbelt,2,1.2\n", "efficiency", "(0, 1]"),
    ],
)
def test_bad_screw_and_gearbox_catalogues(tmp_path, loader, text, column, message):
    path = write(tmp_path, text, "parts.csv")
    with pytest.raises(CatalogueError, match=re.escape(message)) as error:
        loader(path)
    assert error.value.column == column and str(path) in str(error.value)


def test_unreadable_catalogues(tmp_path):
    with pytest.raises(CatalogueError, match="no such motor catalogue"):
        load_motor_catalogue(tmp_path / "missing.csv")
    with pytest.raises(CatalogueError, match="is a folder"):
        load_motor_catalogue(tmp_path)
    path = tmp_path / "latin1.csv"
    path.write_bytes("name,s1_torque_Nm,peak_torque_Nm\nMotör,1,2\n".encode("latin-1"))
    with pytest.raises(CatalogueError, match="UTF-8"):
        load_motor_catalogue(path)
    path.write_bytes(b"\xef\xbb\xbfname,s1_torque_Nm,peak_torque_Nm\nA,1,2\n")  # a byte-order mark is fine
    assert load_motor_catalogue(path)[0][0].name == "A"
