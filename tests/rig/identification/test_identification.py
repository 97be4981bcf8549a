"""Identification on synthetic logs from the plants (a route other than the regressor), the regressor, the TOML."""

import math

import numpy as np
import pytest
from rig_synthetic import FIT_MOTION, exact_run, fit_run, iso_run, machines, plant_run, relative_to_size, write_log
from support import ALL_FRICTION, SmoothMotion, given

import hipsim
import hipsim.machine.parameters
from hipsim.analytic import inverse_dynamics, kinematics
from hipsim.cli.main import main
from hipsim.motion.trajectories import Trajectory, iso14242_at
from hipsim.rig import identify, load_log, regressor
from hipsim.rig.identification.base import derive
from hipsim.rig.identification.consistency import violations as _violations
from hipsim.rig.identification.quantities import QUANTITIES, standard_values, with_values
from hipsim.rig.identification.uncertainty import Z95, read_covariance, torque_std
from hipsim.rig.logs.log import MeasuredLog


def sizes(result, start):
    """Each base parameter's size (file units): its starting value, or its nominal value where that is zero."""
    prior = standard_values(start)
    return np.array([max(abs(prior[k]), QUANTITIES[k].nominal) / QUANTITIES[k].scale for k in result.base.index])


@pytest.mark.parametrize("lever_spin", [False, True])
def test_the_regressor_is_the_inverse_dynamics(lever_spin):
    params = hipsim.load_parameters().replace(**ALL_FRICTION)
    params = params.replace(
        platform_inertia=params.platform_inertia + np.array([[0, 3, 2], [3, 0, 1], [2, 1, 0]]) * 1e-3
    )
    trajectory = SmoothMotion(seed=2)(np.arange(0, 2, 2e-3))
    Y = regressor(params, trajectory, lever_spin)
    tau = inverse_dynamics(params, kinematics(params, trajectory), trajectory.Fe, lever_spin).total
    assert np.abs(Y @ standard_values(params) - tau).max() < 1e-13 * np.abs(tau).max() * 10
    np.testing.assert_array_equal(
        standard_values(with_values(params, standard_values(params))), standard_values(params)
    )


def test_the_synthetic_logs_shortcuts_give_the_recorded_run_to_the_last_bit():
    """rig_synthetic's noisy logs take the compiled loop (no states recorded) and a shorter run as the head of a
    longer one: both the same numbers as the Python loop that records every state, run for that length."""
    start, true = machines()
    recorded = plant_run(true, start, FIT_MOTION, 0.2)
    for run in (plant_run(true, start, FIT_MOTION, 0.2, accelerations=False), fit_run().head(200)):
        for name in ("t", "q", "qd", "tau", "Fe"):
            np.testing.assert_array_equal(getattr(run, name), getattr(recorded, name), err_msg=name)
        assert run.qdd is None


def test_noise_free_logs_recover_the_base_parameters():
    start, true = machines()
    result = identify([exact_run().exact_log()], start)
    values = np.array([e.value for e in result.estimates])
    error = relative_to_size(values, result.combinations(true), sizes(result, start))
    assert error.max() < 1e-6, dict(zip((e.name for e in result.estimates), error))
    # The identified machine reproduces the plant's torques.
    run = exact_run()
    log = run.exact_log()
    tau = inverse_dynamics(result.params, kinematics(result.params, log.trajectory), log.trajectory.Fe, True).total
    assert np.abs(tau - run.tau).max() < 1e-8 * np.abs(run.tau).max()
    # The prior is irrelevant in the limit of rich noise-free data: a far tighter, shifted prior changes nothing.
    other = identify([log], start, prior={"platform": "1 %", "friction": "1 %", "slider": "1 %"})
    assert relative_to_size(np.array([e.value for e in other.estimates]), values, sizes(result, start)).max() < 1e-6


def test_base_parameters_are_structural_and_named_by_the_geometry():
    start, _ = machines()
    a, b = derive(start, True, seed=0), derive(start, True, seed=1)
    assert a.names == b.names and [p.definition for p in a.parameters] == [p.definition for p in b.parameters]
    np.testing.assert_allclose(a.beta, b.beta, rtol=1e-9, atol=0)
    definitions = {p.label: p.definition for p in a.parameters}
    # The lever's mass regroups: half with the slider it stands on, l²/4 out of its transverse inertia.
    assert definitions["m_L"] == "m_L + 0.5·m_l"
    l_mm = start.lever_length * 1e3
    assert definitions["I_l,xx"] == f"I_l,xx − {l_mm**2 / 4:.10g} mm²·m_l"
    # A guide force F reaches the motor as (p/2π)·F per platform, two platforms.
    assert definitions["τ_c,screw"] == f"τ_c,screw + {2 * start.lead / (2 * math.pi) * 1e3:.10g} mm·F_c,guide"
    assert {"m_l", "F_c,guide", "b_guide"} == {QUANTITIES[j].label for j in a.dependent}


