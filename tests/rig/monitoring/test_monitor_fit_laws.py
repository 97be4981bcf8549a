"""hipsim.rig.monitoring.monitor_fit by hand: the sandwich standard error on a 3-row regressor worked out in fractions
(its lag window, its degrees of freedom, rows of one sample summed), and one snapshot's row on tiny exact logs written
here by the analytic model (hipsim.analyse, not the monitor's regressor): the terms it recovers, the window it passes
(rows per independent row: the low-pass's inflation and the model error's floor), the samples it refuses, the split
per station, a batch that skips a bad file.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from monitor_synthetic import EXACT_MACHINE, write_exact, write_snapshot

import hipsim
from hipsim.exceptions import IdentificationError, ParameterError, TrajectoryError
from hipsim.fingerprint import fingerprint
from hipsim.rig.monitoring import monitor_fit
from hipsim.rig.monitoring.monitor_fit import (
    ESTIMATE_COLUMNS,
    ESTIMATOR,
    STATION_SEPARABLE,
    MonitorSetup,
    _solve,
    estimate,
    estimate_batch,
)
from hipsim.rig.monitoring.snapshots import Skipped, find_snapshots

PARAMS = hipsim.load_parameters()
MACHINE = EXACT_MACHINE

# The regressor worked by hand: columns (1, 0, 1) and (0, 1, 1), targets (1, 2, 4). AᵀA = [[2, 1], [1, 2]],
# x = (4/3, 7/3), residual (-1/3, -1/3, 1/3), scores g_t = A_t·r_t = (-1/3, 0), (0, -1/3), (1/3, 1/3);
# the residual is short of 2 of 3 degrees of freedom: the covariance times 3/(3 - 2) = 3.
A = np.array([[1.0, 0.0], [0.0, 1.0], [1.0, 1.0]])
Y = np.array([1.0, 2.0, 4.0])


def test_the_sandwich_by_hand_for_windows_0_1_2():
    # window 0: S = Σ g·gᵀ = [[2, 1], [1, 2]]/9, (AᵀA)⁻¹·S·(AᵀA)⁻¹·3 = [[2, -1], [-1, 2]]/9.
    # window 1: S += (1 - 1/2)·(C + Cᵀ), C = g_0·g_1ᵀ + g_1·g_2ᵀ, so S = [[2, 1], [1, 1]]/9 and the covariance
    # [[5, -1], [-1, 2]]/27. window 2: lag 1 weighted 2/3, lag 2 (g_0·g_2ᵀ) 1/3: S = [[4, 2], [2, 2]]/27,
    # the covariance [[10, -2], [-2, 4]]/81.
    for window, std in (
        (0, (math.sqrt(2) / 3, math.sqrt(2) / 3)),
        (1, (math.sqrt(5 / 27), math.sqrt(2 / 27))),
        (2, (math.sqrt(10) / 9, 2 / 9)),
    ):
        x, s, residual = _solve(A, Y, np.array([0, 1, 2]), window)
        np.testing.assert_allclose(x, [4 / 3, 7 / 3], rtol=1e-14)
        np.testing.assert_allclose(residual, [-1 / 3, -1 / 3, 1 / 3], rtol=1e-13)
        np.testing.assert_allclose(s, std, rtol=1e-13, err_msg=f"window {window}")


def test_rows_of_one_sample_are_summed_before_the_window():
    # Rows 0 and 1 of one sample (two motors): g_0 = (-1/3, -1/3), g_1 = (1/3, 1/3); S = 2/9·[[1, 1], [1, 1]],
    # (AᵀA)⁻¹·(1, 1)ᵀ = (1, 1)ᵀ/3: the covariance 3·(2/81)·[[1, 1], [1, 1]], each deviation √(2/27).
    x, s, _ = _solve(A, Y, np.array([0, 0, 1]), 0)
    np.testing.assert_allclose(x, [4 / 3, 7 / 3], rtol=1e-14)
    np.testing.assert_allclose(s, [math.sqrt(2 / 27)] * 2, rtol=1e-13)
    # Samples two apart are beyond a window of 1: the same deviations as with no window.
    np.testing.assert_allclose(_solve(A, Y, np.array([0, 2, 4]), 1)[1], [math.sqrt(2) / 3] * 2, rtol=1e-13)
    # Within a window of 2 the pairs 0-2 and 2-4 are two apart, weighted 1 - 2/3: S = [[6, 3], [3, 4]]/27, the
    # covariance [[16, -5], [-5, 10]]/81.
    np.testing.assert_allclose(_solve(A, Y, np.array([0, 2, 4]), 2)[1], [4 / 9, math.sqrt(10) / 9], rtol=1e-13)


def test_the_columns_scale_and_the_degrees_of_freedom():
    # A column in other units: its estimate and deviation in those units, the other column's unchanged.
    x, s, residual = _solve(A * [1000.0, 1.0], Y, np.array([0, 1, 2]), 1)
    np.testing.assert_allclose(x, [4 / 3000, 7 / 3], rtol=1e-13)
    np.testing.assert_allclose(s, [math.sqrt(5 / 27) / 1000, math.sqrt(2 / 27)], rtol=1e-12)
    np.testing.assert_allclose(residual, [-1 / 3, -1 / 3, 1 / 3], rtol=1e-12)
    # Four rows, one column (1, 1, 1, 1) against (0, 0, 0, 4): x = 1, residual (-1, -1, -1, 3), S = 12,
    # (AᵀA)⁻¹ = 1/4, times 4/(4 - 1): the variance 12/16·4/3 = 1.
    x, s, _ = _solve(np.ones((4, 1)), np.array([0.0, 0.0, 0.0, 4.0]), np.arange(4), 0)
    assert x == pytest.approx([1.0], rel=1e-15) and s == pytest.approx([1.0], rel=1e-14)
    # As many rows as columns: an exact fit, no deviation (the factor's floor of one row does not divide by zero).
    x, s, residual = _solve(A[:2], Y[:2], np.array([0, 1]), 0)
    np.testing.assert_allclose(x, [1.0, 2.0], rtol=1e-15)
    assert np.all(s == 0.0) and np.all(np.abs(residual) < 1e-15)


def test_dependent_columns_give_nan_and_infinite_deviations():
    for columns in (np.column_stack([A[:, 0], 2 * A[:, 0]]), np.column_stack([A[:, 0], 0 * A[:, 0]])):
        x, s, residual = _solve(columns, Y, np.array([0, 1, 2]), 0)
        assert np.all(np.isnan(x)) and np.all(np.isinf(s)) and np.all(np.isnan(residual))
        assert x.shape == (2,) and s.shape == (2,) and residual.shape == (3,)
    # Columns (1, 0, 1) and (1, d, 1), each of unit norm: singular values √2 and d/2 (to first order in d). Dependent
    # below d/2 = 1e-6·√2: d = 2e-6 is, d = 4e-6 is not.
    for d, dependent in ((2e-6, True), (4e-6, False)):
        close = np.column_stack([A[:, 0], A[:, 0] + [0.0, d, 0.0]])
        assert np.all(np.isnan(_solve(close, Y, np.array([0, 1, 2]), 0)[0])) == dependent, d
    # Columns of very different sizes are each scaled to unit norm first: not mistaken for dependent ones.
    for scale in (1e7, 1e-7):
        x, s, _ = _solve(A * [scale, 1.0], Y, np.array([0, 1, 2]), 0)
        np.testing.assert_allclose(x, [4 / 3 / scale, 7 / 3], rtol=1e-9)
        np.testing.assert_allclose(s, [math.sqrt(2) / 3 / scale, math.sqrt(2) / 3], rtol=1e-9)


# ---------------------------------------------------------------------------------------------------- the snapshot's row


def snapshot(path: Path):
    (found,), _ = find_snapshots(str(path))
    return found


def terms(machine=MACHINE) -> dict[str, float]:
    """The fitted terms of a machine in the row's units (N·mm per N of load, N·mm, N·mm·s/rad)."""
    f = machine.friction
    return {
        "load_friction_mm": (f.hip_radius * f.hip_mu + f.thrust_radius * f.thrust_mu) * 1e3,
        "weight_friction_Nmm": f.thrust_radius * f.thrust_mu * machine.platform_mass * machine.gravity * 1e3,
        "screw_coulomb_Nmm": f.screw_coulomb * 1e3,
        "screw_viscous_Nmm_s_rad": f.screw_viscous * 1e3,
    }


