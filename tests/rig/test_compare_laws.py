"""hipsim.rig.compare by hand: the per-motor and per-phase statistics of hand-made torque arrays (RMS, peak and
when, relative errors, reversals' share, parts, phase bins), the period of a known motion, the phases anchored at heel
strike; and whole comparisons of tiny exact logs whose measured torque is the model's (hipsim.analyse) plus a known
error, whole or in windows.
"""

from __future__ import annotations

import math
from collections.abc import Iterator

import numpy as np
import pytest
from support import given

import hipsim
from hipsim.motion.trajectories import Trajectory, iso14242_at
from hipsim.results import Torques
from hipsim.rig import compare
from hipsim.rig.compare import (
    FIGURE_SAMPLES,
    PERIOD_SAMPLES,
    _ErrorSums,
    _period,
    _phase_anchor,
    compare_log,
    compare_torques,
    detect_period,
    model_torques,
)
from hipsim.rig.logs.log import Log, MeasuredLog
from hipsim.rig.logs.reversals import reversal_mask
from hipsim.rig.logs.smoothing import lowpass

PARAMS = hipsim.load_parameters()
PARTS = Torques.PARTS  # platforms, levers, sliders, screws, friction

# ------------------------------------------------------------------------------------------- the sums, by hand

T = np.array([0.0, 0.25, 0.5, 0.75])  # times of whole binary fractions: phases without round-off
# Motor 1: measured (1, -3, 2, 0) N·mm, error (1, 0, 4, 0); motor 2: nothing at all; motor 3: error (2, -2, 2, 1),
# measured 5 throughout (the peak error 2 first at t = 0).
MEASURED = np.array([[1.0, 0.0, 5.0], [-3.0, 0.0, 5.0], [2.0, 0.0, 5.0], [0.0, 0.0, 5.0]]) * 1e-3
ERROR = np.array([[1.0, 0.0, 2.0], [0.0, 0.0, -2.0], [4.0, 0.0, 2.0], [0.0, 0.0, 1.0]]) * 1e-3
# Motor 1 near a reversal at its second sample, motor 2 throughout, motor 3 never.
NEAR = np.array([[False, True, False], [True, True, False], [False, True, False], [False, True, False]])
COND = np.array([0.5, 0.2, 0.3, 0.4])


def model(measured=MEASURED, error=ERROR) -> dict[str, np.ndarray]:
    """The model's torques: total = measured + error; part p of motor i at (p + 1)·(i + 1) N·mm throughout."""
    out = {"total": measured + error}
    for p, part in enumerate(PARTS):
        out[part] = np.tile([(p + 1) * (i + 1) * 1e-3 for i in range(3)], (len(measured), 1))
    return out


def sums(period=1.0, t0=0.0, bins=2, pieces=1, block=None):
    s = _ErrorSums(period, t0, bins)
    if block is not None:
        s.BLOCK = block
    m = model()
    for part in np.array_split(np.arange(4), pieces):
        s.add(T[part], MEASURED[part], {k: v[part] for k, v in m.items()}, COND[part], NEAR[part])
    return s.result()