def test_a_parameter_the_logs_cannot_see_returns_its_prior_exactly():
    """A static log (the load varies, nothing moves): inertias and speed-dependent friction are unseen."""
    start, _ = machines()
    n = 3000
    t = np.arange(n) * 1e-3
    q = np.tile(np.radians([5.0, -3.0, 2.0]), (n, 1))
    Fe = 1500 + 800 * np.sin(2 * np.pi * t)
    trajectory = Trajectory(t, q, np.zeros((n, 3)), np.zeros((n, 3)), Fe)
    tau = inverse_dynamics(start, kinematics(start, trajectory), Fe, True).total
    result = identify([MeasuredLog(trajectory, tau + 1e-3, None, "static")], start)
    by_name = {e.name: e for e in result.estimates}
    for name in ("I_m,xx", "I_L", "b_screw", "τ_c,U"):
        e = by_name[name]
        assert e.value == e.prior and e.std == pytest.approx(e.prior_std, rel=1e-12), name
    assert by_name["m_L"].determined


@pytest.fixture(scope="module")
def noisy(tmp_path_factory):
    """Logs of the Pinocchio plant of the true machine: the fit's excitation (20 s) and the ISO cycle (held out), with noise."""
    folder = tmp_path_factory.mktemp("noisy")
    rng = np.random.default_rng(2024)
    start, _ = machines()
    fit = write_log(folder / "fit.csv", fit_run(), rng, torque_noise_Nmm=3.0, angle_noise_deg=0.003)
    held_out = write_log(folder / "iso.csv", iso_run(), rng, torque_noise_Nmm=3.0, angle_noise_deg=0.003)
    result = identify([load_log(fit, start)], start, validate=[load_log(held_out, start)])
    return folder, fit, held_out, result


def test_noisy_logs_identify_each_base_parameter_within_three_std(noisy):
    _, _, _, result = noisy
    start, true = machines()
    values = np.array([e.value for e in result.estimates])
    std = np.array([e.std for e in result.estimates])
    truth = result.combinations(true)
    table = {e.definition: (e.value, t, e.std) for e, t in zip(result.estimates, truth)}
    assert np.all(np.abs(values - truth) <= 3 * std + 1e-9 * sizes(result, start)), table
    assert {"I_m,xx", "I_m,yy", "I_m,zz", "m_L", "I_L", "μ_h", "τ_c,screw", "b_screw"} <= {
        q.label for q in result.quantities
    }
    # The weight-dependent friction r_t·μ_t·m_m·g within 5 %, the load-proportional r_h·μ_h + r_t·μ_t within 2 %.
    f, g = true.friction, true.platform_mass * true.gravity
    mu = {e.name: e.value for e in result.estimates}
    assert f.thrust_radius * mu["μ_t"] * g == pytest.approx(f.thrust_radius * f.thrust_mu * g, rel=0.05)
    assert f.hip_radius * mu["μ_h"] + f.thrust_radius * mu["μ_t"] == pytest.approx(
        f.hip_radius * f.hip_mu + f.thrust_radius * f.thrust_mu, rel=0.02
    )


def test_two_log_sets_give_the_same_base_definitions(noisy):
    _, fit, held_out, result = noisy
    start, _ = machines()
    other = identify([load_log(held_out, start)], start)
    assert [e.definition for e in other.estimates] == [e.definition for e in result.estimates]
    assert [e.name for e in other.estimates] == result.base.names


def test_the_95_percent_band_covers_the_true_torque(noisy, tmp_path):
    _, _, _, result = noisy
    start, true = machines()
    path = result.write_toml(tmp_path / "identified.toml")
    covariance = read_covariance(path, hipsim.load_parameters(path))
    trajectory = iso14242_at(np.arange(0, 2, 2e-3), frequency=1.2)
    predicted = inverse_dynamics(result.params, kinematics(result.params, trajectory), trajectory.Fe, True).total
    actual = inverse_dynamics(true, kinematics(true, trajectory), trajectory.Fe, True).total
    half = Z95 * torque_std(result.params, trajectory, given(covariance))
    assert np.mean(np.abs(predicted - actual) <= half) >= 0.9
    # ... and is not uselessly wide: a calibrated normal band's half-width is 1.96 RMS errors.
    assert np.sqrt(np.mean(half**2)) <= 4 * np.sqrt(np.mean((predicted - actual) ** 2))