@pytest.fixture
def solved(monkeypatch):
    """Every call of the fit's least squares, its arguments and results, as it ran."""
    calls = []

    def spy(A, y, time, window):
        out = _solve(A, y, time, window)
        calls.append({"A": A, "y": y, "time": time, "window": window, "out": out})
        return out

    monkeypatch.setattr(monitor_fit, "_solve", spy)
    return calls


def test_an_exact_log_gives_the_machine_s_terms(tmp_path, solved):
    path = write_exact(tmp_path / "snap.csv", first_cycle=1_000_000, cycles=2)
    row = estimate(MonitorSetup(MACHINE, cutoff=None), snapshot(path))
    assert set(row) == set(ESTIMATE_COLUMNS)
    for name, value in terms().items():  # the weight's term, small beside the others, to 0.1 %: the derivatives' error
        assert row[name] == pytest.approx(value, rel=1e-3 if name.startswith("weight") else 2e-4), name
    data = path.read_bytes()
    assert (row["cycle"], row["last_cycle"], row["file"], row["samples"]) == (1_000_000, 1_000_001, "snap.csv", 100)
    assert (row["bytes"], row["note"]) == (len(data), "")
    assert row["sha256"] == snapshot(path).sha256 and math.isnan(row["load_gain"])
    # The row's numbers are the fit's, in N·mm: the deviations and the residual's RMS.
    (call,) = solved
    x, std, residual = call["out"]
    for k, name in enumerate(
        ("load_friction_mm", "weight_friction_Nmm", "screw_coulomb_Nmm", "screw_viscous_Nmm_s_rad")
    ):
        assert row[name] == x[k] * 1e3 and row[name + "_std"] == std[k] * 1e3
    assert row["residual_rms_Nmm"] == pytest.approx(1e3 * np.sqrt(np.mean(residual**2)), rel=1e-12)
    assert 0 < row["residual_rms_Nmm"] < 0.01  # 17 digits: the derivatives' error only
    # The rows: 100 samples of 3 motors, all used (no filter, no reversal here), 4 columns; each row's sample.
    assert call["A"].shape == (len(call["time"]), 4) and np.all(np.diff(call["time"]) >= 0)
    assert call["time"][0] == 0 and call["time"][-1] == 99
    assert row["stations"] == "not logged" and math.isnan(row["load_friction_1_mm"])