def test_the_motors_statistics_by_hand():
    statistics, phase_rms = sums()
    one, two, three = (statistics["motors"][k] for k in "123")
    # Motor 1: error² 1 + 0 + 16 + 0 over 4, measured² 1 + 9 + 4 + 0; away from its reversal (samples 0, 2, 3)
    # 17 and 5 over 3.
    assert one["rms_error_Nmm"] == pytest.approx(math.sqrt(17) / 2, rel=1e-14)
    assert one["measured_rms_Nmm"] == pytest.approx(math.sqrt(14) / 2, rel=1e-14)
    assert one["relative_rms_error"] == pytest.approx(math.sqrt(17 / 14), rel=1e-14)
    assert (one["peak_error_Nmm"], one["peak_error_t_s"], one["measured_peak_Nmm"]) == pytest.approx((4.0, 0.5, 3.0))
    assert one["relative_peak_error"] == pytest.approx(4 / 3, rel=1e-14)
    assert one["rms_error_away_from_reversals_Nmm"] == pytest.approx(math.sqrt(17 / 3), rel=1e-14)
    assert one["relative_rms_error_away_from_reversals"] == pytest.approx(math.sqrt(17 / 5), rel=1e-14)
    assert one["share_near_reversals"] == 0.25
    # Motor 2: no error, no torque: relative errors infinite, none away from reversals; the first sample's time.
    assert (two["rms_error_Nmm"], two["peak_error_Nmm"], two["peak_error_t_s"], two["measured_peak_Nmm"]) == (
        0,
        0,
        0,
        0,
    )
    assert two["relative_rms_error"] == math.inf and two["relative_peak_error"] == math.inf
    assert math.isnan(two["rms_error_away_from_reversals_Nmm"]) and two["share_near_reversals"] == 1.0
    assert two["relative_rms_error_away_from_reversals"] == math.inf
    # Motor 3: error² 4 + 4 + 4 + 1 = 13 over 4; its peak 2 first at t = 0 (the later ties are not it).
    assert three["rms_error_Nmm"] == pytest.approx(math.sqrt(13) / 2, rel=1e-14)
    assert (three["peak_error_Nmm"], three["peak_error_t_s"]) == pytest.approx((2.0, 0.0))
    assert three["relative_rms_error"] == pytest.approx(math.sqrt(13) / 10, rel=1e-14)
    assert three["relative_rms_error_away_from_reversals"] == pytest.approx(math.sqrt(13) / 10, rel=1e-14)
    assert three["share_near_reversals"] == 0.0 and three["relative_peak_error"] == pytest.approx(0.4, rel=1e-14)
    for i in range(3):
        for p, part in enumerate(PARTS):
            assert statistics["parts"][str(i + 1)][Torques.COLUMN[part]] == pytest.approx((p + 1) * (i + 1), rel=1e-14)
    assert statistics["cond_inv_min"] == 0.2 and statistics["samples"] == 4
    assert all(isinstance(v, float) for v in one.values())
    # Phases 0, 0.25 | 0.5, 0.75 of a 1 s cycle: bins of two samples, RMS in N·m.
    expected = np.array([[1, 0, math.sqrt(8)], [4, 0, math.sqrt(5)]]) / math.sqrt(2) * 1e-3
    np.testing.assert_allclose(phase_rms, expected, rtol=1e-14)


def test_a_motor_without_error_peaks_at_its_first_sample():
    s = _ErrorSums(None, 0.0, 1)
    zeros = np.zeros((3, 3))
    s.add(np.array([5.0, 5.5, 6.0]), zeros, model(zeros, zeros), np.ones(3), np.zeros((3, 3), dtype=bool))
    for m in s.result()[0]["motors"].values():
        assert (m["peak_error_Nmm"], m["peak_error_t_s"], m["rms_error_Nmm"]) == (0.0, 5.0, 0.0)


def test_torques_below_one_newton_millimetre_and_one_sample_away():
    # Motor 1: measured 0.3, 0.4 N·mm, error 0.1, 0.2, near its reversal at the first sample: away, the one sample
    # 1 (0.2 of 0.4). Motor 3: no measured torque, an error of 1 N·mm: relative errors infinite.
    measured = np.array([[0.3, 1.0, 0.0], [0.4, 1.0, 0.0]]) * 1e-3
    error = np.array([[0.1, 0.0, 1.0], [0.2, 0.0, 1.0]]) * 1e-3
    near = np.array([[True, False, False], [False, False, False]])
    s = _ErrorSums(None, 0.0, 1)
    s.add(np.array([0.0, 1.0]), measured, model(measured, error), np.ones(2), near)
    one, _, three = s.result()[0]["motors"].values()
    assert one["rms_error_away_from_reversals_Nmm"] == pytest.approx(0.2, rel=1e-14)
    assert one["relative_rms_error_away_from_reversals"] == pytest.approx(0.5, rel=1e-14)
    assert one["relative_rms_error"] == pytest.approx(math.sqrt(0.025 / 0.125), rel=1e-14)
    assert one["relative_peak_error"] == pytest.approx(0.5, rel=1e-14) and one["peak_error_t_s"] == 1.0
    assert three["relative_rms_error"] == math.inf and three["relative_peak_error"] == math.inf
    assert three["relative_rms_error_away_from_reversals"] == math.inf
    assert three["rms_error_away_from_reversals_Nmm"] == pytest.approx(1.0, rel=1e-14)


