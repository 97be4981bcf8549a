"""Weighings (ISO 14242-2): reading and refusals, soak correction, rates with intervals by hand, bedding-in, outliers,
differences between stations; wear factors of both kinds; wear accumulated over intervals of cycles."""

from __future__ import annotations

import math

import numpy as np
import pytest
from support import given

from hipsim.exceptions import ArgumentError, FileRowError
from hipsim.motion.trajectories import Trajectory, iso14242
from hipsim.wear import cup_grid, wear_maps
from hipsim.wear.accumulate import Exposure, interval_table, snapshot_intervals
from hipsim.wear.factors import (
    ForceTrackFactor,
    MotionIntegrals,
    fit_factors,
    fitted_wear_law,
    motion_integrals,
    parse_wear_factor,
)
from hipsim.wear.gravimetric import gravimetry, line_fit, rate_difference, station_rate
from hipsim.wear.laws import WearFactor, predict_wear
from hipsim.wear.test_summary import RateSummary
from hipsim.wear.weighings import StationWeighings, read_weighings


def _station(name, cycles, mass, soak=None):
    cycles = np.asarray(cycles, dtype=float)
    soak = np.full(cycles.size, 500.0) if soak is None else np.asarray(soak, dtype=float)
    return StationWeighings(name, "soak", cycles, np.asarray(mass, dtype=float), soak, np.arange(cycles.size) + 2)


def test_a_line_fit_and_its_interval_by_hand():
    """(0, 0), (1, 10), (2, 21): slope 10.5, s² = 1/6, se = √(1/12), t(0.975, 1) = 12.7062."""
    fit = line_fit(np.array([0.0, 1.0, 2.0]), np.array([0.0, 10.0, 21.0]))
    assert fit.slope == pytest.approx(10.5, rel=1e-12)
    assert fit.intercept == pytest.approx(-1 / 6, rel=1e-12)
    assert fit.se == pytest.approx(math.sqrt(1 / 12), rel=1e-12)
    low, high = fit.interval()
    assert (low, high) == pytest.approx((10.5 - 12.7062047 * math.sqrt(1 / 12), 10.5 + 12.7062047 * math.sqrt(1 / 12)))


def test_soak_correction_density_and_rate_by_hand():
    """Loss = cup's loss + soak control's gain; volume = loss / density; an exact line has a zero-width interval."""
    cycles = [0, 500_000, 1_000_000, 1_500_000]
    soak = [500.0, 500.4, 500.6, 500.7]  # fluid uptake
    true_loss = np.array([0.0, 5.0, 10.0, 15.0])  # 10 mg/Mc
    mass = 30_000.0 - true_loss + (np.array(soak) - 500.0)  # the cup takes up the same fluid as its control
    rate = station_rate(_station("1", cycles, mass, soak), density_mg_per_mm3=0.94, from_cycle=0)
    np.testing.assert_allclose(rate.loss_mg, true_loss, atol=1e-9)
    assert rate.rate_mg_per_Mc == pytest.approx(10.0, rel=1e-9)
    assert rate.rate_mm3_per_Mc == pytest.approx(10.0 / 0.94, rel=1e-9)
    assert rate.ci95_mm3_per_Mc == pytest.approx((10.0 / 0.94, 10.0 / 0.94), rel=1e-6)
    document = RateSummary.of(rate).to_json()
    assert document["wear_rate_mg_per_Mc"] == pytest.approx(10.0)
    assert document["wear_rate_ci95_mm3_per_Mc"][0] == pytest.approx(10.0 / 0.94, rel=1e-6)


def test_bedding_in_is_found_when_the_data_show_it_and_not_otherwise():
    cycles = np.arange(0, 3_000_001, 500_000)
    rng = np.random.default_rng(3)
    noise = rng.normal(0, 0.05, cycles.size)
    steady = 10.0 * cycles / 1e6
    bedded = steady + np.where(cycles > 0, 4.0, 0.0)  # the first 0.5 Mc wear 4 mg more
    rate = station_rate(_station("1", cycles, 30_000 - bedded - noise))
    assert rate.bedding_in == "detected" and rate.from_cycle == 500_000
    assert rate.rate_mg_per_Mc == pytest.approx(10.0, abs=0.2)
    assert rate.bedding_in_rate_mg_per_Mc == pytest.approx(18.0, abs=0.5)
    plain = station_rate(_station("1", cycles, 30_000 - steady - noise))
    assert plain.bedding_in == "none" and plain.from_cycle == 0
    given = station_rate(_station("1", cycles, 30_000 - bedded - noise), from_cycle=1_000_000)
    assert given.bedding_in == "given" and given.from_cycle == 1_000_000 and len(given.cycles) == cycles.size


