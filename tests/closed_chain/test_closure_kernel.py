"""The compiled arithmetic of the closure solver (hipsim.closed_chain.closure_kernel), each piece against another route.

The drift against Pinocchio's own frame accelerations, the force solve against
the full 21×21 system, the body-group torques against Pinocchio's joint-torque
regressor, the predictor against a motion it must extrapolate exactly.
"""

from __future__ import annotations

import math
import sys

import numpy as np
import pinocchio as pin
import pytest
from support import closed_hip, smooth_cycle

from hipsim.closed_chain import closure_kernel
from hipsim.closed_chain.constraints import constraint_jacobian
from hipsim.closed_chain.rnea import BatchedRNEA, group_trees
from hipsim.closed_chain.workspace import k_order


@pytest.fixture(scope="module")
def closed():
    return closed_hip()


def _order(closed, blocks: bool = True):
    """B's rows, columns and block starts for closure_kernel.velocity: the solver's block order, or one block in the plain order."""
    if blocks:
        return k_order(closed.ws, closed.layout.platform_v[0])
    others = np.setdiff1d(np.arange(closed.chain.model.nv), closed.layout.platform_v[0])
    return np.arange(len(others)), others, np.array([0, len(others)])


def _velocity(closed, k, blocks: bool = True):
    """K⁻¹ at sample k of the closed motion, through closure_kernel.velocity, and the tips it read."""
    ws, layout, nv = closed.ws, closed.layout, closed.chain.model.nv
    ws.place(closed.kin.q[k])
    tips = ws.tip_frames()
    V, J_rates, K_inv = np.empty((1, nv)), np.empty((1, 3, 3)), np.empty((nv, nv))
    status = closure_kernel.velocity(
        ws.jacobian(),
        layout.platform_v[0],
        *_order(closed, blocks),
        closed.kin.angle_rates[k],
        layout.platform_v[1],
        tips,
        V,
        0,
        layout.slider_v,
        J_rates,
        0,
        K_inv,
    )
    assert status == closure_kernel.OK
    return K_inv, tips, V[0], J_rates[0]


def test_block_lower_inverse_inverts_by_blocks():
    """A random block lower triangular matrix (blocks 1, 3, 2, 4) inverted by blocks equals LAPACK's inverse of the whole."""
    rng = np.random.default_rng(5)
    starts = np.array([0, 1, 4, 6, 10])
    M = rng.normal(size=(10, 10)) + 4 * np.eye(10)
    for b in range(len(starts) - 1):
        M[starts[b] : starts[b + 1], starts[b + 1] :] = 0.0
    np.testing.assert_allclose(closure_kernel.block_lower_inverse(M, starts), np.linalg.inv(M), rtol=0, atol=1e-14)
    np.testing.assert_allclose(
        closure_kernel.block_lower_inverse(M, np.array([0, 10])), np.linalg.inv(M), rtol=0, atol=1e-14
    )


def test_block_inverse_pivots_and_refuses_singular_blocks():
    """A block whose diagonal is zero needs row exchanges (a permutation times a scaling); a singular block raises LinAlgError, as LAPACK does."""
    D = np.zeros((5, 5))
    D[[0, 1, 2, 3, 4], [3, 0, 4, 1, 2]] = [
        2.0,
        -3.0,
        0.5,
        7.0,
        1.5,
    ]  # a scaled permutation: every pivot comes from another row
    D[4, 3] = 1e-3
    M = np.zeros((8, 8))
    M[:3, :3] = np.array([[0.0, 1.0, 2.0], [1.0, 0.0, 3.0], [4.0, 5.0, 0.0]])
    M[3:, 3:] = D
    M[3:, :3] = np.arange(15.0).reshape(5, 3)
    starts = np.array([0, 3, 8])
    np.testing.assert_allclose(closure_kernel.block_lower_inverse(M, starts), np.linalg.inv(M), rtol=0, atol=1e-13)
    for block in (slice(0, 3), slice(3, 8)):
        singular = M.copy()
        singular[block, block] = 0.0
        singular[block.start, block.start] = 1.0  # rank 1: the elimination meets a zero pivot
        with pytest.raises(np.linalg.LinAlgError):
            closure_kernel.block_lower_inverse(singular, starts)


