"""The Pinocchio closed-chain model (hipsim.closed_chain: build, constraints, closure, dynamics): closures, rates, and inverse dynamics checked by physics.

Nothing here compares against numbers produced by the code under test: the
kinematics are checked against the constraints and finite differences, the
torques against the power balance of the whole tree and of each body group,
and the closure forces against Newton–Euler balances of single bodies, all
computed from Pinocchio's body motions or from the spec's formulas.
"""

from __future__ import annotations

import dataclasses
import math
from types import SimpleNamespace

import numpy as np
import pinocchio as pin
import pytest
import yaml
from support import given

from hipsim import ModelError, PoseError, Torques, load_parameters
from hipsim.closed_chain.build import load_closed_chain, load_model
from hipsim.closed_chain.closure import kinematics
from hipsim.closed_chain.constraints import (
    closure_residuals,
    constraint_jacobian,
    constraint_rank,
    platform_joint_positions,
)
from hipsim.closed_chain.dynamics import inverse_dynamics, trajectory_dynamics
from hipsim.machine.model_files import closure_file_path, default_urdf_path

DEG = math.pi / 180.0
H = 1e-5  # time step of the central differences in [s]
LWA = pin.LOCAL_WORLD_ALIGNED
FRICTION = dict(
    screw_coulomb=0.05,
    screw_viscous=2e-4,
    guide_coulomb=20.0,
    guide_viscous=30.0,
    ujoint_coulomb=0.3,
    ujoint_viscous=0.05,
    sjoint_coulomb=0.2,
    sjoint_viscous=0.04,
)


def motion(t, frequency: float = 1.0):
    """The reference orientation cycle with exact derivatives, and a smooth load; duck-typed trajectory."""
    t = np.atleast_1d(np.asarray(t, dtype=float))
    w = 2 * math.pi * frequency
    offset = np.array([3.5, 1.5, -4.0]) * DEG
    amplitude = np.array([21.5, 5.5, 6.0]) * DEG
    phase = np.array([0.0, -40.0 * DEG, -math.pi])
    arg = w * t[:, None] + phase
    return SimpleNamespace(
        t=t,
        q=offset + amplitude * np.cos(arg),
        qd=-w * amplitude * np.sin(arg),
        qdd=-w * w * amplitude * np.cos(arg),
        Fe=1650.0 - 1350.0 * np.cos(w * t),
        name="test motion",
    )


def rotation(q):
    """Rz(γ)·Ry(β)·Rx(α) (spec §2), for one q = [α, β, γ]."""
    (ca, cb, cg), (sa, sb, sg) = np.cos(q), np.sin(q)
    Rx = np.array([[1, 0, 0], [0, ca, -sa], [0, sa, ca]])
    Ry = np.array([[cb, 0, sb], [0, 1, 0], [-sb, 0, cb]])
    Rz = np.array([[cg, -sg, 0], [sg, cg, 0], [0, 0, 1]])
    return Rz @ Ry @ Rx


def smooth_sign(w, eps):
    return w / np.sqrt(np.dot(w, w) + eps * eps)


