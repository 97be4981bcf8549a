"""Laws of the uncertainty carried forward, on tiny inputs: the covariance read back and checked (errors naming file and
key), √(y_kᵀ Σ y_k) against Σ pushed through the regressor's columns by hand, the draws' factor recovered exactly from
their normal numbers, the 95 % bands, the band summary worked out by hand, the machines one standard deviation away."""

import math

import numpy as np
import pytest
import scipy.stats
from support import given

import hipsim
from hipsim.exceptions import ParameterError
from hipsim.motion.trajectories import Trajectory
from hipsim.rig.identification.base import base_parameters
from hipsim.rig.identification.quantities import QUANTITIES, standard_values
from hipsim.rig.identification.regressor import regressor
from hipsim.rig.identification.uncertainty import (
    Z95,
    Covariance,
    band_columns,
    band_summary,
    log_torque_std,
    read_covariance,
    sigma_machines,
    torque_draws,
    torque_std,
)
from hipsim.rig.logs.log import MeasuredLog

PARAMS = hipsim.load_parameters()
BASE = base_parameters(PARAMS, True)
NAMES = BASE.names
R = len(NAMES)
TRAJECTORY = hipsim.iso14242(rate=10)
# The regressor's base columns, the route the code under test does not take: its index, by label.
Y = regressor(PARAMS, TRAJECTORY, True)[:, :, [[q.label for q in QUANTITIES].index(name) for name in NAMES]]


def _toml(value) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        return '"' + value + '"'
    if isinstance(value, (list, tuple, np.ndarray)):
        return "[" + ", ".join(_toml(v) for v in value) + "]"
    value = float(value)
    return "nan" if math.isnan(value) else ("inf" if value == math.inf else repr(value))


def _file(tmp_path, **table):
    path = tmp_path / "identified.toml"
    path.write_text("[identification]\n" + "".join(f"{k} = {_toml(v)}\n" for k, v in table.items()), encoding="utf-8")
    return path


def _covariance(matrix, lever_spin=True) -> Covariance:
    return Covariance(tuple(NAMES), np.asarray(matrix, float), (True,) * R, lever_spin, "test")


def _unit(p: int, s: float = 1.0) -> np.ndarray:
    out = np.zeros((R, R))
    out[p, p] = s * s
    return out


def test_no_file_or_no_covariance_is_none(tmp_path):
    assert read_covariance(None, PARAMS) is None
    assert read_covariance(_file(tmp_path, base=NAMES), PARAMS) is None


def test_a_covariance_is_read_in_si_with_its_flags_and_residual(tmp_path):
    rng = np.random.default_rng(1)
    A = rng.normal(size=(R, 4))
    C = A @ A.T  # file units, rank 4
    path = _file(tmp_path, base=NAMES, covariance=C, residual_rms_Nmm=[1.0, 2.5, 4.0])
    got = given(read_covariance(path, PARAMS))
    scale = np.array([QUANTITIES[[q.label for q in QUANTITIES].index(n)].scale for n in NAMES])
    np.testing.assert_allclose(got.matrix, C * scale[:, None] * scale[None, :], rtol=1e-12)
    assert got.names == tuple(NAMES) and got.determined == (True,) * R and got.lever_spin is True
    assert got.source == str(path)
    np.testing.assert_allclose(given(got.residual), np.array([1e-3, 2.5e-3, 4e-3]), rtol=1e-15)
    determined = [1] * (R - 1) + [0]
    other = given(
        read_covariance(_file(tmp_path, base=NAMES, covariance=C, determined=determined, lever_spin=False), PARAMS)
    )
    assert other.determined == (True,) * (R - 1) + (False,) and other.lever_spin is False and other.residual is None


def test_an_undetermined_parameter_of_no_variance_is_accepted(tmp_path):
    C = np.eye(R)
    C[3, :] = C[:, 3] = 0.0
    got = given(read_covariance(_file(tmp_path, base=NAMES, covariance=C), PARAMS))
    assert got.matrix[3, 3] == 0.0 and got.matrix[0, 0] == BASE.scale[0] ** 2


def _refused(path, key, message):
    with pytest.raises(ParameterError) as caught:
        read_covariance(path, PARAMS)
    assert str(caught.value) == f"{path}, key 'identification.{key}': {message}"


