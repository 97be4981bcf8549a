"""hipsim.motion.trajectories pinned by hand: the built-in cycle's formulas and knots, sampling, interpolation, checks.

The cycle of spec §7.2: α = 3.5° + 21.5°·cos(2πft), β = 1.5° + 5.5°·cos(2πft − 40°),
γ = −4° − 6°·cos(2πft) (a phase of 180°), and the twin-peak load through the
knots (0, 300 N), (0.12, 3000 N), (0.32, 1500 N), (0.5, 3000 N), (0.62, 300 N).
"""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest
from support import given

from hipsim.exceptions import TrajectoryError
from hipsim.motion.trajectories import (
    MIN_SAMPLES,
    Trajectory,
    interpolator,
    iso14242,
    iso14242_angles,
    iso14242_at,
    iso14242_load,
    iso14242_samples,
    trajectory_arrays,
)

DEG = math.pi / 180.0


def test_the_cycle_angles_and_their_derivatives_by_hand():
    # t = 0: α = 3.5 + 21.5 = 25°, β = 1.5 + 5.5·cos 40° = 5.7132°, γ = −4 − 6 = −10°.
    q, qd, qdd = iso14242_angles(np.array([0.0, 0.25]), frequency=2.0)
    np.testing.assert_allclose(q[0] / DEG, [25.0, 1.5 + 5.5 * math.cos(40 * DEG), -10.0], rtol=1e-12)
    # ω = 2π·2 = 4π: α̇(0) = 0, β̇(0) = −5.5°·4π·sin(−40°) = 5.5°·4π·sin 40°, γ̇(0) = 0.
    w = 4 * math.pi
    np.testing.assert_allclose(qd[0] / DEG, [0.0, 5.5 * w * math.sin(40 * DEG), 0.0], atol=1e-12)
    # α̈(0) = −21.5°·ω², β̈(0) = −5.5°·ω²·cos 40°, γ̈(0) = +6°·ω².
    np.testing.assert_allclose(qdd[0] / DEG, [-21.5 * w**2, -5.5 * w**2 * math.cos(40 * DEG), 6.0 * w**2], rtol=1e-12)
    # t = 0.25 s at 2 Hz is half a cycle: α = 3.5 − 21.5 = −18°, γ = −4 + 6 = 2°.
    assert q[1, 0] / DEG == pytest.approx(-18.0) and q[1, 2] / DEG == pytest.approx(2.0)


def test_the_load_through_its_knots_periodically():
    s = np.array([0.0, 0.12, 0.32, 0.5, 0.62, 0.8, 1.0])
    np.testing.assert_allclose(iso14242_load(s), [300, 3000, 1500, 3000, 300, 300, 300], rtol=1e-12)
    # At 2 Hz, 0.06 s is 12 % of a cycle; 1.16 s is 2.32 cycles: 32 %.
    np.testing.assert_allclose(iso14242_load(np.array([0.06, 1.16]), 2.0), [3000.0, 1500.0], rtol=1e-12)
    # Between the knots the curve stays within them (no overshoot) and rises over 0–12 %.
    fine = iso14242_load(np.linspace(0.0, 0.12, 50))
    assert np.all(np.diff(fine) >= 0) and fine.max() == pytest.approx(3000.0)