def test_pieces_and_blocks_give_the_same_numbers():
    whole = sums()
    for pieces, block in ((4, None), (2, None), (1, 1), (1, 3), (3, 2)):
        statistics, phase_rms = sums(pieces=pieces, block=block)
        assert statistics == whole[0], (pieces, block)
        np.testing.assert_array_equal(phase_rms, whole[1])
    assert _ErrorSums.BLOCK == 1 << 15


def test_phase_bins_their_anchor_and_an_empty_one():
    # Anchored at 0.25 s: phases 0.75, 0, 0.25, 0.5; in 4 bins each sample its own.
    _, phase_rms = sums(t0=0.25, bins=4)
    np.testing.assert_allclose(phase_rms[:, 0], [0.0, 4e-3, 0.0, 1e-3], atol=1e-18)
    # A cycle of 2 s in 4 bins: phases 0, 1/8, 1/4, 3/8: bins 0, 0, 1, 1; bins 2 and 3 empty (NaN).
    _, phase_rms = sums(period=2.0, bins=4)
    np.testing.assert_allclose(phase_rms[:2, 0], [1e-3 / math.sqrt(2), 4e-3 / math.sqrt(2)], rtol=1e-14)
    assert np.isnan(phase_rms[2:]).all()
    # A sample a hair before the anchor is at phase 1 by rounding (mod gives 1.0): the last bin, not one past it.
    # Bin 0: sample 1 (error 0); bin 1: samples 0, 2, 3 (errors 1, 4, 0).
    _, phase_rms = sums(t0=1e-18, bins=2)
    np.testing.assert_allclose(phase_rms[:, 0], [0.0, math.sqrt(17 / 3) * 1e-3], rtol=1e-14)
    # No period: no phases.
    statistics, phase_rms = sums(period=None)
    assert phase_rms is None and statistics["samples"] == 4


# ----------------------------------------------------------------------------------------------------- the period


def test_the_period_of_a_repeating_motion():
    # 0.987 s at 100 Hz (98.7 samples): found between samples, to a hundredth of one.
    t = np.arange(500) / 100.0
    q = np.column_stack([np.sin(2 * np.pi * t / 0.987), 0.5 * np.cos(4 * np.pi * t / 0.987), np.zeros_like(t)])
    assert detect_period(t, q) == pytest.approx(0.987, abs=1e-4)
    assert detect_period(t + 7.0, q) == pytest.approx(0.987, abs=1e-4)  # the times' origin does not matter
    # Twice 0.987 s is not the answer though the motion repeats there too: the first period.
    assert detect_period(t[:250], q[:250]) == pytest.approx(0.987, abs=1e-4)
    # Too short, still, or never dipping below half its correlation: none.
    assert detect_period(t[:7], q[:7]) is None
    assert detect_period(t, np.ones((500, 3))) is None
    assert detect_period(t, np.column_stack([t, t**2, t**3])) is None


def test_the_period_at_the_edges_of_the_search():
    # Eight samples, two periods of four: x = (0, 1, 0, -1, ...); the correlation at lag 4 (the last one searched,
    # n // 2) is that of lag 0, lag 1's is 0: period 4 samples of 0.1 s. Each angle about its own mean (0.3, -0.2, 0.1 rad).
    t = np.arange(8) * 0.1
    x = np.array([0.0, 1.0, 0.0, -1.0] * 2)
    q = np.column_stack([0.3 + x, -0.2 + 0.5 * x, 0.1 + x])
    assert detect_period(t, q) == pytest.approx(0.4, rel=1e-12)
    assert detect_period(t[:7], q[:7]) is None  # fewer than eight samples
    # Alternating samples: lag 1 is the first dip, lag 2 the period (0.2 s at 10 Hz), lag 3 no better.
    t = np.arange(20) * 0.1
    x = np.array([1.0, -1.0] * 10)
    assert detect_period(t, np.column_stack([x, x, 2 * x])) == pytest.approx(0.2, rel=1e-12)
    # Small angles (a sum of squares below one) and an offset from zero change nothing.
    t = np.arange(500) / 100.0
    q = np.column_stack([np.sin(2 * np.pi * t / 0.987), 0.5 * np.cos(4 * np.pi * t / 0.987), np.zeros_like(t)])
    assert detect_period(t, 1e-3 * q) == pytest.approx(0.987, abs=1e-4)
    assert detect_period(t, q + [2.0, -1.0, 0.5]) == pytest.approx(0.987, abs=1e-4)