def test_a_covariance_that_is_not_a_square_table_of_numbers_is_named(tmp_path):
    _refused(_file(tmp_path, base=NAMES, covariance="big"), "covariance", "expected a square table of numbers")
    _refused(
        _file(tmp_path, base=NAMES, covariance=[[1.0, 2.0], [3.0]]), "covariance", "expected a square table of numbers"
    )
    _refused(
        _file(tmp_path, base=NAMES, covariance=np.eye(R - 1)),
        "covariance",
        f"expected {R} rows and columns (one per name in base), got shape ({R - 1}, {R - 1})",
    )
    _refused(
        _file(tmp_path, covariance=np.eye(2)),
        "covariance",
        "expected one row per base parameter rows and columns (one per name in base), got shape (2, 2)",
    )
    _refused(
        _file(tmp_path, base="I_m,xx", covariance=np.eye(1)),
        "covariance",
        "expected one row per base parameter rows and columns (one per name in base), got shape (1, 1)",
    )
    bad = np.eye(R)
    bad[2, 2] = math.nan
    _refused(_file(tmp_path, base=NAMES, covariance=bad), "covariance", "not finite")
    bad[2, 2] = math.inf
    _refused(_file(tmp_path, base=NAMES, covariance=bad), "covariance", "not finite")


def test_symmetry_to_a_billionth_of_the_largest_entry(tmp_path):
    C = 4.0 * np.eye(R)
    C[0, 1] = C[1, 0] = 1.0
    C[0, 1] += 5e-9  # 1.25e-9 of the largest (4): refused
    _refused(_file(tmp_path, base=NAMES, covariance=C), "covariance", "not symmetric")
    C[0, 1] = 1.0 + 3e-9  # 0.75e-9 of it: accepted
    assert given(read_covariance(_file(tmp_path, base=NAMES, covariance=C), PARAMS)).matrix.shape == (R, R)
    C = 4.0 * np.eye(R)
    C[0, 1] = 1e-9 * 4.0  # exactly a billionth of the largest: accepted
    assert read_covariance(_file(tmp_path, base=NAMES, covariance=C), PARAMS) is not None
    C = -4e-6 * np.eye(R)  # the largest by magnitude: 4e-6
    C[0, 1] = 5e-15
    _refused(_file(tmp_path, base=NAMES, covariance=C), "covariance", "not symmetric")


def test_positive_semi_definite_by_the_correlation_matrix(tmp_path):
    # Correlation 1 + δ between two parameters: eigenvalues 2 + δ, −δ and 1 (R − 2 times); the limit is −1e-8·(2 + δ).
    for variance in (1.0, 1e-12, 1e6):  # the correlation matrix does not see the scale
        C = variance * np.eye(R)
        C[4, 5] = C[5, 4] = variance * (1.0 + 1e-7)
        with pytest.raises(ParameterError) as caught:
            read_covariance(_file(tmp_path, base=NAMES, covariance=C), PARAMS)
        assert str(caught.value) == (
            f"{tmp_path / 'identified.toml'}, key 'identification.covariance': "
            "not positive semi-definite (smallest eigenvalue -1e-07 of the correlation matrix)"
        )
        C[4, 5] = C[5, 4] = variance * (1.0 + 1e-8)  # −1e-8 > −2e-8: round-off of a singular matrix, accepted
        assert read_covariance(_file(tmp_path, base=NAMES, covariance=C), PARAMS) is not None
    # Three parameters correlated by c = −1/2 − δ: eigenvalues 1 + 2c = −2δ and 1 − c = 3/2 + δ (twice); the limit is
    # −1e-8·(3/2 + δ), and the others' zero variances are floored so that their correlations are 0.
    for delta, refused in ((0.875e-8, True), (0.7e-8, False)):
        C = np.zeros((R, R))
        C[:3, :3] = -0.5 - delta
        C[[0, 1, 2], [0, 1, 2]] = 1.0
        path = _file(tmp_path, base=NAMES, covariance=C)
        if refused:
            _refused(
                path,
                "covariance",
                "not positive semi-definite (smallest eigenvalue -1.75e-08 of the correlation matrix)",
            )
        else:
            assert read_covariance(path, PARAMS) is not None


def test_base_parameters_of_another_machine_are_named(tmp_path):
    names = [NAMES[1], NAMES[0]] + NAMES[2:]
    _refused(
        _file(tmp_path, base=names, covariance=np.eye(R)),
        "base",
        f"{', '.join(names)} are not this machine's base parameters ({', '.join(NAMES)})",
    )