class Run:
    """One model along the reference motion, at t and at t ± H."""

    def __init__(self, params):
        self.params = params
        self.chain = load_model(params)
        self.t = np.linspace(0.0, 1.0, 201)
        self.traj = motion(self.t)
        self.kin, self.dyn = trajectory_dynamics(self.chain, self.traj)
        self.plus = kinematics(self.chain, motion(self.t + H))
        self.minus = kinematics(self.chain, motion(self.t - H))
        self.model = self.chain.model
        self.data = self.model.createData()

    def frame(self, name):
        return self.model.getFrameId(name)

    def motor_power(self):
        return np.sum(self.dyn.torques.total * self.motor_speed(), axis=1)

    def motor_speed(self):
        return 2 * math.pi / self.params.lead * self.kin.v[:, given(self.chain.layout).slider_v]

    def rate_of(self, quantity):
        """d/dt of quantity(q, v) along the motion, by central differences."""
        plus = np.array([quantity(q, v) for q, v in zip(self.plus.q, self.plus.v)])
        minus = np.array([quantity(q, v) for q, v in zip(self.minus.q, self.minus.v)])
        return (plus - minus) / (2 * H)

    def body_energy(self, names, q, v):
        """Kinetic + potential energy of some bodies from Pinocchio's body motions (not from the torques)."""
        model, data = self.model, self.data
        pin.forwardKinematics(model, data, q, v)
        pin.updateFramePlacements(model, data)
        energy = 0.0
        for name in names:
            joint = model.frames[self.frame(name)].parentJoint
            inertia = model.inertias[joint]
            com = pin.SE3(np.eye(3), inertia.lever)
            R = data.oMi[joint].rotation
            w = pin.getFrameVelocity(model, data, joint, com, LWA)
            I_world = R @ inertia.inertia @ R.T
            height = (data.oMi[joint] * com).translation[2]
            energy += 0.5 * inertia.mass * w.linear @ w.linear + 0.5 * w.angular @ I_world @ w.angular
            energy += inertia.mass * self.params.gravity * height
        return energy

    def friction_power(self):
        """Power dissipated by every friction of spec §4.3, from Pinocchio's body velocities."""
        fr, p = self.params.friction, self.params
        model, data = self.model, self.data
        power = np.zeros(len(self.t))
        for n, (q, v) in enumerate(zip(self.kin.q, self.kin.v)):
            pin.forwardKinematics(model, data, q, v)
            pin.updateFramePlacements(model, data)
            Fe = self.traj.Fe[n]
            hip = fr.hip_radius * fr.hip_mu * abs(Fe)
            thrust = fr.thrust_radius * fr.thrust_mu * abs(Fe + p.platform_mass * p.gravity)
            for j in (1, 2):
                w = pin.getFrameVelocity(model, data, self.frame(f"platform_{j}"), LWA).angular
                if fr.thrust_bearing_axial_only:  # the bearing turns only about the platform's z axis
                    spin = w @ data.oMf[self.frame(f"platform_{j}")].rotation[:, 2]
                    power[n] += hip * w @ smooth_sign(w, fr.epsilon) + thrust * spin * spin / math.sqrt(
                        spin**2 + fr.epsilon**2
                    )
                else:
                    power[n] += (hip + thrust) * w @ smooth_sign(w, fr.epsilon)
                for i in (1, 2, 3):
                    wl = pin.getFrameVelocity(model, data, self.frame(f"lever_{j}{i}"), LWA).angular
                    power[n] += wl @ (fr.ujoint_coulomb * smooth_sign(wl, fr.epsilon) + fr.ujoint_viscous * wl)
                    wr = wl - w
                    power[n] += wr @ (fr.sjoint_coulomb * smooth_sign(wr, fr.epsilon) + fr.sjoint_viscous * wr)
        Ld = self.kin.v[:, given(self.chain.layout).slider_v]
        speed = self.motor_speed()
        ss = speed / np.sqrt(speed**2 + fr.epsilon**2)
        power += np.sum(2 * (fr.guide_coulomb * ss + fr.guide_viscous * Ld) * Ld, axis=1)
        power += np.sum((fr.screw_coulomb * ss + fr.screw_viscous * speed) * speed, axis=1)
        return power


@pytest.fixture(scope="module")
def run():
    return Run(load_parameters())


@pytest.fixture(scope="module")
def rough():
    """Every friction coefficient non-zero."""
    return Run(load_parameters().replace(**FRICTION))


@pytest.fixture(scope="module")
def axial():
    """Every friction coefficient non-zero, and a thrust bearing that resists only its own axis' rotation."""
    return Run(load_parameters().replace(**FRICTION, thrust_bearing_axial_only=True))


# --- kinematics --------------------------------------------------------------------------


def test_closure_jacobian_full_rank_three_dof(run):
    nv = run.model.nv
    for q in run.kin.q[::10]:
        sigma = np.linalg.svd(constraint_jacobian(run.chain, q), compute_uv=False)
        assert sigma.size == 18 and sigma[-1] > 1e-3 * sigma[0]
        assert constraint_rank(run.chain, q) == 18
        assert nv - constraint_rank(run.chain, q) == 3


