"""Carriage commands for two platforms on one set of carriages, and tolerances before building.

The follower's attitude is checked against tests/stations_synthetic.py's hand-written per-chain machine (SciPy
rotations, Newton on central differences): another route than hipsim.analytic.stations.
"""

from __future__ import annotations

import json

import numpy as np
import pytest
from stations_synthetic import deviated, reference_attitude, reference_carriages

from hipsim.cli.main import main
from hipsim.exceptions import HipsimError, ParameterError
from hipsim.machine.chains import ChainGeometry
from hipsim.machine.parameters import load_parameters
from hipsim.motion.trajectories import iso14242
from hipsim.stations import deviations as dv
from hipsim.stations import station_commands, tolerance_draws
from hipsim.stations import tolerance as tolerance_module
from hipsim.stations.commands import squared_errors
from hipsim.stations.tolerance import error_sensitivity, half_widths, parse_tolerances


@pytest.fixture(scope="module")
def drawing():
    return load_parameters()


@pytest.fixture(scope="module")
def machine(drawing):
    return drawing.replace(geometry=deviated(seed=5, size_mm=0.3))


@pytest.fixture(scope="module")
def cycle():
    return iso14242(rate=100)


@pytest.fixture(scope="module")
def runs(machine, cycle):
    return {c: station_commands(machine, cycle.t, cycle.q, c) for c in ("1", "2", "both")}


def test_a_single_command_is_exact_on_its_platform_and_the_other_follows(drawing, machine, cycle, runs):
    for c in ("1", "2"):
        j, other = int(c), 3 - int(c)
        run = runs[c]
        assert np.allclose(run.carriages, reference_carriages(drawing, machine.geometry, j, cycle.q), atol=1e-13)
        assert np.all(np.abs(run.errors[:, j - 1]) < 1e-12)
        follower = reference_attitude(drawing, machine.geometry, other, run.carriages, cycle.q)
        assert np.allclose(run.attitudes[:, other - 1], follower, atol=1e-11)
        assert np.degrees(np.abs(run.errors[:, other - 1])).max() > 0.05  # 0.3 mm deviations: a visible follower error


@pytest.mark.parametrize("weights", [(1.0, 1.0), (1.0, 3.0)])
def test_both_is_never_worse_than_either_single_command(machine, cycle, runs, weights):
    both = station_commands(machine, cycle.t, cycle.q, "both", weights)
    cost = squared_errors(both.errors, weights)
    singles = [squared_errors(runs[c].errors, weights) for c in ("1", "2")]
    assert np.all(cost <= np.minimum(*singles) * (1 + 1e-12) + 1e-24)
    assert cost.sum() < 0.8 * min(s.sum() for s in singles)  # and much better: it shares the error
    # The attitudes reported are those the commanded carriages give (hand route).
    for j in (1, 2):
        reference = reference_attitude(load_parameters(), machine.geometry, j, both.carriages, cycle.q)
        assert np.allclose(both.attitudes[:, j - 1], reference, atol=1e-11)


def test_with_identical_chains_all_three_commands_are_the_same(drawing, cycle):
    one = deviated(seed=7, size_mm=0.3)
    same = ChainGeometry(
        ujoint=np.stack([one.ujoint[0]] * 2),
        slider=np.stack([one.slider[0]] * 2),
        joint=np.stack([one.joint[0]] * 2),
        lever=np.stack([one.lever[0]] * 2),
        centre=np.stack([one.centre[0]] * 2),
    )
    machine = drawing.replace(geometry=same)
    runs = [station_commands(machine, cycle.t, cycle.q, c) for c in ("1", "2", "both")]
    for run in runs[1:]:
        assert np.allclose(run.carriages, runs[0].carriages, atol=1e-12)
    for run in runs:
        assert np.all(np.abs(run.errors) < 1e-11)


@pytest.mark.parametrize(("at", "control"), [("deviated", "1"), ("deviated", "2"), ("drawing", "both")])
def test_first_order_error_sensitivity_matches_the_commands(drawing, machine, cycle, at, control):
    """S·δ against the commands' own errors for a small δ (for both, at the drawing, where Gauss–Newton is exact)."""
    base = machine if at == "deviated" else drawing
    q, t = cycle.q[::5], cycle.t[::5]
    delta = np.random.default_rng(0).uniform(-1e-5, 1e-5, dv.COUNT)
    moved = dv.machine(base, dv.deviation(base) + delta)
    S = error_sensitivity(base, q, control)
    change = station_commands(moved, t, q, control).errors - station_commands(base, t, q, control).errors
    predicted = S @ delta
    assert np.abs(change - predicted).max() <= 1e-3 * np.abs(predicted).max()


def test_tolerance_monte_carlo_agrees_with_first_order(drawing, cycle):
    q, t = cycle.q[::4], cycle.t[::4]
    bands = parse_tolerances("all=0.1")
    result = tolerance_draws(drawing, t, q, bands, ("2",), draws=200, seed=1, workers=0)
    mean_square = (result.rms[:, 0, 0] ** 2).mean(axis=0)  # the follower m_1, per angle
    S = error_sensitivity(drawing, q, "2")
    expected = ((S[:, 0] ** 2).mean(axis=0) @ (half_widths(bands) ** 2 / 3)).ravel()
    assert np.all(np.abs(mean_square / expected - 1) < 0.2), mean_square / expected
    assert np.all(result.rms[:, 0, 1] < 1e-12)  # the controlled platform is exact on every machine
    shares = [row["share"] for row in result.sensitivity["2"]]
    assert shares == sorted(shares, reverse=True) and abs(sum(shares) - 1) < 1e-12


