"""The MuJoCo model's closed-chain kinematics and inverse dynamics, with MuJoCo's own functions.

Everything here reads MuJoCo: joint anchors and site positions from
``mj_kinematics``, the closure residual and Jacobian J_c from the ``connect``
equalities' constraint rows (``efc_pos``, ``efc_J`` after ``mj_fwdPosition``),
J̇_c·v from ``mj_jacDot``, the mass matrix (armature included) from
``mj_fullM``, the bias forces (gravity, Coriolis, centrifugal) from
``qfrc_bias``, body angular velocities from ``mj_objectVelocity``, and the
generalised forces of friction moments from ``mj_applyFT``. Nothing comes
from the Pinocchio model or the analytic formulas, so that the three engines
check each other.

Closed-chain kinematics (:func:`kinematics`): per sample, both platforms'
angle coordinates are set to the trajectory's (angle_signs applied) and the
15 leg coordinates solved by Gauss–Newton on the 18 closure residuals
(consistent, so it converges quadratically), warm-started by a Taylor step
from the previous sample. With K = [P₁; J_c] (P₁ picks platform 1's angles)
the velocities solve K v = [q̇; 0] and the accelerations K a = [q̈; −J̇_c v].

Inverse dynamics (:func:`inverse_dynamics`): ``mj_inverse`` is not used on
purpose. MuJoCo's constraints are soft (a regularised, Baumgarte-like
reference acceleration), so the constraint forces it reports are not the
rigid closure's multipliers. Instead the tree's generalised forces
τ = M(q)·a + c(q, v) come from MuJoCo's M and bias, and the rigid closure is
solved exactly: [Sᵀ  J_cᵀ]·[F; λ] = τ − Q_f, with S the three actuated slider
columns, J_c MuJoCo's constraint Jacobian and Q_f the friction forces of spec
§4.3 / §7.3 applied as external moments and forces (they enter as applied
forces, which is how a MuJoCo user would add them). The torque parts of spec
§4.4 come from one solve with five right-hand sides: the bias and inertia of
each body group (platforms, levers, carriages) from ``mj_rne`` on a copy of
the model in which only that group has mass, the screws' armature·a, and the
friction. They add up to the total to rounding.

Sign conventions: the connect rows are the derivative of p₁ − p₂ (world
axes), p₁ the lever tip, p₂ the platform joint; λ_ji is the force the platform
exerts on lever ji at a_ji, in world axes.
"""

from __future__ import annotations

import copy
import math
from dataclasses import dataclass

import numpy as np
from scipy.linalg import lapack

from ..physics import laws
from ..arrays import check_shapes
from ..exceptions import ArgumentError, ClosureError, ModelError, PoseError, TrajectoryError
from ..motion.trajectories import trajectory_arrays
from ..results import JointForces, Run, Torques
from ..physics.friction import central_chain_friction
from ..physics.orientation import angular_velocity_map, rotation_matrix
from ..physics.transmission import lead_from_ratio, radians_per_travel, travel_per_radian
from ..machine.parameters import Parameters, load_parameters
from ._dependency import mujoco

__all__ = [
    "FrictionForces",
    "MujocoKinematics",
    "MujocoMachine",
    "MujocoModel",
    "MujocoDynamics",
    "closure_gaps",
    "constraint_jacobian",
    "friction_forces",
    "inverse_dynamics",
    "kinematics",
    "load_model",
    "trajectory_dynamics",
]