def test_sampling_the_cycle():
    tr = iso14242(rate=100.0, cycles=2)
    assert len(tr) == 200 and tr.periodic and tr.name == "ISO 14242-1"
    assert tr.t[1] == 0.01 and tr.t[-1] == pytest.approx(1.99)
    half = iso14242(rate=100.0, cycles=1.5, frequency=1.0)
    assert len(half) == 150 and not half.periodic
    # 3 cycles at 2 Hz and 10 Hz: 15 samples, whole.
    assert iso14242_samples(10.0, 3, 2.0, 100) == (15, True)
    # 1.25 cycles at 8 Hz, 1 Hz: 10 samples, not whole cycles.
    assert iso14242_samples(8.0, 1.25, 1.0, 100) == (10, False)
    with pytest.raises(TrajectoryError, match="10 cycle\\(s\\) at 1000.0 Hz gives 10,000 samples; at most 5,000 fit"):
        iso14242_samples(1000.0, 10, 1.0, 5000)
    assert iso14242_samples(1000.0, 5, 1.0, 5000) == (5000, True)
    with pytest.raises(TrajectoryError, match="fewer than 2 samples"):
        iso14242(rate=1.0, cycles=1)
    for name, value in (("rate", 0.0), ("cycles", math.nan), ("frequency", True), ("rate", "100"), ("cycles", -1)):
        with pytest.raises(TrajectoryError, match=f"{name} must be a positive number"):
            iso14242(**{name: value})  # type: ignore[arg-type]  # wrong types on purpose


def test_the_cycle_at_any_times():
    at = iso14242_at(0.25, frequency=2.0)
    assert len(at) == 1 and not at.periodic
    q, qd, qdd = iso14242_angles(np.array([0.25]), 2.0)
    np.testing.assert_array_equal(at.q, q)
    np.testing.assert_array_equal(at.qdd, qdd)
    assert at.Fe[0] == pytest.approx(3000.0)  # half a cycle: 50 %, the second peak


def polynomial_trajectory(n=11):
    """Angles cubic in t (a quintic spline is exact on them), the load linear, on t = 0 … 1 s."""
    t = np.linspace(0.0, 1.0, n)
    c = np.array([0.1, -0.2, 0.3])
    q = np.outer(t**3, c) + np.outer(t, [0.05, 0.0, -0.1])
    qd = np.outer(3 * t**2, c) + [0.05, 0.0, -0.1]
    qdd = np.outer(6 * t, c)
    return Trajectory(t, q, qd, qdd, 100.0 + 50.0 * t, name="cubic"), c


def test_interpolation_is_exact_on_a_cubic_and_linear_on_the_load():
    tr, c = polynomial_trajectory()
    at = interpolator(tr)
    times = np.array([0.0, 0.05, 0.33, 0.999, 1.0])
    out = at(times)
    np.testing.assert_allclose(out.q, np.outer(times**3, c) + np.outer(times, [0.05, 0.0, -0.1]), atol=1e-12)
    np.testing.assert_allclose(out.qd, np.outer(3 * times**2, c) + [0.05, 0.0, -0.1], atol=1e-10)
    np.testing.assert_allclose(out.qdd, np.outer(6 * times, c), atol=1e-8)
    np.testing.assert_allclose(out.Fe, 100.0 + 50.0 * times, rtol=1e-12)
    assert out.name == "cubic"
    assert len(at(0.5)) == 1
    with pytest.raises(TrajectoryError, match="times -0.1 to 0.5 s reach outside the trajectory \\(0 to 1 s\\)"):
        at(np.array([-0.1, 0.5]))
    with pytest.raises(TrajectoryError, match="reach outside"):
        at(1.01)
    with pytest.raises(TrajectoryError, match=f"5 samples; at least {MIN_SAMPLES} are needed to interpolate"):
        interpolator(tr.slice(slice(0, 5)))


def test_a_periodic_trajectory_interpolates_around_and_beyond_its_period():
    tr = iso14242(rate=50.0, cycles=1)
    at = interpolator(tr)
    # At its samples it is the samples; one and two periods later the same again.
    np.testing.assert_allclose(at(tr.t).q, tr.q, atol=1e-12)
    np.testing.assert_allclose(at(tr.t + 1.0).q, tr.q, atol=1e-12)
    np.testing.assert_allclose(at(tr.t - 2.0).Fe, tr.Fe, rtol=1e-12)
    # Between the last sample (0.98 s) and the period's end the curve wraps to the first: at 0.99 s the
    # angles are the cycle's (a periodic spline of 50 samples a cycle, to 1e-5 rad), the load halfway.
    mid = at(0.99)
    np.testing.assert_allclose(mid.q[0], iso14242_angles(np.array([0.99]))[0][0], atol=1e-5)
    assert mid.Fe[0] == pytest.approx(0.5 * (tr.Fe[-1] + tr.Fe[0]))


