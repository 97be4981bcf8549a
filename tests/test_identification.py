"""Identification on synthetic logs from the plants (a route other than the regressor), the regressor, the TOML."""

import math

import numpy as np
import pytest

import hipsim
from hipsim.rig import identify, load_log, regressor
from hipsim.rig.consistency import violations as _violations
from hipsim.rig.quantities import QUANTITIES, standard_values, with_values
from hipsim.analytic import inverse_dynamics, kinematics
from hipsim.cli.main import main

from rig_synthetic import exact_run, fit_run, iso_run, machines, relative_to_size, write_log
from support import ALL_FRICTION, SmoothMotion


def sizes(result, start):
    """Each identified quantity's size (file units): its starting value, or its nominal value where that is zero."""
    prior = standard_values(start)
    return np.array([max(abs(prior[k]), QUANTITIES[k].nominal) / QUANTITIES[k].scale for k in result.base])


@pytest.mark.parametrize("lever_spin", [False, True])
def test_the_regressor_is_the_inverse_dynamics(lever_spin):
    params = hipsim.load_parameters().replace(**ALL_FRICTION)
    params = params.replace(platform_inertia=params.platform_inertia + np.array([[0, 3, 2], [3, 0, 1], [2, 1, 0]]) * 1e-3)
    trajectory = SmoothMotion(seed=2)(np.arange(0, 2, 2e-3))
    Y = regressor(params, trajectory, lever_spin)
    tau = inverse_dynamics(params, kinematics(params, trajectory), trajectory.Fe, lever_spin).total
    assert np.abs(Y @ standard_values(params) - tau).max() < 1e-13 * np.abs(tau).max() * 10
    np.testing.assert_array_equal(standard_values(with_values(params, standard_values(params))), standard_values(params))


def test_noise_free_logs_recover_the_parameters():
    start, true = machines()
    result = identify([exact_run().exact_log()], start)
    assert not any("too weakly" in reason for _, reason, _, _ in result.held)
    error = relative_to_size(np.array([q.value for q in result.quantities]), result.combinations(true), sizes(result, start))
    assert error.max() < 1e-6, dict(zip((q.label for q in result.quantities), error))
    # The identified machine reproduces the plant's torques.
    run = exact_run()
    log = run.exact_log()
    tau = inverse_dynamics(result.params, kinematics(result.params, log.trajectory), log.trajectory.Fe, True).total
    assert np.abs(tau - run.tau).max() < 1e-8 * np.abs(run.tau).max()


def test_collinear_parameters_are_reported_as_combinations():
    start, true = machines()
    result = identify([exact_run(constant_load=True).exact_log()], start)
    by_label = {q.label: q for q in result.quantities}
    held = {label: reason for label, reason, _, _ in result.held}
    for label in ("μ_t", "F_c,guide", "b_guide", "m_l"):
        assert "cannot be told apart" in held[label], label
    # Under a constant load the hip joint and the thrust bearing act alike: μ_h·r_h·F_e + μ_t·r_t·(F_e + m_m·g).
    f = start.friction
    load = 1500.0
    expected = f.thrust_radius * (load + start.platform_mass * start.gravity) / (f.hip_radius * load)
    terms = dict((label, coefficient) for label, coefficient, _ in by_label["μ_h"].terms)
    assert terms["μ_t"] == pytest.approx(expected, rel=1e-9)
    # A guide force F reaches the motor as (p/2π)·F per platform, two platforms: 3.183 N·mm per N.
    terms = dict((label, coefficient) for label, coefficient, _ in by_label["τ_c,screw"].terms)
    assert terms["F_c,guide"] == pytest.approx(2 * start.lead / (2 * math.pi) * 1e3, rel=1e-9)
    # The lever's mass regroups: half with the slider it stands on.
    terms = dict((label, coefficient) for label, coefficient, _ in by_label["m_L"].terms)
    assert terms["m_l"] == pytest.approx(0.5, rel=1e-9)
    # The combinations are what comes back, exactly.
    error = relative_to_size(np.array([q.value for q in result.quantities]), result.combinations(true), sizes(result, start))
    assert error.max() < 1e-6
    assert "μ_h + " in result.toml() and "cannot be told apart" in result.toml()


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


