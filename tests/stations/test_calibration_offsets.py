"""Calibration with a sensor offset per log: the posterior carries the offsets' trade with the joint patterns, the output
names it, and a fixture's known-attitude rows separate them.

Logs of hidden machines from tests/stations_synthetic.py (SciPy rotations, the chain equations written out): another
route than hipsim.analytic.stations, which the calibration uses.
"""

from __future__ import annotations

import functools
import json

import numpy as np
import pytest
from stations_synthetic import deviated, reference_attitude, reference_carriages, synthetic_log

from hipsim.cli.main import main
from hipsim.machine.parameters import load_parameters
from hipsim.stations import CalibrationLog, calibrate
from hipsim.stations.calibration import prediction_errors
from hipsim.stations.logs import read_calibration_log

PARAMS = load_parameters()
SPREAD = 0.3e-3 / np.sqrt(3.0)  # the hidden machines' values: uniform within ±0.3 mm
OFFSETS = np.radians([[0.2, 0.0, 0.1], [0.0, -0.1, -0.15]])


def fixture_rows(truth, n: int, seed: int):
    """A fixture holds m_1, then m_2, at home: carriages, both attitudes and the known ones (NaN where free)."""
    L: list[np.ndarray] = []
    q: list[np.ndarray] = []
    known: list[np.ndarray] = []
    for j in (1, 2):
        home = np.zeros((n, 3))
        Lj = reference_carriages(PARAMS, truth, j, home)
        L.append(Lj)
        q.append(np.stack([reference_attitude(PARAMS, truth, i, Lj, home) for i in (1, 2)], axis=1))
        k = np.full((n, 2, 3), np.nan)
        k[:, j - 1] = 0.0
        known.append(k)
    attitudes = np.concatenate(q)
    noise = np.random.default_rng(seed).normal(0.0, np.radians(0.05), attitudes.shape)
    return np.concatenate(L), attitudes + noise, np.concatenate(known)


@functools.cache
def _hidden(truth_seed: int):
    return deviated(seed=truth_seed)


@functools.cache
def _motion_log(truth_seed: int, seed: int, n: int):
    """A log of the hidden machine ``truth_seed`` along a motion, made once per test module."""
    return synthetic_log(PARAMS, _hidden(truth_seed), n, seed=seed, noise_deg=0.05)


def log(truth_seed: int, seed: int, offsets=None, fixture: bool = False, n: int = 1200) -> CalibrationLog:
    t, L, _, sensors = _motion_log(truth_seed, seed, n)
    known = None
    if fixture:
        Lf, sf, known = fixture_rows(_hidden(truth_seed), 150, seed + 1)
        L, sensors = np.concatenate([Lf, L]), np.concatenate([sf, sensors])
        known = np.concatenate([known, np.full((n, 2, 3), np.nan)])
        t = np.arange(len(L)) / 500.0
    if offsets is not None:
        sensors = sensors + offsets
    return CalibrationLog(f"log{seed}", t, L, sensors, known)


@pytest.mark.parametrize("seed", [3, 5])
def test_held_out_z_scores_near_one_on_a_hidden_machine_without_offsets(seed):
    """The attitudes a calibration with per-log offsets predicts are off by about what it says (z ~ 1, not 7)."""
    truth = _hidden(seed)
    fit = calibrate([log(seed, 10 + seed), log(seed, 11 + seed)], PARAMS, prior=SPREAD, offsets=True)
    t, L, true, sensors = synthetic_log(PARAMS, truth, 800, seed=40 + seed, noise_deg=0.05)
    q = prediction_errors(fit.machine, CalibrationLog("held", t, L, sensors), offsets=False)[2]
    error = q - true
    z = np.sqrt((error**2).mean(axis=0)) / np.sqrt((fit.prediction_std(q) ** 2).mean(axis=0))
    assert 0.3 < np.sqrt((z**2).mean()) < 1.8 and z.max() < 3.5, z
    # the offsets took a tilt the machine does not have: the error is real, not noise (and up to a constant, tiny)
    assert np.degrees(np.abs(error).mean(axis=0)).max() > 0.02
    shape = error - error.mean(axis=0)
    z_shape = shape.std(axis=0) / np.sqrt((fit.prediction_std(q, up_to_constant=True) ** 2).mean(axis=0))
    assert np.sqrt((z_shape**2).mean()) < 2.0, z_shape