def test_a_bad_residual_is_named(tmp_path):
    for value in ("small", [1.0, 2.0], [[1.0], [2.0, 3.0]]):
        _refused(
            _file(tmp_path, base=NAMES, covariance=np.eye(R), residual_rms_Nmm=value),
            "residual_rms_Nmm",
            f"expected three numbers (N·mm per motor), got {value!r}",
        )
    for value in ([1.0, -2.0, 3.0], [1.0, math.nan, 3.0], [math.inf, 1.0, 1.0]):
        path = _file(tmp_path, base=NAMES, covariance=np.eye(R), residual_rms_Nmm=value)
        with pytest.raises(ParameterError) as caught:
            read_covariance(path, PARAMS)
        assert str(caught.value).startswith(
            f"{path}, key 'identification.residual_rms_Nmm': expected three non-negative numbers, got ["
        )
    zero = given(read_covariance(_file(tmp_path, base=NAMES, covariance=np.eye(R), residual_rms_Nmm=[0, 0, 0]), PARAMS))
    assert given(zero.residual).tolist() == [0.0, 0.0, 0.0]


def test_the_std_of_one_parameter_is_its_column_times_its_std():
    for p, s in ((0, 3.0), (6, 0.01), (R - 1, 2e-4)):
        np.testing.assert_allclose(
            torque_std(PARAMS, TRAJECTORY, _covariance(_unit(p, s))), s * np.abs(Y[:, :, p]), rtol=1e-12
        )


def test_the_std_of_two_correlated_parameters_by_hand():
    p, q, a, b, c = 6, 14, 0.04, 9e-4, -0.005  # c² < a·b
    S = np.zeros((R, R))
    S[p, p], S[q, q], S[p, q], S[q, p] = a, b, c, c
    want = np.sqrt(a * Y[:, :, p] ** 2 + 2 * c * Y[:, :, p] * Y[:, :, q] + b * Y[:, :, q] ** 2)
    np.testing.assert_allclose(torque_std(PARAMS, TRAJECTORY, _covariance(S)), want, rtol=1e-12)


@pytest.mark.parametrize("lever_spin", [True, False])
def test_a_covariance_pushed_through_the_base_columns(lever_spin):
    """Σ = A·Aᵀ: y_kᵀ Σ y_k = |Aᵀ y_k|², each sample and motor; with or without the levers' spin."""
    A = np.random.default_rng(2).normal(size=(R, 3)) * (1.0 / np.maximum(np.abs(Y).max(axis=(0, 1)), 1e-9))[:, None]
    rows = regressor(PARAMS, TRAJECTORY, lever_spin)[:, :, base_parameters(PARAMS, lever_spin).index]
    want = np.sqrt(np.sum((rows @ A) ** 2, axis=-1))
    got = torque_std(PARAMS, TRAJECTORY, _covariance(A @ A.T, lever_spin))
    assert got.shape == (len(TRAJECTORY), 3)
    np.testing.assert_allclose(got, want, rtol=1e-9)


def test_the_draws_are_the_factor_of_the_covariance_times_normal_numbers():
    """Draws = Z·Rᵀ·Y_bᵀ with Z the seed's normal numbers and R·Rᵀ = Σ: recovered from Z by least squares, Y_b Σ Y_bᵀ exactly."""
    A = np.random.default_rng(3).normal(size=(R, 3)) * 1e-3  # rank 3: most eigenvalues are round-off, some below 0
    S = A @ A.T
    for kwargs, count, seed in (({"draws": 40, "seed": 7}, 40, 7), ({}, 200, 0)):
        draws = torque_draws(PARAMS, TRAJECTORY, _covariance(S), **kwargs)
        assert draws.shape == (count, len(TRAJECTORY), 3) and np.all(np.isfinite(draws))
        Z = np.random.default_rng(seed).standard_normal((count, R))
        M = np.linalg.lstsq(Z, draws.reshape(count, -1), rcond=None)[0]  # Rᵀ·Y_bᵀ
        YA = (Y @ A).reshape(-1, 3)
        np.testing.assert_allclose(M.T @ M, YA @ YA.T, rtol=1e-6, atol=1e-9 * np.abs(YA @ YA.T).max())


def test_z95_is_the_normal_quantile():
    assert Z95 == pytest.approx(scipy.stats.norm.ppf(0.975), rel=1e-15)


