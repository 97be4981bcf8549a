"""hipsim.rig.identification.fit pinned on tiny logs (a hundred samples, fast without numba) and by hand.

The fit by another route: the weighted Bayesian least squares written out by its
normal equations over the regressor's rows (the fit itself accumulates QR factors):
an unweighted minimum-norm fit for each motor's residual level σ_i, weights 1/σ_i,
the information divided by the rows per independent row (averaged over the logs by
their rows), θ̂_b = θ_b0 + s·(AᵀWA/ν + I)⁻¹AᵀWz/ν in the prior's units, the
posterior widened by the residual's χ² when that exceeds one. What the result
shows (the estimates, the held parameters, the table, the summary, the comment
header) is pinned on an identification made by hand.
"""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest
from support import ALL_FRICTION, SmoothMotion, given

import hipsim
from hipsim.analytic.inverse_kinematics import kinematics
from hipsim.analytic.virtual_work import inverse_dynamics
from hipsim.exceptions import IdentificationError, ParameterError
from hipsim.rig.compare_summary import MotorError
from hipsim.rig.identification.base import BaseParameter, BaseParameters, base_parameters
from hipsim.rig.identification.fit import (
    DETERMINED,
    BaseEstimate,
    Identification,
    IdentifiedQuantity,
    _Accumulator,
    _condition,
    _percent,
    _plausible,
    identify,
)
from hipsim.rig.identification.identified_file import IDENTIFIED_MARK, read_identified_file
from hipsim.rig.identification.prior import prior as make_prior
from hipsim.rig.identification.quantities import QUANTITIES, standard_values, with_values
from hipsim.rig.identification.regressor import regressor, rows_per_independent_row
from hipsim.rig.identification.summary import PhaseNote
from hipsim.rig.logs.log import MeasuredLog

P = len(QUANTITIES)
INDEX = {q.label: k for k, q in enumerate(QUANTITIES)}
NOISE = np.array([0.002, 0.005, 0.01])  # N·m per motor


@pytest.fixture(scope="module")
def start():
    return hipsim.load_parameters().replace(**ALL_FRICTION)


@pytest.fixture(scope="module")
def true(start):
    theta = standard_values(start) * np.linspace(0.9, 1.15, P)
    return with_values(start, theta)


def _log(true, seed, n, rate, name, lever_spin=True, noise=NOISE, edge=2):
    motion = SmoothMotion(seed=seed, amplitude_deg=15.0)(np.arange(n) / rate)
    tau = inverse_dynamics(true, kinematics(true, motion), motion.Fe, lever_spin).total
    tau = tau + np.random.default_rng(seed).normal(size=(n, 3)) * noise
    return MeasuredLog(motion, tau, None, name, edge=edge)


@pytest.fixture(scope="module")
def logs(true):
    """Two unfiltered logs at 1 kHz and 500 Hz: 50 and 25 rows per independent row (the model error's floor)."""
    return [_log(true, 1, 120, 1000.0, "a.csv"), _log(true, 2, 80, 500.0, "b.csv")]


def _by_normal_equations(params, logs, lever_spin=True, entries=None, rows=None):
    """The fit written out (module docstring): θ_b, posterior covariance (SI), θ, residual RMS, condition number.

    rows: (Y, τ, use, ν) to take in place of the logs' rows.
    """
    base = base_parameters(params, lever_spin)
    belief = make_prior(base, params, entries)
    index, r = base.index, len(base.index)
    if rows is None:
        Y = [
            np.concatenate([regressor(params, log.trajectory, lever_spin)[log.usable][:, i] for log in logs])
            for i in range(3)
        ]
        tau = [np.concatenate([log.tau[log.usable][:, i] for log in logs]) for i in range(3)]
        nu = sum(3 * (len(log) - 2 * log.edge) * rows_per_independent_row(log) for log in logs) / (3 * len(tau[0]))
    else:
        Yr, taur, use, nu = rows
        Y = [Yr[use[:, i], i] for i in range(3)]
        tau = [taur[use[:, i], i] for i in range(3)]
    n = np.array([len(t) for t in tau])
    A = [Yi[:, index] * belief.std for Yi in Y]
    z = [ti - Yi[:, index] @ belief.mean for Yi, ti in zip(Y, tau)]
    x0 = np.linalg.lstsq(np.vstack(A), np.concatenate(z), rcond=1e-12)[0]
    sigma = np.array([np.linalg.norm(Ai @ x0 - zi) / math.sqrt(ni) for Ai, zi, ni in zip(A, z, n)])
    w2 = 1.0 / sigma**2
    information = sum(w * Ai.T @ Ai for w, Ai in zip(w2, A)) / nu
    x = np.linalg.solve(information + np.eye(r), sum(w * Ai.T @ zi for w, Ai, zi in zip(w2, A, z)) / nu)
    theta_b = belief.mean + belief.std * x
    theta = base.standard(theta_b, standard_values(params))
    chi2 = sum(w * np.sum((Yi @ theta - ti) ** 2) for w, Yi, ti in zip(w2, Y, tau)) / max(n.sum() - r, 1)
    covariance = np.linalg.inv(information / max(chi2, 1.0) + np.eye(r)) * np.outer(belief.std, belief.std)
    residual = np.array([np.linalg.norm(Yi @ theta - ti) / math.sqrt(ni) for Yi, ti, ni in zip(Y, tau, n)])
    determined = np.sqrt(np.diag(covariance)) <= 0.5 * belief.std
    weighted = np.vstack([Yi[:, index][:, determined] / s for Yi, s in zip(Y, sigma)])
    weighted = weighted / np.linalg.norm(weighted, axis=0)
    s = np.linalg.svd(weighted, compute_uv=False)
    return SimpleNamespace(
        base=base, belief=belief, theta_b=theta_b, covariance=covariance, theta=theta, residual=residual,
        condition=s[0] / s[-1], rows=int(n.sum()), chi2=chi2, nu=nu,
    )  # fmt: skip


