"""The MuJoCo model's rigid inverse dynamics: motor torques, their parts and the joint forces.

``mj_inverse`` is not used on purpose. MuJoCo's constraints are soft (a
regularised, Baumgarte-like reference acceleration), so the constraint forces
it reports are not the rigid closure's multipliers. Instead the tree's
generalised forces τ = M(q)·a + c(q, v) come from MuJoCo's M (``mj_fullM``,
armature included) and bias (``qfrc_bias``), and the rigid closure is solved
exactly: [Sᵀ  J_cᵀ]·[F; λ] = τ − Q_f, with S the three actuated slider
columns, J_c MuJoCo's constraint Jacobian and Q_f the friction forces of
:mod:`~hipsim.mujoco_engine.friction`. The torque parts of spec §4.4 come from
one solve with five right-hand sides: the bias and inertia of each body group
(platforms, levers, carriages) from ``mj_rne`` on a copy of the model in which
only that group has mass, the screws' armature·a, and the friction. They add
up to the total to rounding.

λ_ji is the force the platform exerts on lever ji at a_ji, in world axes.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..arrays import check_shapes
from ..physics.transmission import radians_per_travel, travel_per_radian
from ..results import JointForces, Torques
from ._dependency import mujoco
from .closure import MujocoKinematics
from .friction import FrictionForces
from .machine import MujocoMachine

__all__ = ["MujocoDynamics", "inverse_dynamics"]


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


def _full_inertia(model, data, out: np.ndarray) -> None:
    """The dense mass matrix M (armature included) into ``out``; MuJoCo 3.x and 4.x spell the call differently."""
    if hasattr(data, "qM"):  # MuJoCo 3.x: mj_fullM(m, dst, M)
        mujoco.mj_fullM(model, out, data.qM)
    else:  # MuJoCo 4: mj_fullM(m, d, dst)
        mujoco.mj_fullM(model, data, out)


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
        for g, group in enumerate(machine.group_models):
            self.rhs[k, :, g] = self._rne(group, q, v, a)
        if machine.placeholder_model is not None:  # the stack-up's placeholder masses out, the load on m_1's slide in
            self.total[k] -= self._rne(machine.placeholder_model, q, v, a)
            self.total[k, machine.stackup_dof] += self.Fe[k]
            self.rhs[k, machine.stackup_dof, 0] += self.Fe[k]
        self.rhs[k, :, 3] = model.dof_armature * a
        friction = self.rhs[k, :, 4]
        friction[:] = 0.0
        self.friction.add(data, float(self.Fe[k]), friction)
        friction *= -1.0
        self.system[k, :, 3:] = J.T

    def _rne(self, group, q, v, a) -> np.ndarray:
        """M·a + bias of one body group's model (``mj_rne``) at (q, v, a), (nv,) (a view, overwritten by the next call)."""
        group_model, group_data = group
        group_data.qpos[:], group_data.qvel[:], group_data.qacc[:] = q, v, a
        mujoco.mj_kinematics(group_model, group_data)
        mujoco.mj_comPos(group_model, group_data)
        mujoco.mj_comVel(group_model, group_data)
        mujoco.mj_rne(group_model, group_data, 1, self.rne)
        return self.rne

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
        if machine.stackup_dof is not None:  # m_1's centre rides the spline: its weight's share accelerates with it
            centre[:, 0, 2] += params.platform_mass * kin.a[:, machine.stackup_dof]
        motor_speed = radians_per_travel(machine.lead) * kin.Ld[:, 0]
        torques = Torques(
            total=tau,
            platforms=tau_m,
            levers=tau_l,
            sliders=tau_s,
            screws=tau_L,
            friction=tau_f,
            motor_speed=motor_speed,
            friction_moment=self.friction_moment,
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