def test_closures_hold(run):
    assert run.kin.residual.max() <= 1e-10
    gaps = np.linalg.norm(closure_residuals(run.chain, run.kin.q), axis=-1)
    assert gaps.max() <= 1e-10


def test_platforms_follow_the_given_angles(run):
    platform = run.chain.layout.platform_v
    for j in range(2):
        np.testing.assert_array_equal(run.kin.q[:, platform[j]], run.traj.q)
        np.testing.assert_array_equal(run.kin.v[:, platform[j]], run.traj.qd)
        np.testing.assert_array_equal(run.kin.a[:, platform[j]], run.traj.qdd)


def test_platform_joints_are_where_the_spec_puts_them(run):
    a = platform_joint_positions(run.chain, run.kin.q[::20])
    p = run.params
    for n, q in enumerate(run.traj.q[::20]):
        for j in range(2):
            expected = p.heights[j] * np.array([0, 0, 1]) + p.platform_points @ rotation(q).T
            np.testing.assert_allclose(a[n, j], expected, atol=1e-14)


def test_sliders_are_the_universal_joint_heights(run):
    model, data, p = run.model, run.data, run.params
    for n in range(0, 201, 25):
        pin.forwardKinematics(model, data, run.kin.q[n])
        for j in (1, 2):
            for i in (1, 2, 3):
                b = data.oMi[model.getJointId(f"u1_{j}{i}")].translation
                np.testing.assert_allclose(b, p.screw_points[i - 1] + [0, 0, run.kin.L[n, j - 1, i - 1]], atol=1e-14)
    np.testing.assert_allclose(run.kin.L[:, 0] - run.kin.L[:, 1], p.heights[0] - p.heights[1], atol=1e-14)
    np.testing.assert_array_equal(run.kin.Ld[:, 0], run.kin.Ld[:, 1])
    np.testing.assert_array_equal(run.kin.Ldd[:, 0], run.kin.Ldd[:, 1])


def test_velocity_and_acceleration_satisfy_the_constraints(run):
    """J_c v = 0 and J_c a + J̇_c v = 0, with J̇_c from Pinocchio's Jacobian time variation."""
    model, data = run.model, run.data
    frames = [run.frame(name) for pair in run.chain.closure_frames for name in pair]
    for q, v, a in zip(run.kin.q[::10], run.kin.v[::10], run.kin.a[::10]):
        Jc = constraint_jacobian(run.chain, q)
        assert np.abs(Jc @ v).max() <= 1e-13 * np.abs(v).max()
        pin.computeJointJacobiansTimeVariation(model, data, q, v)
        pin.updateFramePlacements(model, data)
        J = np.vstack([pin.getFrameJacobian(model, data, f, LWA)[:3] for f in frames]).reshape(-1, 2, 3, model.nv)
        dJ = np.vstack([pin.getFrameJacobianTimeVariation(model, data, f, LWA)[:3] for f in frames]).reshape(
            -1, 2, 3, model.nv
        )
        J, dJ = (J[:, 0] - J[:, 1]).reshape(-1, model.nv), (dJ[:, 0] - dJ[:, 1]).reshape(-1, model.nv)
        assert np.abs(J @ a + dJ @ v).max() <= 1e-12 * np.abs(a).max()


def test_rates_match_finite_differences(run):
    model = run.model
    v_fd = np.array([pin.difference(model, qm, qp) for qm, qp in zip(run.minus.q, run.plus.q)]) / (2 * H)
    a_fd = (run.plus.v - run.minus.v) / (2 * H)
    assert np.abs(v_fd - run.kin.v).max() <= 1e-8 * np.abs(run.kin.v).max()
    assert np.abs(a_fd - run.kin.a).max() <= 1e-8 * np.abs(run.kin.a).max()
    Ld_fd = (run.plus.L - run.minus.L) / (2 * H)
    assert np.abs(Ld_fd - run.kin.Ld).max() <= 1e-8 * np.abs(run.kin.Ld).max()