def test_the_window_is_the_rows_per_independent_row(tmp_path, solved):
    # No filter at 50 Hz: 50 rows a second over twice the model error's 10 Hz bandwidth, 2.5: a window of 3.
    estimate(MonitorSetup(MACHINE, cutoff=None), snapshot(write_exact(tmp_path / "a.csv")))
    # 250 Hz through 20 Hz: every 3rd sample kept (250 // 80), 83.3 rows a second; the filter's inflation
    # 83.3/(2·20) = 2.08 is below the floor 83.3/(2·10) = 4.17: a window of 5 rows, the rows 3 samples apart.
    row = estimate(MonitorSetup(MACHINE, cutoff=20.0), snapshot(write_exact(tmp_path / "b.csv", rate=250.0, cycles=2)))
    assert [call["window"] for call in solved] == [3, 5]
    time = solved[1]["time"]
    # Rows of every kept sample (gaps only at the reversals left out), counted in kept rows, not samples.
    assert np.all(np.diff(time) >= 0) and time[0] >= 0 and time[-1] < 500 / 3 and len(np.unique(time)) > 100
    for name, value in terms().items():
        assert row[name] == pytest.approx(value, rel=2e-3), name


def test_the_model_s_lever_spin_is_the_set_up_s(tmp_path):
    # Levers of a large axial inertia (0.09 kg·m², 190 times the published), whose spin shows in the torques.
    machine = MACHINE.replace(lever_inertia=np.diag([0.05, 0.05, 0.09]))
    for spin in (False, True):
        path = write_exact(tmp_path / "spin.csv", machine, lever_spin=spin)
        right = estimate(MonitorSetup(machine, lever_spin=spin, cutoff=None), snapshot(path))
        wrong = estimate(MonitorSetup(machine, lever_spin=not spin, cutoff=None), snapshot(path))
        assert right["residual_rms_Nmm"] < 0.01 < 0.05 < wrong["residual_rms_Nmm"], spin
        assert right["weight_friction_Nmm"] == pytest.approx(terms()["weight_friction_Nmm"], rel=1e-3)