class MujocoMachine:
    """A compiled MuJoCo model of the hip simulator and where its parts sit.

    Args:
        model: the ``mujoco.MjModel`` (from :func:`hipsim.mujoco_engine.mjcf.mjcf_text`).
        params: the parameter set it was built from.

    Attributes:
        model: the MjModel.
        params: the parameter set.
        platform_dof: (2, 3) dof (= qpos) indices of platform j's [rx, ry, rz], i.e. [α, β, γ].
        slider_dof: (3,) dof indices of the sliders (the actuated joints, motor order).
        ujoint_anchor: (2, 3) joint ids of the u1 joints (their anchors are b_ji).
        leg_dof: (15,) the leg coordinates (sliders and universal joints).
        closure: (2, 3) equality index of lever ji's closure.
        platform_body, lever_body: body ids, shapes (2,) and (2, 3).
        lead: screw lead p in [m] (gear 2π/p).

    Not thread-safe: each MujocoMachine has one MjData for its computations.
    """

    def __init__(self, model, params: Parameters):
        self.model, self.params = model, params
        if model.nq != model.nv:
            raise ModelError("the hip simulator's MuJoCo model must consist of 1-DoF joints (nq = nv)")

        def joint(name: str) -> int:
            k = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, name)
            if k < 0:
                raise ModelError(f"the MuJoCo model has no joint '{name}'")
            return k

        def body(name: str) -> int:
            k = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, name)
            if k < 0:
                raise ModelError(f"the MuJoCo model has no body '{name}'")
            return k

        self.platform_dof = np.array([[model.jnt_dofadr[joint(f"platform_{j}_r{a}")] for a in "xyz"] for j in (1, 2)])
        if model.nu != 3:
            raise ModelError(f"the hip simulator has three motors, the MuJoCo model {model.nu}")
        self.slider_dof = np.array([model.jnt_dofadr[model.actuator_trnid[i, 0]] for i in range(3)])
        self.ujoint_anchor = np.array([[joint(f"u1_{j}{i}") for i in (1, 2, 3)] for j in (1, 2)])
        self.leg_dof = np.array(sorted(set(range(model.nv)) - set(self.platform_dof.ravel())))
        self.platform_body = np.array([body(f"platform_{j}") for j in (1, 2)])
        self.lever_body = np.array([[body(f"lever_{j}{i}") for i in (1, 2, 3)] for j in (1, 2)])
        if model.neq != 6 or np.any(model.eq_type != mujoco.mjtEq.mjEQ_CONNECT):
            raise ModelError("the hip simulator's MuJoCo model needs its six connect equalities")
        names = [mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_EQUALITY, k) for k in range(model.neq)]
        pairs = [[f"lever_{j}{i}_tip-platform_{j}_joint_{i}" for i in (1, 2, 3)] for j in (1, 2)]
        missing = sorted(set(sum(pairs, [])) - set(names))
        if missing:
            raise ModelError(f"the MuJoCo model has no closure {missing[0]}")
        self.closure = np.array([[names.index(name) for name in row] for row in pairs])
        self.lead = lead_from_ratio(float(model.actuator_gear[0, 0]))
        self.data = mujoco.MjData(model)
        # One model per body group, the other groups massless: mj_rne on it gives that group's share.
        self.group_models = []
        carriages = {model.body_parentid[b] for b in self.lever_body.ravel()}
        members = (set(self.platform_body), set(self.lever_body.ravel()), carriages)
        if set().union(*members) != set(range(1, model.nbody)):
            raise ModelError("every moving body must be a platform, a lever or a carriage")
        for member in members:
            group = copy.deepcopy(model)
            for b in range(1, model.nbody):
                if b not in member:
                    group.body_mass[b] = 0.0
                    group.body_inertia[b] = 0.0
            group.dof_armature[:] = 0.0
            self.group_models.append((group, mujoco.MjData(group)))

    @property
    def nv(self) -> int:
        return self.model.nv

    def place(self, q: np.ndarray, data=None) -> None:
        """Positions, closure rows (efc_pos, efc_J) and the mass matrix at q, in ``data`` (default: the model's own)."""
        data = self.data if data is None else data
        data.qpos[:] = q
        mujoco.mj_fwdPosition(self.model, data)

    def closure_rows(self, data=None) -> tuple[np.ndarray, np.ndarray]:
        """(residual p₁ − p₂ (18,) in [m], Jacobian J_c (18, nv)) of the six closures, after :meth:`place`."""
        data = self.data if data is None else data
        rows = 3 * self.model.neq
        # No contacts and no joint limits: the closures' rows are MuJoCo's whole constraint list.
        if data.nefc != rows:
            raise ModelError(f"MuJoCo's constraint list has {data.nefc} rows, not the closures' {rows}")
        return data.efc_pos.copy(), data.efc_J.reshape(rows, self.model.nv).copy()


