"""Drive sizing (issue 14): the sizing table of a run names its binding check; the command line hipsim size.

The demand, the ratings, the checks and the ranking have their own tests
(test_demand, test_ratings, test_checks, test_ranking).
"""

import json
import re
import sys

import jsonschema
import pytest
from support import given

import hipsim
from hipsim.cli.documents import schema
from hipsim.design.sizing import CHECKS, sizing
from hipsim.design.sizing_summary import sizing_summary
from hipsim.machine.drive import Drive, Motor
from hipsim.motion.trajectories import iso14242


@pytest.fixture(scope="module")
def params():
    return hipsim.load_parameters()


def test_the_published_machine_sizing_names_a_binding_check(params):
    size = sizing(hipsim.analyse(params, iso14242(rate=200)), Drive(Motor("m", rotor_inertia=14e-6)))
    assert given(size.binding).name == "inertia_ratio" and size.passed is False  # 2.8 kg·cm² on a 0.14 kg·cm² rotor
    document = sizing_summary(size).to_json()
    assert document["binding"]["name"] == "inertia_ratio" and len(document["checks"]) == 3 * len(CHECKS)


# ---------------------------------------------------------------------------
# The command line: hipsim size


MOTORS = """\
name,s1_torque_Nm,peak_speed_rpm,peak_torque_Nm,rotor_inertia_kgcm2
small,1.0,0;3000,0.25;0.25,1.0
right,1.3,0;5000,3.8;3.0,1.0
"""


def test_size_ranks_a_catalogue(tmp_path, capsys):
    from hipsim.cli import main

    motors = tmp_path / "motors.csv"
    motors.write_text(MOTORS)
    screws = tmp_path / "screws.csv"
    screws.write_text("name,lead_mm,dynamic_load_rating_N\nten,10,9000\n")
    assert main(["size", "--rate", "200", "--catalogue", str(motors), "--screws", str(screws)]) == 0
    out = capsys.readouterr().out
    lines = [line for line in out.splitlines() if re.match(r"[12]\s{2,}", line)]
    assert lines[0].split()[1] == "right" and "pass" in lines[0]
    assert (
        lines[1].split()[1] == "small"
        and "FAIL" in lines[1]
        and "torque under the peak curve" in lines[1]
        and "LN1" in lines[1]
    )
    assert "Every check of rank 1: right + ten" in out
    assert "verdict: FEASIBLE: 1 of 2 combinations pass every check" in out
    assert main(["size", "--rate", "200", "--catalogue", str(motors), "--summary-format", "json", "--top", "1"]) == 0
    import json

    document = json.loads(capsys.readouterr().out)
    assert [c["motor"] for c in document["candidates"]] == ["right"]
    assert document["verdict"]["level"] == "FEASIBLE" and document["verdict"]["numbers"]["passing"] == 1
    jsonschema.Draft202012Validator(schema("size-catalogue")).validate(document)
    # Only the motor that fails: no combination passes, NOT FEASIBLE, exit 1.
    motors.write_text("\n".join(MOTORS.splitlines()[:2]) + "\n")
    assert main(["size", "--rate", "200", "--catalogue", str(motors), "--summary-format", "json"]) == 1
    document = json.loads(capsys.readouterr().out)
    assert document["verdict"]["level"] == "NOT FEASIBLE" and [c["passed"] for c in document["candidates"]] == [False]
    jsonschema.Draft202012Validator(schema("size-catalogue")).validate(document)


def test_size_checks_one_drive_and_fails_with_status_1(tmp_path, capsys):
    from importlib import resources

    from hipsim.cli import main

    drive = str(resources.files("hipsim.models").joinpath("drive_example.toml"))
    assert main(["size", "--rate", "200", "--drive", drive]) == 1  # the example 200 W motor fails the 10:1 inertia rule
    out = capsys.readouterr().out
    assert "-> FAIL; binding: load-to-rotor inertia ratio (worst pose), LN1" in out
    assert main(["size", "--rate", "200", "--drive", drive, "--summary-format", "json"]) == 1
    document = json.loads(capsys.readouterr().out)
    jsonschema.Draft202012Validator(schema("size")).validate(document)
    (entry,) = document.values()  # keyed by the trajectory's name
    assert entry["verdict"]["level"] == "FAIL" and entry["binding"]["name"] == "inertia_ratio"
    assert entry["passed"] is False and entry["drive"]["motor"]["rotor_inertia"] > 0
    assert main(["size", "--rate", "200", "--drive", drive, "--inertia-ratio", "25"]) == 0
    capsys.readouterr()