def test_a_trajectory_checks_its_arrays():
    tr, _ = polynomial_trajectory(4)
    arrays = dict(t=tr.t, q=tr.q, qd=tr.qd, qdd=tr.qdd, Fe=tr.Fe)
    with pytest.raises(TrajectoryError, match="t must be a non-empty 1-D array, got shape \\(0,\\)"):
        Trajectory(np.zeros(0), np.zeros((0, 3)), np.zeros((0, 3)), np.zeros((0, 3)), np.zeros(0))
    with pytest.raises(TrajectoryError, match="t must be a non-empty 1-D array"):
        Trajectory(**(arrays | {"t": tr.t[None]}))
    for name, bad, shape in (("q", tr.q[:, :2], "\\(4, 3\\)"), ("Fe", tr.Fe[:3], "\\(4,\\)")):
        with pytest.raises(TrajectoryError, match=f"{name} must have shape {shape}"):
            Trajectory(**(arrays | {name: bad}))
    qd = tr.qd.copy()
    qd[2, 1] = math.inf
    with pytest.raises(TrajectoryError, match="qd is not finite at t = 0.666667 s"):
        Trajectory(**(arrays | {"qd": qd}))
    # The arrays are frozen, floats, whatever came in.
    t = Trajectory(**(arrays | {"Fe": [1, 2, 3, 4]}))
    assert t.Fe.dtype == float and not t.Fe.flags.writeable and not t.q.flags.writeable and not t.t.flags.writeable
    with pytest.raises(ValueError, match="read-only"):
        t.qdd[0, 0] = 1.0


def test_lines_slices_and_the_line_at_a_time():
    tr, _ = polynomial_trajectory(4)  # t = 0, 1/3, 2/3, 1
    arrays = dict(t=tr.t, q=tr.q, qd=tr.qd, qdd=tr.qdd, Fe=tr.Fe)
    with pytest.raises(TrajectoryError, match="lines must be integers of shape \\(4,\\)"):
        Trajectory(**arrays, lines=np.array([1.0, 2.0, 3.0, 4.0]))
    with pytest.raises(TrajectoryError, match="lines must be integers"):
        Trajectory(**arrays, lines=np.array([1, 2, 3]))
    lined = Trajectory(**arrays, name="walk.csv", periodic=True, lines=np.array([10, 11, 12, 14], dtype=np.int32))
    assert given(lined.lines).dtype == int and not given(lined.lines).flags.writeable
    # A sample's own time (to a millionth of a step) has its line; between samples none.
    assert lined.line_at(0.0) == 10 and lined.line_at(1.0) == 14
    assert lined.line_at(2 / 3) == 12 and lined.line_at(2 / 3 + 1e-8) == 12 and lined.line_at(2 / 3 - 1e-8) == 12
    assert lined.line_at(0.5) is None and lined.line_at(2 / 3 + 1e-5) is None
    assert lined.line_at(math.nan) is None and lined.line_at(5.0) is None and lined.line_at(-1.0) is None
    assert tr.line_at(0.0) is None
    one = lined.slice(slice(2, 3))
    assert one.line_at(2 / 3) == 12 and one.line_at(2 / 3 + 0.5e-6) == 12 and one.line_at(2 / 3 + 2e-6) is None
    # A slice: the selected samples, their lines, no longer periodic.
    part = lined.slice(np.array([True, False, True, True]))
    assert len(part) == 3 and not part.periodic and part.name == "walk.csv"
    np.testing.assert_array_equal(part.lines, [10, 12, 14])
    np.testing.assert_array_equal(part.qd, tr.qd[[0, 2, 3]])
    np.testing.assert_array_equal(part.Fe, tr.Fe[[0, 2, 3]])
    assert tr.slice(slice(1, 3)).lines is None