def test_no_weight_term_without_a_platform_weight_or_a_thrust_radius(tmp_path):
    for machine in (MACHINE.replace(platform_mass=0.0), MACHINE.replace(thrust_radius=0.0)):
        row = estimate(MonitorSetup(machine, cutoff=None), snapshot(write_exact(tmp_path / "w.csv", machine)))
        assert math.isnan(row["weight_friction_Nmm"]) and math.isnan(row["weight_friction_Nmm_std"])
        for name in ("load_friction_mm", "screw_coulomb_Nmm", "screw_viscous_Nmm_s_rad"):
            assert row[name] == pytest.approx(terms(machine)[name], rel=2e-4), name


def test_a_file_without_a_last_line_end_is_noted(tmp_path):
    row = estimate(MonitorSetup(MACHINE, cutoff=None), snapshot(write_exact(tmp_path / "cut.csv", newline=False)))
    assert row["note"] == "no line end after its last line: the file may be cut"


def test_too_few_samples_left_are_refused_at_the_edge(tmp_path, monkeypatch):
    # The reversals' mask decides which rows are used: all but `used` of them marked. Four columns: more than
    # 4 + 2 = 6 rows are needed.
    path = write_exact(tmp_path / "few.csv")
    for used, refused in ((6, True), (7, False)):

        def mask(params, log, used=used):
            near = np.ones((len(log), 3), dtype=bool)
            near.flat[:used] = False
            return near

        monkeypatch.setattr(monitor_fit, "reversal_mask", mask)
        if refused:
            with pytest.raises(IdentificationError) as error:
                estimate(MonitorSetup(MACHINE, cutoff=None), snapshot(path))
            assert str(error.value) == (
                f"{path}: 6 samples left after the filter's edges and the reversals: too few to estimate from"
            )
            assert error.value.logs == (str(path),)
        else:
            row = estimate(MonitorSetup(MACHINE, cutoff=None), snapshot(path))
            assert np.isfinite(row["load_friction_mm"])


def test_the_stations_apart_when_their_loads_differ(tmp_path, solved):
    rng = np.random.default_rng(3)
    path = write_snapshot(
        tmp_path / "s.csv",
        MACHINE,
        0.1,
        0,
        rng,
        cycles=2,
        rate=50.0,
        torque_noise_Nmm=0.0,
        angle_noise_deg=0.0,
        station_loads=(0.9, 1.1),
        station_mu=(0.09, 0.13),
    )
    row = estimate(MonitorSetup(MACHINE, cutoff=None), snapshot(path))
    assert row["stations"] == "separated" and set(row) == set(ESTIMATE_COLUMNS)
    _, std, _ = solved[1]["out"]  # the fit with the stations' two columns
    assert (row["load_friction_1_mm_std"], row["load_friction_2_mm_std"]) == (std[0] * 1e3, std[1] * 1e3)
    for p, mu in ((1, 0.09), (2, 0.13)):
        assert row[f"load_friction_{p}_mm"] == pytest.approx(
            terms(MACHINE.replace(hip_mu=mu))["load_friction_mm"], rel=1e-3
        )
        assert 0 < row[f"load_friction_{p}_mm_std"] < STATION_SEPARABLE * row["load_friction_mm"]


