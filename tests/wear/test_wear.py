"""hipsim.wear: the definitions against an independent computation, the analytic cases, convergence, pieces."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import minimize_scalar
from scipy.spatial.transform import Rotation

from hipsim.exceptions import ArgumentError, TrajectoryError
from hipsim.motion.trajectories import Trajectory, iso14242, iso14242_load
from hipsim.physics.orientation import angular_velocity_map, rotation_matrix
from hipsim.wear import CupSetup, cup_grid, cup_points, wear_maps
from hipsim.wear.kinematics import body_velocity, sequence_rotation

R_MM = 14.0
DEG = math.pi / 180


def _motion(q_of, load_of, n=1000, period=1.0, name="synthetic"):
    """A periodic trajectory from angle and load functions of time; rates by central differences of the functions."""
    t = np.arange(n) * period / n
    h = 1e-6
    q = q_of(t)
    qd = (q_of(t + h) - q_of(t - h)) / (2 * h)
    return Trajectory(t, q, qd, np.zeros_like(q), load_of(t), name=name, periodic=True)


def _reference(q_of, load_of, w, sequence="ZYX", n=5000):
    """s, W and CS at the points w by another route: scipy's rotations, Ω from central differences of R,
    the pressure and velocity evaluated as the definitions state, the trapezoid on a 5x finer grid, and the
    direction of most work by a search over 720 directions refined by Brent's method."""
    t = np.arange(n) / n
    h = 1e-5

    def R(times):
        q = q_of(times)
        angles = [q[:, "XYZ".index(letter)] for letter in sequence]
        return Rotation.from_euler(sequence, np.stack(angles, axis=1)).as_matrix()

    Rt = R(t)
    Rd = (R(t + h) - R(t - h)) / (2 * h)
    skew = np.swapaxes(Rt, 1, 2) @ Rd
    omega = np.stack([skew[:, 2, 1], skew[:, 0, 2], skew[:, 1, 0]], axis=1)
    n_c = Rt[:, 2, :]  # Rᵀ·ẑ: the third row of R
    F = load_of(t)
    dt = 1.0 / n
    out = []
    for wi in w:
        v = -R_MM * np.cross(omega, wi)
        p = 3 * F / (2 * math.pi * R_MM**2) * np.maximum(0.0, n_c @ wi)
        speed = np.linalg.norm(v, axis=1)
        s, W = np.sum(speed) * dt, np.sum(p * speed) * dt
        a = np.cross(wi, [1.0, 0.0, 0.0]) if abs(wi[0]) < 0.9 else np.cross(wi, [0.0, 1.0, 0.0])
        a /= np.linalg.norm(a)
        b = np.cross(wi, a)

        def work(theta, a=a, b=b, v=v, p=p):
            e = math.cos(theta) * a + math.sin(theta) * b
            return np.sum(p * np.abs(v @ e)) * dt

        thetas = np.linspace(0, math.pi, 720, endpoint=False)
        values = np.abs(np.outer(np.cos(thetas), v @ a) + np.outer(np.sin(thetas), v @ b)) @ p
        k = int(np.argmax(values))
        step = thetas[1]
        best = minimize_scalar(
            lambda x: -work(x), bounds=(thetas[k] - step, thetas[k] + step), method="bounded", options={"xatol": 1e-10}
        )
        e = math.cos(best.x) * a + math.sin(best.x) * b
        along = -best.fun
        across = np.sum(p * np.abs(v @ np.cross(wi, e))) * dt
        out.append((s, W, across / (along + across) if W > 0 else math.nan))
    return np.array(out)


def _iso_q(t):
    from hipsim.motion.trajectories import iso14242_angles

    return iso14242_angles(t)[0]


def _lively_q(t):
    """A running-like motion with every angle's harmonics: wide flexion, rotation out of phase."""
    s = 2 * math.pi * t
    return np.stack(
        [
            (10 + 35 * np.cos(s) + 6 * np.sin(2 * s)) * DEG,
            (3 + 8 * np.cos(s - 1.0) + 3 * np.cos(3 * s)) * DEG,
            (-5 + 9 * np.sin(s + 0.4) + 2 * np.sin(2 * s)) * DEG,
        ],
        axis=1,
    )


def _running_load(t):
    s = np.mod(t, 1.0)
    return 300.0 + 3500.0 * np.where(s < 0.4, np.sin(math.pi * s / 0.4) ** 2, 0.0)


@pytest.fixture(scope="module")
def probe():
    """Cup points in and around the contact: the pole, rings at 20°, 45° and 70°."""
    rows = [[0.0, 0.0, 1.0]]
    for theta, phi in ((20, 10), (20, 200), (45, 80), (45, 300), (70, 150), (70, 30), (35, 250)):
        th, ph = theta * DEG, phi * DEG
        rows.append([math.sin(th) * math.cos(ph), math.sin(th) * math.sin(ph), math.cos(th)])
    return np.array(rows)