def test_angle_signs_flip_the_platform_angles():
    params = load_parameters().replace(angle_signs=np.array([-1.0, 1.0, -1.0]))
    chain = load_model(params)
    traj = motion(np.linspace(0, 0.5, 11))
    flipped = kinematics(chain, traj)
    signs = np.array([-1.0, 1.0, -1.0])
    direct = kinematics(
        dataclasses.replace(chain, params=load_parameters()),
        SimpleNamespace(t=traj.t, q=traj.q * signs, qd=traj.qd * signs, qdd=traj.qdd * signs),
    )
    np.testing.assert_array_equal(flipped.q[:, given(chain.layout).platform_v[0]], traj.q * signs)
    np.testing.assert_allclose(flipped.L, direct.L, atol=1e-14)


def test_unreachable_pose_raises_at_its_time():
    chain = load_model()
    p = given(chain.params)
    t = np.linspace(0.0, 1.0, 101)
    gamma = 80.0 * DEG * t
    zeros = np.zeros_like(t)
    rate = np.full_like(t, 80.0 * DEG)
    traj = SimpleNamespace(
        t=t, q=np.stack([zeros, zeros, gamma], 1), qd=np.stack([zeros, zeros, rate], 1), qdd=np.zeros((101, 3))
    )
    # First sample where some lever cannot span the horizontal gap (spec §3's negative radicand).
    gap = [
        np.linalg.norm((p.platform_points @ rotation([0, 0, g]).T - p.screw_points)[:, :2], axis=1).max() for g in gamma
    ]
    first = int(np.argmax(np.array(gap) >= p.lever_length))
    assert first > 0
    with pytest.raises(PoseError, match=rf"t = {t[first]:.6g} s") as error:
        kinematics(chain, traj)
    assert error.value.index == first and error.value.time == t[first]
    with pytest.raises(PoseError, match=rf"t = {t[-1]:.6g} s: ") as error:
        kinematics(chain, SimpleNamespace(t=t[-1:], q=traj.q[-1:], qd=traj.qd[-1:], qdd=traj.qdd[-1:]))
    assert error.value.index == 0


# --- inverse dynamics --------------------------------------------------------------------


def test_kinetic_energy_counts_the_rotors_once(run):
    """computeKineticEnergy already contains ½·armature·v² (Pinocchio ≥ 3): no extra term in the balances."""
    q, v = run.kin.q[17], run.kin.v[17]
    bare = run.model.copy()
    bare.armature = np.zeros(run.model.nv)
    rotor = 0.5 * np.sum(run.model.armature * v * v)
    assert rotor > 0
    with_rotors = pin.computeKineticEnergy(run.model, run.data, q, v)
    assert with_rotors == pytest.approx(pin.computeKineticEnergy(bare, bare.createData(), q, v) + rotor, rel=1e-12)


@pytest.mark.parametrize("name", ["run", "rough", "axial"])
def test_power_balance(name, request):
    """Motor power = d/dt (kinetic + potential energy of the tree) + friction power."""
    r = request.getfixturevalue(name)
    model, data = r.model, r.data

    def energy(q, v):
        return pin.computeKineticEnergy(model, data, q, v) + pin.computePotentialEnergy(model, data, q)

    motor = r.motor_power()
    balance = r.rate_of(energy) + r.friction_power()
    assert np.abs(motor - balance).max() <= 1e-6 * np.abs(motor).max()


def test_each_part_is_the_power_of_its_bodies(run):
    p, speed = run.params, run.motor_speed()
    platforms = [f"platform_{j}" for j in (1, 2)]
    levers = [f"lever_{j}{i}" for j in (1, 2) for i in (1, 2, 3)]
    for part, bodies in (("platforms", platforms), ("levers", levers)):
        power = np.sum(getattr(run.dyn.torques, part) * speed, axis=1)
        rate = run.rate_of(lambda q, v: run.body_energy(bodies, q, v))
        assert np.abs(power - rate).max() <= 1e-6 * np.abs(power).max(), part
    Ldd = run.kin.Ldd[:, 0]
    np.testing.assert_allclose(
        run.dyn.torques.sliders, p.lead / (2 * math.pi) * 2 * p.slider_mass * (Ldd + p.gravity), rtol=1e-12
    )
    np.testing.assert_allclose(
        run.dyn.torques.screws, 2 * math.pi * p.screw_inertia / p.lead * Ldd, rtol=1e-12, atol=1e-15
    )
    friction = np.sum(run.dyn.torques.friction * speed, axis=1)
    assert np.abs(friction - run.friction_power()).max() <= 1e-9 * np.abs(friction).max()