def test_an_outlier_is_named_and_kept():
    cycles = np.arange(0, 4_000_001, 500_000)
    loss = 10.0 * cycles / 1e6 + np.random.default_rng(5).normal(0, 0.05, cycles.size)
    loss[5] += 3.0
    rate = station_rate(_station("2", cycles, 30_000 - loss), from_cycle=0)
    assert [o.cycle for o in rate.outliers] == [2_500_000]
    assert "kept in the fit" in rate.outliers[0].describe()
    assert rate.rate_mg_per_Mc == pytest.approx(line_fit(cycles / 1e6, loss).slope, rel=1e-12)  # not dropped
    clean = station_rate(_station("2", cycles, 30_000 - loss + np.where(np.arange(cycles.size) == 5, 3.0, 0.0)))
    assert clean.outliers == ()


def test_the_difference_of_two_rates_welch_by_hand():
    a = station_rate(_station("1", [0, 1e6, 2e6], 1000 - np.array([0.0, 10.0, 21.0])), from_cycle=0)
    b = station_rate(_station("2", [0, 1e6, 2e6, 3e6], 1000 - np.array([0.0, 12.0, 25.0, 36.0])), from_cycle=0)
    d = rate_difference(a, b)
    assert d.difference_mg_per_Mc == pytest.approx(b.rate_mg_per_Mc - a.rate_mg_per_Mc)
    se2 = a.se_mg_per_Mc**2 + b.se_mg_per_Mc**2
    dof = se2**2 / (a.se_mg_per_Mc**4 / 1 + b.se_mg_per_Mc**4 / 2)
    from scipy import stats

    half = stats.t.ppf(0.975, dof) * math.sqrt(se2)
    assert d.ci95_mg_per_Mc == pytest.approx((d.difference_mg_per_Mc - half, d.difference_mg_per_Mc + half))
    assert d.significant == (d.ci95_mg_per_Mc[0] > 0 or d.ci95_mg_per_Mc[1] < 0)


WEIGHINGS = "cycle,station,mass_mg\n0,A,30000\n0,soak,29000\n500000,A,29990\n500000,soak,29000.5\n"


@pytest.mark.parametrize(
    ("text", "message"),
    [
        (WEIGHINGS + "250000,A,29995\n250000,soak,29000.2\n", "line 6, column 'cycle': station A: cycle 250000 after"),
        (WEIGHINGS.replace("soak", "dry"), "station A has no soak control"),
        (WEIGHINGS.replace("29990", "29.99"), "line 4, column 'mass_mg': station A: 29.99 mg after 30000 mg"),
        (WEIGHINGS.replace("500000,soak,29000.5\n", ""), "station A is weighed at cycle 500000 and its soak control"),
        ("cycle,station,mass_mg,soak_mg\n0,A,30000,29000\n5,A,29990,\n", "line 3, column 'soak_mg': station A has no"),
        (WEIGHINGS.replace("29990", "-3"), "a mass of -3 mg"),
        (WEIGHINGS.replace("500000,A", "5.5e5x,A"), "expected a number"),
    ],
)
def test_bad_weighings_are_refused_by_line(tmp_path, text, message):
    path = tmp_path / "w.csv"
    path.write_text(text)
    with pytest.raises(FileRowError, match=None) as caught:
        read_weighings(path)
    assert message in str(caught.value)