def _full_inertia(model, data, out: np.ndarray) -> None:
    """The dense mass matrix M (armature included) into ``out``; MuJoCo 3.x and 4.x spell the call differently."""
    if hasattr(data, "qM"):  # MuJoCo 3.x: mj_fullM(m, dst, M)
        mujoco.mj_fullM(model, out, data.qM)
    else:  # MuJoCo 4: mj_fullM(m, d, dst)
        mujoco.mj_fullM(model, data, out)


def load_model(params: Parameters | None = None, settings=None) -> MujocoMachine:
    """The hip simulator as a compiled MuJoCo model, from one parameter set.

    Args:
        params: the machine, SI; None for the published machine.
        settings: :class:`~hipsim.mujoco_engine.mjcf.MjcfSettings` (time step,
            integrator, closure softness); None for the defaults.
    """
    from .mjcf import compile_mjcf, mjcf_text

    params = load_parameters() if params is None else params
    return MujocoMachine(compile_mjcf(mjcf_text(params, settings, keyframe=False)), params)


def closure_gaps(machine: MujocoMachine, q) -> np.ndarray:
    """|p₁ − p₂| of each closure in [m] at configuration(s) q: shape (6,) or (N, 6), lever order of the equalities."""
    q = np.asarray(q, dtype=float)
    single = q.ndim == 1
    q = np.atleast_2d(q)
    out = np.empty((len(q), machine.model.neq))
    for k, qk in enumerate(q):
        machine.place(qk)
        out[k] = np.linalg.norm(machine.closure_rows()[0].reshape(-1, 3), axis=1)
    return out[0] if single else out


def constraint_jacobian(machine: MujocoMachine, q) -> np.ndarray:
    """MuJoCo's closure Jacobian J_c at q, shape (18, nv): d(p₁ − p₂)/dq in world axes."""
    machine.place(np.asarray(q, dtype=float))
    return machine.closure_rows()[1]


@dataclass(frozen=True, eq=False)
class MujocoKinematics:
    """The closed configuration of the MuJoCo model along a trajectory.

    Attributes:
        t: sample times in [s], (N,).
        q, v, a: qpos, qvel, qacc in [m, rad, s], (N, nv); J_c v = 0 and J_c a + J̇_c v = 0.
        L, Ld, Ldd: height of each universal-joint centre b_ji (MuJoCo's joint
            anchor) in [m], its rate [m/s] and acceleration [m/s²], (N, 2, 3).
        cond_inv: inverse condition number of J = ∂L̇/∂ω (from K⁻¹ and the
            platform's angular Jacobian), (N,).
        residual: largest closure gap of each sample in [m], (N,).
    """

    t: np.ndarray
    q: np.ndarray
    v: np.ndarray
    a: np.ndarray
    L: np.ndarray
    Ld: np.ndarray
    Ldd: np.ndarray
    cond_inv: np.ndarray
    residual: np.ndarray

    def __post_init__(self):
        nv = np.shape(self.q)[1]
        shapes = {"t": ("N",), "q": ("N", nv), "v": ("N", nv), "a": ("N", nv), "L": ("N", 2, 3), "Ld": ("N", 2, 3),
                  "Ldd": ("N", 2, 3), "cond_inv": ("N",), "residual": ("N",)}  # fmt: skip
        check_shapes(self, shapes, samples=len(self.t))