def test_proportional_station_loads_cannot_be_told_apart(tmp_path):
    path = write_exact(tmp_path / "s.csv")
    lines = path.read_text().splitlines()
    k = lines[0].split(",").index("Fe_N")
    halves = [f"{float(line.split(',')[k]) / 2!r}" for line in lines[1:]]
    path.write_text(
        "\n".join([lines[0] + ",Fe_1_N,Fe_2_N"] + [f"{ln},{h},{h}" for ln, h in zip(lines[1:], halves)]) + "\n"
    )
    row = estimate(MonitorSetup(MACHINE, cutoff=None), snapshot(path))
    assert row["stations"] == "not separable: the two stations' loads are proportional"
    assert all(math.isnan(row[f"load_friction_{p}_mm{s}"]) for p in (1, 2) for s in ("", "_std"))
    assert row["load_friction_mm"] == pytest.approx(terms()["load_friction_mm"], rel=2e-4)


def test_station_loads_too_alike_are_not_split(tmp_path):
    # Loads that differ by a 1 % wobble: separable in principle, but each station's deviation is over 20 % of the term.
    rng = np.random.default_rng(5)
    path = write_snapshot(
        tmp_path / "s.csv",
        MACHINE,
        0.1,
        0,
        rng,
        cycles=1,
        rate=50.0,
        torque_noise_Nmm=3.0,
        angle_noise_deg=0.0,
        station_loads=(1.0, 1.0),
        wobble=(0.01, 1.0),
    )
    row = estimate(MonitorSetup(MACHINE, cutoff=None), snapshot(path))
    assert row["stations"] == (
        "not separable: the two stations' loads vary too much alike (standard deviation over 20% of the term)"
    )
    assert math.isnan(row["load_friction_1_mm"]) and math.isnan(row["load_friction_2_mm_std"])


def test_a_batch_skips_what_cannot_be_read_and_keeps_the_rest(tmp_path):
    good = snapshot(write_exact(tmp_path / "good.csv"))
    bad_path = tmp_path / "bad.csv"
    rows = "".join(f"{k / 50},1,0,0,0,1,1,1\n" for k in range(60))
    bad_path.write_text("t_s,Fe_N,alpha_deg,beta_deg,gamma_deg,tau_1_Nmm,tau_2_Nmm,tau_3_Nmm\n" + rows)
    bad = snapshot(bad_path)
    out = estimate_batch([bad, good], MonitorSetup(MACHINE, cutoff=None))
    assert isinstance(out[0], Skipped) and isinstance(out[1], dict) and len(out) == 2
    identity = (bad.size, bad.sha256)  # the refused file's, kept
    assert out[0] == Skipped("bad.csv", str(bad_path), out[0].reason, "unreadable", None, *identity)
    assert out[0].reason.startswith(f"{bad_path}") and "'cycle'" in out[0].reason
    assert out[1]["file"] == "good.csv" and estimate_batch([], MonitorSetup(MACHINE)) == []


def test_the_set_up_refuses_what_the_load_term_cannot_read():
    with pytest.raises(ParameterError) as error:
        MonitorSetup(PARAMS.replace(thrust_bearing_axial_only=True))
    assert error.value.key == "friction.thrust_bearing_axial_only" and error.value.value is True
    assert str(error.value) == (
        f"{PARAMS.source}, key 'friction.thrust_bearing_axial_only': the monitor's load term r_h·μ_h + r_t·μ_t "
        "needs the thrust bearing's moment along ω (friction.thrust_bearing_axial_only = false)"
    )
    assert error.value.source == PARAMS.source
    for radius in (0.0, -0.01):
        with pytest.raises(ParameterError) as error:
            MonitorSetup(PARAMS.replace(hip_radius=radius))
        assert error.value.key == "friction.hip_radius_mm" and error.value.value == radius
        assert str(error.value) == (
            f"{PARAMS.source}, key 'friction.hip_radius_mm': the hip joint's friction radius must be positive to read "
            "its friction"
        )
    MonitorSetup(PARAMS.replace(hip_radius=1e-6))  # any positive radius