def test_band_columns_are_the_torque_plus_and_minus_z95_std_in_newton_millimetres():
    s = 0.02
    tau = {f"tau_{i + 1}_Nmm": np.arange(10.0) * (i + 1) - 3 for i in range(3)}
    out = band_columns(PARAMS, TRAJECTORY, _covariance(_unit(6, s)), tau)
    assert sorted(out) == sorted(f"tau_{i}_{side}95_Nmm" for i in (1, 2, 3) for side in ("lo", "hi"))
    for i in range(3):
        half = 1.959963984540054 * s * np.abs(Y[:, i, 6]) * 1e3
        np.testing.assert_allclose(out[f"tau_{i + 1}_lo95_Nmm"], tau[f"tau_{i + 1}_Nmm"] - half, rtol=1e-12)
        np.testing.assert_allclose(out[f"tau_{i + 1}_hi95_Nmm"], tau[f"tau_{i + 1}_Nmm"] + half, rtol=1e-12)


def _unreachable(trajectory: Trajectory, k: int) -> Trajectory:
    q = trajectory.q.copy()
    q[k] = np.radians([120.0, 0.0, 0.0])  # lever 2 cannot span the gap
    return Trajectory(trajectory.t, q, trajectory.qd, trajectory.qdd, trajectory.Fe)


def test_a_pose_out_of_reach_leaves_its_piece_without_band():
    tau = {f"tau_{i + 1}_Nmm": np.ones(10) for i in range(3)}
    out = band_columns(PARAMS, _unreachable(TRAJECTORY, 3), _covariance(_unit(6, 0.02)), tau)
    assert all(np.isnan(v).all() and v.shape == (10,) for v in out.values())


class Pieces:
    """A log handed out in windows of ``piece`` samples with ``halo`` samples around each (as a long log's reader)."""

    def __init__(self, whole: MeasuredLog, piece: int, halo: int):
        self.whole, self.piece, self.halo = whole, piece, halo

    def windows(self):
        n = len(self.whole)
        for start in range(0, n, self.piece):
            stop = min(start + self.piece, n)
            lo, hi = max(0, start - self.halo), min(n, stop + self.halo)
            yield (
                MeasuredLog(self.whole.trajectory.slice(slice(lo, hi)), self.whole.tau[lo:hi]),
                slice(start - lo, stop - lo),
                start,
            )


def test_the_std_along_a_log_at_its_samples_window_by_window():
    s = 0.05
    whole = MeasuredLog(TRAJECTORY, np.zeros((10, 3)))
    times = np.sort(np.r_[TRAJECTORY.t[[1, 4, 5, 8, 9]], 0.123])  # 0.123 s is no sample of the log
    want = np.full((6, 3), np.nan)
    keep = [0, 2, 3, 4, 5]  # the rows of times that are samples
    want[keep] = s * np.abs(Y[[1, 4, 5, 8, 9], :, 6])
    for log in (whole, Pieces(whole, 3, 2), Pieces(whole, 4, 0), Pieces(whole, 2, 5)):
        got = log_torque_std(PARAMS, log, np.array(list(times)), _covariance(_unit(6, s)))
        np.testing.assert_allclose(got, want, rtol=1e-12)
    # A window of no kept sample first, then one out of reach: only that one is left without a value.
    bad = MeasuredLog(_unreachable(TRAJECTORY, 5), np.zeros((10, 3)))
    got = log_torque_std(PARAMS, Pieces(bad, 3, 1), TRAJECTORY.t[[4, 5, 6, 8]], _covariance(_unit(6, s)))
    assert np.isnan(got[:2]).all()  # samples 4 and 5: the window of samples 3 … 5 has the pose out of reach
    np.testing.assert_allclose(got[2:], s * np.abs(Y[[6, 8], :, 6]), rtol=1e-12)