def test_trajectory_arrays_of_anything_trajectory_like():
    tr, _ = polynomial_trajectory(4)
    t, q, qd, qdd = trajectory_arrays(SimpleNamespace(t=list(tr.t), q=tr.q, qd=tr.qd, qdd=tr.qdd))
    assert t.dtype == float
    # Integers come back as floats.
    ints = trajectory_arrays(SimpleNamespace(t=[0, 1], q=[[1, 2, 3]] * 2, qd=[[0, 0, 0]] * 2, qdd=[[0, 0, 0]] * 2))
    assert all(a.dtype == float for a in ints)
    np.testing.assert_array_equal(qdd, tr.qdd)
    with pytest.raises(TrajectoryError, match="expected a trajectory with t, q, qd, qdd"):
        trajectory_arrays(SimpleNamespace(t=tr.t, q=tr.q, qd=tr.qd))
    with pytest.raises(TrajectoryError, match="t must be a non-empty 1-D array"):
        trajectory_arrays(SimpleNamespace(t=[], q=tr.q, qd=tr.qd, qdd=tr.qdd))
    with pytest.raises(TrajectoryError, match="qd must have shape \\(4, 3\\), got \\(4, 2\\)"):
        trajectory_arrays(SimpleNamespace(t=tr.t, q=tr.q, qd=tr.qd[:, :2], qdd=tr.qdd))
    with pytest.raises(TrajectoryError, match="t must increase strictly"):
        trajectory_arrays(SimpleNamespace(t=[0.0, 1.0, 1.0, 2.0], q=tr.q, qd=tr.qd, qdd=tr.qdd))
    assert len(trajectory_arrays(SimpleNamespace(t=[0.0], q=tr.q[:1], qd=tr.qd[:1], qdd=tr.qdd[:1]))[0]) == 1


def refusal(call, *args, **kwargs) -> str:
    """The whole message of the TrajectoryError that ``call`` raises."""
    with pytest.raises(TrajectoryError) as refused:
        call(*args, **kwargs)
    return str(refused.value)


def test_a_trajectorys_refusals_name_it_the_array_and_the_sample_time():
    tr, _ = polynomial_trajectory(4)  # t = 0, 1/3, 2/3, 1
    arrays = dict(t=tr.t, q=tr.q, qd=tr.qd, qdd=tr.qdd, Fe=tr.Fe, name="walk.csv")
    assert refusal(Trajectory, **(arrays | {"t": tr.t[None]})) == (
        "walk.csv: t must be a non-empty 1-D array, got shape (1, 4)"
    )
    assert refusal(Trajectory, **(arrays | {"qdd": tr.qdd[:3]})) == "walk.csv: qdd must have shape (4, 3), got (3, 3)"
    assert refusal(Trajectory, **(arrays | {"Fe": tr.Fe[:, None]})) == "walk.csv: Fe must have shape (4,), got (4, 1)"
    # The first non-finite sample of q is the second (t = 1/3 s), whatever its column.
    q = tr.q.copy()
    q[3, 0] = math.nan
    q[1, 2] = -math.inf
    assert refusal(Trajectory, **(arrays | {"q": q})) == "walk.csv: q is not finite at t = 0.333333 s"
    Fe = tr.Fe.copy()
    Fe[3] = math.nan
    assert refusal(Trajectory, **(arrays | {"Fe": Fe})) == "walk.csv: Fe is not finite at t = 1 s"
    assert refusal(Trajectory, **arrays, lines=np.array([1.0, 2.0, 3.0, 4.0])) == (
        "walk.csv: lines must be integers of shape (4,), got float64 (4,)"
    )
    assert refusal(Trajectory, **arrays, lines=np.array([[1, 2, 3, 4]])) == (
        "walk.csv: lines must be integers of shape (4,), got int64 (1, 4)"
    )
    # Unnamed, a trajectory is "trajectory".
    assert refusal(Trajectory, tr.t, tr.q[:, :2], tr.qd, tr.qdd, tr.Fe) == (
        "trajectory: q must have shape (4, 3), got (4, 2)"
    )


