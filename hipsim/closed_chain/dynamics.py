"""The closed-chain inverse dynamics with Pinocchio (spec §6): motor torques by part and joint forces.

The tree's generalised forces by part, each exact — RNEA of the tree with
only one group of bodies' inertias (platforms, levers, carriages; RNEA is
linear in them for a fixed motion, gravity included), the armature term for
the screws, and the friction generalised forces of spec §4.3 / §7.3
(:mod:`~hipsim.closed_chain.friction`) — then, per sample, the actuator
forces of Sᵀ F + J_cᵀ λ = τ from the K⁻¹ the kinematics computed (a 3×3
solve: see :func:`hipsim.closed_chain.closure_kernel.actuator_and_closure_forces`).
The parts therefore add up to the total to rounding. The tree's torques are
computed for a whole chunk of samples at once
(:class:`~hipsim.closed_chain.rnea.BatchedRNEA`).
:func:`trajectory_dynamics` runs the kinematics (:mod:`~hipsim.closed_chain.closure`)
and the dynamics in one pass, reusing the Jacobians.

Sign conventions: λ_ji is the force the platform exerts on lever ji at a_ji,
in the lever-tip frame (the lever exerts −λ on the platform).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from ..arrays import check_shapes
from ..exceptions import PoseError
from ..machine.parameters import load_parameters
from ..physics import laws
from ..physics.friction import central_chain_friction
from ..physics.orientation import angular_velocity_map, rotation_matrix
from ..physics.transmission import angle_from_travel, travel_per_radian
from ..results import JointForces, Torques
from . import closure_kernel
from .build import ClosedChainModel, load_model, require_layout, require_params
from .closure import ClosedKinematics, Closer, Continuation, close_chain
from .friction import friction_from_jacobians, platform_frames, platform_z_axes
from .workspace import Workspace

__all__ = ["ClosedChainDynamics", "inverse_dynamics", "trajectory_dynamics", "warm_up"]

# Samples per batch of the inverse-dynamics solve: bounds the memory of the
# stacked (n, 21, 21) K⁻¹ while keeping the batched RNEA and solve efficient.
_CHUNK = 512


@dataclass(frozen=True, eq=False)
class ClosedChainDynamics:
    """Motor torques and joint forces of the closed-chain inverse dynamics.

    Attributes:
        torques: motor torques and their parts in [N·m] (the shared type of every model).
        F_act: actuator force on each carriage in [N], shape (N, 3)
            (total torque = p/2π · F_act).
        lambdas: closure forces in [N], shape (N, 2, 3, 3): the force the
            platform exerts on lever ji at a_ji, in the lever-tip frame.
        joint_forces: force magnitudes at the spherical joints a_ji and the
            central joints o_j in [N] (load F_e included, see :func:`inverse_dynamics`).
    """

    torques: Torques
    F_act: np.ndarray
    lambdas: np.ndarray
    joint_forces: JointForces

    def __post_init__(self):
        check_shapes(self, {"F_act": ("N", 3), "lambdas": ("N", 2, 3, 3)})


class _InverseDynamics:
    """Closure data sample by sample; the tree's torques and the closed-chain solve a chunk of samples at a time.

    The caller fills q, v and a (shape (n, nv)) up to sample k, has
    ``closure_kernel.store`` keep sample k's K⁻¹ (K = [P₁; J_c], see
    :mod:`hipsim.closed_chain.closure_kernel`) and joint Jacobians where
    :meth:`keep` says (``closure_kernel.closed_sample`` does), then calls
    :meth:`stored` for k with the workspace still placed at sample k.

    The solve. With N = K⁻¹[:, :3] (tree velocities per platform angle rate:
    J_c N = 0) and G = S N (the actuated joints' rates per platform angle
    rate), the actuator forces F of Sᵀ F + J_cᵀ λ = τ follow from projecting
    on the motions the closures allow, Gᵀ F = Nᵀ τ (3×3), and the closure
    forces from the rest, λ = (K⁻ᵀ (τ − Sᵀ F))[3:] (the first three
    components vanish, as τ − Sᵀ F lies in the range of J_cᵀ). The same
    solution as the full 21×21 system's, from the K⁻¹ the kinematics computed.
    """

    def __init__(self, chain: ClosedChainModel, q: np.ndarray, v: np.ndarray, a: np.ndarray, Fe, parts: bool = True):
        self.chain, self.layout, self.model = chain, require_layout(chain), chain.model
        self.parts_asked = bool(parts)
        # The whole tree (armature included) for the total, or one tree per body group for the parts.
        self.rneas = chain.solver.rneas(parts)  # this thread's, kept from run to run
        self.q, self.v, self.a = q, v, a
        n, nv = len(v), chain.model.nv
        self.Fe = np.broadcast_to(np.asarray(Fe, dtype=float), (n,))
        self.params = require_params(chain)
        self.lever_friction = laws.lever_joint_friction_on(self.params.friction)
        # The axial-only thrust bearing needs each platform's z axis, read from the placements.
        self.platform_frames = platform_frames(chain) if self.params.friction.thrust_bearing_axial_only else None
        size = min(_CHUNK, n)
        self.K_inv = np.empty((size, nv, nv))
        # Generalised forces of [platforms, levers, carriages, screws, friction], or of all at once without parts.
        self.rhs = np.empty((5 if parts else 1, size, nv))
        # Angular rows of the world-frame joint Jacobians: a body's ω is their sum over its support.
        self.angular = np.empty((size, 3, nv))
        self.platform_z = np.empty((size, 2, 3)) if self.platform_frames is not None else None
        self.parts = np.empty((n, 3, 5 if parts else 1))  # actuator forces per part (or their sum)
        self.lambdas = np.empty((n, chain.n_closures, 3))
        self.rotations = np.empty((n, chain.n_closures, 3, 3))
        self.start = 0

    def keep(self, k: int) -> tuple:
        """Where closure_kernel.store keeps sample k: ``(K_invs, angular, rotations, slot)``."""
        return self.K_inv, self.angular, self.rotations, k - self.start

    def stored(self, k: int, ws: Workspace) -> None:
        """Sample k is kept (closure_kernel.store, with the workspace still placed at it): solve the chunk once it is full."""
        slot = k - self.start
        if self.platform_z is not None:
            self.platform_z[slot] = platform_z_axes(ws.data, self.platform_frames)
        if slot + 1 == len(self.K_inv) or k + 1 == len(self.v):
            self._solve(k + 1)

    def _solve(self, stop: int) -> None:
        start, m, layout = self.start, stop - self.start, self.layout
        q, v, a = self.q[start:stop], self.v[start:stop], self.a[start:stop]
        rhs, angular, K_inv = self.rhs[:, :m], self.angular[:m], self.K_inv[:m]
        # The tree's torques, all samples of the chunk in one call per body group (RNEA is
        # linear in the bodies' inertias: the groups' torques add up to the whole tree's).
        for rnea, out in zip(self.rneas, rhs):
            rnea(q, v, a, out)
        platform_J = np.moveaxis(angular[:, :, layout.platform_v], 1, 2)  # (m, j, xyz, joint)
        lever_J = np.moveaxis(angular[:, :, layout.ujoint_v], 1, 3) if self.lever_friction else None
        platform_z = self.platform_z[:m] if self.platform_z is not None else None
        friction = friction_from_jacobians(self.chain, v, self.Fe[start:stop], platform_J, lever_J, platform_z)
        if self.parts_asked:
            rhs[3] = self.model.armature * a
            rhs[4] = friction
        else:
            rhs[0] += friction
        if layout.stackup_v.size:
            # The load presses m_1's centre down, which rides the spline's slide now: −F_e on that coordinate, to
            # be balanced (counted with the platforms, as the analytic model counts it).
            rhs[0][:, layout.stackup_v[0]] += self.Fe[start:stop]
        tau = np.moveaxis(rhs, 0, 2)  # (m, nv, parts)
        closure_kernel.actuator_and_closure_forces(
            K_inv, tau, self.chain.actuated_v, self.parts[start:stop], self.lambdas[start:stop].reshape(m, -1)
        )
        self.start = stop

    def result(self, kin: ClosedKinematics) -> ClosedChainDynamics:
        params, closure = self.params, self.layout.closure
        if self.parts_asked:
            tau_m, tau_l, tau_s, tau_L, tau_f = np.moveaxis(travel_per_radian(self.chain.lead) * self.parts, 2, 0)
            total = tau_m + tau_l + tau_s + tau_L + tau_f
        else:  # not computed: NaN, so that no one reads a zero as a part
            total = travel_per_radian(self.chain.lead) * self.parts[:, :, 0]
            tau_m = tau_l = tau_s = tau_L = tau_f = np.full_like(total, np.nan)
        motor_speed = angle_from_travel(kin.Ld[:, 0], self.chain.lead)
        omega = np.einsum("nab,nb->na", angular_velocity_map(kin.angles), kin.angle_rates)
        lambdas = self.lambdas[:, closure]  # (n, 2, 3, 3)
        # Platform j: its centre is fixed, so the central joint balances the levers, weight and load.
        centre = np.einsum("nkab,nkb->nka", self.rotations, self.lambdas)[:, closure].sum(axis=2)
        centre[:, :, 2] += params.platform_mass * params.gravity + self.Fe[:, None]
        if self.layout.stackup_v.size:  # m_1's centre rides the spline: its weight's share accelerates with it
            centre[:, 0, 2] += params.platform_mass * self.a[:, self.layout.stackup_v[0]]
        torques = Torques(
            total=total,
            platforms=tau_m,
            levers=tau_l,
            sliders=tau_s,
            screws=tau_L,
            friction=tau_f,
            motor_speed=motor_speed,
            friction_moment=np.linalg.norm(
                central_chain_friction(
                    params.friction, params.platform_mass * params.gravity, omega, self.Fe, rotation_matrix(kin.angles)
                ),
                axis=-1,
            ),
            # By virtual power the motors' friction share times their speed is the whole friction loss.
            friction_power=np.sum(tau_f * motor_speed, axis=1),
        )
        joint_forces = JointForces(Fa=np.linalg.norm(lambdas, axis=-1), Fo=np.linalg.norm(centre, axis=-1))
        return ClosedChainDynamics(
            torques=torques, F_act=self.parts.sum(axis=2), lambdas=lambdas, joint_forces=joint_forces
        )


def inverse_dynamics(chain: ClosedChainModel, kin: ClosedKinematics, Fe, *, parts: bool = True) -> ClosedChainDynamics:
    """Motor torques (with their parts) and joint forces along a closed motion, with Pinocchio.

    The tree's generalised forces are split exactly into parts: RNEA of the
    tree with only one body group's inertias (platforms, levers, carriages;
    RNEA is linear in the inertial parameters for a fixed motion, gravity
    included), armature·a for the screws, and the
    friction generalised forces of spec §4.3 at their joints (central-chain
    moment on each platform along ŝ(ω_j); U- and S-joint moments on the
    levers, S also on the platform; slider-guide forces and the screw's
    motor-side friction mapped to the carriage). One solve of
    Sᵀ F + J_cᵀ λ = τ for all parts then gives each part's actuator force, so
    the parts add up to the total to rounding.

    Platform j's central joint force: the platform's centre does not
    accelerate, so F_o,j = Σ_i λ_ji (in world axes: minus the levers' forces on
    the platform) + (m_m g + F_e) ẑ, i.e. the joint also carries the
    platform's weight and the load F_e, which presses down through the
    centre of both platforms (spec §1, §4.3; the spring that carries m_1's
    weight is ignored, as in the friction model).

    Args:
        chain: the hip model from :func:`~hipsim.closed_chain.build.load_model`.
        kin: the closed motion from :func:`~hipsim.closed_chain.closure.kinematics`.
        Fe: hydraulic load magnitude in [N], shape (N,) (or a scalar).
        parts: split the torques into their parts (three body-group RNEAs
            per sample, batched); False: the total only, from one RNEA of the
            whole tree, with the parts and the friction power NaN (the joint
            forces are computed either way).

    Returns:
        Torques in [N·m], forces in [N].
    """
    dynamics = _InverseDynamics(chain, kin.q, kin.v, kin.a, Fe, parts)
    # The solver's own per-sample call, at configurations closed already: its velocities and
    # accelerations go to by-product arrays, what the dynamics reuse is kept as in a solver run.
    closer = Closer(chain, tol=math.inf, max_iter=0)
    ws, n, nv = closer.ws, len(kin.q), chain.model.nv
    V, A, J_rates, residual = np.empty((1, nv)), np.empty((1, nv)), np.empty((n, 3, 3)), np.empty(n)
    # Writable C-ordered copies, as the solver passes its own: a kinematics result's read-only arrays would
    # compile closed_sample a second time (about 4 s of CPU in a fresh process).
    rates, accels = np.array(kin.angle_rates, order="C"), np.array(kin.angle_accels, order="C")
    for k, q in enumerate(kin.q):
        pin.computeJointJacobians(ws.model, ws.data, q)
        status, _ = closure_kernel.closed_sample(
            *ws.frame_arguments(),
            math.inf,
            *closer.constants,
            rates,
            accels,
            V,
            A,
            0,
            J_rates,
            residual,
            k,
            closer.K_inv,
            *dynamics.keep(k),
        )
        if status != closure_kernel.OK:
            raise PoseError("singular pose: the closure Jacobian loses rank (spec §3)", float(kin.t[k]), k)
        dynamics.stored(k, ws)
    return dynamics.result(kin)


def warm_up() -> None:
    """Load the closure solver's compiled kernels now: on a machine's first run numba compiles them (some 7 s).

    Closes the published machine's chain at three samples of the ISO cycle,
    with the inverse dynamics, so that every kernel is loaded with the
    argument types a real run passes. Callers use it to say "compiling"
    before a run whose progress would otherwise stall on it.
    """
    from ..motion.trajectories import iso14242_at

    trajectory_dynamics(load_model(load_parameters()), iso14242_at(np.array([0.0, 0.001, 0.002])))


def trajectory_dynamics(
    chain: ClosedChainModel,
    traj,
    *,
    tol: float = 1e-12,
    max_iter: int = 50,
    parts: bool = True,
    continuation: Continuation | None = None,
) -> tuple[ClosedKinematics, ClosedChainDynamics]:
    """:func:`~hipsim.closed_chain.closure.kinematics` and :func:`inverse_dynamics` in one pass, with the trajectory's own load.

    Faster than the two calls: the dynamics reuse the Jacobians the
    kinematics computed at each closed configuration.

    Args:
        chain: the hip model from :func:`~hipsim.closed_chain.build.load_model`.
        traj: a Trajectory-like object with t, q, qd, qdd (see
            :func:`~hipsim.closed_chain.closure.kinematics`) and Fe (N,) in [N].
        tol: closure gap accepted in [m], as in :func:`~hipsim.closed_chain.closure.kinematics`.
        max_iter: damped Gauss–Newton iterations allowed per sample.
        parts: split the torques into their parts (as :func:`inverse_dynamics`).
        continuation: for a run in pieces, one :class:`~hipsim.closed_chain.closure.Continuation` passed to
            every piece in time order: the pieces then give the one-piece
            results bit for bit.

    Returns:
        The closed motion and the torques.
    """
    Fe = traj.Fe

    def dynamics_for(q: np.ndarray, v: np.ndarray, a: np.ndarray) -> _InverseDynamics:
        return _InverseDynamics(chain, q, v, a, Fe, parts)

    return close_chain(chain, traj, tol, max_iter, dynamics_for, continuation)