def test_band_summary_by_hand():
    half = np.array([[1.0, np.nan, 3.0], [2.0, np.nan, 3.0], [np.nan, np.nan, 3.0], [2.0, np.nan, 3.0]]) * 1e-3
    error = np.array([[0.5, 1.0, -3.0], [-2.5, 1.0, 3.5], [9.0, 1.0, 0.0], [2.0, 1.0, 1.0]]) * 1e-3
    residual = np.array([2.0, 7.0, 4.0]) * 1e-3 / Z95  # Z95·residual: 2, 7, 4 mN·m
    plain = band_summary(half, error)
    assert plain["2"] == {"rms_half_width_Nmm": None, "max_half_width_Nmm": None, "measured_within_band": None}
    assert plain["1"] == pytest.approx(
        {"rms_half_width_Nmm": math.sqrt(3.0), "max_half_width_Nmm": 2.0, "measured_within_band": 2 / 3}, rel=1e-12
    )
    assert plain["3"] == pytest.approx(
        {"rms_half_width_Nmm": 3.0, "max_half_width_Nmm": 3.0, "measured_within_band": 3 / 4}, rel=1e-12
    )
    wide = band_summary(half, error, residual)
    # Motor 1: widths √(1 + 4), √(4 + 4), √(4 + 4): all within (2.5 < 2.83).
    assert wide["1"] == pytest.approx(
        {
            "rms_half_width_Nmm": math.sqrt(3.0),
            "max_half_width_Nmm": 2.0,
            "measured_within_band": 2 / 3,
            "prediction_rms_half_width_Nmm": math.sqrt(3.0 + 4.0),
            "measured_within_prediction_band": 1.0,
        },
        rel=1e-12,
    )
    assert wide["2"]["prediction_rms_half_width_Nmm"] is None and wide["2"]["measured_within_prediction_band"] is None
    # Motor 3: widths 5 (9 + 16): all four within.
    assert wide["3"]["prediction_rms_half_width_Nmm"] == pytest.approx(5.0, rel=1e-12)
    assert wide["3"]["measured_within_prediction_band"] == 1.0
    assert set(wide) == {"1", "2", "3"}
    # On the edge of a band is within it: |error| = half, and = √(0 + (1.96·residual)²).
    edge = band_summary(np.array([[2e-3, 0.0, 0.0]]), np.array([[-2e-3, Z95 * 3e-3, 0.0]]), np.array([1e-3, 3e-3, 0.0]))
    assert edge["1"]["measured_within_band"] == 1.0 and edge["2"]["measured_within_band"] == 0.0
    assert edge["2"]["measured_within_prediction_band"] == 1.0 and edge["3"]["measured_within_prediction_band"] == 1.0


def test_sigma_machines_factor_the_covariance_along_its_principal_directions():
    theta_b = BASE.transform @ standard_values(PARAMS)
    v1 = np.zeros(R)
    v1[[0, 6]] = [1.0, 1.0]
    v2 = np.zeros(R)
    v2[[0, 6]] = [1.0, -1.0]
    v1, v2 = v1 / math.sqrt(2), v2 / math.sqrt(2)
    S = 1e-6 * np.outer(v1, v1) + 4e-8 * np.outer(v2, v2)  # rank 2, standard deviations 1e-3 and 2e-4
    machines = sigma_machines(PARAMS, _covariance(S))
    assert len(machines) == 2
    steps = [BASE.transform @ standard_values(m) - theta_b for m in machines]
    np.testing.assert_allclose(sum(np.outer(d, d) for d in steps), S, atol=1e-14)
    norms = sorted(np.linalg.norm(d) for d in steps)
    assert norms == pytest.approx([2e-4, 1e-3], rel=1e-9)
    assert sigma_machines(PARAMS, _covariance(np.zeros((R, R)))) == []


def test_a_table_where_numbers_belong_is_named(tmp_path):
    path = tmp_path / "identified.toml"
    names = "[" + ", ".join(f'"{n}"' for n in NAMES) + "]"
    path.write_text(f"[identification]\nbase = {names}\ncovariance = {{ a = 1 }}\n", encoding="utf-8")
    _refused(path, "covariance", "expected a square table of numbers")
    eye = "[" + ", ".join("[" + ", ".join("1.0" if i == j else "0.0" for j in range(R)) + "]" for i in range(R)) + "]"
    path.write_text(
        f"[identification]\nbase = {names}\ncovariance = {eye}\nresidual_rms_Nmm = {{ a = 1 }}\n", encoding="utf-8"
    )
    _refused(path, "residual_rms_Nmm", "expected three numbers (N·mm per motor), got {'a': 1}")


def test_sigma_machines_of_tiny_variances_keep_every_direction():
    """The cut for directions of no variance is relative to the largest: variances of 1e-26 are still two directions."""
    S = np.zeros((R, R))
    S[6, 6], S[14, 14] = 1e-26, 4e-28
    machines = sigma_machines(PARAMS, _covariance(S))
    assert len(machines) == 2
    theta_b = BASE.transform @ standard_values(PARAMS)
    steps = sorted(np.abs(BASE.transform @ standard_values(m) - theta_b).max() for m in machines)
    assert steps == pytest.approx([2e-14, 1e-13], rel=1e-2)