def test_soak_controls_per_station_and_as_a_column(tmp_path):
    path = tmp_path / "w.csv"
    path.write_text(WEIGHINGS + "0,B,31000\n0,soak_B,29100\n500000,B,30980\n500000,soak_B,29102\n")
    w = read_weighings(path)
    assert [(s.station, s.soak_control) for s in w.stations] == [("A", "soak"), ("B", "soak_B")]
    np.testing.assert_allclose(w.stations[1].loss_mg, [0.0, 22.0])
    path.write_text("cycle;station;mass_mg;soak_mg\n0;A;30000;29000\n500000;A;29990,5;29000,5\n")
    np.testing.assert_allclose(read_weighings(path).stations[0].loss_mg, [0.0, 10.0])


def test_density_out_of_range_is_refused(tmp_path):
    path = tmp_path / "w.csv"
    path.write_text(WEIGHINGS)
    assert gravimetry(read_weighings(path), 25.0).density_mg_per_mm3 == 25.0  # the densest taken
    for bad in (0.0, 25.000001, math.inf, True):
        with pytest.raises(ArgumentError, match=rf"--density: expected a density in \(0, 25\] mg/mm³, got {bad!r}"):
            gravimetry(read_weighings(path), bad)
    with pytest.raises(ArgumentError, match=r"--density: expected a density in \(0, 25\] mg/mm³"):
        gravimetry(read_weighings(path), -0.9)


@pytest.fixture(scope="module")
def iso_maps():
    return wear_maps(iso14242(rate=200), 1.0, points=cup_grid(15, 30, 14.0))


def test_both_kinds_of_wear_factor(iso_maps):
    """local: V = k·ΣW·dA; force-track: V = k·∫F ds (the cup's total, spread as the work); a bare value refused."""
    integrals = motion_integrals(iso_maps)
    local = predict_wear(iso_maps, parse_wear_factor("8e-8:local"))
    track = predict_wear(iso_maps, parse_wear_factor("8e-8:force-track"))
    assert local.total_mm3_per_Mc == pytest.approx(8e-8 * integrals.load_slide_integral_Nm * 1e6, rel=1e-12)
    assert track.total_mm3_per_Mc == pytest.approx(8e-8 * iso_maps.force_track_load_Nm * 1e6, rel=1e-12)
    assert "force-track" in track.law and "local" in local.law
    assert isinstance(parse_wear_factor("1e-7:local"), WearFactor)
    assert isinstance(parse_wear_factor("1e-7:force-track"), ForceTrackFactor)
    for bad in ("8e-8", "8e-8:saikko", "x:local", "-1e-8:local", "2e-3:local"):
        with pytest.raises(ArgumentError, match="--wear-factor"):
            parse_wear_factor(bad)


def test_fitted_factors_invert_the_prediction():
    """k = rate / (integral·10⁶) for each kind, the interval likewise; it predicts k·(another's integral)·10⁶."""
    motion = MotionIntegrals(40.0, 30.0, 0.15, "m")
    fit = fit_factors("1", 12.0, (11.0, 13.0), motion)
    assert fit.k("local") == pytest.approx(12.0 / 40e6) and fit.k("force-track") == pytest.approx(12.0 / 30e6)
    assert fit.ci95("local") == pytest.approx((11.0 / 40e6, 13.0 / 40e6))
    other = MotionIntegrals(80.0, 45.0, 0.2, "other")
    predicted = fit.predict(other)
    assert predicted["local"] == pytest.approx((24.0, 22.0, 26.0))
    assert predicted["force-track"] == pytest.approx((18.0, 16.5, 19.5))
    law = fitted_wear_law((fit, fit_factors("2", 30.0, (29.0, 31.0), MotionIntegrals(50.0, 30.0, 0.05, "n"))))
    assert law is not None and law.cross_shear.tolist() == [0.05, 0.15]
    assert law.k.tolist() == pytest.approx([30.0 / 50e6, 12.0 / 40e6])
    assert fitted_wear_law((fit, fit_factors("2", 12.0, (11.0, 13.0), MotionIntegrals(40.0, 30.0, 0.155, "n")))) is None