def _check(result, expected, params, atol=1e-6):
    rtol = atol  # the same round-off, relative
    base = expected.base
    scale = base.scale
    std = np.sqrt(np.diag(expected.covariance))
    assert result.rows == expected.rows
    assert [e.name for e in result.estimates] == base.names
    assert [(e.definition, e.key, e.unit) for e in result.estimates] == [
        (p.definition, p.key, p.unit) for p in base.parameters
    ]
    # The estimates to round-off of the two routes, in prior standard deviations.
    values = np.array([e.value for e in result.estimates]) * scale
    np.testing.assert_allclose((values - expected.theta_b) / expected.belief.std, 0, atol=atol)
    np.testing.assert_allclose(np.array([e.std for e in result.estimates]) * scale, std, rtol=rtol)
    np.testing.assert_allclose(np.array([e.prior for e in result.estimates]) * scale, expected.belief.mean, rtol=1e-12)
    np.testing.assert_allclose(
        np.array([e.prior_std for e in result.estimates]) * scale, expected.belief.std, rtol=1e-12
    )
    np.testing.assert_allclose(
        result.covariance,
        expected.covariance / np.outer(scale, scale),
        rtol=10 * rtol,
        atol=atol * np.outer(std / scale, std / scale).max(),
    )
    np.testing.assert_allclose(result.residual_rms, expected.residual, rtol=rtol)
    assert result.condition_number == pytest.approx(expected.condition, rel=rtol)
    # The identified machine: the base values split as the base map says, the start's geometry.
    np.testing.assert_allclose(
        base.values(result.params), expected.theta_b, rtol=rtol, atol=atol * np.abs(expected.belief.std).min()
    )
    assert result.params.lever_length == params.lever_length and result.start is params


def test_the_fit_is_the_weighted_bayesian_least_squares(start, logs):
    result = identify(logs, start)
    expected = _by_normal_equations(start, logs)
    assert expected.nu == pytest.approx((116 * 3 * 50 + 76 * 3 * 25) / (192 * 3))  # the logs' floors, by their rows
    assert expected.chi2 > 1.0  # the posterior is widened
    _check(result, expected, start)
    assert result.logs == ("a.csv", "b.csv") and result.lever_spin is True and result.active_constraints == ()
    assert result.params.source == "identified from a.csv, b.csv"
    assert result.base is base_parameters(start) and result.validation == () and result.notes == ()
    determined = [e.determined for e in result.estimates]
    assert sum(determined) >= 3 and not all(determined)  # both kinds


def test_the_fit_without_lever_spin_and_with_a_prior(start, true):
    log = _log(true, 3, 100, 1000.0, "c.csv", lever_spin=False)
    entries = {"μ_h": "2 %", "slider": 0.2}
    result = identify([log], start, lever_spin=False, prior=entries)
    _check(result, _by_normal_equations(start, [log], False, entries), start)
    assert result.lever_spin is False and result.base.lever_spin is False
    # A parameter held by `fixed` (a prior of zero) stays at its start; a held one names no source but the option's.
    held = identify([log], start, lever_spin=False, prior=entries, fixed=["μ_t"])
    expected = _by_normal_equations(start, [log], False, entries | {"μ_t": 0.0})
    _check(held, expected, start)
    by_name = {e.name: e for e in held.estimates}
    assert by_name["μ_t"].value == pytest.approx(start.friction.thrust_mu, rel=1e-8)
    with pytest.raises(ParameterError, match="--prior"):
        identify([log], start, prior={"μ_h": "two %"}, prior_source="--prior")


