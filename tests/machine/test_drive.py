"""Drive files (issue 14): the TOML tables, bad files naming the key, the parameter file's [motor] table, the shipped examples (the curves themselves: test_drive_parts.py)."""

import re
from importlib import resources
from pathlib import Path

import pytest
from drive_support import RPM, write
from support import given

from hipsim.exceptions import ParameterError
from hipsim.machine.drive import (
    drive_from_motor_table,
    load_drive,
    load_gearbox_catalogue,
    load_motor_catalogue,
    load_screw_catalogue,
)


def test_drive_file_tables(tmp_path):
    path = write(
        tmp_path,
        """
[motor]
name = "m"
s1_speed_rpm = [0, 3000]
s1_torque_Nmm = [640, 600]
peak_torque_Nm = 1.91
[amplifier]
amplifier_peak_current_A = 5.1
[gearbox]
ratio = 2
efficiency = 0.9
[lead_screw]
lead_mm = 5
dynamic_load_rating_N = 9000
end_fixing = "fixed-fixed"
[rules]
life_target_cycles = 1e7
inertia_ratio_max = 5
""",
        "drive.toml",
    )
    drive = load_drive(path)
    assert given(drive.motor.continuous).at(1500 * RPM) == pytest.approx(0.62) and given(drive.motor.peak).flat
    assert (
        given(drive.amplifier).peak_current == 5.1
        and given(drive.gearbox).ratio == 2.0
        and given(drive.screw).lead == pytest.approx(0.005)
    )
    assert drive.rules.life_target_cycles == 1e7 and drive.rules.inertia_ratio_max == 5.0
    assert drive.name == "m + gearbox + lead screw"


@pytest.mark.parametrize(
    ("text", "key", "message"),
    [
        ("[motor]\npeak_speed_rpm = [0, 1000]\n", "motor.peak_speed_rpm", "speeds without torques"),
        (
            "[motor]\npeak_speed_rpm = [0, 1000, 900]\npeak_torque_Nm = [1, 1, 1]\n",
            "motor.peak_speed_rpm",
            "rise strictly",
        ),
        ("[motor]\nrated_torque_Nmm = 640\ns1_torque_Nmm = 600\n", "motor.rated_torque_Nmm", "either"),
        ("[motor]\npeak_torque_Nm = 1\npeak_torque_Nmm = 1000\n", "motor.peak_torque_Nmm", "given twice"),
        ("[motor]\npeak_torque_Nm = 1\n[lead_screw]\nend_fixing = 'glued'\n", "lead_screw.end_fixing", "fixed-free"),
        ("[motor]\npeak_torque_Nm = 1\n[rules]\nbuckling_factor = 2\n", "rules.buckling_factor", "(0, 1]"),
        (
            "[motor]\nstroke_mm = 100\n[lead_screw]\nstroke_mm = 120\n",
            "lead_screw.stroke_mm",
            "in [motor] and in [lead_screw]",
        ),
    ],
)
def test_bad_drive_files_name_the_key(tmp_path, text, key, message):
    path = write(tmp_path, text, "drive.toml")
    with pytest.raises(ParameterError, match=re.escape(message)) as error:
        load_drive(path)
    assert f"key '{key}'" in str(error.value) and str(path) in str(error.value)


def test_the_parameter_files_motor_table_is_a_drive():
    drive = drive_from_motor_table(
        {"rated_torque_Nmm": 640.0, "peak_torque_Nmm": 1910.0, "stroke_mm": 200.0}, "machine.toml"
    )
    assert given(drive.motor.continuous).at(0.0) == pytest.approx(0.64) and given(drive.screw).stroke == pytest.approx(
        0.2
    )


def test_the_shipped_examples_load_and_say_they_are_examples():
    models = resources.files("hipsim.models")
    for name, loader in (
        ("motors_example.csv", load_motor_catalogue),
        ("screws_example.csv", load_screw_catalogue),
        ("gearboxes_example.csv", load_gearbox_catalogue),
        ("drive_example.toml", load_drive),
    ):
        path = Path(str(models.joinpath(name)))
        assert "EXAMPLE" in path.read_text(encoding="utf-8").upper(), name
        assert loader(path)
    motors = load_motor_catalogue(Path(str(models.joinpath("motors_example.csv"))))
    assert all("example" in motor.name for motor, _ in motors)
