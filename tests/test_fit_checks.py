"""Fits that check themselves (issue 48): each gate of hipsim.fit_checks at its boundary, and calibrate's gates end to end.

The gates' laws are pinned on hand-made numbers; the end-to-end cases are the
issue's slips on synthetic logs of a known machine (tests/stations_synthetic.py,
made by the reference kinematics, not by the calibration under test).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from stations_synthetic import deviated, synthetic_log, write_log

from hipsim.cli.main import main
from hipsim.fit_checks import (
    NOISE_FLOOR,
    PATTERN_GAIN,
    PRIOR_SIGMA,
    RESIDUAL_FACTOR,
    FitCheck,
    column_pattern,
    difference_noise,
    duplicate_inputs,
    fit_verdict,
    prior_gate,
    residual_gate,
)
from hipsim.machine.parameters import load_parameters
from hipsim.records import Level, exit_status

NAMES = ("a", "b", "c")


def test_the_thresholds_are_the_issues():
    assert (RESIDUAL_FACTOR, PRIOR_SIGMA, PATTERN_GAIN, NOISE_FLOOR) == (3.0, 5.0, 0.5, 0.05)


def test_residuals_at_three_times_the_noise_pass_and_above_fail():
    assert residual_gate([3.0, 1.0, 0.0], [1.0, 1.0, 1.0], NAMES, "N·mm") is None
    found = residual_gate([3.0 + 1e-9, 1.0, 7.5], [1.0, 1.0, 2.5], NAMES, "N·mm")
    assert found == "residuals beyond 3 times the noise: a 3 N·mm (3×)"
    # a zero noise: any residual is beyond it, none is not
    assert residual_gate([0.0], [0.0], NAMES, "°") is None
    assert "(inf×)" in str(residual_gate([1e-3], [0.0], NAMES, "°"))
    assert "(nan" in str(residual_gate([math.nan], [1.0], NAMES, "°"))  # NaN never passes


def test_a_move_of_five_prior_sigma_passes_and_beyond_fails():
    assert prior_gate([10.0, -4.0], [0.0, 6.0], [2.0, 2.0], ("x", "y"), "mm") is None  # 5σ both
    found = prior_gate([10.0, -4.001, 99.0], [0.0, 6.0, 0.0], [2.0, 2.0, 0.0], ("x", "y", "held"), "mm")
    assert found == "beyond 5 prior standard deviations: y -10 mm (5σ)"  # 5.0005σ shown at 3 digits; 'held' skipped
    many = prior_gate(np.arange(6) + 10.0, np.zeros(6), np.ones(6), tuple("uvwxyz"), "")
    assert (
        many is not None
        and many.startswith("beyond 5 prior standard deviations: z +15  (15σ)")
        and many.endswith("and 2 more")
    )


def _signals(n=200):
    t = np.linspace(0.0, 1.0, n)
    return np.column_stack([np.sin(2 * np.pi * t), 2 * np.cos(2 * np.pi * 3 * t), 0.5 + t**2])


def test_column_patterns_are_named():
    q = _signals()
    assert column_pattern(q[:, [1, 0, 2]], q, NAMES) == "columns a and b look swapped"
    flipped = q.copy()
    flipped[:, 2] *= -1
    assert column_pattern(flipped, q, NAMES) == "column c looks sign-flipped"
    offset = q.copy()
    offset[:, 1] += 3.0
    assert column_pattern(offset, q, NAMES, "°") == "column b looks offset by +3 ° (a zero?)"
    assert column_pattern(q * math.pi / 180, q, NAMES) == "the columns look like radians read as degrees"
    assert column_pattern(q, q, NAMES) is None  # nothing to explain
    six = np.column_stack([q, q + 5.0])
    names = ("a1", "b1", "c1", "a2", "b2", "c2")
    assert (
        column_pattern(six[:, [3, 4, 5, 0, 1, 2]], six, names)
        == "the two halves (a1, b1, c1) and (a2, b2, c2) look swapped"
    )


def test_a_pattern_that_removes_exactly_half_is_not_named():
    q = _signals(100)
    y = q.copy()
    d = np.where(np.arange(100) % 2 == 0, 1.0, -1.0)
    y[:, 0] += 1.0 + d  # offset 1 and a zero-mean ±1: the offset removes 100 of 200
    assert column_pattern(y, q, NAMES) is None
    y[:, 0] = q[:, 0] + 1.0 + 0.99 * d  # the offset now removes more than half
    assert column_pattern(y, q, NAMES) == "column a looks offset by +1 (a zero?)"


def test_difference_noise_measures_white_noise_and_ignores_a_cubic():
    t = np.linspace(0.0, 1.0, 4001)
    cubic = 3 * t**3 - t + 2
    assert np.allclose(difference_noise(cubic), 0.0, atol=1e-9)
    noisy = np.column_stack([cubic, np.sin(3 * t)]) + np.random.default_rng(1).normal(0.0, 0.1, (t.size, 2))
    assert np.allclose(difference_noise(noisy), 0.1, rtol=0.06)
    assert np.isnan(difference_noise(np.zeros(4)))


def test_the_same_file_twice_is_found_by_its_bytes(tmp_path):
    a, b, c = tmp_path / "a.csv", tmp_path / "copy.csv", tmp_path / "c.csv"
    a.write_text("t_s\n0\n")
    b.write_text("t_s\n0\n")
    c.write_text("t_s\n1\n")
    assert duplicate_inputs([str(a), str(c)]) is None
    found = duplicate_inputs([str(a), str(c), str(b)])
    assert (
        found is not None
        and found.startswith(f"{b} holds the same bytes as {a} (SHA-256 ")
        and "halves the stated variance" in found
    )


def test_a_fit_check_is_plausible_without_findings():
    assert FitCheck("calibrate").plausible and FitCheck("calibrate").to_json()["findings"] == []
    check = FitCheck("identify", ("x", "y"))
    assert not check.plausible and check.message() == "identify: implausible result: x; y"
    assert check.verdict() == "self-check: IMPLAUSIBLE, written with --force: x; y"
    assert FitCheck("calibrate").verdict(1) == (
        "self-check: plausible: residuals within 3 times the noise, no parameter beyond 5 prior standard deviations; "
        "1 held-out log predicted within it"
    )


def test_a_fit_s_verdict_passes_without_findings_and_fails_with_one():
    plausible = fit_verdict(FitCheck("calibrate"), 2, "the unseen values")
    assert plausible.level is Level.PASS and plausible.not_judged == "the unseen values"
    assert plausible.judged == (
        "calibrate: residuals against 3 times the noise, each parameter's move against 5 prior standard deviations; "
        "2 held-out logs against the same gate"
    )
    assert plausible.numbers == {"residual_factor": 3.0, "prior_sigma": 5.0, "held_out_logs": 2.0, "findings": 0.0}
    one = FitCheck("identify", ("held-out h.csv: residuals beyond 3 times the noise",))
    failed = fit_verdict(one, 1)
    assert failed.level is Level.FAIL and failed.judged.endswith(": held-out h.csv: residuals beyond 3 times the noise")
    assert "1 held-out log against" in failed.judged and failed.numbers["findings"] == 1.0
    assert "held-out" not in fit_verdict(FitCheck("identify")).judged  # none held out: not said
    record = one.summary(1)
    assert (record.fit, record.plausible, record.findings, record.verdict) == ("identify", False, one.findings, failed)
    assert record.level is Level.FAIL and exit_status([record]) == 1 and exit_status([FitCheck("c").summary()]) == 0
    assert record.to_json()["verdict"]["level"] == "FAIL" and record.verdict.not_judged == ""


# --------------------------------------------------------------------------- calibrate, end to end

NOISE_DEG = 0.05


@pytest.fixture(scope="module")
def drawing():
    return load_parameters()


@pytest.fixture(scope="module")
def logs(drawing, tmp_path_factory):
    """Training and held-out logs of a machine within ±0.3 mm of its drawing, in degrees, and their slips."""
    folder = tmp_path_factory.mktemp("calibration")
    truth = deviated(seed=3, size_mm=0.3)
    t, L, _, sensors = synthetic_log(drawing, truth, 300, seed=1, noise_deg=NOISE_DEG)
    th, Lh, _, held = synthetic_log(drawing, truth, 150, seed=2, noise_deg=NOISE_DEG)
    offset = sensors.copy()
    offset[:, 0, 0] += math.radians(3.0)  # one sensor's zero off by 3°
    return {
        "train": write_log(folder / "train.csv", t, L, sensors),
        "held": write_log(folder / "held.csv", th, Lh, held),
        "held_rad": write_log(folder / "held_rad.csv", th, Lh, np.radians(held)),  # radians under _deg
        "offset": write_log(folder / "offset.csv", t, L, offset),
        "swapped": write_log(folder / "swapped.csv", t, L, sensors[:, :, [2, 1, 0]]),  # alpha and gamma swapped
        "flipped": write_log(folder / "flipped.csv", t, L, sensors * np.array([1, -1, 1])),  # beta's sign flipped
    }


def _calibrate(capsys, out, *words):
    status = main(["calibrate", *map(str, words), "--out", str(out)])
    return status, capsys.readouterr().err


def test_a_right_log_calibrates_without_a_word(logs, tmp_path, capsys):
    out = tmp_path / "c.toml"
    status = main(["calibrate", "--log", str(logs["train"]), "--validate", str(logs["held"]), "--out", str(out)])
    printed = capsys.readouterr()
    assert status == 0 and "warning" not in printed.err and out.exists()
    assert "self-check: plausible" in printed.out and "1 held-out log predicted within it" in printed.out


@pytest.mark.parametrize(
    ("case", "words", "cause"),
    [
        ("sensor offset", ("--log", "offset"), "column alpha_1 looks offset by +3"),
        ("alpha and gamma swapped", ("--log", "swapped"), "a wrong column, unit or sensor"),  # the reach check's
        ("a sign flipped", ("--log", "flipped"), "a wrong column, unit or sensor"),
        ("held-out log in radians", ("--log", "train", "--validate", "held_rad"), "like radians read as degrees"),
        ("the same log twice", ("--log", "train", "--validate", "train"), "holds the same bytes as"),
    ],
)
def test_an_implausible_calibration_is_refused_naming_the_cause(logs, tmp_path, capsys, case, words, cause):
    out = tmp_path / "c.toml"
    args = [logs.get(w, w) if not w.startswith("--") else w for w in words]
    status, err = _calibrate(capsys, out, *args)
    assert status == 2 and err.count("\n") == 1 and cause in err, (case, err)
    assert not out.exists()


def test_force_writes_an_implausible_calibration_and_keeps_the_warning(logs, tmp_path, capsys):
    out = tmp_path / "c.toml"
    status, err = _calibrate(capsys, out, "--log", logs["offset"], "--force")
    assert status == 1 and "written with --force" in err  # written, and the self-check's FAIL is the exit status
    text = out.read_text()
    assert "# WARNING (written with --force): " in text and "warnings = [" in text


# --------------------------------------------------------------------------- identify, end to end


def _torque_log(path, seconds: float, seed: int, swap: bool = False):
    """A 1 kHz log of the analytic model (N·mm noise of 3) along five harmonics of 0.5 Hz; ``swap``: tau_1 and tau_2 swapped."""
    import hipsim
    from hipsim.analytic.inverse_kinematics import kinematics
    from hipsim.analytic.virtual_work import inverse_dynamics

    params = load_parameters()
    rng = np.random.default_rng(seed)
    t = np.arange(int(seconds * 1000)) / 1000.0
    w = 2 * np.pi * 0.5 * np.arange(1, 6)
    amplitude = np.radians(rng.uniform(1.0, 4.0, (5, 3))) / np.arange(1, 6)[:, None]
    arg = w[None, :, None] * t[:, None, None] + rng.uniform(0, 2 * np.pi, (5, 3))
    q = np.sum(amplitude * np.sin(arg), axis=1)
    qd = np.sum(amplitude * w[:, None] * np.cos(arg), axis=1)
    qdd = -np.sum(amplitude * w[:, None] ** 2 * np.sin(arg), axis=1)
    load = 1650 + 1300 * np.sin(2 * np.pi * 0.5 * t)
    tau = inverse_dynamics(params, kinematics(params, hipsim.Trajectory(t, q, qd, qdd, load)), load, True).total * 1e3
    tau = tau + rng.normal(0, 3, tau.shape)
    if swap:
        tau = tau[:, [1, 0, 2]]
    columns = np.column_stack([t, load, tau, np.degrees(q)])
    with open(path, "w") as stream:
        stream.write("t_s,Fe_N,tau_1_Nmm,tau_2_Nmm,tau_3_Nmm,alpha_deg,beta_deg,gamma_deg\n")
        np.savetxt(stream, columns, delimiter=",", fmt="%.10g")
    return path


@pytest.fixture(scope="module")
def torque_logs(tmp_path_factory):
    folder = tmp_path_factory.mktemp("identify")
    return {
        "right": _torque_log(folder / "right.csv", 4.0, 1),
        "swapped": _torque_log(folder / "swapped.csv", 4.0, 1, swap=True),
    }


def test_identify_with_two_torque_columns_swapped_is_refused_naming_them(torque_logs, tmp_path, capsys):
    out = tmp_path / "m.toml"
    status = main(["identify", "--log", str(torque_logs["swapped"]), "--out", str(out), "--no-plausibility-check"])
    err = capsys.readouterr().err
    assert status == 2 and not out.exists() and err.count("\n") == 1, err
    assert "residuals beyond 3 times the noise" in err and "columns tau_1 and tau_2 look swapped" in err
    assert main(["identify", "--log", str(torque_logs["right"]), "--out", str(out)]) == 0  # the same log, right
    assert out.exists() and "WARNING" not in out.read_text()


def test_identify_refuses_the_same_log_twice(torque_logs, tmp_path, capsys):
    copy = tmp_path / "copy.csv"
    copy.write_bytes(torque_logs["right"].read_bytes())
    out = tmp_path / "m.toml"
    assert main(["identify", "--log", str(torque_logs["right"]), "--log", str(copy), "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert "holds the same bytes as" in err and not out.exists()


def test_identify_gives_a_verdict_on_a_held_out_log_it_does_not_predict(torque_logs, tmp_path, capsys):
    out = tmp_path / "m.toml"
    argv = [
        "identify",
        "--log",
        str(torque_logs["right"]),
        "--validate",
        str(torque_logs["swapped"]),
        "--out",
        str(out),
    ]
    assert main([*argv, "--no-plausibility-check"]) == 2
    err = capsys.readouterr().err
    assert "held-out " in err and "residuals beyond 3 times the noise" in err and "tau_1 and tau_2 look swapped" in err
    assert not out.exists()
    assert main([*argv, "--no-plausibility-check", "--force"]) == 1  # written, the finding kept; the verdict FAIL
    assert "written with --force" in capsys.readouterr().err
    assert "# WARNING (written with --force): held-out" in out.read_text()


def test_a_monitor_snapshot_whose_fit_leaves_three_times_the_noise_is_named():
    from hipsim.rig.monitoring.monitor_fit import snapshot_check

    t = np.linspace(0.0, 2.0, 400)
    model = np.column_stack([np.sin(2 * np.pi * t), 0.8 * np.cos(2 * np.pi * t), 0.5 * np.sin(4 * np.pi * t)])
    assert snapshot_check("s.csv", model * 1.01, model).plausible  # 1 % off: at the noise
    rms = np.sqrt(np.mean(model**2, axis=0))
    edge = model.copy()
    edge[:, 0] += (
        np.where(np.arange(400) % 2 == 0, 1.0, -1.0) * 3 * NOISE_FLOOR * rms[0]
    )  # 3 times 5 % of the model RMS: just within (the measured RMS is larger)
    assert snapshot_check("s.csv", edge, model).plausible
    swapped = snapshot_check("s.csv", model[:, [1, 0, 2]], model)
    assert not swapped.plausible and "columns tau_1 and tau_2 look swapped" in swapped.findings[0]
    noisy = snapshot_check("s.csv", model + np.random.default_rng(0).normal(0, 0.3, model.shape), model)
    assert not noisy.plausible and "(is the filter off, --no-filter?)" in noisy.findings[0]