def test_noisy_logs_predict_the_held_out_trajectory_within_one_percent(noisy):
    _, _, _, result = noisy
    ((identified, starting),) = result.validation
    for i, entry in identified.motor_errors().items():
        before = starting.motor_errors()[i]
        assert entry["relative_rms_error_away_from_reversals"] < 0.01
        assert entry["relative_rms_error"] < 0.0125  # with the few milliseconds of sticking at each reversal
        assert before["relative_rms_error"] > 0.15  # the starting machine, for contrast
    assert "vs" in result.toml()  # the validation is in the file's header


@pytest.mark.usefixtures("quick_figures")  # the numbers and the text: tests/rig/test_compare.py draws the figures
def test_the_parameter_file_round_trips_and_every_command_takes_it(noisy, tmp_path, capsys):
    _, _, held_out, result = noisy
    path = result.write_toml(tmp_path / "identified.toml")
    text = path.read_text()
    assert text.startswith("# Identified by hipsim identify") and "fit.csv" in text
    loaded = hipsim.load_parameters(path)
    np.testing.assert_allclose(standard_values(loaded), standard_values(result.params), rtol=1e-12, atol=1e-15)
    assert not _violations(standard_values(loaded))
    assert main(["torques", "--params", str(path), "--rate", "200", "--out", str(tmp_path / "t.csv")]) == 0
    assert main(["compare", "--log", str(held_out), "--params", str(path), "--out", str(tmp_path / "cmp")]) == 0
    capsys.readouterr()