def test_parts_add_up_to_the_plain_rnea_solution(rough):
    r = rough
    d = r.dyn
    np.testing.assert_allclose(
        d.torques.total,
        d.torques.platforms + d.torques.levers + d.torques.sliders + d.torques.screws + d.torques.friction,
        rtol=0,
        atol=1e-15,
    )
    # Without friction, one RNEA with every inertia (and the armature) gives the same motor torque.
    S = np.zeros((r.model.nv, 3))
    S[r.chain.actuated_v, range(3)] = 1.0
    for n in range(0, 201, 20):
        q, v, a = r.kin.q[n], r.kin.v[n], r.kin.a[n]
        x = np.linalg.solve(np.hstack([S, constraint_jacobian(r.chain, q).T]), pin.rnea(r.model, r.data, q, v, a))
        np.testing.assert_allclose(
            d.torques.total[n] - d.torques.friction[n], r.params.lead / (2 * math.pi) * x[:3], rtol=1e-10, atol=1e-12
        )


def _lever_tip_force(r, n, j, i):
    """Force of the platform on lever ji in world axes, and the lever's placement."""
    R = r.data.oMf[r.frame(f"lever_{j}{i}_tip")].rotation
    return R @ r.dyn.lambdas[n, j - 1, i - 1]


@pytest.mark.parametrize("lever", [(1, 1), (2, 3), (1, 2)])
def test_lever_free_body(run, lever):
    """Newton–Euler of one lever: the frictionless universal joint carries no moment about its axes."""
    j, i = lever
    r, p = run, run.params
    model, data = r.model, r.data
    joint = model.getJointId(f"u2_{j}{i}")
    com = pin.SE3(np.eye(3), np.array([0, 0, p.lever_length / 2]))
    g = np.array([0, 0, -p.gravity])
    for n in range(0, 201, 13):
        pin.forwardKinematics(model, data, r.kin.q[n], r.kin.v[n], r.kin.a[n])
        pin.updateFramePlacements(model, data)
        R = data.oMi[joint].rotation
        b, c = data.oMi[joint].translation, (data.oMi[joint] * com).translation
        tip = data.oMf[r.frame(f"lever_{j}{i}_tip")].translation
        w = pin.getFrameVelocity(model, data, joint, com, LWA).angular
        w_dot = pin.getFrameAcceleration(model, data, joint, com, LWA).angular
        a_c = pin.getFrameClassicalAcceleration(model, data, joint, com, LWA).linear
        I = R @ p.lever_inertia @ R.T
        f_tip = _lever_tip_force(r, n, j, i)
        f_b = p.lever_mass * (a_c - g) - f_tip  # the universal joint's reaction force
        m_b = I @ w_dot + np.cross(w, I @ w) - np.cross(tip - c, f_tip) - np.cross(b - c, f_b)
        u1, u2 = p.ujoint_axes[i - 1], R[:, 0]
        scale = np.linalg.norm(f_tip) * p.lever_length + 1e-9
        assert abs(m_b @ u1) <= 1e-10 * scale and abs(m_b @ u2) <= 1e-10 * scale