def test_the_built_in_cycles_refusals_name_it_and_the_numbers():
    assert refusal(iso14242_samples, 0.0, 1, 1.0, 100) == "ISO 14242-1: rate must be a positive number, got 0.0"
    assert refusal(iso14242_samples, 10.0, 1, -2.0, 100) == (
        "ISO 14242-1: frequency must be a positive number, got -2.0"
    )
    assert refusal(iso14242_samples, 10.0, math.inf, 1.0, 100) == (
        "ISO 14242-1: cycles must be a positive number, got inf"
    )
    # 0.1 cycle of 1 Hz at 10 Hz is 1 sample.
    assert refusal(iso14242_samples, 10.0, 0.1, 1.0, 100) == (
        "ISO 14242-1: 0.1 cycle(s) of 1.0 Hz sampled at 10.0 Hz give fewer than 2 samples"
    )
    # 0.15 cycle of 1 Hz at 10 Hz rounds to 2 samples (1.5 → 2): enough, and not whole.
    assert iso14242_samples(10.0, 0.15, 1.0, 100) == (2, False)
    assert refusal(iso14242_samples, 1000.0, 3, 0.5, 5000, "to keep the run short") == (
        "ISO 14242-1: 3 cycle(s) at 1000.0 Hz gives 6,000 samples; at most 5,000 to keep the run short"
    )
    assert iso14242_samples(1000.0, 3, 0.6, 5000) == (5000, True)


def test_whole_cycles_are_whole_numbers_of_cycles_and_of_samples():
    # 2 cycles of 3 Hz at 10 Hz: 20/3 = 6.67 samples, rounded to 7: a whole number of cycles but not of
    # samples, so not whole; 2 cycles of 2 Hz at 10 Hz: 10 samples, whole.
    assert iso14242_samples(10.0, 2, 3.0, 100) == (7, False)
    assert iso14242_samples(10.0, 2, 2.0, 100) == (10, True)
    # 2.0000001 cycles: not a whole number (further from 2 than 1e-12).
    assert iso14242_samples(10.0, 2.0000001, 2.0, 100) == (10, False)


def test_interpolations_refusals_name_the_trajectory():
    tr, _ = polynomial_trajectory()
    named = Trajectory(tr.t, tr.q, tr.qd, tr.qdd, tr.Fe, name="walk.csv")
    at = interpolator(named)
    assert refusal(at, np.array([0.5, 1.25])) == (
        "walk.csv: times 0.5 to 1.25 s reach outside the trajectory (0 to 1 s)"
    )
    assert (
        refusal(interpolator, named.slice(slice(0, 5))) == "walk.csv: 5 samples; at least 6 are needed to interpolate"
    )
    # The ends themselves, and a round-off (1e-13 s) beyond them, are inside: clipped to the ends.
    out = at(np.array([-1e-13, 1.0 + 1e-13]))
    np.testing.assert_allclose(out.q, [tr.q[0], tr.q[-1]], atol=1e-12)
    assert out.name == "walk.csv" and not out.periodic
    # 1e-11 s beyond the end is outside.
    assert refusal(at, 1.0 + 1e-11).startswith("walk.csv: times 1 to 1 s reach outside")
    assert refusal(at, -1e-11).startswith("walk.csv: times -1e-11 to -1e-11 s reach outside")