def test_the_threshold_decides_a_weak_repeat():
    # A period-1 s motion with white noise of 0.7 of its size: its repeat correlates at about half, below 0.9.
    rng = np.random.default_rng(1)
    t = np.arange(600) / 100.0
    q = np.column_stack([np.sin(2 * np.pi * t)] * 3) + rng.normal(0.0, 0.7, (600, 3))
    assert detect_period(t, q) is None
    clean = np.column_stack([np.sin(2 * np.pi * t)] * 3)
    assert detect_period(t, clean) == pytest.approx(1.0, abs=1e-4)
    assert detect_period(t, clean, threshold=1.5) is None  # no lag correlates above 1.5 of lag 0


def test_the_period_to_bin_by():
    t = np.arange(400) / 100.0
    q = np.column_stack([np.sin(2 * np.pi * t)] * 3)
    assert _period(None, t, q, 0.0, 3.99) == pytest.approx(1.0, abs=1e-3)
    assert _period(0.0, t, None, 0.0, 3.99) is None and _period(-1.0, t, None, 0.0, 3.99) is None
    assert _period(2.0, t, None, 0.0, 4.0) == 2.0  # exactly two cycles
    assert _period(2.0, t, None, 1.0, 5.0 - 1e-10) == 2.0  # two cycles to round-off
    assert _period(2.0, t, None, 0.0, 3.99) is None  # fewer than two
    assert _period(2.0, t, None, 1.0, 4.9) is None  # 3.9 s from the first to the last
    assert _period(2.0, t, None, 0.0, 2 * 2.0 * (1 - 1e-9)) == 2.0  # at the tolerance itself


# -------------------------------------------------------------------------------------------- whole comparisons

RATE = 100.0


def exact(start: float = 0.0, cycles: float = 3.0, cutoff: float | None = None, edge: int = 0, error=None):
    """The built-in cycle from ``start`` [s] at 100 Hz, the measured torque the model's plus ``error`` (N·m, (N, 3))
    (filtered like the log when it has a cutoff)."""
    trajectory = iso14242_at(start + np.arange(int(cycles * RATE)) / RATE)
    tau = hipsim.analyse(PARAMS, trajectory, lever_spin=True).torques.total
    if cutoff is not None:
        tau = lowpass(tau, RATE, cutoff)
    error = np.zeros_like(tau) if error is None else error
    return MeasuredLog(trajectory, tau + error, cutoff=cutoff, name="exact", edge=edge, notes=("made here",))


def stance_error(log_or_trajectory) -> np.ndarray:
    """An error in stance only: proportional to the load above its swing level, up to 10 N·mm, on motor 2."""
    load = log_or_trajectory.Fe
    out = np.zeros((len(load), 3))
    out[:, 1] = 0.01 * (load - 300.0) / 2700.0
    return out


def test_the_model_s_torques_filtered_as_the_log_s():
    log = exact(cutoff=20.0)
    run, parts = model_torques(PARAMS, log)
    direct = hipsim.analyse(PARAMS, log.trajectory, lever_spin=True).torques
    np.testing.assert_allclose(run.torques.total, direct.total, rtol=1e-12, atol=1e-12)
    assert list(parts) == ["total", *PARTS]
    for field in ("total", *PARTS):
        np.testing.assert_allclose(parts[field], lowpass(getattr(direct, field), RATE, 20.0), atol=1e-12)
    # Without a cutoff the torques are the run's; without lever spin, the spin-free levers'.
    run, parts = model_torques(PARAMS, exact(), lever_spin=False)
    free = hipsim.analyse(PARAMS, exact().trajectory, lever_spin=False).torques
    np.testing.assert_allclose(parts["total"], free.total, rtol=1e-12, atol=1e-12)
    assert not np.allclose(parts["total"], direct.total, rtol=0, atol=1e-9)