def test_hip_closure_jacobian_splits_into_blocks(closed):
    """The solver's order of B: blocks 3, 3, 3, 9 on the hip, zero above them at a real configuration, and K⁻¹ as the plain 18×18 inverse gives it."""
    rows, columns, starts = k_order(closed.ws, closed.layout.platform_v[0])
    assert np.diff(starts).tolist() == [3, 3, 3, 9]
    closed.ws.place(closed.kin.q[7])
    B = closed.ws.jacobian()[rows][:, columns]
    for b in range(len(starts) - 1):
        assert not B[starts[b] : starts[b + 1], starts[b + 1] :].any()
    for k in (7, 30):
        by_blocks, plain = _velocity(closed, k), _velocity(closed, k, blocks=False)
        for a, b in zip(by_blocks, plain):
            np.testing.assert_allclose(a, b, rtol=0, atol=1e-13 * np.abs(b).max())


@pytest.mark.parametrize("k", [0, 13, 29])
def test_velocity_solves_the_velocity_closure(closed, k):
    """K v = [q̇; 0] written out: platform 1 at q̇, J_c v = 0, platform 2 at q̇, J_rates the sliders' rates per angle rate."""
    K_inv, _, v, J_rates = _velocity(closed, k)
    layout, qd = closed.layout, closed.kin.angle_rates[k]
    Jc = constraint_jacobian(closed.chain, closed.kin.q[k])
    np.testing.assert_allclose(v[layout.platform_v], [qd, qd], rtol=0, atol=1e-15)
    assert np.abs(Jc @ v).max() <= 1e-13 * np.abs(v).max()
    np.testing.assert_allclose(J_rates @ qd, v[layout.slider_v], rtol=0, atol=1e-14)
    K = np.vstack([np.eye(closed.chain.model.nv)[layout.platform_v[0]], Jc])
    np.testing.assert_allclose(K_inv @ K, np.eye(len(K)), rtol=0, atol=1e-12)
    np.testing.assert_allclose(K @ K_inv, np.eye(len(K)), rtol=0, atol=1e-12)


@pytest.mark.parametrize("k", [5, 20, 33])
def test_acceleration_drift_is_pinocchios_relative_classical_acceleration(closed, k):
    """J̇_c v from J and J̇ equals the lever-tip and platform points' classical accelerations at a = 0 (getFrameClassicalAcceleration)."""
    ws, chain, kin, layout = closed.ws, closed.chain, closed.kin, closed.layout
    model, data = chain.model, ws.data
    K_inv, tips, v, _ = _velocity(closed, k)
    d = ws.residual()
    # The kernel's acceleration with q̈ = 0 is −K⁻¹[0; drift], so K·a gives the drift back.
    V, A = v[None].copy(), np.empty((1, model.nv))
    closure_kernel.acceleration(K_inv, data.J, V, A, 0, ws.support_masks, tips, d, np.zeros(3), layout.platform_v[1])
    Jc = constraint_jacobian(chain, kin.q[k])
    drift = -(Jc @ A[0])
    # The other route: Pinocchio's classical accelerations of both closure frames, in frame 1's axes.
    pin.forwardKinematics(model, data, kin.q[k], v, np.zeros(model.nv))
    expected = []
    for cm, tip in zip(chain.constraint_models, tips):
        ends = [
            pin.getFrameClassicalAcceleration(model, data, joint, placement, pin.LOCAL_WORLD_ALIGNED).linear
            for joint, placement in ((cm.joint1_id, cm.joint1_placement), (cm.joint2_id, cm.joint2_placement))
        ]
        expected.append(tip[:3, :3].T @ (ends[0] - ends[1]))
    expected_all = np.concatenate(expected)
    np.testing.assert_allclose(drift, expected_all, rtol=0, atol=1e-11 * np.abs(expected_all).max())


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_frame_motion_rate_is_pinocchios_jacobian_time_variation(closed, seed):
    """J̇·v over a closure frame's supporting joints, from J and v alone, equals Pinocchio's data.dJ·v (computeJointJacobiansTimeVariation).

    At arbitrary (q, v), not closed ones: the identity is the tree's, whatever the loops do.
    """
    model, masks = closed.chain.model, closed.ws.support_masks
    rng = np.random.default_rng(seed)
    q = pin.randomConfiguration(model, -np.ones(model.nq), np.ones(model.nq))
    v = rng.uniform(-3.0, 3.0, model.nv)
    data = model.createData()
    pin.computeJointJacobiansTimeVariation(model, data, q, v)
    for mask in masks:
        twist, rate = closure_kernel._frame_motion(mask, v, data.J)
        np.testing.assert_allclose(twist, data.J @ (mask * v), rtol=0, atol=1e-13)
        np.testing.assert_allclose(rate, data.dJ @ (mask * v), rtol=0, atol=1e-12)
    # The order matters: the chain read from its tip inwards gives another (wrong) rate.
    chain_mask = masks[0]
    reversed_J = data.J[:, ::-1].copy()
    _, wrong = closure_kernel._frame_motion(chain_mask[::-1].copy(), v[::-1].copy(), reversed_J)
    assert np.abs(np.array(wrong) - data.dJ @ (chain_mask * v)).max() > 1e-3