def test_the_output_names_what_trades_and_a_fixture_separates_it():
    free = calibrate([log(3, 20, OFFSETS), log(3, 21, OFFSETS)], PARAMS, offsets=True)
    held = calibrate([log(3, 20, OFFSETS, True), log(3, 21, OFFSETS, True)], PARAMS, offsets=True)
    # Without the fixture: every offset trades with its platform's joint pattern (R² near 1), named.
    assert {c.sensor for c in free.confounded} == {f"{a}_{j}" for j in (1, 2) for a in ("alpha", "beta", "gamma")}
    for c in free.confounded:
        assert (
            c.explained > 0.99 and c.values and all(v.endswith(c.sensor[-1]) or v[-2] == c.sensor[-1] for v in c.values)
        )
        assert "known attitude" in c.separated_by
    # With it: nothing left to trade, and the offsets are the true ones to a few thousandths of a degree.
    assert held.confounded == ()
    err_held = np.degrees(np.abs(held.offsets - OFFSETS)).max()
    err_free = np.degrees(np.abs(free.offsets - OFFSETS)).max()
    assert err_held < 0.01 < 5 * err_held < err_free, (err_held, err_free)


def test_a_fixtures_rows_read_from_the_log_file(tmp_path):
    original = log(3, 30, OFFSETS, fixture=True, n=50)
    assert original.known is not None
    names = ["t_s", "L_11_mm", "L_12_mm", "L_13_mm"]
    names += [f"{a}_{j}_deg" for j in (1, 2) for a in ("alpha", "beta", "gamma")]
    names += [f"known_{a}_{j}_deg" for j in (1, 2) for a in ("alpha", "beta", "gamma")]
    rows = np.column_stack(
        [
            original.t,
            original.carriages * 1e3,
            np.degrees(original.sensors).reshape(-1, 6),
            np.degrees(original.known).reshape(-1, 6),
        ]
    )
    text = (
        ",".join(names) + "\n" + "\n".join(",".join("" if np.isnan(v) else repr(float(v)) for v in row) for row in rows)
    )
    path = tmp_path / "fixture.csv"
    path.write_text(text + "\n", encoding="utf-8")
    read = read_calibration_log(path, PARAMS.lead)
    assert read.known is not None
    assert np.array_equal(np.isnan(read.known), np.isnan(original.known))
    np.testing.assert_allclose(read.known[~np.isnan(read.known)], 0.0, atol=0)
    # a row with one known angle of a platform but not the others is refused by line and column
    broken = text.splitlines()
    cells = broken[1].split(",")
    cells[names.index("known_beta_1_deg")] = ""
    broken[1] = ",".join(cells)
    path.write_text("\n".join(broken) + "\n", encoding="utf-8")
    with pytest.raises(Exception, match=r"fixture.*line 2.*known_beta_1_deg"):
        read_calibration_log(path, PARAMS.lead)


def test_calibrate_prints_and_records_the_confounded_offsets(tmp_path, capsys):
    from stations_synthetic import write_log

    truth = deviated(seed=3)
    paths = []
    for k in range(2):
        t, L, _, sensors = synthetic_log(PARAMS, truth, 600, seed=50 + k, noise_deg=0.05)
        paths += ["--log", str(write_log(tmp_path / f"log{k}.csv", t, L, sensors))]
    out = tmp_path / "cal.toml"
    args = ["calibrate", *paths, "--sensor-offset", "per-log", "--out", str(out)]
    assert main([*args, "--summary-format", "json"]) == 0
    summary = json.loads(capsys.readouterr().out)["summary"]
    assert summary["confounded"] and "known attitude" in summary["confounded"][0]["separated_by"]
    assert "Sensor offset" in out.read_text(encoding="utf-8") and "not told apart" in out.read_text(encoding="utf-8")