def test_exposure_over_intervals_by_hand():
    """Snapshots at 0, 1, 2 Mc over stops 0 … 3 Mc: boundaries 0, 0.5, 1.5, 3 Mc; the integral over [1, 2] Mc."""
    b = snapshot_intervals(np.array([0.0, 1e6, 2e6]), 0.0, 3e6)
    np.testing.assert_allclose(b, [0.0, 0.5e6, 1.5e6, 3e6])
    motions = tuple(MotionIntegrals(x, x / 2, 0.1) for x in (10.0, 20.0, 40.0))
    exposure = Exposure("1", b, motions, "test")
    assert exposure.integral("local", 1e6, 2e6) == pytest.approx(0.5e6 * 20 + 0.5e6 * 40)
    assert exposure.integral("force-track", 0.0, 3e6) == pytest.approx((0.5e6 * 10 + 1e6 * 20 + 1.5e6 * 40) / 2)
    assert exposure.integral("local", -1e6, 0.0) == pytest.approx(1e6 * 10)  # before the first: the first's motion
    rows = interval_table("1", (0, 1_000_000, 3_000_000), (0.0, 1.0, 5.0), exposure, 1e-7, "local")
    assert [r.predicted_mm3 for r in rows] == pytest.approx(
        [1e-7 * (0.5e6 * 10 + 0.5e6 * 20), 1e-7 * (0.5e6 * 20 + 1.5e6 * 40)]
    )
    assert [r.measured_mm3 for r in rows] == pytest.approx([1.0, 4.0])
    assert exposure.mean(0.0, 3e6).load_slide_integral_Nm == pytest.approx(exposure.integral("local", 0.0, 3e6) / 3e6)


def test_a_cycle_written_without_its_closing_sample_counts_one_cycle():
    """The built-in cycle as stations and simulate write it (no closing sample, not flagged periodic) gives the
    built-in's numbers exactly, not 1/0.999 of them; a motion cut short of whole cycles is not closed."""
    periodic = iso14242(rate=200)
    grid = cup_grid(10, 20, 14.0)
    open_file = Trajectory(periodic.t, periodic.q, periodic.qd, periodic.qdd, periodic.Fe, "file", periodic=False)
    a, b = wear_maps(periodic, 1.0, points=grid), wear_maps(open_file, 1.0, points=grid)
    assert b.cycles == pytest.approx(1.0, abs=1e-12)
    assert b.force_track_load_Nm == pytest.approx(a.force_track_load_Nm, rel=1e-12)
    np.testing.assert_allclose(b.work_N_per_mm, a.work_N_per_mm, rtol=1e-12)
    cut = open_file.slice(slice(0, 150))  # 0.745 s: a step short of 0.75 s, but the angles do not run on into the first
    assert wear_maps(cut, 0.75, points=grid).cycles == pytest.approx(0.745 / 0.75, rel=1e-12)


def test_motion_error_against_iso_by_gait_phase():
    """The built-in cycle itself has no error; an offset of 1° on α and a delay of 10 ms show as such."""
    from hipsim.wear.test_context import iso_error, motion_error

    base = iso14242(rate=500, cycles=3)
    assert np.max(np.abs(iso_error(base))) < 1e-9
    q = base.q.copy()
    q[:, 0] += math.radians(1.0)
    shifted = Trajectory(base.t + 7.3, q, base.qd, base.qdd, base.Fe, "offset")  # another clock: the phase decides
    error = motion_error(iso_error(shifted), "offset")
    assert error.rms_deg == pytest.approx((1.0, 0.0, 0.0), abs=1e-9)
    assert error.max_deg[0] == pytest.approx(1.0, abs=1e-9)
    from hipsim.motion.trajectories import iso14242_angles

    late = iso14242_angles(base.t - 0.006)  # the angles 6 ms behind the load: a timing offset, not a motion error
    delayed = Trajectory(base.t, late[0], late[1], late[2], base.Fe, "delayed")
    assert np.max(np.abs(iso_error(delayed))) < 1e-6


