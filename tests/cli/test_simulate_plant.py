"""``hipsim simulate --plant-params``: plant and model apart on the command line; its bad input (issue 44)."""

import json

import jsonschema
import numpy as np
import pyarrow.parquet as pq
import pytest
from stations_synthetic import deviated

import hipsim
from hipsim.cli.documents import schema
from hipsim.cli.main import main
from hipsim.machine.chains import geometry_table

SHORT = ["--cycles", "0.05", "--controller", "pd"]


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    """The drawing as a full parameter file, and a machine as built (the drawing plus a [geometry] table)."""
    folder = tmp_path_factory.mktemp("machines")
    drawing = folder / "drawing.toml"
    drawing.write_text(open(hipsim.load_parameters().source, encoding="utf-8").read())
    table = geometry_table(deviated(seed=5))
    built = folder / "built.toml"
    built.write_text(drawing.read_text() + "\n[geometry]\n" + "".join(f"{k} = {v!r}\n" for k, v in table.items()))
    return drawing, built


def test_a_plant_equal_to_the_model_is_todays_run(files, tmp_path):
    drawing, _ = files
    today, again = tmp_path / "today.csv", tmp_path / "again.csv"
    assert main(["simulate", *SHORT, "--plant", "analytic", "--out", str(today)]) == 0
    assert main(["simulate", *SHORT, "--plant", "analytic", "--plant-params", str(drawing), "--out", str(again)]) == 0
    assert today.read_bytes() == again.read_bytes()