class _Closer:
    """Closes the chain sample after sample with MuJoCo's closure rows."""

    def __init__(self, machine: MujocoMachine, tol: float, max_iter: int):
        self.machine, self.tol, self.max_iter = machine, tol, max_iter
        model = machine.model
        if np.any(model.eq_objtype != mujoco.mjtObj.mjOBJ_SITE):
            raise ModelError("the closures must be site-to-site connect equalities")
        self.K = np.zeros((model.nv, model.nv))
        self.K[np.arange(3), machine.platform_dof[0]] = 1.0
        self.K_inv = None  # K⁻¹ at the last closed sample: the chord steps' Jacobian
        self.platforms = machine.platform_dof.ravel()
        # Both ends of every closure, (site, body), closure after closure; their J̇ stacked.
        self.ends = [(int(site), int(model.site_bodyid[site])) for k in range(model.neq)
                     for site in (model.eq_obj1id[k], model.eq_obj2id[k])]  # fmt: skip
        self.jacdot = np.zeros((len(self.ends), 3, model.nv))

    def _rows(self, q: np.ndarray):
        self.machine.place(q)
        e, J = self.machine.closure_rows()
        return e, J, float(np.abs(e).max())

    def close(self, q: np.ndarray, angles: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """q with both platforms at ``angles`` and the legs moved until the closures hold; its residual and J_c.

        On return MuJoCo's data holds q's positions. Raises ClosureError (with the gap) if the loops cannot close.
        """
        q = q.copy()
        q[self.platforms] = np.tile(angles, 2)
        e, J, gap = self._rows(q)
        if self.K_inv is not None:
            # Chord steps: Newton with the previous sample's K⁻¹ while the gap shrinks tenfold a step.
            for _ in range(6):
                if gap <= self.tol:
                    return q, e, J
                trial = q - self.K_inv[:, 3:] @ e
                trial[self.platforms] = q[self.platforms]
                e_trial, J_trial, gap_trial = self._rows(trial)
                if gap_trial > 0.1 * gap:
                    break
                q, e, J, gap = trial, e_trial, J_trial, gap_trial
        legs, best = self.machine.leg_dof, math.inf
        for _ in range(self.max_iter):
            if gap <= self.tol:
                return q, e, J
            if best < 1e-6 and not gap < 0.5 * best:
                break  # no longer contracting: rounding reached
            best = min(best, gap)
            step, *_ = np.linalg.lstsq(J[:, legs], e, rcond=None)
            q[legs] -= step
            e, J, gap = self._rows(q)
        if gap > 1e3 * self.tol:
            raise ClosureError(f"cannot close the loops: the closure gap stays at {gap:.3g} m (the pose is out of the levers' reach)", gap)
        return q, e, J

    def rates(self, J: np.ndarray, qd: np.ndarray, qdd: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """v and a at the closed q whose positions MuJoCo's data holds; leaves its velocities computed at v."""
        model, data = self.machine.model, self.machine.data
        self.K[3:] = J
        K_inv = _inverse(self.K)
        # K⁻¹ blows up near a singularity (its entries are O(1..10) in m, rad, s elsewhere).
        if K_inv is None or not np.abs(K_inv).max() < 1e8:
            raise ClosureError("singular pose: the closure Jacobian loses rank (spec §3)")
        self.K_inv = K_inv
        v = K_inv[:, :3] @ qd
        data.qvel[:] = v
        mujoco.mj_fwdVelocity(model, data)
        for jacdot, (site, body) in zip(self.jacdot, self.ends):
            mujoco.mj_jacDot(model, data, jacdot, None, data.site_xpos[site], body)
        drift = (self.jacdot[0::2] - self.jacdot[1::2]).reshape(-1, model.nv) @ v
        a = K_inv[:, :3] @ qdd - K_inv[:, 3:] @ drift
        return v, a


def _inverse(matrix: np.ndarray) -> np.ndarray | None:
    """The inverse through LAPACK (np.linalg.inv's checks cost as much again on small matrices); None if singular."""
    lu, pivots, info = lapack.dgetrf(matrix)
    if info != 0:
        return None
    inverse, info = lapack.dgetri(lu, pivots)
    return inverse if info == 0 else None


def kinematics(machine: MujocoMachine, traj, *, tol: float = 1e-13, max_iter: int = 30) -> MujocoKinematics:
    """Close the MuJoCo model's chain along a platform trajectory.

    Args:
        machine: the model from :func:`load_model`.
        traj: a Trajectory-like object: t (N,) in [s]; q, qd, qdd (N, 3) [α, β, γ]
            in [rad], [rad/s], [rad/s²] (the parameter set's angle_signs applied here).
        tol: closure gap accepted in [m] (largest component of p₁ − p₂).
        max_iter: Gauss–Newton iterations allowed per sample.

    Returns:
        The closed configurations, velocities and accelerations, slider motion and singularity measure.

    Raises:
        PoseError: at the first sample whose pose is out of reach or singular.
    """
    return _close(machine, traj, tol, max_iter, Fe=None)[0]


def _close(machine: MujocoMachine, traj, tol: float, max_iter: int, Fe):
    t, q_in, qd_in, qdd_in = trajectory_arrays(traj)
    signs = machine.params.angle_signs
    angles, rates, accels = q_in * signs, qd_in * signs, qdd_in * signs
    model, data = machine.model, machine.data
    n, nv = len(t), model.nv
    Q, V, A = np.empty((n, nv)), np.empty((n, nv)), np.empty((n, nv))
    L = np.empty((n, 2, 3))
    cond_inv, residual = np.empty(n), np.empty(n)
    closer = _Closer(machine, tol, max_iter)
    dynamics = _InverseDynamics(machine, n, Fe) if Fe is not None else None
    jacr = np.zeros((3, nv))
    q = _initial_guess(machine)
    for k in range(n):
        if k > 1:
            h = t[k] - t[k - 1]
            q = Q[k - 1] + h * (V[k - 1] + h * (0.5 * A[k - 1] + h / 6.0 * (A[k - 1] - A[k - 2]) / (t[k - 1] - t[k - 2])))
        elif k == 1:
            h = t[1] - t[0]
            q = Q[0] + h * (V[0] + 0.5 * h * A[0])
        try:
            q, e, J = closer.close(q, angles[k])
            if np.min(data.xmat[machine.lever_body.ravel(), 8]) <= 1e-6:
                raise ClosureError("a lever is horizontal or points down (singular pose, spec §3)")
            v, a = closer.rates(J, rates[k], accels[k])
        except (ClosureError, np.linalg.LinAlgError) as error:
            raise PoseError(str(error), float(t[k]), k, source=getattr(traj, "name", None)) from None
        Q[k], V[k], A[k] = q, v, a
        residual[k] = np.linalg.norm(e.reshape(-1, 3), axis=1).max()
        L[k] = data.xanchor[machine.ujoint_anchor][:, :, 2]
        # J = ∂L̇/∂ω = (∂L̇/∂q̇)·T⁻¹, both from MuJoCo: K⁻¹ gives the first, platform 1's angular Jacobian T.
        mujoco.mj_jacBody(model, data, None, jacr, machine.platform_body[0])
        T = jacr[:, machine.platform_dof[0]]
        G = closer.K_inv[machine.slider_dof, :3]
        singular = np.linalg.svd(G @ _inverse(T), compute_uv=False)
        cond_inv[k] = singular[-1] / singular[0]
        if dynamics is not None:
            dynamics.add(k, q, v, a, J)
    sliders = machine.slider_dof
    kin = MujocoKinematics(
        t=t, q=Q, v=V, a=A, L=L,
        Ld=np.repeat(V[:, None, sliders], 2, axis=1), Ldd=np.repeat(A[:, None, sliders], 2, axis=1),
        cond_inv=cond_inv, residual=residual,
    )  # fmt: skip
    if dynamics is None:
        return kin, None
    # The central chain's friction moment, for the summary: the law of spec §4.3 at the platforms' motion.
    omega = np.einsum("nab,nb->na", angular_velocity_map(angles), rates)
    moment = central_chain_friction(machine.params.friction, machine.params.platform_mass * machine.params.gravity, omega, dynamics.Fe, rotation_matrix(angles))
    dynamics.friction_moment = np.linalg.norm(moment, axis=-1)
    return kin, dynamics.result(kin)


def _initial_guess(machine: MujocoMachine) -> np.ndarray:
    """Levers upright and the carriages so that the m1 levers' tips reach platform 1's height."""
    q = np.zeros(machine.model.nv)
    q[machine.slider_dof] = machine.params.heights[0] - machine.params.lever_length
    return q


# ---------------------------------------------------------------------------
# Inverse dynamics
# ---------------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class MujocoDynamics:
    """Motor torques, their parts and the joint forces of the MuJoCo inverse dynamics.

    Attributes:
        torques: motor torques and their parts in [N·m] (the shared type of every model).
        F_act: actuator force on each carriage in [N], (N, 3).
        lambdas: closure forces (platform on lever ji at a_ji) in world axes in [N], (N, 2, 3, 3).
        joint_forces: force magnitudes at the spherical joints a_ji and through
            platform j's central joint in [N] (weight and load included).
    """

    torques: Torques
    F_act: np.ndarray
    lambdas: np.ndarray
    joint_forces: JointForces

    def __post_init__(self):
        check_shapes(self, {"F_act": ("N", 3), "lambdas": ("N", 2, 3, 3)})


def friction_forces(machine: MujocoMachine, data, Fe: float) -> np.ndarray:
    """The generalised forces friction applies at the state in ``data`` (velocities computed), (nv,).

    Spec §4.3 / §7.3 as forces on the bodies: the central chain's moment
    −ŝ(ω_j)·[r_h μ_h |F_e| + r_t μ_t |F_e + m_m g|] on each platform; the U
    joint's moment (lever relative to its translating carriage) and the S
    joint's (lever relative to the platform; its reaction on the platform) on
    the levers; the slider guides' force and the screw's torque (through the
    lead) on each slider. MuJoCo maps each moment with ``mj_applyFT``. With the
    opposite sign this is what the motors must supply against friction.

    Args:
        machine: the model.
        data: an MjData of ``machine.model`` after ``mj_fwdVelocity`` (or a step).
        Fe: the load in [N].
    """
    model, params = machine.model, machine.params
    fr = params.friction
    eps = fr.epsilon
    out = np.zeros(model.nv)
    velocity = np.empty(6)
    zero = np.zeros(3)

    def omega(body: int) -> np.ndarray:
        mujoco.mj_objectVelocity(model, data, mujoco.mjtObj.mjOBJ_BODY, body, velocity, 0)
        return velocity[:3].copy()

    weight = params.platform_mass * params.gravity
    lever_friction = laws.lever_joint_friction_on(fr)
    for j in range(2):
        platform = machine.platform_body[j]
        w = omega(platform)
        z = data.xmat[platform].reshape(3, 3)[:, 2]  # the platform's z axis, for the axial-only thrust bearing
        moment = -np.array(laws.central_friction_moment(fr, w, z, Fe, weight))
        if lever_friction:
            for i in range(3):
                lever = machine.lever_body[j, i]
                w_l = omega(lever)
                u_moment, s_moment = (np.array(m) for m in laws.lever_joint_friction(fr, w_l, w))
                mujoco.mj_applyFT(model, data, zero, -(u_moment + s_moment), data.xpos[lever], lever, out)
                moment = moment + s_moment
        mujoco.mj_applyFT(model, data, zero, moment, data.xpos[platform], platform, out)
    rate = data.qvel[machine.slider_dof]
    gain = radians_per_travel(machine.lead)
    speed = gain * rate
    out[machine.slider_dof] -= 2.0 * laws.guide_friction(fr, rate, speed) + gain * laws.screw_friction(fr, speed)
    return out


class FrictionForces:
    """:func:`friction_forces` for repeated use, in closed form where it can be.

    Without U- and S-joint friction (the default) the only moments are the
    platforms' central ones, and they map to the platform's own hinges only
    (the base is fixed): Q_k = a_kᵀ·(−load·ŝ(ω_j)) for each hinge axis a_k in
    world axes (MuJoCo's ``xaxis``), ω_j the platform's angular velocity
    (``cvel``), in plain floats. Otherwise the general function.

    Args:
        machine: the model (its params give the coefficients).
    """

    def __init__(self, machine: MujocoMachine):
        self.machine = machine
        params = machine.params
        fr = params.friction
        # The closed form below is the publication's central chain without lever-joint friction; anything else takes the general path.
        self.general = laws.lever_joint_friction_on(fr) or fr.thrust_bearing_axial_only
        self.hip, self.thrust = fr.hip_radius * fr.hip_mu, fr.thrust_radius * fr.thrust_mu
        self.weight, self.eps2 = params.platform_mass * params.gravity, fr.epsilon**2
        self.bodies = machine.platform_body.copy()
        self.dofs = [[int(k) for k in dofs] for dofs in machine.platform_dof]
        # The platform hinges' joints (their world axes, ``xaxis``, are the dofs' rotation axes, ``cdof``).
        self.joints = machine.model.dof_jntid[machine.platform_dof.ravel()]
        self.sliders = [int(k) for k in machine.slider_dof]
        gain = radians_per_travel(machine.lead)
        self.slider_terms = (2.0 * fr.guide_coulomb + gain * fr.screw_coulomb, 2.0 * fr.guide_viscous + gain * gain * fr.screw_viscous, gain)
        self.slider_friction = any(c != 0.0 for c in self.slider_terms[:2])

    def add(self, data, Fe: float, out: np.ndarray) -> None:
        """Add the generalised forces of friction at the state in ``data`` (velocities computed) to ``out`` (nv,)."""
        if self.general:
            out += friction_forces(self.machine, data, Fe)
            return
        load = self.hip * abs(Fe) + self.thrust * abs(Fe + self.weight)
        # Plain floats: element access to numpy arrays costs more than the arithmetic.
        omegas = data.cvel[self.bodies, :3].tolist()
        axes = data.xaxis[self.joints].tolist()
        for (wx, wy, wz), dofs, rows in zip(omegas, self.dofs, ((0, 1, 2), (3, 4, 5))):
            k = -load / math.sqrt(wx * wx + wy * wy + wz * wz + self.eps2)
            for dof, row in zip(dofs, rows):
                ax, ay, az = axes[row]
                out[dof] += k * (ax * wx + ay * wy + az * wz)
        if self.slider_friction:
            # Guides: 2(F_c ŝ + c·L̇); screw: (2π/p)(τ_c ŝ + c_θ·θ̇), θ̇ = (2π/p)·L̇; ŝ on the motor speed.
            coulomb, viscous, gain = self.slider_terms
            qvel = data.qvel
            for dof in self.sliders:
                rate = float(qvel[dof])
                speed = gain * rate
                out[dof] -= coulomb * speed / math.sqrt(speed * speed + self.eps2) + viscous * rate


class _InverseDynamics:
    """Per sample: the five right-hand sides and [Sᵀ J_cᵀ]; solved in one batch at the end."""

    def __init__(self, machine: MujocoMachine, n: int, Fe):
        self.machine = machine
        nv = machine.nv
        self.Fe = np.broadcast_to(np.asarray(Fe, dtype=float), (n,))
        # The central chain's friction moment needs the platform motion, which _close fills in; NaN where unknown.
        self.friction_moment = np.full(n, np.nan)
        self.system = np.zeros((n, nv, nv))
        self.system[:, machine.slider_dof, np.arange(3)] = 1.0
        self.rhs = np.empty((n, nv, 5))  # [platforms, levers, carriages, screws, friction]
        self.total = np.empty((n, nv))  # M a + bias, from MuJoCo's M and qfrc_bias
        self.M = np.empty((nv, nv))
        self.rne = np.empty(nv)
        self.friction = FrictionForces(machine)

    def add(self, k: int, q, v, a, J) -> None:
        machine = self.machine
        model, data = machine.model, machine.data  # positions and velocities are computed at (q, v)
        _full_inertia(model, data, self.M)
        self.total[k] = self.M @ a + data.qfrc_bias
        for g, (group_model, group_data) in enumerate(machine.group_models):
            group_data.qpos[:], group_data.qvel[:], group_data.qacc[:] = q, v, a
            mujoco.mj_kinematics(group_model, group_data)
            mujoco.mj_comPos(group_model, group_data)
            mujoco.mj_comVel(group_model, group_data)
            mujoco.mj_rne(group_model, group_data, 1, self.rne)
            self.rhs[k, :, g] = self.rne
        self.rhs[k, :, 3] = model.dof_armature * a
        friction = self.rhs[k, :, 4]
        friction[:] = 0.0
        self.friction.add(data, float(self.Fe[k]), friction)
        friction *= -1.0
        self.system[k, :, 3:] = J.T

    def result(self, kin: MujocoKinematics) -> MujocoDynamics:
        machine, params = self.machine, self.machine.params
        solution = np.linalg.solve(self.system, self.rhs)  # (n, nv, 5)
        gain = travel_per_radian(machine.lead)
        tau_m, tau_l, tau_s, tau_L, tau_f = np.moveaxis(gain * solution[:, :3], 2, 0)
        # The total from MuJoCo's own M and bias (the parts above from the group models add up to it).
        tau = gain * np.linalg.solve(self.system, (self.total + self.rhs[:, :, 4])[..., None])[:, :3, 0]
        lambdas = solution[:, 3:].sum(axis=2).reshape(len(kin.t), -1, 3)[:, machine.closure]  # (n, 2, 3, 3)
        centre = lambdas.sum(axis=2)
        centre[:, :, 2] += params.platform_mass * params.gravity + self.Fe[:, None]
        motor_speed = radians_per_travel(machine.lead) * kin.Ld[:, 0]
        torques = Torques(
            total=tau, platforms=tau_m, levers=tau_l, sliders=tau_s, screws=tau_L, friction=tau_f,
            motor_speed=motor_speed, friction_moment=self.friction_moment,
            # By virtual power the motors' friction share times their speed is the whole friction loss.
            friction_power=np.sum(tau_f * motor_speed, axis=1),
        )
        joint_forces = JointForces(Fa=np.linalg.norm(lambdas, axis=-1), Fo=np.linalg.norm(centre, axis=-1))
        return MujocoDynamics(torques=torques, F_act=tau / gain, lambdas=lambdas, joint_forces=joint_forces)


def inverse_dynamics(machine: MujocoMachine, kin: MujocoKinematics, Fe) -> MujocoDynamics:
    """Motor torques (with their parts) and joint forces along a closed motion, with MuJoCo.

    Args:
        machine: the model from :func:`load_model`.
        kin: the closed motion from :func:`kinematics` (of this model).
        Fe: load in [N], (N,) or a scalar.
    """
    dynamics = _InverseDynamics(machine, len(kin.t), Fe)
    model, data = machine.model, machine.data
    for k in range(len(kin.t)):
        machine.place(kin.q[k])
        data.qvel[:] = kin.v[k]
        mujoco.mj_fwdVelocity(model, data)
        dynamics.add(k, kin.q[k], kin.v[k], kin.a[k], machine.closure_rows()[1])
    return dynamics.result(kin)


def trajectory_dynamics(machine: MujocoMachine, traj, *, tol: float = 1e-13, max_iter: int = 30):
    """:func:`kinematics` and :func:`inverse_dynamics` in one pass, with the trajectory's own load."""
    return _close(machine, traj, tol, max_iter, Fe=traj.Fe)


class MujocoModel:
    """The MuJoCo engine behind the common model protocol: ``MujocoModel(params).run(trajectory) -> Run``.

    Slider motion, singularity measure, torques and joint forces all come from
    MuJoCo: M and bias from MuJoCo, the rigid closure solved with its
    constraint Jacobian, friction as applied forces (the laws of
    :mod:`hipsim.physics.laws`).

    Args:
        params: the machine.
        machine: ``load_model(params)`` for these very params, to skip building it.
    """

    name = "mujoco"

    def __init__(self, params: Parameters, machine: MujocoMachine | None = None):
        if machine is not None and machine.params is not params:
            raise ArgumentError("machine", machine, "load_model(params) of the same params object")
        self.params = params
        self.machine = load_model(params) if machine is None else machine

    def run(self, trajectory) -> Run:
        """Closed kinematics and inverse dynamics along ``trajectory``.

        Raises:
            PoseError: at the first sample out of reach or singular.
        """
        kin, dynamics = trajectory_dynamics(self.machine, trajectory)
        return Run(
            self.name, self.params, trajectory, kin.L, kin.Ld, kin.Ldd, dynamics.torques, kin.cond_inv,
            np.zeros(len(trajectory.t), dtype=bool), joint_forces=dynamics.joint_forces,
        )
