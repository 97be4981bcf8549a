"""The generalised forces of friction on the MuJoCo model (spec §4.3 / §7.3), applied as external forces.

The laws are :mod:`hipsim.physics.laws`'; MuJoCo maps each moment onto the
generalised coordinates with ``mj_applyFT``, which is how a MuJoCo user would
add them. :class:`FrictionForces` gives the same in closed form where it can,
for the inverse dynamics' samples and the plant's steps.
"""

from __future__ import annotations

import math

import numpy as np

from ..physics import laws
from ..physics.transmission import radians_per_travel
from ._dependency import mujoco
from .machine import MujocoMachine

__all__ = ["FrictionForces", "friction_forces"]


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
        self.slider_terms = (
            2.0 * fr.guide_coulomb + gain * fr.screw_coulomb,
            2.0 * fr.guide_viscous + gain * gain * fr.screw_viscous,
            gain,
        )
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