def test_friction_state_reads_the_monitors_last_snapshot():
    from hipsim.wear.test_context import friction_state

    table: dict[str, list] = {
        "cycle": [0, 250_000, 500_000],
        "hip_mu_change": [0.0, 0.001, 0.004],
        "hip_mu_change_std": [0.0005, 0.0005, 0.0006],
        "hip_mu_change_1": [0.0, float("nan"), float("nan")],
        "hip_mu_change_1_std": [0.001, float("nan"), float("nan")],
        "flag": ["", "", "notice"],
    }
    mean = given(friction_state(table, None, "friction.csv"))
    assert (mean.hip_mu_change, mean.hip_mu_change_std, mean.own, mean.flag, mean.last_cycle) == (
        0.004,
        0.0006,
        False,
        "notice",
        500_000,
    )
    station = given(
        friction_state(table, 1, "friction.csv")
    )  # its own column has no value at the last snapshots: the mean
    assert station.own is False and station.hip_mu_change == 0.004
    assert friction_state({"cycle": []}, 1, "f") is None
    table["hip_mu_change_1"][2], table["hip_mu_change_1_std"][2] = 0.007, 0.001
    own = given(friction_state(table, 1, "friction.csv"))
    assert (own.own, own.hip_mu_change, own.hip_mu_change_std) == (True, 0.007, 0.001)


def _loo_t(x: np.ndarray, y: np.ndarray, k: int) -> float:
    """Stop k's externally studentized residual by leaving it out: its distance from the line of the others over
    that line's prediction error (another route than the leverage formula)."""
    keep = np.arange(x.size) != k
    slope, intercept = np.polyfit(x[keep], y[keep], 1)
    residuals = y[keep] - (intercept + slope * x[keep])
    s = math.sqrt(float(residuals @ residuals) / (keep.sum() - 2))
    xm, sxx = x[keep].mean(), float(np.sum((x[keep] - x[keep].mean()) ** 2))
    return float((y[k] - intercept - slope * x[k]) / (s * math.sqrt(1 + 1 / keep.sum() + (x[k] - xm) ** 2 / sxx)))


WOBBLE = np.array([0.0, 0.04, -0.03, 0.05, -0.02, 0.01, -0.04, 0.03])


@pytest.mark.parametrize(("side", "named"), [(1.0 - 1e-6, False), (1.0 + 1e-6, True)])
def test_an_outlier_at_the_bonferroni_bound(side, named):
    """Stop 4 moved until its studentized residual is the bound t(1 − 0.05/(2·8), 8 − 3) times ``side``."""
    from scipy import stats
    from scipy.optimize import brentq

    cycles = np.arange(8) * 500_000
    x = cycles / 1e6
    bound = float(stats.t.ppf(1 - 0.05 / 16, 5))

    def loss(shift):
        return 10.0 * x + WOBBLE + np.where(np.arange(8) == 4, shift, 0.0)

    shift = brentq(lambda d: _loo_t(x, loss(d), 4) - side * bound, 0.0, 50.0, xtol=1e-14)
    rate = station_rate(_station("2", cycles, 30_000 - loss(shift)), from_cycle=0)
    assert [o.cycle for o in rate.outliers] == ([2_000_000] if named else [])
    if named:
        outlier = rate.outliers[0]
        assert outlier.t == pytest.approx(side * bound, rel=1e-9)
        assert outlier.residual_mg == pytest.approx(line_fit(x, loss(shift)).residuals[4], rel=1e-12)
        assert outlier.describe().startswith(f"station 2 at 2 Mc: {outlier.residual_mg:+.3g} mg off its line (t = +")


def test_a_stop_off_an_exact_line_is_an_outlier_of_infinite_t_and_one_degree_of_freedom_has_none():
    cycles = np.arange(5) * 1_000_000
    loss = 10.0 * cycles / 1e6
    loss[2] += 1.0  # without it the others lie on a line: s = 0 and t = ∞; the others' t stays finite
    rate = station_rate(_station("1", cycles, 30_000 - loss), from_cycle=0)
    assert [(o.cycle, o.t) for o in rate.outliers] == [(2_000_000, math.inf)]
    exact = station_rate(_station("1", cycles, 30_000 - 10.0 * cycles / 1e6), from_cycle=0)
    assert exact.outliers == ()  # e = 0 everywhere: t = 0
    two_dof_one = station_rate(_station("1", cycles[:3], 30_000 - np.array([0.0, 30.0, 20.0])), from_cycle=0)
    assert two_dof_one.dof == 1 and two_dof_one.outliers == ()  # one degree of freedom: no test