def test_an_exact_log_with_a_known_error():
    log0 = exact()
    error = np.zeros((len(log0), 3))
    error[:, 0] = 0.002  # 2 N·mm on motor 1
    error[:, 1] = stance_error(log0.trajectory)[:, 1]
    log = exact(error=error)
    c = compare_torques(PARAMS, log)
    assert c.period == pytest.approx(1.0, abs=1e-3) and c.heel_strike == 0.0
    assert given(c.stance).tolist() == [True] * 6 + [False] * 4  # stance ends at 62 % of the cycle
    assert c.lever_spin and c.params is PARAMS and c.log.name == "exact" and len(c.t) == 300
    np.testing.assert_allclose(c.error, -error, atol=1e-15)
    motors = c.motor_errors()
    measured = log.tau * 1e3
    for i in range(3):
        m = motors[str(i + 1)]
        rms = math.sqrt(np.mean((error[:, i] * 1e3) ** 2))
        assert m["rms_error_Nmm"] == pytest.approx(rms, rel=1e-9, abs=1e-12)
        assert m["measured_rms_Nmm"] == pytest.approx(math.sqrt(np.mean(measured[:, i] ** 2)), rel=1e-12)
        assert m["measured_peak_Nmm"] == pytest.approx(np.abs(measured[:, i]).max(), rel=1e-12)
        assert m["share_near_reversals"] == 0.0  # no filter: no reversal window
        assert m["rms_error_away_from_reversals_Nmm"] == pytest.approx(rms, rel=1e-9, abs=1e-12)
    assert motors["1"]["peak_error_Nmm"] == pytest.approx(2.0, rel=1e-9) and motors["1"]["peak_error_t_s"] == 0.0
    assert motors["2"]["peak_error_Nmm"] == pytest.approx(10.0, rel=1e-6)
    assert motors["3"]["rms_error_Nmm"] < 1e-9
    # The phases: motor 1's 2 N·mm in every bin; motor 2's error in the stance bins only.
    np.testing.assert_allclose(given(c.phase_rms)[:, 0], 0.002, rtol=1e-9)
    assert given(c.phase_rms)[7:, 1].max() < 1e-4 and given(c.phase_rms)[:5, 1].min() > 1e-3
    np.testing.assert_array_equal(c.phase_edges, np.linspace(0, 1, 11))
    summary = c.summary()
    assert summary.phases is not None
    assert summary.phases.from_ == "heel strike" and summary.phases.heel_strike_s == 0.0
    assert summary.phases.labels == ["stance"] * 6 + ["swing"] * 4
    assert summary.phases.rms_error_Nmm["1"] == pytest.approx([2.0] * 10, rel=1e-9)
    assert summary.phases.edges == pytest.approx([k / 10 for k in range(11)])
    assert summary.motors["1"].model_parts_rms_Nmm == c.statistics["parts"]["1"]
    assert summary.motors["2"].rms_error_Nmm == motors["2"]["rms_error_Nmm"]
    assert (summary.log, summary.samples, summary.cutoff_Hz) == ("exact", 300, None)
    assert summary.rate_Hz == pytest.approx(100.0, rel=1e-14) and type(summary.rate_Hz) is float
    assert (summary.motion_from, summary.lever_spin, summary.notes) == ("exact", True, ["made here"])
    assert summary.parameters == PARAMS.source and summary.period_s == c.period
    assert summary.cond_inv_min == pytest.approx(c.cond_inv.min())
    assert summary.to_json()["phases"]["from"] == "heel strike"  # the JSON's key, as before
    # motor_errors is a copy: changing it changes nothing.
    motors["1"]["rms_error_Nmm"] = -1.0
    assert c.motor_errors()["1"]["rms_error_Nmm"] > 0


