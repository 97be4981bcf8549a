"""Uncertainty forward: an identified file's covariance carried into the sizing margins (`hipsim size`), checked by draws."""

import json
from pathlib import Path

import hipsim.models
import numpy as np
import pytest
from conftest import figures_undrawn
from rig_synthetic import fit_run, machines, write_log
from support import given

import hipsim
from hipsim.analysis.runs import analyse
from hipsim.cli.main import main
from hipsim.design.sizing import margin_bands, sizing
from hipsim.machine.drive import load_drive
from hipsim.rig import identify, load_log
from hipsim.rig.identification.base import base_parameters
from hipsim.rig.identification.quantities import standard_values, with_values
from hipsim.rig.identification.uncertainty import read_covariance, sigma_machines

DRIVE = Path(hipsim.models.__file__).with_name("drive_example.toml")


@pytest.fixture(scope="module")
def identified(tmp_path_factory):
    """An identified file from 8 s of the Pinocchio plant's excitation, with noise: its parameters are uncertain enough to show."""
    folder = tmp_path_factory.mktemp("forward")
    start, _ = machines()
    log = write_log(folder / "fit.csv", fit_run(8.0), np.random.default_rng(5))
    path = identify([load_log(log, start)], start).write_toml(folder / "identified.toml")
    return path, hipsim.load_parameters(path)


def test_margin_bands_agree_with_draws_of_the_parameters(identified):
    """The first-order standard deviation of each margin against 300 draws θ_b ~ N(θ̂_b, Σ), each a full model run and sizing."""
    path, params = identified
    covariance = given(read_covariance(path, params))
    drive = load_drive(DRIVE)
    # 100 samples a cycle: the law (Σ carried to first order against draws through the same sizing) holds at any
    # sampling of the cycle; at 100 and 500 Hz the same 30 margins compare, each ratio within 0.012 of the other's.
    trajectory = hipsim.iso14242(rate=100)
    nominal = sizing(analyse(params, trajectory), drive)
    bands = margin_bands(nominal, [sizing(analyse(v, trajectory), drive) for v in sigma_machines(params, covariance)])
    base = base_parameters(params, covariance.lever_spin)
    theta = standard_values(params)
    draws = np.random.default_rng(0).multivariate_normal(base.transform @ theta, covariance.matrix, size=300)
    margins = np.array(
        [
            [
                np.nan if c.margin is None else c.margin
                for c in sizing(analyse(with_values(params, base.standard(d, theta)), trajectory), drive).checks
            ]
            for d in draws
        ]
    )
    compared = 0
    for j, band in enumerate(bands):
        spread = np.std(margins[:, j])
        if band.std is None or not spread > 1e-6:
            continue
        compared += 1
        assert band.std == pytest.approx(spread, rel=0.25), band.check.name
    assert compared >= 10
    assert all(
        b.confident == (b.check.margin - 1.6448536269514722 * b.std >= 0)
        for b in bands
        if b.std is not None and b.check.margin is not None
    )


def test_size_with_an_identified_file_says_which_margins_pass_with_confidence(identified, capsys):
    path, params = identified
    # The exit status is the verdict: 1 when the drive fails a check, else 0 (the JSON's "passed").
    size = ["size", "--params", str(path), "--drive", str(DRIVE), "--rate", "500"]
    json_status = main(size + ["--summary-format", "json"])
    document = json.loads(capsys.readouterr().out)
    (entry,) = document.values()
    assert json_status == (1 if entry["passed"] is False else 0)
    assert len(entry["margin_bands"]) == len(entry["checks"])
    assert {"margin_std", "margin_lo95", "margin_hi95", "passes_with_95_confidence"} <= set(entry["margin_bands"][0])
    assert main(size) == json_status
    printed = capsys.readouterr().out
    assert "passes with 95 % confidence" in printed and "95 % interval" in printed
    # Without a covariance: the output of before, no bands.
    published = ["size", "--drive", str(DRIVE), "--rate", "500"]
    json_status = main(published + ["--summary-format", "json"])
    (entry,) = json.loads(capsys.readouterr().out).values()
    assert json_status == (1 if entry["passed"] is False else 0)
    assert main(published) == json_status
    assert "95 % confidence" not in capsys.readouterr().out


def test_the_parameter_origin_comes_from_the_identification_table(identified, tmp_path):
    """Identified or published, per parameter, from the [identification] table: the comment header below the first line is not needed."""
    import tomllib

    from hipsim.present.provenance import parameter_origin

    path, _ = identified
    lines = path.read_text(encoding="utf-8").splitlines()
    bare = tmp_path / "bare.toml"
    bare.write_text(
        "\n".join([lines[0]] + [line for line in lines[1:] if not line.startswith("#")]) + "\n", encoding="utf-8"
    )
    table = tomllib.loads(path.read_text(encoding="utf-8"))["identification"]
    origin = parameter_origin(bare)
    assert origin.kind == "identified" and origin.logs == ("fit.csv",)
    determined = {
        label: (value, std)
        for label, value, std, d in zip(table["base"], table["value"], table["std"], table["determined"])
        if d
    }
    assert {v.label: (v.value, v.std) for v in origin.identified} == determined
    assert {key for key, _ in origin.held} >= {key for key, d in zip(table["keys"], table["determined"]) if not d}
    assert origin.origin_of("slider.mass_kg")[0] == "identified"
    assert origin.origin_of("lever.mass_kg")[0].startswith(
        "start value"
    )  # folded into m_L, its own value the starting one
    assert parameter_origin(None).kind == "published"


def test_report_with_an_identified_file_states_the_margins_confidence(identified, tmp_path, capsys):
    path, _ = identified
    args = ["report", "--params", str(path), "--motor", str(DRIVE), "--engine", "analytic", "--rate", "200"]
    # The exit status is the rating check's verdict: 1 on FAIL, else 0.
    json_status = main(args + ["--out", str(tmp_path / "b"), "--summary-format", "json"])
    document = json.loads(capsys.readouterr().out)
    assert json_status == (1 if document["verdict"]["level"] == "FAIL" else 0)
    assert len(document["margin_bands"]) == len(document["sizing"]["checks"])
    # The identified report's figures drawn once, above; the runs below are read for their text.
    with figures_undrawn():
        assert main(args + ["--out", str(tmp_path / "a")]) == json_status
    page = (tmp_path / "a" / "index.html").read_text(encoding="utf-8")
    assert "pass with 95 % confidence" in page and "identified" in page
    printed = capsys.readouterr().out
    assert "pass with 95 % confidence" in printed
    published = ["report", "--motor", str(DRIVE), "--engine", "analytic", "--rate", "200", "--out", str(tmp_path / "c")]
    with figures_undrawn():
        json_status = main(published + ["--summary-format", "json"])
    assert json_status == (1 if json.loads(capsys.readouterr().out)["verdict"]["level"] == "FAIL" else 0)
    assert "95 % confidence" not in (tmp_path / "c" / "index.html").read_text(encoding="utf-8")