def test_noise_free_logs_give_the_true_machines_base_parameters(start, true):
    """Weights at the round-off's level: the prior is irrelevant, every base parameter the truth's (to 1e-4 of its size)."""
    log = _log(true, 4, 300, 1000.0, "exact.csv", noise=0.0)
    result = identify([log], start)
    truth = result.combinations(true)
    values = np.array([e.value for e in result.estimates])
    size = np.maximum(np.abs(truth), [QUANTITIES[k].nominal / QUANTITIES[k].scale for k in result.base.index])
    assert np.all(np.abs(values - truth) / size < 1e-4)
    assert np.all(result.residual_rms < 1e-9)


def test_the_bounds_hold_and_a_held_folded_parameter_stays(start, true):
    """A true machine with a negative joint friction (impossible): the fit goes onto the bound τ_c,U ≥ 0."""
    wrong = true.replace(ujoint_coulomb=-0.2)
    log = _log(wrong, 5, 120, 1000.0, "wrong.csv", noise=NOISE * 0.1)
    result = identify([log], start, fixed=["m_l"])
    assert "τ_c,U ≥ 0" in result.active_constraints
    assert result.params.friction.ujoint_coulomb >= 0
    assert result.params.lever_mass == start.lever_mass  # held exactly, not moved by the constrained fit
    # The estimates are the constrained machine's base parameters.
    np.testing.assert_allclose(
        [e.value for e in result.estimates], result.combinations(result.params), rtol=1e-12, atol=1e-12
    )
    free = identify([log], start)
    assert free.params.lever_mass != start.lever_mass  # without --fix the folded parameter may give way


def test_logs_that_cannot_identify_are_refused_naming_them(start, true, logs):
    with pytest.raises(IdentificationError, match="^identification needs at least one log$"):
        identify([], start)
    tiny = _log(true, 6, 5, 1000.0, "tiny.csv")  # one usable sample: three rows
    assert len(tiny) - 2 * tiny.edge == 1
    with pytest.raises(IdentificationError) as error:
        identify([tiny], start)
    assert str(error.value) == "tiny.csv: 3 samples are too few to identify anything" and error.value.logs == (
        "tiny.csv",
    )
    log = _log(true, 7, 40, 1000.0, "still.csv")
    every = ["platform", "slider", "screw", "lever", "friction"]
    with pytest.raises(IdentificationError) as error:
        identify([log, tiny], start, fixed=every)
    assert str(error.value) == (
        "still.csv, tiny.csv: these logs determine none of the base parameters (is anything moving, and is the torque logged?)"
    )
    # Torques ten times too large (a wrong torque constant): an implausible machine, nothing written.
    big = MeasuredLog(logs[0].trajectory, logs[0].tau * 10.0, None, "units.csv", edge=2)
    with pytest.raises(IdentificationError) as error:
        identify([big], start)
    assert str(error.value).startswith("units.csv: the identified machine is implausible: key 'slider.mass_kg' = ")
    assert str(error.value).endswith(
        "the logs and the model disagree (check the log's units, torque constant and sign convention); nothing written"
    )


def test_plausible_by_hand(start):
    theta = standard_values(start)
    _plausible(start, theta, ("a",))  # the start is plausible
    theta[INDEX["m_L"]] = 3000.0
    with pytest.raises(IdentificationError) as error:
        _plausible(start, theta, ("a", "b"))
    assert error.value.logs == ("a", "b")
    assert str(error.value) == (
        "a, b: the identified machine is implausible: key 'slider.mass_kg' = 3000 kg is outside the plausible range "
        "0.3 to 30 kg for this class of machine (a unit slip?); the logs and the model disagree (check the log's "
        "units, torque constant and sign convention); nothing written"
    )


