"""Plausibility of rig logs: unit slips refused before any comparison or fit, milder implausibility warned of.

The logs are the analytic model's torques of another machine (the synthetic
tests' "true" one) along four ISO cycles, written by the test with the unit
slips of a busy lab: torques in N·m, the load in kN, radians under ``_deg``,
currents with a torque constant in N·mm/A.
"""

import numpy as np
import pytest
from rig_synthetic import mismatched

import hipsim
from hipsim.cli.main import main
from hipsim.exceptions import TrajectoryError
from hipsim.rig import load_log
from hipsim.rig.plausibility import check_log

HEADER = ["t_s", "Fe_N", "alpha_deg", "beta_deg", "gamma_deg", "tau_1_Nmm", "tau_2_Nmm", "tau_3_Nmm"]
CURRENTS = HEADER[:5] + ["current_1_A", "current_2_A", "current_3_A"]

#: What is tested here is what the commands accept, refuse and warn of, and the numbers: the comparison's
#: figures are built but not drawn (tests/conftest.py); tests/rig/test_compare.py draws them.
pytestmark = pytest.mark.usefixtures("quick_figures")


@pytest.fixture(scope="module")
def run():
    return hipsim.analyse(mismatched(hipsim.load_parameters()), hipsim.iso14242(rate=500, cycles=4))


def write(path, run, torque=1e3, load=1.0, angle=np.degrees, header=HEADER, separator=",", decimal_comma=False):
    """A rig log of ``run``: torques in N·m × ``torque``, load in N × ``load``, angles through ``angle``."""
    traj = run.trajectory
    values = np.column_stack([traj.t, traj.Fe * load, angle(traj.q), run.torques.total * torque])
    lines = [separator.join(header)]
    for row in values:
        cells = [f"{v:.9g}" for v in row]
        lines.append(separator.join(c.replace(".", ",") for c in cells) if decimal_comma else separator.join(cells))
    path.write_text("\n".join(lines) + "\n")
    return path


def refused(capsys, *words, warned: str = ""):
    err = capsys.readouterr().err
    if warned:  # the option table's warning of the typed value comes first (issue 48)
        first, _, err = err.partition("\n")
        assert first.startswith(f"hipsim: warning: {warned}"), first
    assert err.count("\n") == 1 and err.startswith("hipsim: error: "), err
    for word in words:
        assert word in err, (word, err)
    return err


def test_a_right_log_passes_without_a_word(run, tmp_path, capsys):
    log = write(tmp_path / "ok.csv", run)
    assert check_log(hipsim.load_parameters(), load_log(log)) == []
    assert main(["compare", "--log", str(log), "--out", str(tmp_path / "cmp")]) == 0
    assert "warning" not in capsys.readouterr().err


@pytest.mark.parametrize("command", ["compare", "identify"])
def test_torques_in_newton_metres_are_refused(command, run, tmp_path, capsys):
    log = write(tmp_path / "nm.csv", run, torque=1.0)
    out = tmp_path / ("out" if command == "compare" else "out.toml")
    assert main([command, "--log", str(log), "--out", str(out)]) == 2
    refused(capsys, "nm.csv", "tau_1_Nmm", "like N·m", "1/1000 of the model's")
    assert not out.exists()


@pytest.mark.parametrize("command", ["compare", "identify"])
def test_a_load_in_kilonewtons_is_refused(command, run, tmp_path, capsys):
    log = write(tmp_path / "kn.csv", run, load=1e-3)
    out = tmp_path / ("out" if command == "compare" else "out.toml")
    assert main([command, "--log", str(log), "--out", str(out)]) == 2
    refused(capsys, "Fe_N looks like kN", "1/1000")
    assert not out.exists()


def test_radians_under_degrees_are_refused(run, tmp_path, capsys):
    log = write(tmp_path / "rad.csv", run, angle=lambda q: q)
    assert main(["compare", "--log", str(log), "--out", str(tmp_path / "out")]) == 2
    refused(capsys, "alpha_deg looks like radians", "1/57", "_rad")
    assert not (tmp_path / "out").exists()


def test_a_torque_constant_in_newton_millimetres_per_ampere_is_refused(run, tmp_path, capsys):
    log = write(tmp_path / "currents.csv", run, torque=1 / 0.05, header=CURRENTS)  # a motor of 0.05 N·m/A
    for command, out in (("compare", tmp_path / "out"), ("identify", tmp_path / "out.toml")):
        assert main([command, "--log", str(log), "--torque-constant", "50", "--out", str(out)]) == 2
        refused(
            capsys,
            "current_1_A",
            "--torque-constant",
            "1000 times",
            "N·mm/A",
            "0.05",
            warned="--torque-constant 50 N·m/A",
        )
        assert not out.exists()
    assert main(["compare", "--log", str(log), "--torque-constant", "0.05", "--out", str(tmp_path / "out")]) == 0
    capsys.readouterr()


