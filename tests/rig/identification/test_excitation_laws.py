"""Laws of the excitation design on tiny inputs: the Fourier series by hand and by finite differences, its sampling and
file, the limits from a parameter file, the condition number of a hand-made regressor, the margins against the public
model run, and the optimiser's plumbing watched through a stand-in for SciPy's minimize (its start, objective, gradients,
the best of the starts, the fall-back to the start and the shrink on the finer grid)."""

import csv
import math
import warnings
from types import SimpleNamespace
from typing import cast

import numpy as np
import pytest
import scipy.optimize

import hipsim
from hipsim.exceptions import ArgumentError, ExcitationError
from hipsim.motion.trajectories import Trajectory
from hipsim.rig.identification import excitation as module
from hipsim.rig.identification.excitation import (
    DESIGN_QUANTITIES,
    Excitation,
    Limits,
    condition_number,
    excitation,
)
from hipsim.rig.identification.excitation_summary import ExcitationPeaks
from hipsim.rig.identification.quantities import QUANTITIES
from hipsim.rig.identification.regressor import regressor

PARAMS = hipsim.load_parameters()
#: The trajectory of a condition number whose regressor a test replaces: never read.
NO_MOTION = cast(Trajectory, None)
LABELS = [q.label for q in QUANTITIES]
# H = 2: rows α, β, γ [rad] and F_e [N]; columns c0, a1, b1, a2, b2.
COEFFICIENTS = np.array(
    [
        [0.02, 0.10, -0.05, 0.02, 0.01],
        [-0.01, 0.05, 0.08, -0.015, 0.0],
        [0.03, -0.06, 0.04, 0.0, 0.02],
        [1500.0, 800.0, 300.0, 0.0, -100.0],
    ]
)