def test_noisy_logs_identify_the_combinations_within_two_percent(noisy):
    _, _, _, result = noisy
    start, true = machines()
    values = np.array([q.value for q in result.quantities])
    truth = result.combinations(true)
    size = sizes(result, start)
    error = relative_to_size(values, truth, size)
    table = {q.expression(): (q.value, t, e) for q, t, e in zip(result.quantities, truth, error)}
    assert error.max() < 0.02, table
    # The standard deviations are honest: every error within four of them (and the platform inertia is identified).
    std = np.array([q.std for q in result.quantities])
    assert np.all(np.abs(values - truth) < 4 * std + 2e-3 * size), table
    assert {"I_m,xx", "I_m,yy", "I_m,zz", "m_L", "I_L", "μ_h", "τ_c,screw", "b_screw"} <= {q.label for q in result.quantities}
    assert result.condition_number_base < 100


def test_noisy_logs_predict_the_held_out_trajectory_within_one_percent(noisy):
    _, _, _, result = noisy
    (identified, starting), = result.validation
    for i, entry in identified.motor_errors().items():
        before = starting.motor_errors()[i]
        assert entry["relative_rms_error_away_from_reversals"] < 0.01
        assert entry["relative_rms_error"] < 0.0125  # with the few milliseconds of sticking at each reversal
        assert before["relative_rms_error"] > 0.15  # the starting machine, for contrast
    assert "vs" in result.toml()  # the validation is in the file's header


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
    assert main(["identify", "--log", str(fit), "--validate", str(held_out), "--fix", "lever", "--out", str(out),
                 "--json", str(tmp_path / "id.json")]) == 0
    printed = capsys.readouterr().out
    for words in ("identified quantity", "relative std", "condition number", "residual RMS per motor", "Prediction error", "held fixed as asked"):
        assert words in printed, words
    assert hipsim.load_parameters(out).lever_mass == machines()[0].lever_mass  # held at the start
    # A bad log: one line, and no file left.
    bad = tmp_path / "bad.csv"
    bad.write_text("t_s,Fe_N,tau_1_Nmm,tau_2_Nmm,alpha_deg,beta_deg,gamma_deg\n" + "\n".join(f"{k / 1000},5,1,2,1,2,3" for k in range(900)))
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
    text = (Path(__file__).resolve().parents[1] / "docs" / "guide" / "rig.md").read_text()
    block = re.search(r"```python\n(.*?)```", text, re.S).group(1)
    exec(compile(block, "docs/guide/rig.md", "exec"), {})
    assert hipsim.load_parameters(folder / "identified.toml")
    assert hipsim.load_trajectory_csv(folder / "excite.csv").periodic
    assert "m_L + 0.5" in capsys.readouterr().out


def test_logs_in_pieces_give_the_same_fit(noisy):
    """The fit of logs read in pieces (cut mid-cycle, each shorter than its halo) against the fit of the whole logs."""
    from hipsim.rig.logs import LogPieces

    _, fit, held_out, whole = noisy
    start, _ = machines()
    with LogPieces(fit, start, piece=3001) as log, LogPieces(held_out, start, piece=1234) as check:
        parts = identify([log], start, validate=[check])
    assert parts.rows == whole.rows and parts.base == whole.base and parts.held == whole.held
    for a, b in zip(whole.quantities, parts.quantities):
        # Round-off of the filters and of the triangular factor updated in other blocks, times the condition number.
        assert b.value == pytest.approx(a.value, rel=1e-9, abs=1e-9 * a.std) and b.std == pytest.approx(a.std, rel=1e-6), a.label
    np.testing.assert_allclose(parts.residual_rms, whole.residual_rms, rtol=1e-9)
    (identified, _), = parts.validation
    (reference, _), = whole.validation
    for i, entry in reference.motor_errors().items():
        assert identified.motor_errors()[i]["rms_error_Nmm"] == pytest.approx(entry["rms_error_Nmm"], rel=1e-6)