def test_identify_command(noisy, tmp_path, capsys):
    _, fit, held_out, _ = noisy
    out = tmp_path / "id.toml"
    assert (
        main(
            [
                "identify",
                "--log",
                str(fit),
                "--validate",
                str(held_out),
                "--fix",
                "lever",
                "--out",
                str(out),
                "--json",
                str(tmp_path / "id.json"),
            ]
        )
        == 0
    )
    printed = capsys.readouterr().out
    for words in (
        "base parameter",
        "moved [prior std]",
        "condition number",
        "residual RMS per motor",
        "Prediction error",
        "gait cycle",
    ):
        assert words in printed, words
    assert hipsim.load_parameters(out).lever_mass == machines()[0].lever_mass  # held at the start
    # A bad log: one line, and no file left.
    bad = tmp_path / "bad.csv"
    bad.write_text(
        "t_s,Fe_N,tau_1_Nmm,tau_2_Nmm,alpha_deg,beta_deg,gamma_deg\n"
        + "\n".join(f"{k / 1000},5,1,2,1,2,3" for k in range(900))
    )
    assert main(["identify", "--log", str(bad), "--out", str(tmp_path / "none.toml")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "missing torque column 'tau_3_Nmm'" in err and "bad.csv" in err
    assert not (tmp_path / "none.toml").exists()


def test_the_rig_guide_example(noisy, monkeypatch, capsys):
    """The example of docs/guide/rig.md ("the rig in the loop"), run as written, on the synthetic logs."""
    import re
    from pathlib import Path

    folder, _, _, _ = noisy
    monkeypatch.chdir(folder)
    text = (Path(__file__).resolve().parents[3] / "docs" / "guide" / "rig.md").read_text()
    block = given(re.search(r"```python\n(.*?)```", text, re.S)).group(1)
    exec(compile(block, "docs/guide/rig.md", "exec"), {})
    assert hipsim.load_parameters(folder / "identified.toml")
    assert hipsim.load_trajectory_csv(folder / "excite.csv").periodic
    assert "m_L + 0.5·m_l" in capsys.readouterr().out


def test_logs_in_pieces_give_the_same_fit(noisy):
    """The fit of logs read in pieces (cut mid-cycle, each shorter than its halo) against the fit of the whole logs."""
    from hipsim.rig.logs.log import LogPieces

    _, fit, held_out, whole = noisy
    start, _ = machines()
    with LogPieces(fit, start, piece=3001) as log, LogPieces(held_out, start, piece=1234) as check:
        parts = identify([log], start, validate=[check])
    assert parts.rows == whole.rows and parts.base is whole.base
    for a, b in zip(whole.estimates, parts.estimates):
        # Round-off of the filters and of the triangular factor updated in other blocks, times the condition number.
        assert b.value == pytest.approx(a.value, rel=1e-7, abs=1e-7 * a.std) and b.std == pytest.approx(
            a.std, rel=1e-6
        ), a.name
    np.testing.assert_allclose(parts.residual_rms, whole.residual_rms, rtol=1e-9)
    ((identified, _),) = parts.validation
    ((reference, _),) = whole.validation
    for i, entry in reference.motor_errors().items():
        assert identified.motor_errors()[i]["rms_error_Nmm"] == pytest.approx(entry["rms_error_Nmm"], rel=1e-6)


def test_identify_base_lists_the_base_parameters(capsys):
    assert main(["identify", "--base"]) == 0
    out = capsys.readouterr().out
    assert "m_L + 0.5·m_l" in out and "b_screw + 5.066059182 mm²/rad·b_guide" in out and "prior std" in out


@pytest.mark.parametrize(
    "case", ["negative prior", "prior table", "bad covariance", "other columns", "tolerance", "not toml"]
)
def test_bad_input_is_one_line_and_writes_nothing(noisy, tmp_path, capsys, case):
    folder, fit, held_out, result = noisy
    out = tmp_path / "id.toml"
    args = ["identify", "--log", str(fit), "--out", str(out)]
    if case == "negative prior":
        args += ["--prior", "μ_h=-0.01"]
        expected = "non-negative"
    elif case == "prior table":
        start_file = tmp_path / "start.toml"
        start_file.write_text(
            hipsim.machine.parameters.default_parameters_path().read_text()
            + '\n[identification.prior]\n"friction.hip_mu" = -1\n'
        )
        args += ["--params", str(start_file)]
        expected = "non-negative"
    elif case == "bad covariance":
        identified = result.write_toml(tmp_path / "identified.toml")
        text = identified.read_text()
        r = len(result.estimates)
        bad = [[1.0 if i != j else -1.0 for j in range(r)] for i in range(r)]
        text = text[: text.index("covariance = ")] + f"covariance = {bad}\n"
        identified.write_text(text)
        args = ["torques", "--params", str(identified), "--rate", "100", "--out", str(tmp_path / "t.csv")]
        out = tmp_path / "t.csv"
        expected = "not positive semi-definite"
    elif case == "other columns":
        other = tmp_path / "other.csv"
        other.write_text(
            "t_s,Fe_N,tau_1_Nmm,tau_2_Nmm,tau_4_Nmm,alpha_deg,beta_deg,gamma_deg\n"
            + "\n".join(f"{k / 1000},5,1,2,3,1,2,3" for k in range(900))
        )
        args += ["--validate", str(other)]
        expected = "other.csv"
    elif case == "tolerance":
        args += ["--angle-tolerance", "nan"]
        expected = "--angle-tolerance"
    else:
        out = tmp_path / "id.csv"
        args = ["identify", "--log", str(fit), "--out", str(out)]
        expected = ".toml"
    assert main(args) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and expected in err, err
    assert not out.exists()


@pytest.mark.usefixtures("quick_figures")  # the numbers and the text: tests/rig/test_compare.py draws the figures
def test_compare_with_an_identified_file_shows_the_model_band(noisy, tmp_path, capsys):
    """The model's 95 % band in compare's JSON and printout; the measured torque (noise included) mostly within it."""
    import json

    _, _, held_out, result = noisy
    path = result.write_toml(tmp_path / "identified.toml")
    assert main(["compare", "--log", str(held_out), "--params", str(path), "--out", str(tmp_path / "cmp")]) == 0
    printed = capsys.readouterr().out
    assert "model's 95 % band" in printed
    bands = json.loads((tmp_path / "cmp" / "comparison.json").read_text())["model_band95"]
    for i in "123":
        assert 0 < bands[i]["rms_half_width_Nmm"] < bands[i]["max_half_width_Nmm"] < 20
        assert 0 <= bands[i]["measured_within_band"] <= 1
        # The model's band is its parameters' uncertainty; the log's noise and sticking at reversals need the prediction band.
        assert bands[i]["prediction_rms_half_width_Nmm"] > bands[i]["rms_half_width_Nmm"]
        assert bands[i]["measured_within_band"] < bands[i]["measured_within_prediction_band"]
        assert bands[i]["measured_within_prediction_band"] > 0.75
    comparison = json.loads((tmp_path / "cmp" / "comparison.json").read_text())
    import jsonschema

    from hipsim.cli.documents import schema

    jsonschema.validate(comparison, schema("compare"))  # the band's keys are in the published contract
    assert "95 % band" in (tmp_path / "cmp" / "index.html").read_text()
    # Without a covariance: no band.
    assert main(["compare", "--log", str(held_out), "--out", str(tmp_path / "plain")]) == 0
    assert "model_band95" not in json.loads((tmp_path / "plain" / "comparison.json").read_text())
    assert "model's 95 % band" not in capsys.readouterr().out
    assert comparison["motors"]["1"]["rms_error_Nmm"] > 0
