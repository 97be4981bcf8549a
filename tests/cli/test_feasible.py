"""The feasibility check at the command line: silent on the built-in cycle, each limit named when crossed, --strict, hipsim feasible."""

import json

import pytest

from hipsim.cli.main import main


def test_the_built_in_cycle_on_the_published_machine_reports_nothing(tmp_path, capsys):
    assert main(["torques", "--out", str(tmp_path / "t.csv")]) == 0
    assert "limit" not in capsys.readouterr().err
    assert main(["feasible"]) == 0
    out = capsys.readouterr().out
    # The published machine has no [motor] table: the verdict covers only what it could check (issue 38).
    assert (
        "within the limits checked (singularity measure, load range); not checked: stroke, motor speed, motor torque"
        in out
    )
    assert "within every machine limit" not in out and "crossed" not in out


@pytest.mark.parametrize(
    ("setting", "named"),
    [
        ("motor.max_speed_rpm=1000", "needs a speed of"),
        ("motor.peak_torque_Nmm=200", "needs a torque of"),
        ("motor.stroke_mm=20", "needs a stroke of"),
    ],
)
def test_a_limit_crossed_is_named_first_and_strict_makes_it_an_error(tmp_path, capsys, setting, named):
    out = tmp_path / "t.csv"
    assert main(["torques", "--set", setting, "--out", str(out)]) == 0
    err = capsys.readouterr().err
    lines = err.strip().split("\n")
    assert lines[0].startswith("hipsim: warning: the motion crosses") and named in lines[1], err
    assert main(["torques", "--set", setting, "--strict", "--out", str(out)]) == 1
    assert capsys.readouterr().err.startswith("hipsim: error: the motion crosses")


def test_feasible_prints_the_table_and_the_speed_that_fits(capsys):
    assert main(["feasible", "--set", "motor.max_speed_rpm=1000", "--frequency", "1.5"]) == 1
    out = capsys.readouterr().out
    assert "Machine limits crossed" in out and "motor speed" in out
    line = next(x for x in out.split("\n") if x.startswith("fits at up to"))
    k = float(line.split("fits at up to ")[1].split("×")[0])
    # The speed scales with the cycle frequency: 1000 rpm over the peak speed needed at 1.5 Hz.
    assert main(["torques", "--frequency", "1.5", "--out", "-", "--summary-format", "json"]) == 0
    peak = max(m["speed_peak_rpm"] for m in json.loads(capsys.readouterr().err)["motors"].values())
    assert k == pytest.approx(1000.0 / peak, rel=5e-3)
    assert f"cycle frequency {1.5 * k:.3g} Hz" in line


def test_a_speed_independent_limit_does_not_fit_at_any_speed(capsys):
    assert main(["feasible", "--set", "motor.stroke_mm=20"]) == 1
    assert "does not fit at any speed" in capsys.readouterr().out


def test_simulate_and_view_check_too(tmp_path, capsys):
    assert main(["view", "--set", "motor.peak_torque_Nmm=200", "--strict", "--html", str(tmp_path / "v.html")]) == 1
    assert "needs a torque of" in capsys.readouterr().err
    assert not (tmp_path / "v.html").exists()