@pytest.mark.parametrize("j", [1, 2])
def test_platform_free_body(run, j):
    """Moments about the centre: lever forces + central friction = platform inertia (the S joint is frictionless)."""
    r, p, fr = run, run.params, run.params.friction
    model, data = r.model, r.data
    frame = r.frame(f"platform_{j}")
    for n in range(0, 201, 11):
        pin.forwardKinematics(model, data, r.kin.q[n], r.kin.v[n], r.kin.a[n])
        pin.updateFramePlacements(model, data)
        R, o = data.oMf[frame].rotation, data.oMf[frame].translation
        w = pin.getFrameVelocity(model, data, frame, LWA).angular
        w_dot = pin.getFrameAcceleration(model, data, frame, LWA).angular
        I = R @ p.platform_inertia @ R.T
        Fe = r.traj.Fe[n]
        load = fr.hip_radius * fr.hip_mu * Fe + fr.thrust_radius * fr.thrust_mu * (Fe + p.platform_mass * p.gravity)
        moment = -load * smooth_sign(w, fr.epsilon)
        for i in (1, 2, 3):
            a = data.oMf[r.frame(f"platform_{j}_joint_{i}")].translation
            moment += np.cross(a - o, -_lever_tip_force(r, n, j, i))
        inertial = I @ w_dot + np.cross(w, I @ w)
        assert np.abs(moment - inertial).max() <= 1e-9 * max(np.abs(inertial).max(), load)


def test_central_joint_force_balances_the_platform(run):
    r, p = run, run.params
    model, data = r.model, r.data
    for n in range(0, 201, 17):
        pin.framesForwardKinematics(model, data, r.kin.q[n])
        for j in (1, 2):
            levers = sum(_lever_tip_force(r, n, j, i) for i in (1, 2, 3))  # = −(forces of the levers on the platform)
            expected = levers + np.array([0, 0, p.platform_mass * p.gravity + r.traj.Fe[n]])
            assert r.dyn.joint_forces.Fo[n, j - 1] == pytest.approx(np.linalg.norm(expected), rel=1e-12)
    np.testing.assert_allclose(r.dyn.joint_forces.Fa, np.linalg.norm(r.dyn.lambdas, axis=-1), rtol=1e-15)


def test_massless_levers_are_two_force_members():
    """With m_l = 0 and I_l = 0 each lever only pushes along itself; at rest nothing loads the levers."""
    params = load_parameters().replace(lever_mass=0.0, lever_inertia=np.zeros((3, 3)))
    chain = load_model(params)
    kin, dyn = trajectory_dynamics(chain, motion(np.linspace(0, 1, 41)))
    transverse = np.abs(dyn.lambdas[..., :2]).max()
    assert transverse <= 1e-10 * np.abs(dyn.lambdas).max()
    # At rest: the carriages' weight goes to the motors, the platforms' weight and load to the centre.
    still = motion(np.array([0.3]))
    still.qd[:], still.qdd[:] = 0.0, 0.0
    kin, dyn = trajectory_dynamics(chain, still)
    np.testing.assert_allclose(dyn.joint_forces.Fa, 0.0, atol=1e-9)
    np.testing.assert_allclose(dyn.joint_forces.Fo, params.platform_mass * params.gravity + still.Fe[0], rtol=1e-12)
    np.testing.assert_allclose(
        dyn.torques.total, params.lead / (2 * math.pi) * 2 * params.slider_mass * params.gravity, rtol=1e-12
    )


def test_results_are_frozen_and_shaped(run):
    n, nv = len(run.t), run.model.nv
    assert run.kin.q.shape == (n, nv) and run.kin.L.shape == (n, 2, 3)
    assert (
        run.dyn.torques.total.shape == (n, 3)
        and run.dyn.joint_forces.Fa.shape == (n, 2, 3)
        and run.dyn.joint_forces.Fo.shape == (n, 2)
    )
    with pytest.raises(ValueError, match="read-only"):
        run.dyn.torques.total[0, 0] = 1.0
    with pytest.raises(AttributeError):
        run.dyn.torques.total = None


def test_accepts_a_hipsim_trajectory():
    from hipsim.motion.trajectories import iso14242

    chain = load_model()
    traj = iso14242(rate=100.0)
    kin = kinematics(chain, traj)
    dyn = inverse_dynamics(chain, kin, traj.Fe)
    assert dyn.torques.total.shape == (len(traj.t), 3) and np.all(np.isfinite(dyn.torques.total))