@pytest.mark.parametrize(
    ("q_of", "load_of", "sequence"),
    [(_iso_q, iso14242_load, "ZYX"), (_lively_q, _running_load, "ZYX"), (_lively_q, _running_load, "XYZ")],
    ids=["iso", "running-like", "running-like-XYZ"],
)
def test_definitions_against_an_independent_computation(probe, q_of, load_of, sequence):
    trajectory = _motion(q_of, load_of)
    maps = wear_maps(trajectory, 1.0, CupSetup(28.0, sequence=sequence), cup_points(probe))
    reference = _reference(q_of, load_of, probe, sequence)
    np.testing.assert_allclose(maps.sliding_mm, reference[:, 0], rtol=1e-4)
    np.testing.assert_allclose(maps.work_N_per_mm, reference[:, 1], rtol=1e-4, atol=1e-4 * reference[:, 1].max())
    loaded = reference[:, 1] > 1e-3 * reference[:, 1].max()
    np.testing.assert_allclose(maps.cross_shear[loaded], reference[loaded, 2], atol=1e-4)
    assert loaded.sum() >= 5


def test_body_velocity_of_the_machine_sequence_is_the_spec_map():
    """Ω = Rᵀ·T(q)·q̇ (spec §2) for ZYX, and R the spec's."""
    rng = np.random.default_rng(3)
    q, qd = rng.uniform(-0.8, 0.8, (50, 3)), rng.uniform(-2, 2, (50, 3))
    R = rotation_matrix(q)
    np.testing.assert_allclose(sequence_rotation(q, "ZYX"), R, atol=1e-14)
    spatial = np.einsum("nij,nj->ni", angular_velocity_map(q), qd)
    np.testing.assert_allclose(body_velocity(q, qd, "ZYX"), np.einsum("nji,nj->ni", R, spatial), atol=1e-13)


def test_pure_flexion_has_no_cross_shear():
    trajectory = _motion(lambda t: np.stack([25 * DEG * np.sin(2 * math.pi * t), 0 * t, 0 * t], 1), iso14242_load)
    maps = wear_maps(trajectory, 1.0, points=cup_grid(30, 60, R_MM))
    loaded = maps.loaded
    assert loaded.sum() > 0.9 * loaded.size
    assert np.nanmax(np.abs(maps.cross_shear)) < 1e-12