def test_trajectory_arrays_refusals_name_the_column():
    tr, _ = polynomial_trajectory(4)
    assert refusal(trajectory_arrays, SimpleNamespace(t=tr.t, q=tr.q, qd=tr.qd[:, :2], qdd=tr.qdd)) == (
        "column 'qd': qd must have shape (4, 3), got (4, 2)"
    )
    assert refusal(trajectory_arrays, SimpleNamespace(t=tr.t, q=tr.q, qd=tr.qd, qdd=tr.qdd[:3])) == (
        "column 'qdd': qdd must have shape (4, 3), got (3, 3)"
    )
    assert refusal(trajectory_arrays, SimpleNamespace(t=[0.0, 2.0, 1.0, 3.0], q=tr.q, qd=tr.qd, qdd=tr.qdd)) == (
        "column 't': t must increase strictly"
    )
    assert refusal(trajectory_arrays, SimpleNamespace(t=np.zeros((2, 2)), q=tr.q, qd=tr.qd, qdd=tr.qdd)) == (
        "t must be a non-empty 1-D array, got shape (2, 2)"
    )
    assert refusal(trajectory_arrays, SimpleNamespace(t=tr.t, q=tr.q, qdd=tr.qdd)) == (
        "expected a trajectory with t, q, qd, qdd ('types.SimpleNamespace' object has no attribute 'qd')"
    )


def test_a_periodic_trajectory_that_does_not_start_at_zero():
    # One cycle of the built-in angles sampled at 50 Hz from t₀ = 0.3 s (the samples end at 1.28 s, the
    # period is 1 s). A sample's time, one period later or earlier, gives its angles; halfway between
    # the last sample and t₀ + 1 s the load is the mean of the last and the first.
    t = 0.3 + np.arange(50) / 50.0
    q, qd, qdd = iso14242_angles(t)
    tr = Trajectory(t, q, qd, qdd, iso14242_load(t), name="loop", periodic=True)
    at = interpolator(tr)
    np.testing.assert_allclose(at(t + 1.0).q, q, atol=1e-12)
    np.testing.assert_allclose(at(t - 3.0).Fe, tr.Fe, rtol=1e-12)
    assert at(1.29).Fe[0] == pytest.approx(0.5 * (tr.Fe[-1] + tr.Fe[0]))
    np.testing.assert_allclose(at(1.29).q[0], iso14242_angles(np.array([1.29]))[0][0], atol=1e-5)
    # Its velocity and acceleration are the spline's: the exact ones of the cycle to a small error.
    out = at(np.array([0.31, 0.77, 1.295]))
    exact = iso14242_angles(np.array([0.31, 0.77, 1.295]))
    np.testing.assert_allclose(out.qd, exact[1], atol=1e-3)
    np.testing.assert_allclose(out.qdd, exact[2], atol=0.1)
    assert out.name == "loop" and not out.periodic


def test_the_line_at_a_time_is_to_a_millionth_of_the_step():
    # Samples every 10 s from 100 s: a time 8e-6 s from a sample (0.8 millionth of the step) is that
    # sample's; 1.5e-5 s from it is not. Two samples 10 s apart: the same. Samples every 1/3 s: 1e-6 s
    # is three millionths of the step, too far. Exactly a millionth of a 1 s step still counts.
    zeros = np.zeros((3, 3))
    slow = Trajectory(np.array([100.0, 110.0, 120.0]), zeros, zeros, zeros, np.zeros(3), lines=np.array([2, 3, 4]))
    assert slow.line_at(110.0 + 8e-6) == 3 and slow.line_at(110.0 - 8e-6) == 3
    assert slow.line_at(110.0 + 1.5e-5) is None and slow.line_at(110.0 - 1.5e-5) is None
    assert slow.line_at(120.0 + 8e-6) == 4 and slow.line_at(100.0 - 8e-6) == 2 and slow.line_at(125.0) is None
    pair = Trajectory(np.array([100.0, 110.0]), zeros[:2], zeros[:2], zeros[:2], np.zeros(2), lines=np.array([7, 9]))
    assert pair.line_at(110.0 + 8e-6) == 9 and pair.line_at(110.0 + 1.5e-5) is None
    tr, _ = polynomial_trajectory(4)
    lined = Trajectory(tr.t, tr.q, tr.qd, tr.qdd, tr.Fe, lines=np.array([5, 6, 7, 8]))
    assert lined.line_at(1 / 3 + 1e-6) is None and lined.line_at(1 / 3 + 1e-7) == 6
    unit = Trajectory(np.array([0.0, 1.0, 2.0]), zeros, zeros, zeros, np.zeros(3), lines=np.array([1, 2, 3]))
    assert unit.line_at(1e-6) == 1