def test_inverse_dynamics_of_a_kinematics_result_reuses_the_solvers_compiled_sample():
    """kinematics() gives read-only rates; inverse_dynamics copies them, so closed_sample is not compiled again for them."""
    from hipsim.closed_chain import closure_kernel
    from hipsim.motion.trajectories import iso14242

    chain, traj = load_model(), iso14242(rate=100.0)
    trajectory_dynamics(chain, traj)  # the solver's own route
    compiled = len(closure_kernel.closed_sample.signatures)
    kin = kinematics(chain, traj)
    assert not kin.angle_rates.flags.writeable  # what made the second signature
    inverse_dynamics(chain, kin, traj.Fe)
    assert len(closure_kernel.closed_sample.signatures) == compiled >= 1


# --- loading -----------------------------------------------------------------------------


def test_generic_loader_reads_the_transmission_from_the_closure_file():
    chain = load_closed_chain(default_urdf_path(), closure_file_path(), gravity=9.8)
    hip = load_model()
    assert chain.layout is None and chain.n_closures == 6
    np.testing.assert_allclose(chain.model.armature, hip.model.armature, rtol=1e-12)
    np.testing.assert_array_equal(chain.actuated_v, hip.actuated_v)
    p = given(hip.params)
    assert hip.model.armature[hip.actuated_v] == pytest.approx(p.screw_inertia * (2 * math.pi / p.lead) ** 2)
    for cm in chain.constraint_models:
        assert cm.type == pin.ContactType.CONTACT_3D and cm.reference_frame == pin.ReferenceFrame.LOCAL
    with pytest.raises(ModelError, match="hip simulator model"):
        kinematics(chain, motion(np.array([0.0])))


def test_a_closure_file_naming_an_unknown_frame_is_rejected(tmp_path):
    content = yaml.safe_load(closure_file_path().read_text(encoding="utf-8"))
    content["closed_loop"][2][1] = "platform_9_joint_1"
    path = tmp_path / "bad.yaml"
    path.write_text(yaml.safe_dump(content))
    with pytest.raises(ModelError, match="platform_9_joint_1"):
        load_closed_chain(default_urdf_path(), path)


def test_one_pass_and_chunked_solves_agree(run, monkeypatch):
    """trajectory_dynamics reuses the kinematics' Jacobians; the batched solve works in chunks."""
    import hipsim.closed_chain.dynamics as module

    separate = inverse_dynamics(run.chain, run.kin, run.traj.Fe)
    monkeypatch.setattr(module, "_CHUNK", 7)
    kin, chunked = trajectory_dynamics(run.chain, run.traj)
    np.testing.assert_array_equal(kin.q, run.kin.q)

    def fields(dyn):
        named = {name: getattr(dyn.torques, name) for name in ("total", *Torques.PARTS)}
        return named | {"Fa": dyn.joint_forces.Fa, "Fo": dyn.joint_forces.Fo, "lambdas": dyn.lambdas}

    for name, value in fields(separate).items():
        np.testing.assert_allclose(fields(chunked)[name], value, rtol=1e-12, atol=1e-12, err_msg=name)
        np.testing.assert_allclose(fields(run.dyn)[name], value, rtol=1e-12, atol=1e-12, err_msg=name)


@pytest.mark.parametrize("machine", ["run", "rough"])
def test_total_without_parts_is_the_sum_of_the_parts(machine, request):
    """One RNEA call and a one-column solve give the total the five parts add up to; the parts are not made up."""
    run = request.getfixturevalue(machine)
    kin, total_only = trajectory_dynamics(run.chain, run.traj, parts=False)
    scale = np.abs(run.dyn.torques.total).max()
    np.testing.assert_allclose(total_only.torques.total, run.dyn.torques.total, rtol=0, atol=1e-12 * scale)
    parts_sum = sum(getattr(run.dyn.torques, name) for name in Torques.PARTS)
    np.testing.assert_allclose(total_only.torques.total, parts_sum, rtol=0, atol=1e-12 * scale)
    np.testing.assert_allclose(total_only.lambdas, run.dyn.lambdas, rtol=0, atol=1e-9 * np.abs(run.dyn.lambdas).max())
    assert all(np.isnan(getattr(total_only.torques, name)).all() for name in Torques.PARTS)
    separate = inverse_dynamics(run.chain, kin, run.traj.Fe, parts=False)
    np.testing.assert_allclose(separate.torques.total, total_only.torques.total, rtol=0, atol=1e-12 * scale)