def test_every_part_of_the_set_up_is_in_its_fingerprint():
    base = MonitorSetup(PARAMS)
    assert (base.lever_spin, base.cutoff, base.torque_constant, base.window, base.rate) == (
        True,
        20.0,
        None,
        None,
        None,
    )
    prints = base.fingerprints()
    assert set(prints) == {"parameters", "model", "window", "estimator", "setup"}
    assert prints == MonitorSetup(PARAMS).fingerprints()
    for change, part in (
        ({"lever_spin": False}, "model"),
        ({"cutoff": None}, "model"),
        ({"torque_constant": 0.1}, "model"),
        ({"tolerance_deg": 1.0}, "model"),
        ({"rate": 100.0}, "model"),
        ({"window": 2}, "window"),
        ({"params": MACHINE}, "parameters"),
    ):
        other = MonitorSetup(**({"params": PARAMS} | change)).fingerprints()
        assert [name for name in prints if prints[name] != other[name]] == [part, "setup"], change
    assert ESTIMATOR == "monitor-2"
    # Each part is the fingerprint of what it names (a table written by an earlier run stays resumable).
    model = {"lever_spin": True, "cutoff": 20.0, "torque_constant": None, "tolerance_deg": 0.5, "rate": None}
    parts = {"parameters": fingerprint(PARAMS), "model": fingerprint(model), "window": fingerprint(None)}
    parts["estimator"] = fingerprint("monitor-2")
    assert prints == parts | {"setup": fingerprint(parts)}


def test_the_stations_loads_filtered_as_the_log_s(tmp_path):
    # At 250 Hz through 20 Hz: the stations' loads go through the torques' low-pass, so each station's term is
    # recovered as without a filter (to the filter's edges and the derivatives: 0.5 %).
    path = write_snapshot(
        tmp_path / "s.csv",
        MACHINE,
        0.1,
        0,
        np.random.default_rng(3),
        cycles=2,
        rate=250.0,
        torque_noise_Nmm=0.0,
        angle_noise_deg=0.0,
        station_loads=(0.9, 1.1),
        station_mu=(0.09, 0.13),
    )
    row = estimate(MonitorSetup(MACHINE, cutoff=20.0), snapshot(path))
    assert row["stations"] == "separated"
    for p, mu in ((1, 0.09), (2, 0.13)):
        expected = terms(MACHINE.replace(hip_mu=mu))["load_friction_mm"]
        assert row[f"load_friction_{p}_mm"] == pytest.approx(expected, rel=5e-3)


def test_chunks_give_the_rows_of_one(tmp_path, monkeypatch):
    # 500 samples at 250 Hz through 20 Hz, every 3rd kept. Chunks of 101 samples are cut to whole steps (99, 33 rows
    # each): the same samples kept as in one chunk, and each chunk's filter run over the 200 samples around it
    # (16 periods of the cutoff) gives the same columns to round-off.
    snap = snapshot(write_exact(tmp_path / "c.csv", rate=250.0, cycles=2))
    blocks = []
    real = monitor_fit._rows

    def spy(*args):
        blocks.append(list(real(*args)))
        return iter(blocks[-1])

    monkeypatch.setattr(monitor_fit, "_rows", spy)
    one = estimate(MonitorSetup(MACHINE, cutoff=20.0), snap)
    monkeypatch.setattr(monitor_fit, "CHUNK", 101)
    chunked = estimate(MonitorSetup(MACHINE, cutoff=20.0), snap)
    whole, parts = blocks
    assert len(whole) == 1 and [len(b[0]) for b in parts] == [33, 33, 33, 33, 2]
    for k in range(5):  # fixed torque, columns, measured torque, rows to use, stations
        if k == 4:
            assert whole[0][k] is None and all(b[k] is None for b in parts)
            continue
        joined = np.concatenate([b[k] for b in parts])
        if k in (2, 3):
            np.testing.assert_array_equal(joined, whole[0][k])
        else:
            np.testing.assert_allclose(joined, whole[0][k], rtol=0, atol=1e-12 * np.abs(whole[0][k]).max())
    for name in terms():
        assert chunked[name] == pytest.approx(one[name], rel=1e-9), name