def test_validation_logs_are_predicted_by_both_machines(start, true, logs):
    held_out = _log(true, 8, 150, 1000.0, "held.csv")
    result = identify(logs, start, validate=[held_out])
    ((identified, starting),) = result.validation
    assert identified.log.name == starting.log.name == "held.csv"
    a, b = identified.motor_errors(), starting.motor_errors()
    assert all(a[i]["rms_error_Nmm"] < b[i]["rms_error_Nmm"] for i in "123")
    assert len(result.notes) == 1 and result.notes[0] is not None
    summary = result.summary()
    (entry,) = given(summary.validation)
    assert entry.log == "held.csv" and entry.identified == identified.summary().motors
    assert {i: m.rms_error_Nmm for i, m in entry.starting.items()} == {i: b[i]["rms_error_Nmm"] for i in "123"}
    assert set(result.notes[0].summary().to_json()) <= set(entry.to_json())
    table = result.table()
    assert table["validation_logs"] == ["held.csv"]
    assert table["validation_rms_error_Nmm"] == [[a[i]["rms_error_Nmm"] for i in "123"]]
    assert table["validation_start_rms_error_Nmm"] == [[b[i]["rms_error_Nmm"] for i in "123"]]
    # The same fit as without them.
    alone = identify(logs, start)
    assert [e.value for e in alone.estimates] == [e.value for e in result.estimates]


# --- Pieces by hand ---------------------------------------------------------------------------------------------


def test_the_accumulator_is_the_normal_equations_of_the_rows_used():
    rng = np.random.default_rng(3)
    acc = _Accumulator(2)
    blocks = []
    for m, nu in ((4, 2.0), (1, 5.0), (6, 1.0)):
        Y, tau = rng.normal(size=(m, 3, 2)), rng.normal(size=(m, 3))
        use = rng.uniform(size=(m, 3)) > 0.3
        use[0] = True
        acc.add(Y, tau, use, nu)
        blocks.append((Y, tau, use, nu))
    assert acc.rows.tolist() == sum(u.sum(axis=0) for _, _, u, _ in blocks).tolist()
    assert acc.inflation == pytest.approx(sum(u.sum() * nu for _, _, u, nu in blocks))
    for i in range(3):
        rows = np.vstack([np.column_stack([Y[u[:, i], i], t[u[:, i], i]]) for Y, t, u, _ in blocks])
        assert acc.R[i].shape == (3, 3)
        np.testing.assert_allclose(acc.R[i].T @ acc.R[i], rows.T @ rows, rtol=1e-12, atol=1e-12)


def test_the_accumulator_pads_a_factor_of_few_rows():
    acc = _Accumulator(3)
    Y = np.ones((1, 3, 3))
    acc.add(Y, np.full((1, 3), 2.0), np.ones((1, 3), bool), 4.0)
    assert all(R.shape == (4, 4) for R in acc.R)
    np.testing.assert_allclose(np.abs(acc.R[0][0]), [1, 1, 1, 2])
    assert not acc.R[0][1:].any()
    assert acc.rows.tolist() == [1, 1, 1] and acc.inflation == 12.0 and acc.rows.dtype.kind == "i"
    # Two rows more (three in all: one short of four): still padded to four.
    two = _Accumulator(3)
    two.add(np.ones((2, 3, 3)), np.ones((2, 3)), np.ones((2, 3), bool), 1.0)
    assert all(R.shape == (4, 4) for R in two.R)


def test_the_condition_number_by_hand():
    # Unit-norm columns (1, 0) and (1, 1)/√2: singular values √(1 ± 1/√2), their ratio 1 + √2. Scale changes nothing.
    assert _condition(np.array([[3.0, 5.0], [0.0, 5.0]])) == pytest.approx(1 + math.sqrt(2), rel=1e-12)
    # A zero column is left out; no column, nan; two equal columns, infinite.
    assert _condition(np.array([[3.0, 0.0, 5.0], [0.0, 0.0, 5.0]])) == pytest.approx(1 + math.sqrt(2), rel=1e-12)
    assert _condition(np.array([[2.0], [0.0]])) == 1.0
    assert math.isnan(_condition(np.zeros((3, 0))))
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no division by a zero singular value
        assert _condition(np.array([[1.0, 2.0], [0.0, 0.0]])) == math.inf
        assert _condition(np.zeros((3, 2))) == math.inf  # every column zero
    # Columns shorter than one count alike.
    assert _condition(np.array([[0.3, 0.05], [0.0, 0.05]])) == pytest.approx(1 + math.sqrt(2), rel=1e-12)