def test_the_phases_start_at_the_first_heel_strike():
    c = compare_torques(PARAMS, exact(start=0.37))
    assert c.heel_strike == pytest.approx(1.0, abs=1e-9) and given(c.stance).tolist() == [True] * 6 + [False] * 4
    # No gait events in the load (a constant one): phase 0 at the first usable sample, no stance.
    log = exact(start=0.37, edge=5)
    flat = Trajectory(
        log.trajectory.t, log.trajectory.q, log.trajectory.qd, log.trajectory.qdd, np.full(len(log), 900.0)
    )
    tau = hipsim.analyse(PARAMS, flat, lever_spin=True).torques.total
    c = compare_torques(PARAMS, MeasuredLog(flat, tau, edge=5), period=1.0)
    assert c.heel_strike == pytest.approx(0.42) and c.stance is None
    summary = c.summary().phases
    assert summary is not None and summary.from_ == "first sample" and summary.labels is None
    anchor, share = _phase_anchor(MeasuredLog(flat, tau, edge=5), 1.0, 5)
    assert (anchor, share) == (pytest.approx(0.42), None)
    anchor, share = _phase_anchor(exact(), 1.0, 0)
    assert anchor == 0.0 and share == pytest.approx(0.62, abs=0.011)
    anchor, share = _phase_anchor(exact(), 2.0, 0)  # the share of a 2 s cycle
    assert anchor == 0.0 and share == pytest.approx(0.31, abs=0.006)
    # An error in stance only, on a log from 0.37 s: the bins from the heel strike at 1 s see it in stance alone.
    log0 = exact(start=0.37)
    c = compare_torques(PARAMS, exact(start=0.37, error=stance_error(log0.trajectory)))
    assert given(c.phase_rms)[7:, 1].max() < 1e-4 and given(c.phase_rms)[:5, 1].min() > 1e-3


def test_a_first_window_without_toe_off_gives_no_stance():
    # Windows of half a cycle: the first has the heel strike at 0 s, not the toe-off at 0.62 s.
    c = compare_torques(PARAMS, Windows(exact(), 50))
    assert c.heel_strike == pytest.approx(0.0, abs=0.021) and c.stance is None and given(c.phase_rms).shape == (10, 3)


def test_the_model_s_lever_spin_is_the_comparison_s():
    trajectory = exact().trajectory
    free = hipsim.analyse(PARAMS, trajectory, lever_spin=False).torques.total
    log = MeasuredLog(trajectory, free, name="free")
    c = compare_torques(PARAMS, log, lever_spin=False)
    assert not c.lever_spin and all(m["rms_error_Nmm"] < 1e-9 for m in c.motor_errors().values())
    assert max(m["rms_error_Nmm"] for m in compare_torques(PARAMS, log).motor_errors().values()) > 1e-5


def test_two_cycles_to_the_sample_are_enough():
    # 201 samples at 100 Hz (int(201.1)): 2 s from the first to the last, two whole cycles of 1 s.
    assert compare_torques(PARAMS, exact(cycles=2.011), period=1.0).period == 1.0


def test_no_phases_without_a_period():
    c = compare_torques(PARAMS, exact(), period=0)
    assert c.period is None and c.phase_rms is None and c.phase_edges is None
    assert (
        c.heel_strike is None
        and c.stance is None
        and c.summary().phases is None
        and "phases" not in c.summary().to_json()
    )
    assert compare_torques(PARAMS, exact(cycles=1.5)).period is None  # fewer than two cycles
    c = compare_torques(PARAMS, exact(), period=1.4, phase_bins=3)
    assert (
        given(c.phase_rms).shape == (3, 3) and c.period == 1.4 and given(c.phase_edges).tolist() == [0, 1 / 3, 2 / 3, 1]
    )


def test_the_usable_samples_and_the_reversals():
    log = exact(cutoff=20.0, edge=20)
    c = compare_torques(PARAMS, log, period=1.0)
    assert len(c.t) == 260 and c.t[0] == log.t[20] and c.statistics["samples"] == 260
    near = reversal_mask(PARAMS, log)[20:280]
    np.testing.assert_array_equal(c.near_reversal, near)
    for i in range(3):
        share = c.motor_errors()[str(i + 1)]["share_near_reversals"]
        assert share == pytest.approx(near[:, i].mean(), rel=1e-15) and 0 < share < 0.5
    # The measured torque is the filtered model's: no error anywhere.
    assert all(m["rms_error_Nmm"] < 1e-9 for m in c.motor_errors().values())
    assert c.heel_strike == 0.0  # the first heel strike of the first window, its edges included