def _by_hand(coefficients, f, t):
    """q, q̇, q̈ of c0 + Σ a_l sin(2πlft) + b_l cos(2πlft), written out."""
    t = np.atleast_1d(t)
    values = np.tile(coefficients[:, :1], (1, t.size)).astype(float)
    rates, accelerations = np.zeros_like(values), np.zeros_like(values)
    for l in range(1, (coefficients.shape[1] - 1) // 2 + 1):
        w = 2 * math.pi * l * f
        a, b = coefficients[:, 2 * l - 1 : 2 * l], coefficients[:, 2 * l : 2 * l + 1]
        values += a * np.sin(w * t) + b * np.cos(w * t)
        rates += a * w * np.cos(w * t) - b * w * np.sin(w * t)
        accelerations += -a * w * w * np.sin(w * t) - b * w * w * np.cos(w * t)
    return values, rates, accelerations


PEAKS = ExcitationPeaks(7.0, 100.0, 1000.0, 0.5, torque_Nmm=300.0, load_min_N=300.0, load_max_N=3000.0)


def _design(coefficients=COEFFICIENTS, frequency=0.5, **changes):
    fields = dict(
        frequency=frequency,
        harmonics=(coefficients.shape[1] - 1) // 2,
        coefficients=coefficients,
        condition_number=12.5,
        iso_condition_number=40.0,
        quantities=("m_L", "I_L"),
        limits=Limits(),
        peaks=PEAKS,
        seconds=0.25,
    )
    fields.update(changes)
    return Excitation(**fields)


def _trajectory(coefficients, frequency, t):
    values, rates, accelerations = _by_hand(coefficients, frequency, t)
    return Trajectory(t, values[:3].T, rates[:3].T, accelerations[:3].T, values[3])


def test_the_series_and_its_derivatives_by_hand_and_by_differences():
    t = np.array([0.0, 0.13, 0.77, 1.5, 1.99])
    got = _design().at(t)
    values, rates, accelerations = _by_hand(COEFFICIENTS, 0.5, t)
    np.testing.assert_allclose(got.q, values[:3].T, rtol=1e-13, atol=1e-15)
    np.testing.assert_allclose(got.qd, rates[:3].T, rtol=1e-13, atol=1e-15)
    np.testing.assert_allclose(got.qdd, accelerations[:3].T, rtol=1e-13, atol=1e-15)
    np.testing.assert_allclose(got.Fe, values[3], rtol=1e-14)
    np.testing.assert_array_equal(got.t, t)
    assert got.name == "excitation"
    h = 1e-5
    design = _design()
    np.testing.assert_allclose(got.qd, (design.at(t + h).q - design.at(t - h).q) / (2 * h), rtol=1e-8, atol=1e-10)
    np.testing.assert_allclose(got.qdd, (design.at(t + h).qd - design.at(t - h).qd) / (2 * h), rtol=1e-7, atol=1e-8)
    # At t = 0 only the cosines: c0 + b1 + b2.
    assert design.at(0.0).Fe[0] == pytest.approx(1500.0 + 300.0 - 100.0, rel=1e-15)
    # A period later, the same.
    np.testing.assert_allclose(design.at(t + 2.0).q, got.q, atol=1e-12)


def test_one_harmonic_and_three():
    one = np.array([[0.1, 0.2, 0.3]] * 3 + [[1000.0, 10.0, 20.0]])
    t = np.array([0.1, 0.4])
    got = _design(one, frequency=2.0).at(t)
    np.testing.assert_allclose(got.q, _by_hand(one, 2.0, t)[0][:3].T, rtol=1e-13)
    three = np.arange(28, dtype=float).reshape(4, 7) * 1e-3
    got = _design(three, frequency=0.25).at(t)
    values, rates, accelerations = _by_hand(three, 0.25, t)
    np.testing.assert_allclose(got.qdd, accelerations[:3].T, rtol=1e-12)
    np.testing.assert_allclose(got.Fe, values[3], rtol=1e-12)


@pytest.mark.parametrize(
    ("duration", "samples"),
    [(None, 20), (2.0, 20), (2.5, 40), (4.0, 40), (4.0000001, 60), (0.1, 20), (3.99999999999, 40)],
)
def test_sampled_over_whole_periods(duration, samples):
    trajectory = _design().trajectory(rate=10.0, duration=duration)  # period 2 s
    assert len(trajectory) == samples and trajectory.periodic
    np.testing.assert_allclose(trajectory.t, np.arange(samples) / 10.0, rtol=1e-15)
    np.testing.assert_allclose(trajectory.q, _by_hand(COEFFICIENTS, 0.5, trajectory.t)[0][:3].T, rtol=1e-12, atol=1e-15)
    assert trajectory.name == "excitation"
    assert len(_design().trajectory()) == 2000  # 1 kHz, one period


def test_the_written_file_closes_the_period(tmp_path):
    design = _design(frequency=1.0)
    path = design.write_csv(tmp_path / "e.csv", rate=4.0, duration=1.5)  # two periods: 8 samples and the closing one
    with open(path, newline="", encoding="utf-8") as f:
        rows = list(csv.reader(f))
    assert rows[0] == ["t_s", "alpha_deg", "beta_deg", "gamma_deg", "Fe_N"]
    table = np.array(rows[1:], dtype=float)
    assert table.shape == (9, 5)
    t = np.arange(9) / 4.0
    values = _by_hand(COEFFICIENTS, 1.0, t)[0]
    np.testing.assert_allclose(table[:, 0], t, rtol=1e-12)
    np.testing.assert_allclose(table[:, 1:4], np.degrees(values[:3].T), rtol=1e-10, atol=1e-10)
    np.testing.assert_allclose(table[:, 4], values[3], rtol=1e-10)
    np.testing.assert_allclose(table[-1, 1:], table[0, 1:], rtol=1e-10, atol=1e-10)
    again = design.write_csv(tmp_path / "f.csv")  # 1 kHz, one period
    assert sum(1 for _ in open(again, encoding="utf-8")) == 1 + 1001


def test_the_summary():
    summary = _design().summary()
    document = summary.to_json()
    verdict = document.pop("verdict")
    assert document == {
        "frequency_Hz": 0.5,
        "period_s": 2.0,
        "harmonics": 2,
        "condition_number": 12.5,
        "iso_condition_number": 40.0,
        "quantities": ["m_L", "I_L"],
        "peaks": {
            "angle_deg": 7.0,
            "speed_mm_s": 100.0,
            "acceleration_mm_s2": 1000.0,
            "cond_inv_min": 0.5,
            "torque_Nmm": 300.0,
            "load_min_N": 300.0,
            "load_max_N": 3000.0,
        },
        "design_seconds": 0.25,
    }
    # The load at both ends of the default range (300 to 3000 N): equal passes; margins limit minus peak.
    assert verdict["level"] == "PASS" and summary.level.value == "PASS"
    assert verdict["numbers"]["load_min_margin_N"] == 0.0 and verdict["numbers"]["speed_margin_mm_s"] == 250.0
    with pytest.raises(ExcitationError, match="peaks were not computed"):
        _design(peaks=None).summary()


def test_limits_from_the_parameter_file():
    assert Limits.for_machine(PARAMS) == Limits()  # the published file has no torque limit and no motor ratings
    rated = PARAMS.replace(motor={"peak_torque_Nmm": 700.0, "max_speed_rpm": 3000.0})
    got = Limits.for_machine(rated)
    assert got.torque_limit == pytest.approx(0.7, rel=1e-15) and got.max_speed == pytest.approx(
        0.5, rel=1e-15
    )  # 50 rev/s, 10 mm lead
    assert got == Limits(torque_limit=got.torque_limit, max_speed=got.max_speed)
    limited = rated.replace(torque_limit=0.5)
    assert Limits.for_machine(limited).torque_limit == 0.5  # the control's limit before the motor's peak
    assert Limits.for_machine(PARAMS.replace(torque_limit=0.45)) == Limits(torque_limit=0.45)
    changed = Limits.for_machine(rated, max_angle=0.2, min_load=None, torque_limit=0.3)
    assert changed == Limits(max_angle=0.2, torque_limit=0.3, max_speed=got.max_speed)
    assert Limits.for_machine(PARAMS.replace(motor={"max_speed_rpm": 600.0})) == Limits(max_speed=0.1)


def _fake_regressor(columns: dict[int, np.ndarray], seen: list):
    def fake(params, trajectory, lever_spin):
        seen.append(lever_spin)
        Y = np.full((4, 3, len(QUANTITIES)), 1e3) * np.arange(1, len(QUANTITIES) + 1)  # other columns: large, parallel
        for k, column in columns.items():
            Y[:, :, k] = column.reshape(4, 3)
        return Y

    return fake


def test_the_condition_number_of_a_hand_made_regressor(monkeypatch):
    """Unit-norm columns u, v with u·v = c: singular values √(1 ± c), condition √((1 + c)/(1 − c))."""
    u = np.zeros(12)
    u[0] = 2.0  # norm 2
    v = np.zeros(12)
    v[0], v[5] = 3.0, 4.0  # norm 5, cosine 3/5 with u
    seen: list = []
    m, i = LABELS.index("m_L"), LABELS.index("I_L")
    monkeypatch.setattr(module, "regressor", _fake_regressor({m: u, i: v}, seen))
    assert condition_number(PARAMS, NO_MOTION, ("m_L", "I_L"), lever_spin=False) == pytest.approx(2.0, rel=1e-12)
    assert seen == [False]
    w = np.zeros(12)
    w[7] = 0.5
    monkeypatch.setattr(module, "regressor", _fake_regressor({m: u, i: v, 0: w}, seen))
    # Three columns: w is orthogonal to both, so the singular values are √1.6, √0.4 and 1.
    assert condition_number(PARAMS, NO_MOTION, ("I_m,xx", "m_L", "I_L")) == pytest.approx(2.0, rel=1e-12)
    assert seen[-1] is True
    monkeypatch.setattr(module, "regressor", _fake_regressor({m: u, i: np.zeros(12)}, seen))
    assert condition_number(PARAMS, NO_MOTION, ("m_L", "I_L")) == math.inf  # a column the motion does not move
    monkeypatch.setattr(module, "regressor", _fake_regressor({m: u, i: 7 * u, 0: w}, seen))
    with np.errstate(divide="raise"):
        assert (
            condition_number(PARAMS, NO_MOTION, ("m_L", "I_L")) == math.inf
        )  # two columns the motion cannot tell apart
        # ... and with a third it can: singular values √2, 1 and 0.
        assert condition_number(PARAMS, NO_MOTION, ("m_L", "I_L", "I_m,xx")) == math.inf


def test_the_condition_number_along_a_trajectory_by_its_gram_matrix():
    trajectory = _trajectory(COEFFICIENTS, 0.5, np.arange(12) / 6.0)
    for quantities, spin in ((DESIGN_QUANTITIES, True), (("m_L", "I_L", "μ_h", "μ_t"), False)):
        A = regressor(PARAMS, trajectory, spin)[:, :, [LABELS.index(q) for q in quantities]].reshape(
            -1, len(quantities)
        )
        A = A / np.linalg.norm(A, axis=0)
        eigen = np.linalg.eigvalsh(A.T @ A)
        assert condition_number(PARAMS, trajectory, quantities, spin) == pytest.approx(
            math.sqrt(eigen[-1] / eigen[0]), rel=1e-6
        )


def test_an_unknown_label_is_named():
    with pytest.raises(ArgumentError) as caught:
        condition_number(PARAMS, NO_MOTION, ("m_L", "m_X"))
    assert str(caught.value) == f"quantities: expected a parameter's label ({', '.join(LABELS)}), got 'm_X'"


LIMITS = Limits(
    max_angle=0.4,
    min_load=250.0,
    max_load=2600.0,
    max_speed=0.3,
    max_acceleration=2.2,
    torque_limit=0.55,
    min_cond_inv=0.2,
)
GRID = np.arange(8) / (8 * 0.5)


def _columns(quantities):
    return [LABELS.index(q) for q in quantities]


def _margins_by_hand(coefficients, spin=True, limits=LIMITS):
    trajectory = _trajectory(coefficients, 0.5, GRID)
    run = hipsim.analyse(PARAMS, trajectory, lever_spin=spin)
    q, F = trajectory.q, trajectory.Fe
    return trajectory, np.concatenate(
        [
            1 - np.abs(q.T).ravel() / limits.max_angle,
            (F - limits.min_load) / limits.max_load,
            (limits.max_load - F) / limits.max_load,
            run.cond_inv / limits.min_cond_inv - 1,
            1 - np.abs(run.Ld[:, 0]).ravel() / limits.max_speed,
            1 - np.abs(run.Ldd[:, 0]).ravel() / limits.max_acceleration,
            1 - np.abs(run.torques.total).ravel() / limits.torque_limit,
        ]
    )


@pytest.mark.parametrize("spin", [True, False])
def test_the_objective_and_margins_against_the_public_model_run(spin):
    quantities = ("m_L", "I_L", "μ_h", "μ_t", "b_screw")
    value, margins = module._evaluate(PARAMS, COEFFICIENTS, 0.5, GRID, _columns(quantities), spin, LIMITS)
    trajectory, want = _margins_by_hand(COEFFICIENTS, spin)
    assert margins.shape == (15 * 8,)
    np.testing.assert_allclose(margins, want, rtol=1e-9, atol=1e-12)
    assert value == pytest.approx(math.log(condition_number(PARAMS, trajectory, quantities, spin)), rel=1e-9)


def test_a_set_out_of_reach_has_no_objective_and_fails_every_model_margin():
    far = COEFFICIENTS.copy()
    far[0, 0] = math.radians(120.0)  # lever 2 cannot span the gap
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # quietly: NumPy's warnings of the NaNs out of reach are silenced
        value, margins = module._evaluate(PARAMS, far, 0.5, GRID, _columns(("m_L", "I_L")), True, LIMITS)
        both = module._evaluate_many(PARAMS, [far, COEFFICIENTS], 0.5, GRID, _columns(("m_L", "I_L")), True, LIMITS)
    assert value == math.inf and margins.shape == (15 * 8,)
    # The set after it is still evaluated, as if alone.
    assert len(both) == 2 and both[0][0] == math.inf
    alone = module._evaluate(PARAMS, COEFFICIENTS, 0.5, GRID, _columns(("m_L", "I_L")), True, LIMITS)
    assert both[1][0] == pytest.approx(alone[0], rel=1e-12)
    q, F = _by_hand(far, 0.5, GRID)[0][:3], _by_hand(far, 0.5, GRID)[0][3]
    np.testing.assert_allclose(margins[:24], 1 - np.abs(q).ravel() / 0.4, rtol=1e-12)
    np.testing.assert_allclose(margins[24:32], (F - 250.0) / 2600.0, rtol=1e-12)
    np.testing.assert_allclose(margins[32:40], (2600.0 - F) / 2600.0, rtol=1e-12)
    assert np.all(margins[40:] == -1.0)


def test_a_first_sample_out_of_reach_flags_its_set():
    """α = 60° + 60°·cos(πt) on two samples: 120° (out of reach) at t = 0, 0° at t = 1 s."""
    far = np.zeros((4, 3))
    far[0, [0, 2]] = math.radians(60.0)
    far[3, 0] = 1000.0
    value, margins = module._evaluate(PARAMS, far, 0.5, np.array([0.0, 1.0]), _columns(("m_L", "I_L")), True, LIMITS)
    assert value == math.inf and margins.shape == (30,)
    np.testing.assert_allclose(margins[:2], [1 - math.radians(120.0) / 0.4, 1.0], rtol=1e-12, atol=1e-15)
    assert np.all(margins[10:] == -1.0)


def test_a_motion_that_leaves_a_column_still_has_no_objective_but_its_margins():
    still = np.zeros((4, 5))
    still[:, 0] = [0.01, -0.02, 0.03, 1200.0]  # a pose held: no speed, so no viscous friction to see
    value, margins = module._evaluate(PARAMS, still, 0.5, GRID, _columns(("m_L", "b_screw")), True, LIMITS)
    assert value == math.inf
    np.testing.assert_allclose(margins, _margins_by_hand(still)[1], rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(margins[48:72], 1.0)  # the sliders do not move


def test_a_set_after_one_of_the_other_sign_of_det_j_is_not_said_to_cross_a_singularity():
    """Sets evaluated together are one run: the first sample of a set is not compared with the set before it."""
    other = np.zeros((4, 5))
    other[:, 0] = [math.radians(-90.0), math.radians(-45.0), 0.0, 1000.0]  # reachable, det J < 0 (home's is > 0)
    columns = _columns(("m_L", "I_L", "μ_h"))
    alone = module._evaluate(PARAMS, COEFFICIENTS, 0.5, GRID, columns, True, LIMITS)
    together = module._evaluate_many(PARAMS, [other, COEFFICIENTS, other], 0.5, GRID, columns, True, LIMITS)
    assert math.isfinite(alone[0]) and together[1][0] == pytest.approx(alone[0], rel=1e-12)
    np.testing.assert_allclose(together[1][1], alone[1], rtol=1e-12, atol=1e-14)
    # The held pose's own margins are not spoiled by the set before it either.
    held = module._evaluate(PARAMS, other, 0.5, GRID, columns, True, LIMITS)
    np.testing.assert_allclose(together[2][1], held[1], rtol=1e-12, atol=1e-14)


@pytest.mark.parametrize(
    ("kwargs", "words"),
    [
        ({"harmonics": 0}, "harmonics: expected a whole number from 1 to 50, got 0"),
        ({"harmonics": 51}, "harmonics: expected a whole number from 1 to 50, got 51"),
        ({"harmonics": True}, "harmonics: expected a whole number from 1 to 50, got True"),
        ({"harmonics": 2.0}, "harmonics: expected a whole number from 1 to 50, got 2.0"),
        ({"frequency": 0.0}, "frequency: expected a base frequency above 0 and at most 20 Hz, got 0.0"),
        ({"frequency": -1}, "frequency: expected a base frequency above 0 and at most 20 Hz, got -1"),
        ({"frequency": 20.5}, "frequency: expected a base frequency above 0 and at most 20 Hz, got 20.5"),
        ({"frequency": math.inf}, "frequency: expected a base frequency above 0 and at most 20 Hz, got inf"),
        ({"frequency": math.nan}, "frequency: expected a base frequency above 0 and at most 20 Hz, got nan"),
        ({"frequency": "1"}, "frequency: expected a base frequency above 0 and at most 20 Hz, got '1'"),
        (
            {"limits": Limits(min_load=500.0, max_load=500.0)},
            "limits: expected a load range in [N] that is not empty, got (500.0, 500.0)",
        ),
        ({"quantities": ("m_L", "nope")}, "quantities: expected a parameter's label"),
    ],
)
def test_impossible_settings_are_named(kwargs, words):
    with pytest.raises(ArgumentError) as caught:
        excitation(PARAMS, **({"harmonics": 1} | kwargs))
    assert str(caught.value).startswith(words)


class Watch:
    """SciPy's minimize watched: each call's objective, start, options and constraints; ``answer`` replaces its result."""

    def __init__(self, answer=None):
        self.calls: list = []
        self.answer = answer
        self.real = scipy.optimize.minimize

    def __call__(self, fun, x0, **kwargs):
        self.calls.append(SimpleNamespace(fun=fun, x0=np.array(x0), kwargs=kwargs, f0=fun(np.array(x0))))
        if self.answer is not None:
            return scipy.optimize.OptimizeResult(x=self.answer(np.array(x0)))
        return self.real(fun, x0, **kwargs)


SPAN = np.array([math.radians(30.0)] * 3 + [1350.0])  # the default limits: ±30°, 300 … 3000 N
SAMPLES = 10


def _run(watch, **kwargs):
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(scipy.optimize, "minimize", watch)
        options = {"frequency": 0.5, "harmonics": 1, "samples": SAMPLES, "max_iter": 3} | kwargs
        return excitation(PARAMS, **options)


def test_a_tiny_design_from_start_to_end():
    """One harmonic, ten samples, six SLSQP iterations; run inside the test (not a fixture), so that the mutation tool
    runs every check below against each change of the design. SciPy must know every option it is given."""
    watch = Watch()
    with warnings.catch_warnings():
        warnings.simplefilter("error", scipy.optimize.OptimizeWarning)
        design = _run(watch, max_iter=6)
    _check_start(design, watch)
    _check_gradients(design, watch)
    _check_result(design, watch)
    _check_moved(design, watch)


def _unpack(x, H=1):
    return x.reshape(4, 2 * H + 1) * SPAN[:, None]


def _check_start(design, watch):
    """The start is feasible and centred, the load swinging over 0.9 of its half range."""
    (call,) = watch.calls
    start = _unpack(call.x0)
    np.testing.assert_allclose(start[:, 0], [0.0, 0.0, 0.0, 1650.0], atol=1e-12)
    assert math.hypot(start[3, 1], start[3, 2]) == pytest.approx(0.9 * 1350.0, rel=1e-12)
    assert np.all(np.abs(start[:3, 1:]) > 0) and np.all(np.abs(start[:3, 1:]) < 0.5 * SPAN[0] * 5)
    grid = np.arange(SAMPLES) / (SAMPLES * 0.5)
    trajectory = _trajectory(start, 0.5, grid)
    assert call.f0 == pytest.approx(math.log(condition_number(PARAMS, trajectory)), rel=1e-9)
    (constraint,) = call.kwargs["constraints"]
    assert constraint["type"] == "ineq"
    margins = constraint["fun"](call.x0)
    assert margins.shape == (15 * SAMPLES,) and np.all(margins >= 0)
    assert call.kwargs["method"] == "SLSQP" and call.kwargs["options"]["maxiter"] == 6


def _central(fun, x, h=1e-6):
    return np.array([(fun(x + h * e) - fun(x - h * e)) / (2 * h) for e in np.eye(x.size)])


def _check_gradients(design, watch):
    """The gradients given to SLSQP are the objective's and the margins' slopes."""
    (call,) = watch.calls
    x = call.x0
    slope = call.kwargs["jac"](x)
    want = _central(call.fun, x)
    np.testing.assert_allclose(slope, want, rtol=1e-4, atol=1e-5 * np.abs(want).max())
    (constraint,) = call.kwargs["constraints"]
    jacobian = constraint["jac"](x)
    want = _central(constraint["fun"], x).T
    assert jacobian.shape == (15 * SAMPLES, x.size)
    np.testing.assert_allclose(jacobian, want, rtol=1e-4, atol=1e-5 * np.abs(want).max())
    # Asked again: the same numbers (cached), and the objective too.
    np.testing.assert_array_equal(call.kwargs["jac"](x), slope)
    assert call.fun(x) == call.f0


def _check_result(design, watch):
    """The design says what it achieves."""
    assert design.frequency == 0.5 and design.harmonics == 1 and design.coefficients.shape == (4, 3)
    assert design.quantities == DESIGN_QUANTITIES and design.limits == Limits()
    fine = np.arange(10 * SAMPLES) / (10 * SAMPLES * 0.5)
    trajectory = design.at(fine)
    assert design.condition_number == pytest.approx(condition_number(PARAMS, trajectory), rel=1e-9)
    assert design.iso_condition_number == pytest.approx(
        condition_number(PARAMS, hipsim.iso14242(rate=10 * SAMPLES)), rel=1e-12
    )
    run = hipsim.analyse(PARAMS, trajectory, lever_spin=True)
    want = {  # in the record's order
        "angle_deg": math.degrees(np.abs(trajectory.q).max()),
        "speed_mm_s": np.abs(run.Ld).max() * 1e3,
        "acceleration_mm_s2": np.abs(run.Ldd).max() * 1e3,
        "cond_inv_min": run.cond_inv.min(),
        "torque_Nmm": np.abs(run.torques.total).max() * 1e3,
        "load_min_N": trajectory.Fe.min(),
        "load_max_N": trajectory.Fe.max(),
    }
    assert design.peaks is not None and design.peaks.to_json() == pytest.approx(want, rel=1e-9)
    limits = design.limits
    assert want["angle_deg"] <= 30.0 and want["cond_inv_min"] >= limits.min_cond_inv
    assert want["speed_mm_s"] <= 350.0 and want["acceleration_mm_s2"] <= 2500.0 and want["torque_Nmm"] <= 600.0
    assert 300.0 <= want["load_min_N"] and want["load_max_N"] <= 3000.0
    assert 0 < design.seconds < 600


def test_a_seed_decides_the_design():
    first = _run(Watch(lambda x: x), seed=4)
    again = _run(Watch(lambda x: x), seed=4)
    other = _run(Watch(lambda x: x), seed=5)
    np.testing.assert_array_equal(first.coefficients, again.coefficients)
    assert not np.allclose(first.coefficients, other.coefficients)


@pytest.mark.parametrize(("seeds", "starts"), [(0, 1), (1, 1), (2, 2), (3, 3)])
def test_one_optimisation_per_start(seeds, starts):
    watch = Watch(lambda x: x)
    _run(watch, seeds=seeds)
    assert len(watch.calls) == starts


def _shrunk(coefficients, start):
    """``coefficients`` are ``start`` with its harmonics shrunk by 0.995ᵏ (the finer grid's check); k returned."""
    np.testing.assert_allclose(coefficients[:, 0], start[:, 0], rtol=1e-15)
    ratio = coefficients[:, 1:] / start[:, 1:]
    k = math.log(ratio[0, 0]) / math.log(0.995)
    np.testing.assert_allclose(ratio, 0.995 ** round(k), rtol=1e-12)
    return round(k)


def test_the_best_start_is_kept():
    watch = Watch(lambda x: x)  # no optimisation: each result is its start
    design = _run(watch, seeds=3, seed=2)
    best = min(watch.calls, key=lambda c: c.f0)
    assert len({c.f0 for c in watch.calls}) == 3
    _shrunk(design.coefficients, _unpack(best.x0))


def test_a_result_outside_the_limits_falls_back_to_its_start():
    watch = Watch(lambda x: 40.0 * x)  # far beyond every limit
    design = _run(watch, seed=1)
    _shrunk(design.coefficients, _unpack(watch.calls[0].x0))


def test_a_result_of_no_objective_falls_back_to_its_start():
    watch = Watch(lambda x: x + np.r_[[math.radians(120.0) / SPAN[0]], np.zeros(x.size - 1)])  # out of reach
    design = _run(watch, seed=1)
    _shrunk(design.coefficients, _unpack(watch.calls[0].x0))


class FineFails:
    """``_evaluate`` that reports a broken limit on the finer grid ``times`` times, else the real one; calls recorded."""

    def __init__(self, times, samples=SAMPLES):
        self.times, self.real, self.seen, self.fine = times, module._evaluate, [], 10 * samples

    def __call__(self, params, coefficients, frequency, grid, columns, lever_spin, limits):
        self.seen.append((grid.size, coefficients.copy()))
        if grid.size == self.fine and self.times > 10**5:  # failing for good: no model run needed
            return 1.0, np.full(15 * grid.size, -1.0)
        value, margins = self.real(params, coefficients, frequency, grid, columns, lever_spin, limits)
        if grid.size == self.fine and self.times > 0:
            self.times -= 1
            margins = margins.copy()
            margins[0] = -1e-6
        return value, margins


def test_the_finer_grid_shrinks_the_harmonics_until_the_limits_hold(monkeypatch):
    fails = FineFails(3)
    monkeypatch.setattr(module, "_evaluate", fails)
    watch = Watch(lambda x: x)
    design = _run(watch)
    assert _shrunk(design.coefficients, _unpack(watch.calls[0].x0)) == 3
    fine = [c for size, c in fails.seen if size == 10 * SAMPLES]
    assert len(fine) == 4
    fine_grid = np.arange(10 * SAMPLES) / (10 * SAMPLES * 0.5)
    assert design.condition_number == pytest.approx(condition_number(PARAMS, design.at(fine_grid)), rel=1e-9)


def test_a_design_that_never_holds_on_the_finer_grid_is_refused(monkeypatch):
    fails = FineFails(10**6, samples=2)
    monkeypatch.setattr(module, "_evaluate", fails)
    with pytest.raises(ExcitationError) as caught:
        _run(Watch(lambda x: x), samples=2)
    assert str(caught.value) == (
        "the designed excitation breaks the limits between its samples: give more samples per period"
    )
    assert sum(1 for size, _ in fails.seen if size == 20) == 100


def test_a_start_is_shrunk_by_0_7_until_it_is_feasible(monkeypatch):
    fails = FineFails(0)
    monkeypatch.setattr(module, "_evaluate", fails)
    watch = Watch(lambda x: x)
    slow = Limits(max_speed=0.03)
    _run(watch, limits=slow)
    starts = [c for size, c in fails.seen if size == SAMPLES]
    start = _unpack(watch.calls[0].x0)
    np.testing.assert_allclose(starts[-1], start, rtol=1e-15)
    assert len(starts) >= 2  # the first random start was too fast for 30 mm/s
    for before, after in zip(starts, starts[1:]):
        np.testing.assert_allclose(after[:3, 1:], 0.7 * before[:3, 1:], rtol=1e-12)
        np.testing.assert_array_equal(after[3], before[3])
        np.testing.assert_array_equal(after[:, 0], before[:, 0])
    for c in starts[:-1]:
        value, margins = module._evaluate(
            PARAMS, c, 0.5, np.arange(SAMPLES) / (SAMPLES * 0.5), _columns(DESIGN_QUANTITIES), True, slow
        )
        assert not (math.isfinite(value) and np.all(margins >= 0))


@pytest.mark.parametrize("spin", [True, False])
def test_the_design_is_for_its_quantities_and_model(spin):
    """With the levers' inertia among the quantities, whose columns the levers' spin changes (I_l,xz: ~100 times).

    (Not I_l,zz: without the spin its column is round-off, ~1e-21, and the condition number of such a column is noise.)
    """
    quantities = ("m_L", "I_L", "I_l,xx", "I_l,xz")
    watch = Watch(lambda x: x)
    design = _run(watch, lever_spin=spin, quantities=list(quantities))
    (call,) = watch.calls
    start = _unpack(call.x0)
    grid = np.arange(SAMPLES) / (SAMPLES * 0.5)
    want = math.log(condition_number(PARAMS, _trajectory(start, 0.5, grid), quantities, lever_spin=spin))
    assert call.f0 == pytest.approx(want, rel=1e-9)
    assert design.quantities == quantities
    assert design.iso_condition_number == pytest.approx(
        condition_number(PARAMS, hipsim.iso14242(rate=10 * SAMPLES), quantities, spin), rel=1e-12
    )
    fine = np.arange(10 * SAMPLES) / (10 * SAMPLES * 0.5)
    assert design.condition_number == pytest.approx(
        condition_number(PARAMS, design.at(fine), quantities, spin), rel=1e-9
    )
    # The gradient's model too: the slope along the first angle's first sine, by central differences.
    e = np.zeros(call.x0.size)
    e[1] = 1e-6
    slope = (call.fun(call.x0 + e) - call.fun(call.x0 - e)) / 2e-6
    assert call.kwargs["jac"](call.x0)[1] == pytest.approx(slope, rel=1e-4, abs=1e-6)


def test_a_result_that_breaks_a_limit_falls_back_to_its_start():
    """A result within reach (a finite objective) whose load exceeds its largest by 1350 N: its start is kept."""
    watch = Watch(lambda x: x + np.r_[np.zeros(9), 1.0, 0.0, 0.0])  # the load's centre up by one half range
    design = _run(watch, seed=1)
    _shrunk(design.coefficients, _unpack(watch.calls[0].x0))


def test_default_samples_are_twenty_per_harmonic_and_at_least_a_hundred(monkeypatch):
    for harmonics, samples in ((1, 100), (5, 100), (6, 120)):
        recorder = Recorder()
        monkeypatch.setattr(module, "_evaluate", recorder)
        with pytest.MonkeyPatch.context() as patch:
            patch.setattr(scipy.optimize, "minimize", Watch(lambda x: x))
            with pytest.raises(Stop):
                excitation(PARAMS, harmonics=harmonics, frequency=0.5)
        assert [r.grid.size for r in recorder.seen] == [samples, 10 * samples]


def test_the_random_start_falls_with_the_harmonic_and_swings_the_load_over_most_of_its_range(monkeypatch):
    """The first start by hand from the seed's numbers: angles N(0, 1)·l^-1.5·span/2, the load 0.9 of its half range at a random phase."""
    recorder = Recorder()
    monkeypatch.setattr(module, "_evaluate", recorder)
    with pytest.raises(Stop):
        _run(Watch(lambda x: x), harmonics=2, seed=3)
    rng = np.random.default_rng(3)
    normal = rng.normal(size=(3, 4))
    phase = rng.uniform(0, 2 * math.pi)
    want = np.zeros((4, 5))
    want[:, 0] = [0.0, 0.0, 0.0, 1650.0]
    want[:3, 1:] = normal * np.array([1.0, 1.0, 2**-1.5, 2**-1.5]) * 0.5 * math.radians(30.0)
    want[3, 1:3] = 0.9 * 1350.0 * np.array([math.cos(phase), math.sin(phase)])
    np.testing.assert_allclose(recorder.seen[0].coefficients, want, rtol=1e-12, atol=1e-15)


def _check_moved(design, watch):
    """The optimiser moves from its start."""
    start = _unpack(watch.calls[0].x0)
    assert not np.allclose(design.coefficients[:3, 1:], start[:3, 1:], rtol=1e-3)
    # Better posed than its start on the design's samples (its last step breaks a margin by ~1e-10: accepted).
    grid = np.arange(SAMPLES) / (SAMPLES * 0.5)
    value, margins = module._evaluate(
        PARAMS, design.coefficients, 0.5, grid, _columns(DESIGN_QUANTITIES), True, Limits()
    )
    assert value < watch.calls[0].f0 - 0.5 and margins.min() > -1e-9


class Stop(Exception):
    """Raised by a stand-in model: the design got past its checks of the settings."""


class Recorder:
    """``_evaluate`` standing in for the model: every set feasible, objective 1; stops at the finer grid (or at once)."""

    def __init__(self, at_once=False):
        self.at_once, self.seen = at_once, []

    def __call__(self, params, coefficients, frequency, grid, columns, lever_spin, limits):
        self.seen.append(SimpleNamespace(coefficients=coefficients.copy(), grid=grid.copy(), lever_spin=lever_spin))
        if self.at_once or len(self.seen) > 1:
            raise Stop
        return 1.0, np.zeros(15 * grid.size)


@pytest.mark.parametrize(
    "kwargs", [{"harmonics": np.int64(1)}, {"harmonics": 50}, {"frequency": 20}, {"frequency": 1e-3}]
)
def test_the_ends_of_the_settings_are_allowed(monkeypatch, kwargs):
    monkeypatch.setattr(module, "_evaluate", Recorder(at_once=True))
    with pytest.raises(Stop):
        excitation(PARAMS, **kwargs)


def test_the_defaults(monkeypatch):
    """0.5 Hz, five harmonics, 100 samples, the levers' spin, one start of seed 0, forty SLSQP iterations."""
    recorder = Recorder()
    monkeypatch.setattr(module, "_evaluate", recorder)
    watch = Watch(lambda x: x)
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(scipy.optimize, "minimize", watch)
        with pytest.raises(Stop):
            excitation(PARAMS)
    (call,) = watch.calls
    assert call.kwargs["options"]["maxiter"] == 40
    first, fine = recorder.seen
    np.testing.assert_allclose(first.grid, np.arange(100) / 50.0, rtol=1e-15)
    np.testing.assert_allclose(fine.grid, np.arange(1000) / 500.0, rtol=1e-15)
    assert first.lever_spin is True and first.coefficients.shape == (4, 11)
    rng = np.random.default_rng(0)
    decay = np.repeat(np.arange(1, 6), 2) ** -1.5
    np.testing.assert_allclose(first.coefficients[:3, 1:], rng.normal(size=(3, 10)) * decay * 0.5 * SPAN[0], rtol=1e-12)


def test_each_start_gets_forty_tries(monkeypatch):
    """Two starts that never hold (a stand-in that says so, and says the objective is finite): 2 × 40 tries, then refused."""
    seen = []

    def never(params, coefficients, frequency, grid, columns, lever_spin, limits):
        seen.append(coefficients.copy())
        return 1.0, np.r_[np.zeros(15 * grid.size - 1), -1e-12]

    monkeypatch.setattr(module, "_evaluate", never)
    with pytest.raises(ExcitationError) as caught:
        _run(Watch(lambda x: x), seeds=2)
    assert str(caught.value) == (
        "no excitation within the limits was found: relax the limits (speed, acceleration, torque, singularity measure)"
    )
    assert len(seen) == 80
    for before, after in zip(seen[:39], seen[1:40]):  # each try smaller by 0.7, the load and centres kept
        np.testing.assert_allclose(after[:3, 1:], 0.7 * before[:3, 1:], rtol=1e-12)
        np.testing.assert_array_equal(after[3], before[3])
        np.testing.assert_array_equal(after[:, 0], before[:, 0])
    # The second start is a new draw, not the first one shrunk further.
    assert not np.allclose(seen[40][:3, 1:], 0.7 * seen[39][:3, 1:])