def test_percent_and_an_estimate_by_hand():
    assert _percent(0.01249) == "±1.2 %" and _percent(9.99) == "±1e+03 %" and _percent(10.0) == "near zero"
    assert DETERMINED == 0.5
    e = BaseEstimate("m_L", "m_L + 0.5·m_l", "slider.mass_kg", "kg", 3.5, 0.45, 3.7, 0.9)
    assert e.determined and e.shift == pytest.approx(-0.2 / 0.9)
    assert not BaseEstimate("a", "a", "k", "", 1.0, 0.46, 1.0, 0.9).determined
    assert BaseEstimate("a", "a", "k", "", 2.0, 0.0, 1.0, 0.0).shift == 0.0
    assert e.row().to_json() == {
        "name": "m_L",
        "definition": "m_L + 0.5·m_l",
        "key": "slider.mass_kg",
        "unit": "kg",
        "value": 3.5,
        "std": 0.45,
        "prior": 3.7,
        "prior_std": 0.9,
        "determined": True,
        "shift_in_prior_std": pytest.approx(-0.2 / 0.9),
    }


def test_a_quantity_in_words():
    terms = (("m_l", 0.5, ""), ("I_L", -2.0, "kg"), ("a", 1.0, ""), ("b", 1.0, ""), ("c", 3.0, "N"), ("d", 1.0, ""))
    q = IdentifiedQuantity("m_L", "slider.mass_kg", "kg", 3.5, 0.01, 0.035, terms)
    assert q.expression(None) == "m_L + 0.5·m_l − 2 kg·I_L + 1·a + 1·b + 3 N·c + 1·d"
    assert q.expression() == "m_L + 0.5·m_l − 2 kg·I_L + 1·a + 1·b + … (2 more)"
    assert q.expression(1) == "m_L + 0.5·m_l + … (5 more)"
    assert q.expression(6) == q.expression(None)
    assert IdentifiedQuantity("μ_h", "friction.hip_mu", "", 0.1, 0.2, 0.02).expression() == "μ_h"
    assert IdentifiedQuantity("a", "k", "", 1.0, 0.1, 0.1, (("b", 0.0, ""),)).expression() == "a + 0·b"


# --- What an identification shows, made by hand -----------------------------------------------------------------


@pytest.fixture(scope="module")
def by_hand():
    params = hipsim.load_parameters()
    beta = np.zeros((P, P))
    beta[INDEX["m_L"], INDEX["m_l"]] = 0.5
    base = BaseParameters(
        (
            BaseParameter(INDEX["m_L"], "m_L", "slider.mass_kg", "kg", (("m_l", 0.5, ""),)),
            BaseParameter(INDEX["μ_h"], "μ_h", "friction.hip_mu", ""),
            BaseParameter(INDEX["I_L"], "I_L", "screw.inertia_kgmm2", "kg·mm²"),
            BaseParameter(INDEX["I_m,xy"], "I_m,xy", "platform.inertia_kgmm2[xy]", "kg·mm²"),
        ),
        (INDEX["m_l"], INDEX["b_guide"]),
        beta,
        True,
    )
    estimates = (
        BaseEstimate("m_L", "m_L + 0.5·m_l", "slider.mass_kg", "kg", 3.5, 0.01, 3.715, 0.9),
        BaseEstimate("μ_h", "μ_h", "friction.hip_mu", "", 0.1, 0.02, 0.095, 0.04),  # 0.02 = half of 0.04: determined
        BaseEstimate("I_L", "I_L", "screw.inertia_kgmm2", "kg·mm²", 50.0, 20.0, 54.91, 25.0),
        BaseEstimate("I_m,xy", "I_m,xy", "platform.inertia_kgmm2[xy]", "kg·mm²", 0.0, 1.0, 0.0, 90000.0),
    )
    errors = (
        {i: {"rms_error_Nmm": v} for i, v in zip("123", (1.0, 2.0, 3.0))},
        {i: {"rms_error_Nmm": v} for i, v in zip("123", (4.0, 5.0, 6.0))},
    )
    identified, starting = (
        SimpleNamespace(
            log=SimpleNamespace(name="v.csv"),
            motor_errors=lambda e=e: e,
            summary=lambda e=e: SimpleNamespace(motors={i: _motor(x["rms_error_Nmm"]) for i, x in e.items()}),
        )
        for e in errors
    )
    note = SimpleNamespace(summary=lambda: PhaseNote(("outside",)))
    return Identification(
        params.replace(slider_mass=3.5 - 0.5 * params.lever_mass, source="identified from a.csv, b.csv"),
        params,
        base,
        estimates,
        np.diag([1e-4, 4e-4, 400.0, 1.0]),
        123.456,
        np.array([0.0012344, 0.00225, 1.23e-5]),
        1234,
        ("a.csv", "b.csv"),
        True,
        ("μ_t ≥ 0", "b_U ≥ 0"),
        ((identified, starting),),  # type: ignore[arg-type]  # stand-ins for the two Comparisons
        (note,),  # type: ignore[arg-type]  # a stand-in for the ValidationNote
    )


