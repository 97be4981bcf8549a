"""hipsim.wear.maps by hand on eight samples and three cup points.

The platform is held at q = 0 (R = I, so n = ẑ and Ω = q̇) while q̇ is set sample by sample: two samples turn about
Y at 2000 N, six about X at 1000 N. Then at a point w: |v| = r·|Ω × w|, p = 3F/(2πr²)·max(0, w_z), |ṅ| = |Ω × ẑ|, and
at a point where the two motions slide along perpendicular lines with works A and B, the direction of most work gives
CS = 2AB/(A + B)² (the work along the angle θ is A·|cos θ| + B·|sin θ|, largest √(A² + B²), across 2AB/√(A² + B²)).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import hipsim.wear.maps as maps_module
from hipsim.exceptions import TrajectoryError
from hipsim.motion.sources import SampledSource
from hipsim.motion.trajectories import Trajectory
from hipsim.wear.kinematics import CupSetup
from hipsim.wear.maps import quadrature_weights, wear_maps
from hipsim.wear.points import cup_points

R = 14.0  # the head's radius in [mm]
A_RATE = 2.0  # [rad/s]
COEF = 3.0 / (2.0 * math.pi * R**2)  # p per N at the contact centre in [1/mm²]
S2 = math.sqrt(0.5)
POINTS = cup_points(np.array([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [S2, 0.0, S2]]))  # pole, rim, 45° towards +x


def _motion(periodic: bool = True, load: np.ndarray | None = None, n: int = 8, name: str = "hand") -> Trajectory:
    qd = np.zeros((n, 3))
    qd[:2, 1] = A_RATE  # about Y: the pole slides along x
    qd[2:, 0] = A_RATE  # about X: the pole slides along y
    Fe = np.where(np.arange(n) < 2, 2000.0, 1000.0) if load is None else load
    zeros = np.zeros((n, 3))
    return Trajectory(np.arange(n) / n, zeros, qd, zeros, Fe, name=name, periodic=periodic)


def _cs(a: float, b: float) -> float:
    return 2 * a * b / (a + b) ** 2


def test_sliding_work_and_cross_shear_at_three_points_by_hand():
    maps = wear_maps(_motion(), 1.0, CupSetup(28.0), POINTS)
    assert maps.cycles == 1.0 and maps.duration_s == 1.0 and maps.samples == 8 and maps.name == "hand"
    # The pole: |v| = r·a always; works 2·2000 along x, 6·1000 along y (per dt = 1/8).
    # The rim (w_z = 0): slides only while turning about Y (|Ω × x̂| = a), carries no load.
    # 45°: |v| = r·a about Y (along (1, 0, −1)/√2), r·a/√2 about X (along y); p ∝ 1/√2.
    s_45 = R * A_RATE * (2 / 8 + 6 / 8 * S2)
    np.testing.assert_allclose(maps.sliding_mm, [R * A_RATE, R * A_RATE * 2 / 8, s_45], rtol=1e-12)
    np.testing.assert_allclose(maps.sliding_loaded_mm, [R * A_RATE, 0.0, s_45], rtol=1e-12)
    work_pole = COEF * R * A_RATE * (2 * 2000 + 6 * 1000) / 8
    work_45 = COEF * S2 * R * A_RATE * (2 * 2000 + 6 * 1000 * S2) / 8
    np.testing.assert_allclose(maps.work_N_per_mm, [work_pole, 0.0, work_45], rtol=1e-12)
    assert maps.loaded.tolist() == [True, False, True]
    assert maps.cross_shear[0] == pytest.approx(_cs(4000.0, 6000.0), abs=1e-12)  # 0.48
    assert math.isnan(maps.cross_shear[1]) and np.all(np.isnan(maps.principal[1]))
    assert maps.cross_shear[2] == pytest.approx(_cs(4000.0, 6000.0 * S2), abs=1e-12)
    # e, the direction of most work at the pole: (±A, ±B)/√(A² + B²) in (x, y) (A·|cos θ| + B·|sin θ| is as large
    # at −θ as at θ: either is the direction).
    e = np.array([4000.0, 6000.0, 0.0]) / math.hypot(4000.0, 6000.0)
    np.testing.assert_allclose(np.abs(maps.principal[0]), e, atol=1e-12)
    # The force track: |ṅ| = |Ω × ẑ| = a at every sample; its load integral weighs each step by F.
    assert maps.force_track_mm == pytest.approx(R * A_RATE, rel=1e-12)
    assert maps.force_track_load_Nm == pytest.approx(R * A_RATE * (2 * 2000 + 6 * 1000) / 8 / 1000, rel=1e-12)
    assert maps.iterations == 0


def test_per_cycle_pieces_and_progress():
    """Half-second cycles: two of them, every sum halved; cut into pieces of 3 samples, the same; progress counts
    the pieces (⌈8/3⌉) and then the one part of the points."""
    whole = wear_maps(_motion(), 1.0, CupSetup(28.0), POINTS)
    calls: list[tuple[int, int]] = []
    halves = wear_maps(_motion(), 0.5, CupSetup(28.0), POINTS, piece=3, progress=lambda d, n: calls.append((d, n)))
    assert halves.cycles == 2.0
    assert calls == [(1, 4), (2, 4), (3, 4), (4, 4)]
    np.testing.assert_allclose(halves.sliding_mm, whole.sliding_mm / 2, rtol=1e-12)
    np.testing.assert_allclose(halves.sliding_loaded_mm, whole.sliding_loaded_mm / 2, rtol=1e-12)
    np.testing.assert_allclose(halves.work_N_per_mm, whole.work_N_per_mm / 2, rtol=1e-12)
    np.testing.assert_allclose(halves.cross_shear, whole.cross_shear, rtol=1e-12)
    assert halves.force_track_mm == pytest.approx(whole.force_track_mm / 2, rel=1e-12)
    assert halves.force_track_load_Nm == pytest.approx(whole.force_track_load_Nm / 2, rel=1e-12)


def test_the_iteration_of_a_long_motion_finds_the_same_direction(monkeypatch):
    monkeypatch.setattr(maps_module, "KEEP_SAMPLES", 0)
    iterated = wear_maps(_motion(), 1.0, CupSetup(28.0), POINTS, piece=5)
    assert iterated.iterations == 3  # two passes to settle the start, one after the restart that confirms it
    assert iterated.cross_shear[0] == pytest.approx(_cs(4000.0, 6000.0), abs=1e-9)
    assert iterated.cross_shear[2] == pytest.approx(_cs(4000.0, 6000.0 * S2), abs=1e-9)
    assert math.isnan(iterated.cross_shear[1])


def test_the_iteration_stops_at_its_limit_with_its_last_values(monkeypatch):
    monkeypatch.setattr(maps_module, "KEEP_SAMPLES", 0)
    monkeypatch.setattr(maps_module, "MAX_ITERATIONS", 1)
    once = wear_maps(_motion(), 1.0, CupSetup(28.0), POINTS)
    assert once.iterations == 1
    assert np.all(np.isfinite(once.cross_shear[[0, 2]])) and np.all(once.cross_shear[[0, 2]] <= 0.5)


def test_a_head_moving_keeps_the_contact_still():
    """The head on the platform: n = Mᵀ·ẑ = ẑ does not move (no force track); the cup sees −Ω, the same s and W."""
    cup = wear_maps(_motion(), 1.0, CupSetup(28.0), POINTS)
    head = wear_maps(_motion(), 1.0, CupSetup(28.0, moving="head"), POINTS)
    assert head.force_track_mm == 0.0 and head.force_track_load_Nm == 0.0
    np.testing.assert_allclose(head.sliding_mm, cup.sliding_mm, rtol=1e-12)
    np.testing.assert_allclose(head.work_N_per_mm, cup.work_N_per_mm, rtol=1e-12)


def test_periodic_quadrature_weights_are_all_one_step():
    source = SampledSource(_motion())
    np.testing.assert_allclose(quadrature_weights(source, 0, 8), np.full(8, 1 / 8), rtol=1e-12)
    np.testing.assert_allclose(quadrature_weights(source, 0, 1), [1 / 8], rtol=1e-12)  # before the first: a step
    np.testing.assert_allclose(quadrature_weights(source, 7, 8), [1 / 8], rtol=1e-12)  # after the last: a step


def test_an_open_motion_that_runs_on_into_its_start_is_one_whole_cycle():
    """Not flagged periodic, no closing sample, but the load runs on into the first sample: the same maps as the
    periodic motion, one cycle (a step counted after the last sample)."""
    flat = np.full(8, 1500.0)
    periodic = wear_maps(_motion(load=flat), 1.0, CupSetup(28.0), POINTS)
    closed = wear_maps(_motion(periodic=False, load=flat), 1.0, CupSetup(28.0), POINTS)
    assert closed.cycles == pytest.approx(1.0, abs=1e-15) and closed.duration_s == pytest.approx(1.0, abs=1e-15)
    np.testing.assert_allclose(closed.work_N_per_mm, periodic.work_N_per_mm, rtol=1e-12)
    np.testing.assert_allclose(closed.sliding_mm, periodic.sliding_mm, rtol=1e-12)


@pytest.mark.parametrize(
    ("last", "closes"),
    [(7.0, True), (6.99, False)],  # |F₀ − F₇| against 3 × the end steps' largest change (1 N): 3 closes, 3.01 does not
)
def test_the_closing_step_at_three_end_steps(last, closes):
    load = np.array([10.0, 11.0, 9.0, 8.0, 8.0, 8.0, last, last])
    _closing_case(load, closes)


@pytest.mark.parametrize(("last", "closes"), [(7.0, True), (6.99, False)])
def test_the_closing_step_counts_the_last_step_too(last, closes):
    load = np.array([10.0, 10.0, 9.0, 8.0, 8.0, 8.0, last + 1.0, last])  # the last step changes by 1 N, the first by 0
    _closing_case(load, closes)


def _closing_case(load: np.ndarray, closes: bool) -> None:
    maps = wear_maps(_motion(periodic=False, load=load), 1.0, CupSetup(28.0), POINTS)
    # Closed: eight steps of 1/8 s (one cycle). Open: 7/8 s, the end samples half a step each.
    assert maps.cycles == pytest.approx(1.0 if closes else 7 / 8, rel=1e-12)
    dt = np.full(8, 1 / 8) if closes else np.array([1 / 16] + [1 / 8] * 6 + [1 / 16])
    s_pole = R * A_RATE * float(np.sum(dt)) / maps.cycles
    assert maps.sliding_mm[0] == pytest.approx(s_pole, rel=1e-12)
    work_pole = COEF * R * A_RATE * float(np.sum(load * dt)) / maps.cycles
    assert maps.work_N_per_mm[0] == pytest.approx(work_pole, rel=1e-12)


@pytest.mark.parametrize(
    ("cycle", "closes"),
    [(1.0 + 0.9e-6, True), (1.0 - 0.9e-6, True), (1.0 - 1.1e-6, False)],
)
def test_the_closing_step_needs_whole_cycles_to_a_millionth(cycle, closes):
    """Span plus a step within a millionth of a cycle closes it (a hair short of the cycle too: once refused as
    shorter than one cycle); beyond, the motion stays open, one step short of its cycle."""
    maps = wear_maps(_motion(periodic=False, load=np.full(8, 1500.0)), cycle, CupSetup(28.0), POINTS)
    assert maps.duration_s == pytest.approx(1.0 if closes else 7 / 8, rel=1e-12)
    assert maps.cycles == pytest.approx(maps.duration_s / cycle, rel=1e-12)


def test_three_samples_are_too_few_to_close_a_cycle():
    """Three samples at k/3 s with a constant load would run on into the first: too few to tell, left open."""
    three = _motion(periodic=False, load=np.full(3, 1500.0), n=3)
    assert three.t[-1] == pytest.approx(2 / 3)
    assert wear_maps(three, 1.0, CupSetup(28.0), POINTS).duration_s == pytest.approx(2 / 3, rel=1e-12)


def test_refusals_name_the_motion():
    with pytest.raises(TrajectoryError, match=r"^hand: the load is negative \(-1 N\) at t = 0\.375 s: a load presses$"):
        wear_maps(_motion(load=np.array([5.0, 0, 5, -1, 5, 5, 5, 5])), 1.0, CupSetup(28.0), POINTS)
    with pytest.raises(TrajectoryError, match="^hand: a motion needs at least two samples$"):
        wear_maps(_motion(n=1), 1.0, CupSetup(28.0), POINTS)
    for bad in (0.0, -1.0, math.nan, math.inf):
        with pytest.raises(
            TrajectoryError, match=rf"^hand: the cycle time must be a positive number of seconds, got {bad!r}$"
        ):
            wear_maps(_motion(), bad, CupSetup(28.0), POINTS)
    with pytest.raises(
        TrajectoryError,
        match=r"^hand: the motion covers 1 s, shorter than one cycle of 1\.01 s: wear is "
        r"given per cycle, and this motion has no whole one$",
    ):
        wear_maps(_motion(), 1.01, CupSetup(28.0), POINTS)
    # One step short of the cycle, not periodic and not closing: still one cycle (of 7/8 s covered).
    open_ = _motion(periodic=False)
    assert wear_maps(open_, 1.0, CupSetup(28.0), POINTS).cycles == pytest.approx(7 / 8, rel=1e-12)
    with pytest.raises(TrajectoryError, match="shorter than one cycle"):
        wear_maps(open_, 1.0 + 1.01 / 8, CupSetup(28.0), POINTS)


def test_the_defaults_are_the_28_mm_head_and_its_grid(monkeypatch):
    """No setup: the 28 mm head on a moving cup; no points: cup_grid at the head's radius (a stand-in here, since
    the 90 × 180 grid takes seconds without numba)."""
    asked: list[dict] = []

    def grid(**kwargs):
        asked.append(kwargs)
        return POINTS

    monkeypatch.setattr(maps_module, "cup_grid", grid)
    maps = wear_maps(_motion(), 1.0, CupSetup(14.0))
    assert asked == [{"radius_mm": 7.0}] and maps.points is POINTS
    plain = wear_maps(_motion(), 1.0, points=POINTS)
    assert plain.setup == CupSetup() and plain.work_N_per_mm[0] == pytest.approx(
        COEF * R * A_RATE * (2 * 2000 + 6 * 1000) / 8, rel=1e-12
    )


def test_a_load_of_zero_wears_nothing():
    maps = wear_maps(_motion(load=np.zeros(8)), 1.0, CupSetup(28.0), POINTS)
    assert not maps.loaded.any() and np.all(np.isnan(maps.cross_shear)) and maps.force_track_load_Nm == 0.0
    assert maps.force_track_mm == pytest.approx(R * A_RATE, rel=1e-12)


def test_a_motion_at_any_start_time_and_cycle_length():
    """The same motion 3.3 s later, or sampled twice as fast against a half-second cycle: the same per-cycle maps."""
    motion = _motion()
    base = wear_maps(motion, 1.0, CupSetup(28.0), POINTS)
    for periodic in (True, False):
        late = Trajectory(motion.t + 3.3, motion.q, motion.qd, motion.qdd, np.full(8, 1500.0), periodic=periodic)
        flat = wear_maps(
            Trajectory(motion.t, motion.q, motion.qd, motion.qdd, np.full(8, 1500.0)), 1.0, POINTS_SETUP, POINTS
        )
        shifted = wear_maps(late, 1.0, POINTS_SETUP, POINTS)
        assert shifted.duration_s == pytest.approx(1.0, rel=1e-12) and shifted.cycles == pytest.approx(1.0, rel=1e-12)
        np.testing.assert_allclose(shifted.work_N_per_mm, flat.work_N_per_mm, rtol=1e-12)
    fast = Trajectory(motion.t / 2, motion.q, 2 * motion.qd, motion.qdd, np.full(8, 1500.0), periodic=False)
    half = wear_maps(fast, 0.5, POINTS_SETUP, POINTS)
    assert half.cycles == pytest.approx(1.0, rel=1e-12)
    np.testing.assert_allclose(half.sliding_mm, base.sliding_mm, rtol=1e-12)  # twice the speed for half the time
    source = wear_maps(SampledSource(motion), 1.0, POINTS_SETUP, POINTS)
    np.testing.assert_allclose(source.work_N_per_mm, base.work_N_per_mm, rtol=1e-12)


POINTS_SETUP = CupSetup(28.0)


def test_the_open_motions_allowance_is_one_step():
    """Open and not closing (the load jumps at the end): a step short of the cycle passes, a step and a half does not,
    nor a hair more than a step (5e-7 of the cycle)."""
    load = np.where(np.arange(8) < 4, 2000.0, 1000.0)
    for cycle, taken in ((1.0, True), (1.0 + 0.5 / 8, False), (1.0 + 5e-7, False)):
        motion = Trajectory(3.3 + np.arange(8) / 8, np.zeros((8, 3)), _motion().qd, np.zeros((8, 3)), load, "open")
        if taken:
            assert wear_maps(motion, cycle, POINTS_SETUP, POINTS).duration_s == pytest.approx(7 / 8, rel=1e-12)
        else:
            with pytest.raises(TrajectoryError, match=r"^open: the motion covers 0\.875 s, shorter than one cycle of "):
                wear_maps(motion, cycle, POINTS_SETUP, POINTS)


def test_four_samples_close_a_cycle_and_two_are_a_motion():
    four = Trajectory(
        np.arange(4) / 4, np.zeros((4, 3)), np.tile([0.0, 2.0, 0.0], (4, 1)), np.zeros((4, 3)), np.full(4, 1500.0)
    )
    assert wear_maps(four, 1.0, POINTS_SETUP, POINTS).duration_s == pytest.approx(1.0, rel=1e-12)
    two = Trajectory(
        np.array([0.0, 0.5]),
        np.zeros((2, 3)),
        np.tile([0.0, 2.0, 0.0], (2, 1)),
        np.zeros((2, 3)),
        np.full(2, 1500.0),
        periodic=True,
    )
    assert wear_maps(two, 1.0, POINTS_SETUP, POINTS).sliding_mm[0] == pytest.approx(R * 2.0, rel=1e-12)


def test_two_cycles_close_to_a_millionth_each():
    motion = _motion(n=16, load=np.full(16, 1500.0))
    slow = Trajectory(motion.t * 2, motion.q, motion.qd, motion.qdd, motion.Fe, periodic=False)  # 16 steps of 1/8 s
    maps = wear_maps(slow, 1.0 / (1.0 + 0.9e-6), POINTS_SETUP, POINTS)
    assert maps.duration_s == pytest.approx(2.0, rel=1e-12)


def test_a_closed_cycle_read_in_pieces_and_a_fourth_point(monkeypatch):
    flat = np.full(8, 1500.0)
    whole = wear_maps(_motion(periodic=False, load=flat), 1.0, POINTS_SETUP, POINTS)
    pieces = wear_maps(_motion(periodic=False, load=flat), 1.0, POINTS_SETUP, POINTS, piece=3)
    np.testing.assert_allclose(pieces.work_N_per_mm, whole.work_N_per_mm, rtol=1e-12)
    four = cup_points(np.vstack([POINTS.w, [[0.0, S2, S2]]]))
    more = wear_maps(_motion(), 1.0, POINTS_SETUP, four)
    base = wear_maps(_motion(), 1.0, POINTS_SETUP, POINTS)
    np.testing.assert_allclose(more.work_N_per_mm[:3], base.work_N_per_mm, rtol=1e-12)
    np.testing.assert_allclose(more.cross_shear[[0, 2]], base.cross_shear[[0, 2]], rtol=1e-12)
    monkeypatch.setattr(maps_module, "KEEP_SAMPLES", 0)
    iterated = wear_maps(_motion(), 1.0, POINTS_SETUP, four)
    np.testing.assert_allclose(iterated.cross_shear[[0, 2]], base.cross_shear[[0, 2]], atol=1e-9)


def test_a_motion_of_keep_samples_is_held_and_the_iterations_steps_are_its_pieces(monkeypatch):
    monkeypatch.setattr(maps_module, "KEEP_SAMPLES", 8)
    assert wear_maps(_motion(), 1.0, POINTS_SETUP, POINTS).iterations == 0  # 8 samples: held, the exact search
    monkeypatch.setattr(maps_module, "KEEP_SAMPLES", 7)
    calls: list[tuple[int, int]] = []
    maps = wear_maps(_motion(), 1.0, POINTS_SETUP, POINTS, piece=3, progress=lambda d, n: calls.append((d, n)))
    assert maps.iterations > 0 and calls == [(1, 3), (2, 3), (3, 3)]  # no parts of points: only the pieces


def test_a_light_load_still_carries_work_and_cross_shear():
    """At a thousandth of the load W is under 1 N/mm at every point, yet the points carry work: CS and e as before."""
    heavy = wear_maps(_motion(), 1.0, POINTS_SETUP, POINTS)
    light = wear_maps(_motion(load=np.where(np.arange(8) < 2, 2.0, 1.0)), 1.0, POINTS_SETUP, POINTS)
    assert np.nanmax(light.work_N_per_mm) < 1.0 and light.loaded.tolist() == [True, False, True]
    np.testing.assert_allclose(light.cross_shear[[0, 2]], heavy.cross_shear[[0, 2]], rtol=1e-12)
    np.testing.assert_allclose(np.abs(light.principal[0]), np.abs(heavy.principal[0]), atol=1e-12)


def test_quadrature_weights_of_a_piece_after_the_first_sample():
    """Uneven times, not periodic: a piece from sample 1 takes its left half step from sample 0."""
    t = np.array([0.0, 0.1, 0.3, 0.35])
    source = SampledSource(Trajectory(t, np.zeros((4, 3)), np.zeros((4, 3)), np.zeros((4, 3)), np.ones(4)))
    np.testing.assert_allclose(quadrature_weights(source, 1, 3), [0.15, 0.125], atol=1e-15)
    late = SampledSource(
        Trajectory(t + 3.0, np.zeros((4, 3)), np.zeros((4, 3)), np.zeros((4, 3)), np.ones(4), periodic=True)
    )
    np.testing.assert_allclose(quadrature_weights(late, 0, 1), [(0.1 + 0.35 / 3) / 2], atol=1e-12)