def test_time_reversal_gives_the_same_sliding_work_and_cross_shear():
    forward = _motion(_lively_q, _running_load)
    backward = _motion(lambda t: _lively_q(1.0 - t), lambda t: _running_load(1.0 - t))
    grid = cup_grid(20, 40, R_MM)
    a, b = wear_maps(forward, 1.0, points=grid), wear_maps(backward, 1.0, points=grid)
    np.testing.assert_allclose(b.sliding_mm, a.sliding_mm, rtol=1e-9)
    np.testing.assert_allclose(b.work_N_per_mm, a.work_N_per_mm, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(b.cross_shear, a.cross_shear, atol=1e-9)
    assert b.force_track_mm == pytest.approx(a.force_track_mm, rel=1e-9)


def test_force_track_of_flexion_alone_is_twice_the_arc():
    """β = γ = 0: n sweeps an arc of r·(range of α) out and back."""
    low, high = -18 * DEG, 25 * DEG
    trajectory = _motion(
        lambda t: np.stack([(high + low) / 2 + (high - low) / 2 * np.cos(2 * math.pi * t), 0 * t, 0 * t], 1),
        lambda t: 1000.0 + 0 * t,
        n=4000,
    )
    maps = wear_maps(trajectory, 1.0, points=cup_points(np.array([[0.0, 0.0, 1.0]])))
    assert maps.force_track_mm == pytest.approx(R_MM * (high - low) * 2, rel=1e-6)
    assert maps.force_track_load_Nm == pytest.approx(1000.0 * R_MM * (high - low) * 2 / 1000, rel=1e-6)


def test_the_wear_integral_converges_as_the_grid_is_refined():
    """Σ W·dA over the cup: each halving of the cells shrinks the change by about four (the midpoint rule)."""
    trajectory = iso14242(rate=500)
    totals = []
    for n_theta in (12, 24, 48, 96):
        maps = wear_maps(trajectory, 1.0, points=cup_grid(n_theta, 2 * n_theta, R_MM))
        totals.append(float(np.sum(maps.work_N_per_mm * maps.points.area_mm2)))
    steps = np.abs(np.diff(totals))
    assert steps[1] < 0.4 * steps[0] and steps[2] < 0.4 * steps[1]
    assert steps[2] < 1e-3 * totals[-1]


def test_pieces_give_the_whole_motions_values():
    """Constant memory: a motion handed out 97 samples at a time gives what it gives whole."""
    trajectory = iso14242(rate=1000, cycles=2)
    grid = cup_grid(10, 20, R_MM)
    whole, parts = wear_maps(trajectory, 1.0, points=grid), wear_maps(trajectory, 1.0, points=grid, piece=97)
    assert whole.cycles == pytest.approx(2.0)
    np.testing.assert_allclose(parts.work_N_per_mm, whole.work_N_per_mm, rtol=1e-12)
    np.testing.assert_allclose(parts.cross_shear, whole.cross_shear, atol=1e-12)
    one = wear_maps(iso14242(rate=1000), 1.0, points=grid)
    np.testing.assert_allclose(whole.sliding_mm, one.sliding_mm, rtol=1e-12)  # per cycle


def test_moving_head_fixes_the_contact_on_the_cup():
    trajectory = iso14242(rate=200)
    maps = wear_maps(trajectory, 1.0, CupSetup(moving="head"), cup_grid(10, 20, R_MM))
    assert maps.force_track_mm == pytest.approx(0.0, abs=1e-12)
    cup = wear_maps(trajectory, 1.0, CupSetup(), cup_grid(10, 20, R_MM))
    assert maps.force_track_mm < cup.force_track_mm


@pytest.mark.parametrize(
    ("kwargs", "words"),
    [
        ({"head_diameter_mm": 0.0}, "positive diameter"),
        ({"head_diameter_mm": 150.0}, "at most 100"),
        ({"sequence": "ZZX"}, "permutation"),
        ({"moving": "both"}, "'cup' or 'head'"),
    ],
)
def test_bad_setups_are_refused(kwargs, words):
    with pytest.raises(ArgumentError, match=words):
        CupSetup(**kwargs)


def test_points_off_the_sphere_or_the_cup_are_refused():
    with pytest.raises(ArgumentError, match=r"row 2.*unit sphere"):
        cup_points(np.array([[0.0, 0.0, 1.0], [0.0, 0.5, 0.5]]))
    with pytest.raises(ArgumentError, match=r"row 1.*cup"):
        cup_points(np.array([[0.0, 0.0, -1.0]]))


def test_a_motion_shorter_than_a_cycle_is_refused():
    with pytest.raises(TrajectoryError, match="shorter than one cycle"):
        wear_maps(iso14242(rate=100, cycles=0.5), 1.0, points=cup_grid(4, 8, R_MM))


def test_a_cup_mount_turns_the_maps_with_the_cup():
    """Mounted turned by M, the cup's point w sits where the unmounted cup's M·w does: same s, W and CS."""
    trajectory = iso14242(rate=400)
    grid = cup_grid(6, 12, R_MM)
    M = sequence_rotation(np.array([[0.0, 0.0, math.radians(90.0)]]))[0]
    mounted = wear_maps(trajectory, 1.0, CupSetup(cup_mount_rad=(0.0, 0.0, math.radians(90.0))), grid)
    plain = wear_maps(trajectory, 1.0, CupSetup(), cup_points(grid.w @ M.T))
    np.testing.assert_allclose(mounted.sliding_mm, plain.sliding_mm, rtol=1e-12)
    np.testing.assert_allclose(mounted.work_N_per_mm, plain.work_N_per_mm, rtol=1e-12)
    np.testing.assert_allclose(mounted.cross_shear, plain.cross_shear, atol=1e-12)


def test_wear_laws_by_hand():
    """V = 10⁻³·Σ k(CS)·W·dA per cycle (k linear in CS from a table), and C·Σ s_loaded·dA for the contact-area law."""
    from hipsim.wear.laws import ContactAreaLaw, CrossShearLaw, WearFactor, predict_wear

    maps = wear_maps(iso14242(rate=400), 1.0, points=cup_grid(10, 20, R_MM))
    W, CS, dA = maps.work_N_per_mm, maps.cross_shear, maps.points.area_mm2
    table = predict_wear(maps, CrossShearLaw(np.array([0.0, 0.5]), np.array([1e-7, 6e-7])))
    k = 1e-7 + 1e-6 * CS  # the table's line
    assert table.total_mm3_per_Mc == pytest.approx(1e-3 * np.sum(k * W * dA) * 1e6, rel=1e-12)
    constant = predict_wear(maps, WearFactor(2e-7))
    assert constant.total_mm3_per_Mc == pytest.approx(1e-3 * 2e-7 * np.sum(W * dA) * 1e6, rel=1e-12)
    np.testing.assert_allclose(constant.depth_um_per_Mc, 1e-3 * 2e-7 * W * 1e6 * 1e3, rtol=1e-12)
    area = predict_wear(maps, ContactAreaLaw(1e-9))
    assert area.total_mm3_per_Mc == pytest.approx(1e-9 * np.sum(maps.sliding_loaded_mm * dA) * 1e6, rel=1e-12)
    narrow = CrossShearLaw(np.array([0.1, 0.2]), np.array([1e-7, 2e-7]))
    beyond = int(np.sum((CS < 0.1) | (CS > 0.2)))
    assert beyond > 0 and predict_wear(maps, narrow).beyond_table == beyond


def test_trapezoid_weights_of_an_open_motion_in_pieces():
    """Uneven times, not periodic: the trapezoid's weights (half steps at the ends), the same whether cut in pieces."""
    from hipsim.motion.sources import SampledSource
    from hipsim.wear.maps import quadrature_weights

    t = np.array([0.0, 0.1, 0.3, 0.35, 0.6, 1.0])
    source = SampledSource(Trajectory(t, np.zeros((6, 3)), np.zeros((6, 3)), np.zeros((6, 3)), np.ones(6)))
    expected = [0.05, 0.15, 0.125, 0.15, 0.325, 0.2]
    np.testing.assert_allclose(quadrature_weights(source, 0, 6), expected, atol=1e-15)
    parts = np.concatenate(
        [quadrature_weights(source, 0, 2), quadrature_weights(source, 2, 5, t[2:5]), quadrature_weights(source, 5, 6)]
    )
    np.testing.assert_allclose(parts, expected, atol=1e-15)


def test_the_direction_of_most_work_is_the_global_maximum():
    """A motion of three harmonics per angle, whose work curves have several local maxima: CS at the global
    maximum, found here by a search over 3600 directions on the same samples refined by Brent's method."""
    rng = np.random.default_rng(1)
    A, P = rng.normal(0, 15, (3, 3)) * DEG, rng.uniform(0, 2 * math.pi, (3, 3))

    def q_of(t):
        return np.stack(
            [sum(A[i, h] * np.cos(2 * math.pi * (h + 1) * t + P[i, h]) for h in range(3)) for i in range(3)], 1
        )

    trajectory = _motion(q_of, lambda t: 300 + 2000 * (1 + np.cos(2 * math.pi * t + 1.0)), n=1000)
    th, ph = rng.uniform(0, math.pi / 2, 25), rng.uniform(0, 2 * math.pi, 25)
    w = np.stack([np.sin(th) * np.cos(ph), np.sin(th) * np.sin(ph), np.cos(th)], 1)
    maps = wear_maps(trajectory, 1.0, points=cup_points(w))
    omega = body_velocity(trajectory.q, trajectory.qd)
    n_c = sequence_rotation(trajectory.q)[:, 2, :]
    angles = np.linspace(0, math.pi, 3600, endpoint=False)
    for i, wi in enumerate(w):
        p = 3 * trajectory.Fe / (2 * math.pi * R_MM**2) * np.maximum(0.0, n_c @ wi) / 1000
        v = -R_MM * np.cross(omega, wi)
        a = np.cross(wi, [0.0, 0.0, 1.0]) if abs(wi[2]) < 0.9 else np.cross(wi, [1.0, 0.0, 0.0])
        a /= np.linalg.norm(a)
        b = np.cross(wi, a)
        va, vb = v @ a, v @ b

        def work(x, va=va, vb=vb, p=p):
            return float(np.abs(math.cos(x) * va + math.sin(x) * vb) @ p)

        k = int(np.argmax(np.abs(np.outer(np.cos(angles), va) + np.outer(np.sin(angles), vb)) @ p))
        top = minimize_scalar(
            lambda x: -work(x), bounds=(angles[k] - 1e-3, angles[k] + 1e-3), method="bounded", options={"xatol": 1e-12}
        )
        along, across = -top.fun, work(top.x + math.pi / 2)
        assert maps.cross_shear[i] == pytest.approx(across / (along + across), abs=1e-7)


def test_a_motion_too_long_to_hold_takes_the_iteration(monkeypatch):
    """Beyond KEEP_SAMPLES the direction comes from the L1 fixed-point iteration over pieces: a local maximum, on the
    ISO cycle near the global one (CS within 1e-3 of the exact search's; s and W are not touched)."""
    import hipsim.wear.maps as maps_module

    grid = cup_grid(12, 24, R_MM)
    exact = wear_maps(iso14242(rate=500), 1.0, points=grid)
    monkeypatch.setattr(maps_module, "KEEP_SAMPLES", 0)
    iterated = wear_maps(iso14242(rate=500), 1.0, points=grid, piece=128)
    assert iterated.iterations > 0 and exact.iterations == 0
    np.testing.assert_allclose(iterated.cross_shear, exact.cross_shear, atol=1e-3)
    np.testing.assert_allclose(iterated.work_N_per_mm, exact.work_N_per_mm, rtol=1e-12)