def test_what_is_determined_and_what_is_held(by_hand):
    q = by_hand.quantities
    assert [x.label for x in q] == ["m_L", "μ_h", "I_m,xy"]
    assert q[0] == IdentifiedQuantity("m_L", "slider.mass_kg", "kg", 3.5, 0.01 / 3.5, 0.01, (("m_l", 0.5, ""),))
    assert q[1].relative_std == pytest.approx(0.2) and q[1].std == 0.02 and q[1].terms == ()
    assert q[2].relative_std == math.inf
    assert by_hand.held == (
        ("I_L", "not determined by these logs: near its prior 54.91 ± 25 (posterior std 20)", 50.0, "kg·mm²"),
        ("m_l", "folded into m_L (starting value kept)", 1.43, "kg"),
        ("b_guide", "no effect on the motor torques (starting value kept)", 0.0, "N·s/mm"),
    )
    # Another machine's base parameters in file units: m_L + 0.5·m_l, μ_h, I_L in kg·mm², I_m,xy.
    other = by_hand.start.replace(slider_mass=2.0, lever_mass=1.0, screw_inertia=5e-5)
    np.testing.assert_allclose(by_hand.combinations(other), [2.5, 0.095, 50.0, 0.0], rtol=1e-12)


def test_the_table_by_hand(by_hand):
    assert by_hand.table() == {
        "logs": ["a.csv", "b.csv"],
        "start": by_hand.start.source,
        "lever_spin": True,
        "base": ["m_L", "μ_h", "I_L", "I_m,xy"],
        "definitions": ["m_L + 0.5·m_l", "μ_h", "I_L", "I_m,xy"],
        "keys": ["slider.mass_kg", "friction.hip_mu", "screw.inertia_kgmm2", "platform.inertia_kgmm2[xy]"],
        "units": ["kg", "", "kg·mm²", "kg·mm²"],
        "value": [3.5, 0.1, 50.0, 0.0],
        "std": [0.01, 0.02, 20.0, 1.0],
        "prior": [3.715, 0.095, 54.91, 0.0],
        "prior_std": [0.9, 0.04, 25.0, 90000.0],
        "determined": [True, True, False, True],
        "covariance": [[1e-4, 0, 0, 0], [0, 4e-4, 0, 0], [0, 0, 400.0, 0], [0, 0, 0, 1.0]],
        "residual_rms_Nmm": [pytest.approx(1.2344), 2.25, pytest.approx(0.0123)],
        "validation_logs": ["v.csv"],
        "validation_rms_error_Nmm": [[1.0, 2.0, 3.0]],
        "validation_start_rms_error_Nmm": [[4.0, 5.0, 6.0]],
    }
    assert all(type(x) is float for row in by_hand.table()["covariance"] for x in row)


def _motor(rms: float) -> MotorError:
    """A motor's errors with only its RMS error set, in [N·mm]."""
    return MotorError(0.0, 0.0, 0.0, rms, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, {})


def test_the_summary_by_hand(by_hand):
    s = by_hand.summary().to_json()
    assert s["logs"] == ["a.csv", "b.csv"] and s["starting_parameters"] == by_hand.start.source
    assert s["lever_spin"] is True and s["rows"] == 1234 and s["condition_number"] == 123.456
    assert s["residual_rms_Nmm"] == {"1": pytest.approx(1.2344), "2": 2.25, "3": pytest.approx(0.0123)}
    assert s["base_parameters"] == [e.row().to_json() for e in by_hand.estimates]
    assert s["identified"][0] == {
        "quantity": "m_L + 0.5·m_l",
        "key": "slider.mass_kg",
        "value": 3.5,
        "std": 0.01,
        "unit": "kg",
        "relative_std": 0.01 / 3.5,
    }
    assert [x["quantity"] for x in s["identified"]] == ["m_L + 0.5·m_l", "μ_h", "I_m,xy"]
    assert s["held"][1] == {
        "quantity": "m_l",
        "reason": "folded into m_L (starting value kept)",
        "value": 1.43,
        "unit": "kg",
    }
    assert len(s["held"]) == 3
    assert s["active_constraints"] == ["μ_t ≥ 0", "b_U ≥ 0"]
    assert s["validation"] == [
        {
            "log": "v.csv",
            "identified": {i: _motor(v).to_json() for i, v in zip("123", (1.0, 2.0, 3.0))},
            "starting": {i: _motor(v).to_json() for i, v in zip("123", (4.0, 5.0, 6.0))},
            "envelope_warnings": ["outside"],
        }
    ]
    # Without notes, no note's keys; without validation, no validation.
    from dataclasses import replace

    assert replace(by_hand, notes=()).summary().to_json()["validation"][0].keys() == {"log", "identified", "starting"}
    assert "validation" not in replace(by_hand, validation=(), notes=()).summary().to_json()
    assert "validation_logs" not in replace(by_hand, validation=(), notes=()).table()