def test_forces_solve_the_full_system(closed):
    """F and λ from K⁻¹ (a 3×3 solve per sample) equal the solution of [Sᵀ J_cᵀ]·[F; λ] = τ, part by part."""
    chain, kin = closed.chain, closed.kin
    nv, rng = chain.model.nv, np.random.default_rng(7)
    samples = [3, 17, 30]
    K_invs = np.array([_velocity(closed, k)[0] for k in samples])
    tau = rng.normal(size=(len(samples), nv, 4)) * 10.0
    F, lambdas = np.empty((len(samples), 3, 4)), np.empty((len(samples), 3 * chain.n_closures))
    closure_kernel.actuator_and_closure_forces(K_invs, tau, chain.actuated_v, F, lambdas)
    S = np.zeros((nv, 3))
    S[chain.actuated_v, range(3)] = 1.0
    for s, k in enumerate(samples):
        system = np.hstack([S, constraint_jacobian(chain, kin.q[k]).T])
        x = np.linalg.solve(system, tau[s])
        np.testing.assert_allclose(F[s], x[:3], rtol=0, atol=1e-10 * np.abs(x[:3]).max())
        np.testing.assert_allclose(lambdas[s], x[3:].sum(axis=1), rtol=0, atol=1e-10 * np.abs(x[3:]).max())


def test_body_group_torques_are_the_regressors(closed):
    """Batched RNEA of each body group's (reduced) tree equals Pinocchio's joint-torque regressor times that group's inertial parameters."""
    chain, kin = closed.chain, closed.kin
    model, data = chain.model, chain.model.createData()
    groups = [BatchedRNEA(*tree) for tree in group_trees(chain.model, chain.layout.groups)]
    whole = BatchedRNEA(model, np.arange(model.nv))
    assert sorted(len(rnea.columns) for rnea in groups) == [
        3,
        6,
        15,
    ]  # carriages, platforms, levers: only their supports
    n = 8
    q, v, a = kin.q[:n], kin.v[:n] + 0.1, kin.a[:n] - 0.2  # any motion: RNEA does not know the closures
    out = np.full((n, model.nv), np.nan)
    for g, rnea in enumerate(groups):
        rnea(q, v, a, out)
        for k in range(n):
            expected = pin.computeJointTorqueRegressor(model, data, q[k], v[k], a[k]) @ chain.layout.groups[:, g]
            np.testing.assert_allclose(out[k], expected, rtol=0, atol=1e-12 * max(1.0, np.abs(expected).max()))
    whole(q, v, a, out)
    for k in range(n):
        np.testing.assert_allclose(out[k], pin.rnea(model, data, q[k], v[k], a[k]), rtol=0, atol=1e-12)


def test_prediction_is_exact_for_a_cubic():
    """The third-order Taylor step with jerk from two accelerations extrapolates a cubic exactly; the first step is second order."""
    t = np.array([0.0, 0.002, 0.0035, 0.005])  # uneven steps
    c = np.array([[0.3, -1.0], [2.0, 0.5], [-4.0, 1.5], [7.0, -3.0]])  # q = c0 + c1 t + c2 t² + c3 t³, two coordinates
    Q = c[0] + np.outer(t, c[1]) + np.outer(t**2, c[2]) + np.outer(t**3, c[3])
    V = c[1] + np.outer(2 * t, c[2]) + np.outer(3 * t**2, c[3])
    A = 2 * c[2] + np.outer(6 * t, c[3])
    NONE = np.zeros(0, dtype=np.int64)  # no platform coordinates to set

    def predicted(row, platforms=NONE, angles=np.zeros(0)):
        known = Q.copy()
        known[row:] = np.nan  # the samples from row on are not known yet
        out = np.full(Q.shape[1], np.nan)
        closure_kernel.predict(t, known, V, A, row, platforms, angles, out)
        return out

    np.testing.assert_allclose(predicted(3), Q[3], rtol=0, atol=1e-15)
    np.testing.assert_allclose(predicted(2), Q[2], rtol=0, atol=1e-15)
    h = t[1]
    np.testing.assert_allclose(predicted(1), Q[0] + h * V[0] + h * h / 2 * A[0], rtol=0, atol=1e-15)
    assert np.abs(predicted(1) - Q[1]).max() > 1e-9  # the cubic term it cannot know
    set_to = predicted(3, np.array([1]), np.array([0.25]))
    assert set_to[1] == 0.25 and set_to[0] == pytest.approx(Q[3, 0], abs=1e-15)