def test_tolerance_draws_on_dask_equal_those_in_process(drawing, cycle, monkeypatch):
    monkeypatch.setattr(tolerance_module, "BATCH", 5)
    q, t = cycle.q[::10], cycle.t[::10]
    bands = parse_tolerances("all=0.3")
    local = tolerance_draws(drawing, t, q, bands, ("both",), draws=12, workers=0)
    spread = tolerance_draws(drawing, t, q, bands, ("both",), draws=12, workers=2)
    assert np.array_equal(local.rms, spread.rms) and np.array_equal(local.peak, spread.peak)


def test_a_band_that_puts_a_chain_out_of_reach_is_refused(drawing, cycle):
    with pytest.raises(HipsimError, match="out of reach"):
        tolerance_draws(drawing, cycle.t[::10], cycle.q[::10], parse_tolerances("lever=45"), draws=20, workers=0)


def test_parse_tolerances(tmp_path):
    bands = parse_tolerances("all=0.1, lever=±0.05")
    # "all" is the chains' families: the stack-up's seat is drawn only when named.
    assert bands == {"ujoint": 1e-4, "slider": 1e-4, "joint": 1e-4, "lever": 5e-5, "centre": 1e-4}
    assert parse_tolerances("all=0.1, spline=0.2")["spline"] == pytest.approx(2e-4)
    (tmp_path / "tol.toml").write_text("[tolerance]\nujoint = 0.2\n")
    assert parse_tolerances(str(tmp_path / "tol.toml"))["ujoint"] == pytest.approx(2e-4)
    assert parse_tolerances(str(tmp_path / "tol.toml"))["lever"] == 0.0
    for bad in ("levers=0.1", "all=-1", "all=x", "all"):
        with pytest.raises(ParameterError):
            parse_tolerances(bad)


def test_stations_command(tmp_path, capsys):
    lever = "geometry.lever_offset_mm=[0.3, 0, 0, 0, -0.2, 0]"
    out = tmp_path / "run"
    assert (
        main(
            [
                "stations",
                "--set",
                lever,
                "--control",
                "both",
                "--rate",
                "100",
                "--out",
                str(out),
                "--summary-format",
                "json",
            ]
        )
        == 0
    )
    summary = json.loads(capsys.readouterr().out)["summary"]
    header = (out / "stations.csv").read_text().splitlines()[0].split(",")
    assert header == [
        "t_s",
        "L_11_mm",
        "L_12_mm",
        "L_13_mm",
        *(f"{a}_{j}_deg" for j in (1, 2) for a in ("alpha", "beta", "gamma")),
        *(f"err_{a}_{j}_deg" for j in (1, 2) for a in ("alpha", "beta", "gamma")),
        "Fe_N",
    ]
    table = np.genfromtxt(out / "stations.csv", delimiter=",", names=True)
    assert summary["platforms"][0]["angles"]["gamma"]["rms_deg"] == pytest.approx(
        np.sqrt(np.mean(table["err_gamma_1_deg"] ** 2)), rel=1e-9
    )
    assert summary["platforms"][0]["iso"]["verdict"] == "PASS"
    assert (out / "index.html").exists() and (out / "errors.png").exists()
    # The same table as Parquet, by its suffix.
    parquet = tmp_path / "run.parquet"
    argv = ["stations", "--set", lever, "--control", "both", "--rate", "100", "--out", str(tmp_path / "p")]
    assert main([*argv, "--table", str(parquet)]) == 0
    import pyarrow.parquet as pq

    frame = pq.read_table(parquet)
    assert frame.column_names == header
    assert np.allclose(frame.column("err_gamma_1_deg").to_numpy(), table["err_gamma_1_deg"], rtol=1e-10, atol=1e-13)
    # --sliders: the attitudes of both platforms from the logged carriages are those the run reported.
    again = tmp_path / "sliders"
    assert main(["stations", "--set", lever, "--sliders", str(out / "stations.csv"), "--out", str(again)]) == 0
    read = np.genfromtxt(again / "stations.csv", delimiter=",", names=True)
    assert np.allclose(read["gamma_1_deg"], table["gamma_1_deg"], atol=1e-8)
    capsys.readouterr()
    # Bad input: one line, status 2, nothing written.
    for argv, words in (
        (["--weights", "1"], "--weights"),
        (["--bands", "lever=45", "--draws", "20", "--workers", "1"], "out of reach"),
        (["--control", "all"], "--control all"),
        (["--bands", "spring=0.1"], "unknown tolerance"),
    ):
        bad = tmp_path / "bad"
        assert main(["stations", "--rate", "100", "--out", str(bad), *argv]) == 2, argv
        error = capsys.readouterr().err
        assert error.startswith("hipsim: error:") and error.count("\n") == 1 and words in error, error
        assert not bad.exists()