def test_the_comment_header_by_hand(by_hand):
    assert by_hand.comments() == [
        f"{IDENTIFIED_MARK}: a parameter file every hipsim command accepts (--params).",
        "# From the logs: a.csv, b.csv (1234 samples per motor after filtering and decimation).",
        f"# Starting parameters: {by_hand.start.source}.",
        "# Model: analytic, lever spin on; regressor condition number 123.5.",
        "# Residual RMS per motor: M1 1.23 N·mm, M2 2.25 N·mm, M3 0.0123 N·mm.",
        "#",
        "# Identified (value, relative standard deviation); each base parameter is a fixed combination (hipsim identify --base);",
        "# the parameters it folds in keep their starting values below and the first takes the rest:",
        "#  m_L + 0.5·m_l = 3.5 ± 0.01 kg (±0.29 %)",
        "#  μ_h = 0.1 ± 0.02 (±20 %)",
        "#  I_m,xy = 0 ± 1 kg·mm² (near zero)",
        "# Not identified from these logs:",
        "#   I_L = 50 kg·mm²: not determined by these logs: near its prior 54.91 ± 25 (posterior std 20)",
        "#   m_l = 1.43 kg: folded into m_L (starting value kept)",
        "#   b_guide = 0 N·s/mm: no effect on the motor torques (starting value kept)",
        "# Physical consistency constraints active: μ_t ≥ 0; b_U ≥ 0.",
        "# Validation (RMS error of the motor torque, identified vs starting parameters):",
        "#   v.csv: M1 1 vs 4 N·mm, M2 2 vs 5 N·mm, M3 3 vs 6 N·mm",
        "# The [identification] table at the end: base parameters, prior and posterior covariance (file units).",
    ]
    from dataclasses import replace

    bare = replace(
        by_hand,
        lever_spin=False,
        active_constraints=(),
        validation=(),
        notes=(),
        estimates=by_hand.estimates[:2],
        base=replace(by_hand.base, dependent=()),
    )
    lines = bare.comments()
    assert lines[3] == "# Model: analytic, lever spin off; regressor condition number 123.5."
    assert not any(line.startswith(("# Not identified", "# Physical", "# Validation")) for line in lines)
    assert lines[-1].startswith("# The [identification] table")


def test_the_file_written_reads_back(by_hand, tmp_path):
    text = by_hand.toml()
    assert text.startswith("\n".join(by_hand.comments()))
    path = by_hand.write_toml(tmp_path / "id.toml")
    assert path == tmp_path / "id.toml" and path.read_text() == text
    read = read_identified_file(path)
    assert read is not None and read.lever_spin is True
    assert hipsim.load_parameters(path).slider_mass == pytest.approx(by_hand.params.slider_mass)
    from hipsim.rig.identification.identified_file import FileProvenance

    made = FileProvenance("9.9", "2026-11-27T00:00:00Z", "hipsim identify --log a.csv")
    assert "[identification.provenance]" in by_hand.toml(made) and "[identification.provenance]" not in text
    read = read_identified_file(by_hand.write_toml(tmp_path / "made.toml", made))
    assert read is not None and read.provenance == made


# --- Paths the tiny logs above do not take ----------------------------------------------------------------------


def _spy_consistent(monkeypatch):
    from hipsim.rig.identification import fit

    calls = []
    real = fit.consistent

    def spy(*args):
        calls.append(args)
        return real(*args)

    monkeypatch.setattr(fit, "consistent", spy)
    return calls


def test_a_consistent_fit_is_not_solved_again(start, logs, monkeypatch):
    """The posterior mean is kept as it is when the machine it makes is physically consistent."""
    calls = _spy_consistent(monkeypatch)
    identify(logs, start)
    assert calls == []