def test_chord_step_closes_a_perturbed_configuration(closed):
    """From a closed q with its legs moved by 1e-7, chord steps with K⁻¹ shrink the gap at least a thousandfold each."""
    ws, layout, kin = closed.ws, closed.layout, closed.kin
    K_inv, _, _, _ = _velocity(closed, 12)
    q = kin.q[12].copy()
    q[layout.leg_v] += 1e-7 * np.random.default_rng(3).normal(size=layout.leg_v.size)
    angles = q[layout.platform_v.ravel()]
    sizes = []
    for _ in range(2):
        size = ws.place(q)
        assert size == pytest.approx(np.sum(ws.residual() ** 2), rel=1e-15)
        trial = np.empty_like(q)
        closure_kernel.chord_step(q, K_inv, ws.residual(), layout.platform_v.ravel(), angles, trial)
        q = trial
        sizes.append(math.sqrt(size))
    ws.place(q)
    sizes.append(float(np.linalg.norm(ws.residual())))
    assert sizes[0] > 1e-9 and sizes[1] < 1e-3 * sizes[0] and sizes[2] < 1e-14
    np.testing.assert_array_equal(q[layout.platform_v.ravel()], angles)


def test_velocity_reports_a_singular_closure(closed):
    """A K whose constraint rows lose rank is reported, not inverted into nonsense."""
    ws, layout, nv = closed.ws, closed.layout, closed.chain.model.nv
    ws.place(closed.kin.q[0])
    Jc = ws.jacobian().copy()
    Jc[5] = Jc[4] * (1 + 1e-15)  # two rows equal but for round-off
    V, J_rates, K_inv = np.zeros((1, nv)), np.zeros((1, 3, 3)), np.empty((nv, nv))
    arguments = (layout.platform_v[0], *_order(closed), np.ones(3), layout.platform_v[1])
    try:
        status = closure_kernel.velocity(Jc, *arguments, ws.tip_frames(), V, 0, layout.slider_v, J_rates, 0, K_inv)
    except np.linalg.LinAlgError:
        status = closure_kernel.SINGULAR  # exactly singular: LAPACK says so itself
    assert status == closure_kernel.SINGULAR
    tips = ws.tip_frames().copy()
    tips[2, 2, 2] = -0.1  # a lever pointing down
    status = closure_kernel.velocity(ws.jacobian(), *arguments, tips, V, 0, layout.slider_v, J_rates, 0, K_inv)
    assert status == closure_kernel.LEVER_DOWN
    assert not V.any() and not J_rates.any()


def test_threads_running_one_model_do_not_share_pinocchio_data(closed):
    """Two threads closing the same model at once give the serial results bit for bit (each thread has its own workspace and RNEA pools)."""
    from concurrent.futures import ThreadPoolExecutor

    from hipsim.closed_chain.dynamics import trajectory_dynamics

    motions = [smooth_cycle(np.linspace(0.0, 1.0, 301)), smooth_cycle(np.linspace(0.3, 0.8, 301))]
    for m in motions:
        m.Fe = np.full(len(m.t), 1200.0)
    serial = [trajectory_dynamics(closed.chain, m) for m in motions]
    interval = sys.getswitchinterval()
    sys.setswitchinterval(1e-6)  # the threads take turns every few Python operations
    try:
        with ThreadPoolExecutor(max_workers=2) as pool:
            threaded = list(pool.map(lambda m: trajectory_dynamics(closed.chain, m), motions))
    finally:
        sys.setswitchinterval(interval)
    for (kin, dyn), (kin_t, dyn_t) in zip(serial, threaded):
        np.testing.assert_array_equal(kin_t.q, kin.q)
        np.testing.assert_array_equal(dyn_t.torques.total, dyn.torques.total)
        np.testing.assert_array_equal(dyn_t.lambdas, dyn.lambdas)