def test_a_milder_mismatch_is_a_warning(run, tmp_path, capsys):
    """All three motors 5 times the model's: one warning naming the constant factor (issue 38), not three."""
    log = write(tmp_path / "five.csv", run, torque=5e3)
    assert main(["compare", "--log", str(log), "--out", str(tmp_path / "out")]) == 0
    warnings = [line for line in capsys.readouterr().err.splitlines() if line.startswith("hipsim: warning:")]
    assert len(warnings) == 1 and "tau_1_Nmm, tau_2_Nmm, tau_3_Nmm: all three" in warnings[0], warnings
    assert "a constant factor of 5" in warnings[0] and "transmission ratio" in warnings[0]


def test_one_motor_off_is_named_alone(run, tmp_path):
    """Motor 2 alone 5 times the model's: a warning for tau_2_Nmm only (no constant factor to name)."""
    path = write(tmp_path / "m2.csv", run)
    lines = path.read_text().splitlines()
    out = [lines[0]]
    for line in lines[1:]:
        cells = line.split(",")
        cells[6] = f"{float(cells[6]) * 5:.9g}"
        out.append(",".join(cells))
    path.write_text("\n".join(out) + "\n")
    warnings = check_log(hipsim.load_parameters(), load_log(path))
    assert len(warnings) == 1 and "tau_2_Nmm: 6.0" in warnings[0] and "constant" not in warnings[0], (
        warnings
    )  # 5 × 1.2 (the other machine)


def test_a_two_to_one_belt_is_named_as_a_constant_factor(run, tmp_path):
    """Torques doubled by a 2:1 belt the parameters do not know: within the 3× warning band, but one factor on all three."""
    warnings = check_log(hipsim.load_parameters(), load_log(write(tmp_path / "belt.csv", run, torque=2e3)))
    assert len(warnings) == 1 and "a constant factor of 2" in warnings[0], warnings
    assert check_log(hipsim.load_parameters(), load_log(write(tmp_path / "ok.csv", run))) == []


def test_the_check_can_be_turned_off(run, tmp_path, capsys):
    log = write(tmp_path / "nm.csv", run, torque=1.0)
    assert main(["compare", "--log", str(log), "--no-plausibility-check", "--out", str(tmp_path / "out")]) == 0
    capsys.readouterr()
    with pytest.raises(TrajectoryError, match="1/1000"):
        check_log(hipsim.load_parameters(), load_log(log))


# --- Tab- and semicolon-separated rig logs with decimal commas: read as the comma file, to the last digit ------------

from hipsim.rig import compare_torques, identify  # noqa: E402
from hipsim.rig.identification.quantities import standard_values  # noqa: E402


def _without_names(document):
    if isinstance(document, dict):
        return {k: _without_names(v) for k, v in document.items() if k not in ("log", "provenance")}
    if isinstance(document, list):
        return [_without_names(v) for v in document]
    return document


def test_tab_and_semicolon_logs_give_the_comma_files_results(run, tmp_path, capsys):
    import json

    params = hipsim.load_parameters()
    files = {
        "comma": write(tmp_path / "comma.csv", run),
        "tab": write(tmp_path / "tab.tsv", run, separator="\t", decimal_comma=True),
        "semicolon": write(tmp_path / "semicolon.csv", run, separator=";", decimal_comma=True),
    }
    assert "\t" in files["tab"].read_text() and "," in files["tab"].read_text().splitlines()[1]
    logs = {name: load_log(path, params) for name, path in files.items()}
    for name in ("tab", "semicolon"):
        np.testing.assert_array_equal(logs[name].tau, logs["comma"].tau)
        np.testing.assert_array_equal(logs[name].trajectory.q, logs["comma"].trajectory.q)
        assert (
            compare_torques(params, logs[name]).summary().motors
            == compare_torques(params, logs["comma"]).summary().motors
        )
    fits = {name: identify([log], params) for name, log in logs.items()}
    for name in ("tab", "semicolon"):
        a, b = fits[name], fits["comma"]
        np.testing.assert_array_equal([q.value for q in a.quantities], [q.value for q in b.quantities])
        np.testing.assert_array_equal([q.std for q in a.quantities], [q.std for q in b.quantities])
        np.testing.assert_array_equal(standard_values(a.params), standard_values(b.params))
        np.testing.assert_array_equal(a.residual_rms, b.residual_rms)
    # The command: the same comparison.json but for the log's name and hashes.
    documents = {}
    for name, path in files.items():
        assert main(["compare", "--log", str(path), "--out", str(tmp_path / name)]) == 0
        documents[name] = _without_names(json.loads((tmp_path / name / "comparison.json").read_text()))
    capsys.readouterr()
    assert documents["tab"] == documents["comma"] and documents["semicolon"] == documents["comma"]