def test_a_built_machine_under_the_drawing_and_the_stations_on_its_log(files, tmp_path, capsys):
    drawing, built = files
    run = tmp_path / "run.parquet"
    argv = ["simulate", *SHORT, "--plant-params", str(built), "--feedback", "sensors", "--sensor-noise", "0"]
    assert main([*argv, "--encoder-step", "0", "--out", str(run), "--summary-format", "json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    jsonschema.Draft202012Validator(schema("simulate-plant")).validate(summary)
    entry = summary["simulations"][0]
    assert (entry["feedback"], entry["control"], summary["plant"]) == ("sensors", 2, str(built))
    assert [s["verdict"] for s in entry["stations"]] == ["NOT MADE", "NOT MADE"]  # 0.05 cycle: no whole cycle
    assert [(e["platform"], e["angle"]) for e in entry["errors"]] == [
        (j, a) for j in (1, 2) for a in ("alpha", "beta", "gamma")
    ]
    table = tmp_path / "stations.parquet"
    assert (
        main(
            [
                "stations",
                "--params",
                str(built),
                "--sliders",
                str(run),
                "--table",
                str(table),
                "--out",
                str(tmp_path / "st"),
            ]
        )
        == 0
    )
    simulated, stations = pq.read_table(run).to_pydict(), pq.read_table(table).to_pydict()
    for name in ("alpha_1_deg", "beta_1_deg", "gamma_1_deg", "alpha_2_deg", "beta_2_deg", "gamma_2_deg"):
        assert np.abs(np.array(simulated[name]) - np.array(stations[name])).max() < 1e-9, name
    apart = np.array(simulated["gamma_1_deg"]) - np.array(simulated["gamma_2_deg"])
    assert np.sqrt(np.mean(apart**2)) > 0.1  # the built machine's platforms do not turn alike


@pytest.mark.parametrize(
    ("extra", "message"),
    [
        (
            ["--sensor-noise", "-0.1", "--feedback", "sensors"],
            "--sensor-noise -0.1 deg: the attitude sensor's white noise must be at least 0 and at most 5 deg",
        ),
        (
            ["--sensor-noise", "50", "--feedback", "sensors"],
            "--sensor-noise 50 deg: the attitude sensor's white noise must be at least 0 and at most 5 deg",
        ),
        (
            ["--sensor-drift", "1e6", "--feedback", "sensors"],
            "--sensor-drift 1e+06 deg/min: the sensor zero's drift must be at least -10 and at most 10 deg/min",
        ),
        (
            ["--encoder-step", "-1"],
            "--encoder-step -1 mm: the encoders' resolution in carriage travel must be at least 0 and at most 1 mm",
        ),
        (["--sensor-noise", "0.1"], "--sensor-noise describes the attitude sensor: it needs --feedback sensors"),
        (["--plant", "analytic"], "--plant analytic: the reduced plant has one state for both platforms"),
    ],
)
def test_bad_feedback_options(files, tmp_path, capsys, extra, message):
    _, built = files
    out = tmp_path / "run.csv"
    assert main(["simulate", *SHORT, "--plant-params", str(built), *extra, "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1
    assert not list(tmp_path.iterdir())


def test_a_plant_of_another_design(files, tmp_path, capsys):
    drawing, _ = files
    other = tmp_path / "other.toml"
    text = drawing.read_text()
    lever = hipsim.load_parameters().lever_length * 1e3
    other.write_text(text.replace(f"length_mm = {lever!r}", f"length_mm = {lever + 80.0!r}", 1))
    assert other.read_text() != text
    assert main(["simulate", *SHORT, "--plant-params", str(other), "--out", str(tmp_path / "run.csv")]) == 2
    err = capsys.readouterr().err
    assert "other.toml: not the model's machine as built: the lever length of chain 11 is 80.0 mm off" in err
    assert err.count("\n") == 1 and not (tmp_path / "run.csv").exists()


@pytest.mark.parametrize("command", [["torques"], ["stations"], ["report", "--simulate"]])
def test_plant_params_where_there_is_no_plant(files, tmp_path, capsys, command):
    _, built = files
    assert main([*command, "--plant-params", str(built)]) == 2
    err = capsys.readouterr().err
    assert f"--plant-params: {command[0]} has no plant to give it" in err and err.count("\n") == 1


def test_a_calibrated_model_alone_drives_its_own_machine(files, tmp_path, capsys):
    """A per-chain --params without --plant-params: the plant is that machine, the encoders read through it."""
    _, built = files
    out = tmp_path / "run.csv"
    assert main(["simulate", *SHORT, "--params", str(built), "--out", str(out), "--summary-format", "json"]) == 0
    entry = json.loads(capsys.readouterr().out)["simulations"][0]
    assert (entry["feedback"], entry["control"]) == ("encoders", 2)
    header = out.read_text().splitlines()[0].split(",")
    assert header[:4] == ["t_s", "L_11_mm", "L_12_mm", "L_13_mm"] and "err_gamma_2_deg" in header


def test_fig7_of_a_run(tmp_path, capsys):
    out = tmp_path / "run.csv"
    argv = ["simulate", *SHORT, "--plant", "analytic", "--feedback", "sensors", "--fig7", "--out", str(out)]
    assert main(argv) == 0
    assert sorted(p.name for p in tmp_path.iterdir()) == ["run.csv", "run_fig7.png", "run_fig7.svg"]
    printed = capsys.readouterr().out
    assert "ISO 14242-1 check of station 1's motion under pd (m_1, following)" in printed
    assert "ISO 14242-1 check of station 2's motion under pd (m_2, controlled)" in printed
    assert main(["simulate", *SHORT, "--plant", "analytic", "--fig7", "--out", str(tmp_path / "x.csv")]) == 2
    assert "--fig7 draws both platforms of a run with --plant-params or --feedback" in capsys.readouterr().err
    assert not (tmp_path / "x.csv").exists()


def test_the_sensor_drift_and_encoder_step_in_their_units(tmp_path):
    """--sensor-drift 6 deg/min: the controller sees 0.1°·t[s] above the truth; --encoder-step 0.01 mm: readings on 0.01 mm."""
    out = tmp_path / "run.parquet"
    argv = ["simulate", *SHORT, "--plant", "analytic", "--feedback", "sensors", "--sensor-noise", "0"]
    assert main([*argv, "--sensor-drift", "6", "--encoder-step", "0.01", "--out", str(out)]) == 0
    run = pq.read_table(out).to_pydict()
    t = np.array(run["t_s"])
    for a in ("alpha", "beta", "gamma"):
        seen = np.array(run[f"{a}_meas_deg"]) - np.array(run[f"{a}_2_deg"])
        assert seen == pytest.approx(0.1 * t, abs=1e-12)
    L = np.array(run["L_12_mm"]) / 0.01
    assert np.abs(L - np.rint(L)).max() < 1e-6 and np.ptp(L) > 1


def test_a_stacked_plant_under_the_drawing_agrees_with_the_stations_on_its_log(files, tmp_path, quick_figures):
    """The intermediate chain's stack-up in the Pinocchio plant: its true attitudes are what stations predicts from its
    carriages (the kinematic route of the stack-up) to 1e-9° (measured 3e-10°)."""
    drawing, _ = files
    stacked = tmp_path / "stacked.toml"
    table = geometry_table(deviated(seed=5).replace(spline=np.array([1e-3, 2e-3, -1e-3])))
    stacked.write_text(drawing.read_text() + "\n[geometry]\n" + "".join(f"{k} = {v!r}\n" for k, v in table.items()))
    run, predicted = tmp_path / "run.parquet", tmp_path / "stations.parquet"
    argv = ["simulate", "--cycles", "0.02", "--controller", "pd", "--plant-params", str(stacked)]
    assert main([*argv, "--feedback", "sensors", "--sensor-noise", "0", "--encoder-step", "0", "--out", str(run)]) == 0
    assert main(["stations", "--params", str(stacked), "--sliders", str(run), "--table", str(predicted)]) == 0
    simulated, stations = pq.read_table(run).to_pydict(), pq.read_table(predicted).to_pydict()
    for name in ("alpha_1_deg", "beta_1_deg", "gamma_1_deg", "alpha_2_deg", "beta_2_deg", "gamma_2_deg"):
        assert np.abs(np.array(simulated[name]) - np.array(stations[name])).max() < 1e-9, name