class Windows(Log):
    """A log in memory given out in windows whose cores are ``size`` samples (the tests' logs have no filter)."""

    def __init__(self, log: MeasuredLog, size: int):
        self.log, self.size = log, size
        self.name, self.cutoff, self.motion_from, self.notes, self.edge = log.name, None, "exact", (), log.edge

    def __len__(self) -> int:
        return len(self.log)

    @property
    def rate(self) -> float:
        return self.log.rate

    @property
    def t(self) -> np.ndarray:
        return self.log.t

    def windows(self) -> Iterator[tuple[MeasuredLog, slice, int]]:
        tr, halo = self.log.trajectory, 5  # each window with 5 samples around its core, as a log read in pieces
        for a in range(0, len(self), self.size):
            b = min(a + self.size, len(self))
            lo, hi = max(0, a - halo), min(len(self), b + halo)
            piece = Trajectory(tr.t[lo:hi], tr.q[lo:hi], tr.qd[lo:hi], tr.qdd[lo:hi], tr.Fe[lo:hi])
            yield MeasuredLog(piece, self.log.tau[lo:hi], name=self.name), slice(a - lo, b - lo), a

    def filtered_angles(self, most=None):
        return self.log.filtered_angles(most)


def test_windows_give_the_whole_log_s_numbers_and_every_kth_sample():
    log0 = exact(edge=10)
    log = exact(edge=10, error=stance_error(log0.trajectory))
    whole = compare_torques(PARAMS, log)
    done = []
    pieces = compare_torques(PARAMS, Windows(log, 128), progress=lambda k, n: done.append((k, n)))
    assert pieces.statistics == whole.statistics and pieces.heel_strike == whole.heel_strike == 0.0
    np.testing.assert_array_equal(pieces.phase_rms, whole.phase_rms)
    np.testing.assert_array_equal(pieces.t, whole.t)
    assert done == [(128, 300), (256, 300), (300, 300)]
    # At most 100 of the 280 usable samples for the figures: every 3rd, counted from the first usable one.
    thin = compare_torques(PARAMS, Windows(log, 128), figure_samples=100)
    np.testing.assert_array_equal(thin.t, whole.t[::3])
    for name in ("measured", "cond_inv", "near_reversal"):
        np.testing.assert_array_equal(getattr(thin, name), getattr(whole, name)[::3], err_msg=name)
    for field in ("total", *PARTS):
        np.testing.assert_array_equal(thin.model[field], whole.model[field][::3], err_msg=field)
    assert thin.statistics == whole.statistics
    assert len(compare_torques(PARAMS, log, figure_samples=280).t) == 280
    assert len(compare_torques(PARAMS, log, figure_samples=279).t) == 140


def test_the_period_from_every_kth_sample_and_compare_log_s_limits(monkeypatch):
    log = exact(cycles=4.0)
    asked = []
    real = MeasuredLog.filtered_angles

    def spy(self, most=None):
        asked.append(most)
        return real(self, most)

    monkeypatch.setattr(MeasuredLog, "filtered_angles", spy)
    assert compare_torques(PARAMS, log, period_samples=50).period == pytest.approx(1.0, abs=0.02)
    assert asked == [50]
    calls = []
    monkeypatch.setattr(compare, "compare_torques", lambda *args: calls.append(args))
    compare_log(PARAMS, log)
    assert calls.pop() == (PARAMS, log, True, None, 10, FIGURE_SAMPLES, PERIOD_SAMPLES, None)
    progress = object()
    compare_log(PARAMS, log, False, 2.0, 7, progress=progress)
    assert calls == [(PARAMS, log, False, 2.0, 7, FIGURE_SAMPLES, PERIOD_SAMPLES, progress)]
    assert (FIGURE_SAMPLES, PERIOD_SAMPLES) == (20_000, 262_144)