def test_the_set_up_s_reading_options_reach_the_snapshot(tmp_path):
    a = terms()["load_friction_mm"]
    # Slider heights from the encoders (the machine's kinematics read them) beside angles 1° off: refused at the
    # default tolerance of 0.5°, read at 2°.
    path = write_exact(tmp_path / "enc.csv", encoders=True, angle_offset_deg=1.0)
    with pytest.raises(TrajectoryError, match="disagree by 1° in alpha"):
        estimate(MonitorSetup(MACHINE, cutoff=None), snapshot(path))
    row = estimate(MonitorSetup(MACHINE, cutoff=None, tolerance_deg=2.0), snapshot(path))
    assert row["load_friction_mm"] == pytest.approx(a, rel=2e-4)
    # Currents through the torque constant.
    path = write_exact(tmp_path / "amps.csv", torque_constant=0.5)
    row = estimate(MonitorSetup(MACHINE, cutoff=None, torque_constant=0.5), snapshot(path))
    assert row["load_friction_mm"] == pytest.approx(a, rel=2e-4)
    # Time stamps rounded down to 30 ms at 50 Hz (some repeat): read from the sample index at the rate given.
    path = write_exact(tmp_path / "coarse.csv", cycles=2, stamp_step=0.03)
    row = estimate(MonitorSetup(MACHINE, cutoff=None, rate=50.0), snapshot(path))
    assert row["load_friction_mm"] == pytest.approx(a, rel=2e-4)


def test_a_light_platform_s_weight_term(tmp_path):
    # 50 g: a weight of 0.49 N, below one newton, still a term of its own (r_t·μ_t·m_m·g = 0.784 N·mm).
    machine = MACHINE.replace(platform_mass=0.05)
    row = estimate(MonitorSetup(machine, cutoff=None), snapshot(write_exact(tmp_path / "w.csv", machine)))
    # Weakly determined beside a load term of 3.1 N·mm per N (the derivatives' error moves it by a fifth): fitted.
    assert row["weight_friction_Nmm"] == pytest.approx(terms(machine)["weight_friction_Nmm"], rel=0.3)
    assert row["load_friction_mm"] == pytest.approx(terms(machine)["load_friction_mm"], rel=2e-4)


def test_the_first_and_last_cycles_are_the_counter_s_ends(tmp_path):
    path = write_exact(tmp_path / "c.csv")
    lines = path.read_text().splitlines()
    counter = [7] + [8] * (len(lines) - 3) + [9]  # 7 on the first sample, 9 on the last
    lines[1:] = [",".join([ln.split(",")[0], str(c), *ln.split(",")[2:]]) for ln, c in zip(lines[1:], counter)]
    path.write_text("\n".join(lines) + "\n")
    row = estimate(MonitorSetup(MACHINE, cutoff=None), snapshot(path))
    assert (row["cycle"], row["last_cycle"]) == (7, 9)


def test_the_encoders_are_read_with_the_set_up_s_machine(tmp_path):
    # Levers 5 % longer than the published machine's: its slider heights are no pose of the published one.
    machine = MACHINE.replace(lever_length=MACHINE.lever_length * 1.05)
    row = estimate(
        MonitorSetup(machine, cutoff=None), snapshot(write_exact(tmp_path / "e.csv", machine, encoders=True))
    )
    assert row["load_friction_mm"] == pytest.approx(terms(machine)["load_friction_mm"], rel=2e-4)