def test_the_constrained_fit_gets_the_weighted_rows_the_prior_and_the_free_parameters(start, true, monkeypatch):
    wrong = true.replace(ujoint_coulomb=-0.2)
    log = _log(wrong, 5, 120, 1000.0, "wrong.csv", noise=NOISE * 0.1)
    calls = _spy_consistent(monkeypatch)
    result = identify([log], start, fixed=["m_l", "b_guide"])
    ((rows_all, rhs, theta, index, free, theta0, sizes),) = calls
    base = result.base
    assert index == base.index and free == [INDEX["F_c,guide"]]  # the held ones (m_l, b_guide) stay exactly
    np.testing.assert_array_equal(theta0, standard_values(start))
    # Each parameter's size: its starting value, or its typical value where that is zero (the products of inertia).
    expected = np.abs(standard_values(start))
    zero = expected == 0
    assert zero.sum() == 6
    expected[zero] = [QUANTITIES[k].nominal for k in np.flatnonzero(zero)]
    np.testing.assert_array_equal(sizes, expected)
    # The prior's rows: T/s_b against θ_b0/s_b, after the data's P + 1.
    belief = make_prior(base, start, {"m_l": 0.0, "b_guide": 0.0})
    np.testing.assert_allclose(rows_all[P + 1 :], base.transform / belief.std[:, None], rtol=1e-12)
    np.testing.assert_allclose(rhs[P + 1 :], belief.mean / belief.std, rtol=1e-12)
    assert rows_all.shape == (P + 1 + len(base.index), P) and rhs.shape == (P + 1 + len(base.index),)
    assert result.params.friction.guide_viscous == start.friction.guide_viscous


def _rows_of(Y, tau, use):
    def fake(params, log, lever_spin):
        yield Y, tau, use

    return fake


def test_more_rows_than_base_parameters_are_needed(start, logs, monkeypatch):
    """At most r rows: the unweighted fit matches them all, no residual is left to weigh the motors by: refused.
    Three rows or fewer: too few for anything."""
    from hipsim.rig.identification import fit

    Y = regressor(start, logs[0].trajectory)[10:18]
    r = len(base_parameters(start).index)
    use = np.zeros((8, 3), bool)
    use.flat[:r] = True
    monkeypatch.setattr(fit, "log_rows", _rows_of(Y, np.ones((8, 3)), use))
    with pytest.raises(IdentificationError) as error:
        identify(logs[:1], start)
    assert str(error.value) == (
        f"a.csv: {r} samples are too few to identify {r} base parameters and measure the noise (more than {r} needed)"
    )
    use.flat[:] = False
    use.flat[:4] = True
    with pytest.raises(IdentificationError, match="^a.csv: 4 samples are too few to identify 22 base parameters"):
        identify(logs[:1], start)
    use.flat[3] = False
    with pytest.raises(IdentificationError, match="^a.csv: 3 samples are too few to identify anything$"):
        identify(logs[:1], start)


def test_the_prior_names_its_source(start, logs):
    with pytest.raises(ParameterError) as error:
        identify(logs, start, prior={"μ_h": "two %"})
    assert error.value.source == "prior" and str(error.value).startswith("prior: prior of 'μ_h'")
    with pytest.raises(ParameterError) as error:
        identify(logs, start, prior={"μ_h": "two %"}, prior_source="p.toml")
    assert error.value.source == "p.toml"


@pytest.mark.parametrize("lever_spin", [True, False])
def test_validation_compares_both_machines_with_the_fits_model(start, true, lever_spin):
    """A held-out ISO cycle (two heel strikes: the per-phase errors of both machines) at 200 Hz."""
    from hipsim.motion.trajectories import iso14242_at
    from hipsim.rig.compare import compare_log
    from hipsim.rig.identification.validation import training_envelope, validation_note

    fit_log = _log(true, 1, 120, 1000.0, "a.csv", lever_spin=lever_spin)
    iso = iso14242_at(np.arange(0.0, 2.2, 0.005))
    tau = inverse_dynamics(true, kinematics(true, iso), iso.Fe, lever_spin).total
    held_out = MeasuredLog(iso, tau, None, "iso.csv")
    result = identify([fit_log], start, lever_spin=lever_spin, validate=[held_out])
    ((identified, starting),) = result.validation
    assert identified.motor_errors() == compare_log(result.params, held_out, lever_spin).motor_errors()
    assert starting.motor_errors() == compare_log(start, held_out, lever_spin).motor_errors()
    assert starting.motor_errors() != compare_log(start, held_out, not lever_spin).motor_errors()
    (note,) = result.notes
    expected = validation_note(identified, starting, held_out, training_envelope([fit_log]))
    assert note.starting_phase_rms is not None
    np.testing.assert_array_equal(note.starting_phase_rms, expected.starting_phase_rms)
    np.testing.assert_array_equal(note.identified_phase_rms, expected.identified_phase_rms)
    assert note.warnings == expected.warnings