def test_the_ends_of_an_open_trajectory_take_round_off_of_a_picosecond():
    # 1e-12 s beyond either end is still inside (the comparison is strict); the samples at the ends.
    tr, _ = polynomial_trajectory()
    at = interpolator(tr)
    out = at(np.array([0.0 - 1e-12, 1.0 + 1e-12]))
    np.testing.assert_allclose(out.q, [tr.q[0], tr.q[-1]], atol=1e-11)
    np.testing.assert_allclose(out.Fe, [tr.Fe[0], tr.Fe[-1]], rtol=1e-12)
    with pytest.raises(TrajectoryError, match="reach outside"):
        at(0.0 - 3e-12)


def test_interpolation_is_quintic_and_needs_six_samples():
    # A quintic spline reproduces a polynomial of degree 5 (a cubic one would not): t⁵ and t⁴ on
    # six samples and between them, with their derivatives 5t⁴, 20t³ and 4t³, 12t².
    t = np.linspace(0.0, 1.0, MIN_SAMPLES)
    q = np.stack([t**5, t**4, -(t**5)], axis=1)
    zeros = np.zeros_like(q)
    at = interpolator(Trajectory(t, q, zeros, zeros, 10.0 * t))
    x = np.array([0.05, 0.37, 0.81, 0.99])
    out = at(x)
    np.testing.assert_allclose(out.q, np.stack([x**5, x**4, -(x**5)], axis=1), atol=1e-10)
    np.testing.assert_allclose(out.qd, np.stack([5 * x**4, 4 * x**3, -5 * x**4], axis=1), atol=1e-8)
    np.testing.assert_allclose(out.qdd, np.stack([20 * x**3, 12 * x**2, -20 * x**3], axis=1), atol=1e-6)
    np.testing.assert_allclose(out.Fe, 10.0 * x, rtol=1e-12)


def test_the_cycle_at_any_times_is_named_and_open():
    at = iso14242_at([0, 1])
    assert at.name == "ISO 14242-1" and at.periodic is False and at.t.dtype == float
    np.testing.assert_allclose(at.Fe, [300.0, 300.0])


def test_integer_times_become_floats():
    zeros = np.zeros((3, 3), dtype=int)
    tr = Trajectory(np.array([0, 1, 2]), zeros, zeros, zeros, np.array([0, 0, 0]))
    assert tr.t.dtype == float and tr.q.dtype == float and tr.Fe.dtype == float


def test_trajectory_arrays_name_q_and_refuse_two_samples_back_in_time():
    tr, _ = polynomial_trajectory(4)
    assert refusal(trajectory_arrays, SimpleNamespace(t=tr.t, q=tr.q[:, :1], qd=tr.qd, qdd=tr.qdd)) == (
        "column 'q': q must have shape (4, 3), got (4, 1)"
    )
    two = SimpleNamespace(t=[1.0, 0.0], q=tr.q[:2], qd=tr.qd[:2], qdd=tr.qdd[:2])
    assert refusal(trajectory_arrays, two) == "column 't': t must increase strictly"


def test_a_periodic_spline_is_smooth_across_the_wrap():
    # Velocity and acceleration just before t₀ + 1 s equal those at t₀ (a periodic spline's boundary
    # conditions; an open spline's ends would not meet).
    t = 0.3 + np.arange(50) / 50.0
    q, qd, qdd = iso14242_angles(t)
    at = interpolator(Trajectory(t, q, qd, qdd, iso14242_load(t), periodic=True))
    start, end = at(0.3), at(1.3 - 1e-9)
    np.testing.assert_allclose(end.qd, start.qd, atol=1e-6)
    np.testing.assert_allclose(end.qdd, start.qdd, atol=1e-5)