def _bedding_bound(x: np.ndarray, y: np.ndarray, k: int) -> float:
    """The 99 % prediction interval's lower end at stop k of the line through the stops after it."""
    from scipy import stats

    xs, ys = x[k + 1 :], y[k + 1 :]
    slope, intercept = np.polyfit(xs, ys, 1)
    residuals = ys - intercept - slope * xs
    s = math.sqrt(float(residuals @ residuals) / (xs.size - 2))
    half = (
        stats.t.ppf(0.995, xs.size - 2)
        * s
        * math.sqrt(1 + 1 / xs.size + (x[k] - xs.mean()) ** 2 / np.sum((xs - xs.mean()) ** 2))
    )
    return float(intercept + slope * x[k] - half)


@pytest.mark.parametrize(("below", "detected"), [(1e-6, True), (-1e-6, False)])
def test_bedding_in_at_the_prediction_intervals_lower_end_with_four_stops(below, detected):
    """Four stops (the fewest that are judged: three after the first, one degree of freedom); the first stop just
    below or just above the lower end of the 99 % prediction interval of the line through the other three."""
    cycles = np.array([100_000, 1_100_000, 2_100_000, 3_100_000])
    x = cycles / 1e6
    later = np.array([0.0, 60.0, 70.3, 79.8])  # loss since the first stop, as the station would show it
    # The first stop's loss is 0 by definition: shift the later ones so that 0 sits at the bound ± ``below``.
    shift = below - _bedding_bound(x, later, 0)
    y = later + np.where(np.arange(4) > 0, shift, 0.0)
    rate = station_rate(_station("1", cycles, 30_000 - y))
    assert rate.bedding_in == ("detected" if detected else "none")
    assert rate.from_cycle == (1_100_000 if detected else 100_000)
    if detected:
        assert rate.bedding_in_rate_mg_per_Mc == pytest.approx(y[1] / 1.0, rel=1e-12)  # over (1.1 − 0.1) Mc
        assert rate.rate_mg_per_Mc == pytest.approx(line_fit(x[1:], y[1:]).slope, rel=1e-12)
    else:
        assert math.isnan(rate.bedding_in_rate_mg_per_Mc)


def test_bedding_in_over_two_stops_and_not_from_an_exact_line():
    cycles = np.arange(9) * 500_000
    y = np.array([0.0, 15.0, 30.0, 35.0, 40.02, 44.98, 50.01, 54.99, 60.0])  # stops 0 and 1 below the line after them
    rate = station_rate(_station("1", cycles, 30_000 - y))
    assert rate.bedding_in == "detected" and rate.from_cycle == 1_000_000
    assert rate.bedding_in_rate_mg_per_Mc == pytest.approx(30.0)
    exact = np.array([0.0, 30.0, 40.0, 50.0])  # the stops after the first lie on a line: no interval, no bedding-in
    assert station_rate(_station("1", cycles[:4], 30_000 - exact)).bedding_in == "none"


def test_a_given_start_needs_two_stops_from_it_on():
    station = _station("7", [0, 1e6, 2e6], 1000 - np.array([0.0, 10.0, 21.0]))
    assert station_rate(station, from_cycle=0).bedding_in == "none"
    given = station_rate(station, from_cycle=1_000_000)
    assert (given.bedding_in, given.from_cycle, given.dof) == ("given", 1_000_000, 0)
    assert given.rate_mg_per_Mc == pytest.approx(11.0) and math.isnan(given.ci95_mg_per_Mc[0])
    assert station_rate(station, from_cycle=500_000).from_cycle == 1_000_000  # the first stop from it on
    with pytest.raises(
        ArgumentError, match="--from: expected a cycle with at least two of station 7's stops from it on, got 1000001"
    ):
        station_rate(station, from_cycle=1_000_001)