@pytest.mark.parametrize(
    ("arguments", "message"),
    [
        (["--screws", "s.csv"], "--screws applies to a catalogue"),
        (["--drive", "d.toml", "--catalogue", "m.csv"], "either --drive"),
        (["--without-iso"], "--trajectory"),
        (["--life-cycles", "-3"], "--life-cycles"),
        (["--catalogue", "missing.csv"], "no such motor catalogue"),
    ],
)
def test_size_refuses_bad_options_in_one_line(tmp_path, capsys, monkeypatch, arguments, message):
    from hipsim.cli import main

    monkeypatch.chdir(tmp_path)
    assert main(["size", "--rate", "100", *arguments]) == 2
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1


def test_the_public_names_stay_where_the_readme_says():
    """Sizing's parts live in their own modules; hipsim.design.sizing and hipsim.machine.drive still offer every name."""
    import hipsim.design
    import hipsim.design.ranking
    import hipsim.machine.drive

    # hipsim.design.sizing, as an attribute, is the function (the package exports it); the module is in sys.modules.
    assert hipsim.design.sizing is sizing and hipsim.design.rank_drives is hipsim.design.ranking.rank_drives
    module = sys.modules["hipsim.design.sizing"]
    for name in module.__all__:
        assert getattr(module, name) is not None, name
    for name in ("motor_thrust", "axial_screw_load", "rank_drives", "drive_checks", "screw_side", "CHECKS"):
        assert name in module.__all__
    for name in hipsim.machine.drive.__all__:
        assert getattr(hipsim.machine.drive, name) is not None, name
    for name in (
        "load_drive",
        "load_motor_catalogue",
        "load_screw_catalogue",
        "load_gearbox_catalogue",
        "Drive",
        "SizingRules",
    ):
        assert name in hipsim.machine.drive.__all__


def test_size_ranks_the_example_catalogue_smallest_first_and_says_why_others_fail(capsys):
    """`hipsim size --catalogue`: the 200 W motor first; an overspeeding line in rpm; --rank margin as before; JSON keeps its keys."""
    import json
    from importlib import resources

    from hipsim.cli import main

    folder = resources.files("hipsim.models")
    files = [
        "--catalogue",
        str(folder / "motors_example.csv"),
        "--screws",
        str(folder / "screws_example.csv"),
        "--gearboxes",
        str(folder / "gearboxes_example.csv"),
    ]
    assert main(["size", "--rate", "200", *files]) == 0
    out = capsys.readouterr().out
    lines = [line for line in out.splitlines() if re.match(r"\d+\s{2,}EX-", line)]
    assert len(lines) == 36 and "EX-S200" in lines[0] and "pass" in lines[0] and "201 W" in lines[0]
    over = [line for line in lines if "EX-S200" in line and "belt" in line and "16x5" in line]
    assert (
        len(over) == 1
        and re.search(r"needs [\d,]+ rpm; the motor's top speed is 6,000", over[0])
        and "∞" not in over[0]
    )
    assert "rated power = rated torque × rated speed" in out and "Checks that do not depend on the motor" in out
    assert main(["size", "--rate", "200", "--rank", "margin", *files]) == 0
    lines = [line for line in capsys.readouterr().out.splitlines() if re.match(r"\d+\s{2,}EX-", line)]
    assert "EX-S750" in lines[0] and "carriage stroke" in lines[0]  # today's order: the largest smallest margin
    assert main(["size", "--rate", "200", "--summary-format", "json", "--top", "2", *files]) == 0
    document = json.loads(capsys.readouterr().out)
    first = document["candidates"][0]
    assert {"drive", "motor", "gearbox", "screw", "passed", "margin", "binding", "unchecked", "checks"} <= set(first)
    assert (
        first["rated_power_W"] == pytest.approx(0.64 * 3000 * 2 * 3.141592653589793 / 60) and document["rank"] == "size"
    )
    assert len(document["screw_checks"]) == 3


def test_size_refuses_rank_without_a_catalogue(capsys):
    from hipsim.cli import main

    assert main(["size", "--rate", "100", "--rank", "margin"]) == 2
    assert "--rank applies to a catalogue" in capsys.readouterr().err