def test_a_rate_by_hand():
    station = StationWeighings(
        "3",
        "soak_3",
        np.array([0.0, 1e6, 2e6]),
        1000 - np.array([0.0, 10.0, 21.0]),
        np.full(3, 500.0),
        np.array([2, 4, 6]),
    )
    rate = station_rate(station, density_mg_per_mm3=0.5, from_cycle=0)
    half = 12.7062047 * math.sqrt(1 / 12)
    assert (rate.station, rate.soak_control, rate.cycles, rate.from_cycle, rate.bedding_in, rate.dof) == (
        "3",
        "soak_3",
        (0, 1_000_000, 2_000_000),
        0,
        "none",
        1,
    )
    assert math.isnan(rate.bedding_in_rate_mg_per_Mc) and rate.outliers == ()
    assert rate.rate_mg_per_Mc == pytest.approx(10.5) and rate.rate_mm3_per_Mc == pytest.approx(21.0)
    assert rate.ci95_mg_per_Mc == pytest.approx((10.5 - half, 10.5 + half))
    assert rate.ci95_mm3_per_Mc == pytest.approx(((10.5 - half) / 0.5, (10.5 + half) / 0.5))
    assert rate.se_mg_per_Mc == pytest.approx(math.sqrt(1 / 12))
    assert rate.loss_mg == pytest.approx((0.0, 10.0, 21.0)) and rate.volume_mm3 == pytest.approx((0.0, 20.0, 42.0))


def test_a_tests_gravimetry_every_pair_and_the_density_stated(tmp_path):
    path = tmp_path / "w.csv"
    rows = ["cycle,station,mass_mg"]
    for cycle, k in ((0, 0), (1_000_000, 1), (2_000_000, 2), (3_000_000, 3)):
        rows += [f"{cycle},soak,500", f"{cycle},A,{1000 - 10 * k - 0.1 * (k == 1)}", f"{cycle},B,{1000 - 12 * k}"]
        rows.append(f"{cycle},C,{1000 - 20 * k + 0.1 * (k == 2)}")
    path.write_text("\n".join(rows) + "\n")
    weighings = read_weighings(path)
    result = gravimetry(weighings)
    assert result.density_mg_per_mm3 == 0.935 and result.density_stated == "0.935 mg/mm³ (UHMWPE, the default)"
    assert result.source == str(path)
    assert [(d.a, d.b) for d in result.differences] == [("A", "B"), ("A", "C"), ("B", "C")]
    assert result.station("B").rate_mg_per_Mc == pytest.approx(12.0)
    given = gravimetry(weighings, 1.0, from_cycle=1_000_000)
    assert given.density_stated == "1 mg/mm³ (given)" and given.station("A").bedding_in == "given"
    assert given.station("C").rate_mm3_per_Mc == pytest.approx(given.station("C").rate_mg_per_Mc)
    assert [rate.station for rate in given.stations] == ["A", "B", "C"] and len(given.differences) == 3
    assert given.density_mg_per_mm3 == 1.0 and given.source == str(path)


def test_a_difference_needs_both_intervals():
    a = station_rate(_station("1", [0, 1e6, 2e6], 1000 - np.array([0.0, 10.0, 21.0])), 0.5, from_cycle=0)
    b = station_rate(_station("2", [0, 1e6], 1000 - np.array([0.0, 30.0])), 0.5, from_cycle=0)
    d = rate_difference(a, b)
    assert d.difference_mg_per_Mc == pytest.approx(19.5) and d.difference_mm3_per_Mc == pytest.approx(39.0)
    assert all(math.isnan(v) for v in d.ci95_mg_per_Mc) and d.significant is False
    exact = station_rate(_station("3", [0, 1e6, 2e6], 1000 - np.array([0.0, 10.0, 20.0])), 0.5, from_cycle=0)
    assert all(math.isnan(v) for v in rate_difference(exact, exact).ci95_mg_per_Mc)  # se² = 0: no interval
    reverse = rate_difference(b, a)
    assert (reverse.a, reverse.b, reverse.significant) == ("2", "1", False)
    assert reverse.difference_mg_per_Mc == pytest.approx(-19.5) and reverse.difference_mm3_per_Mc == pytest.approx(
        -39.0
    )


@pytest.mark.parametrize(
    ("interval", "significant"),
    [((0.0, 2.0), False), ((1e-12, 2.0), True), ((-2.0, 0.0), False), ((-2.0, -1e-12), True)],
)
def test_a_difference_is_significant_when_its_interval_excludes_zero(interval, significant):
    from hipsim.wear.gravimetric import RateDifference

    d = RateDifference("1", "2", 1.0, interval, 0.5)
    assert d.significant is significant
    assert d.ci95_mm3_per_Mc == pytest.approx((interval[0] / 0.5, interval[1] / 0.5))
