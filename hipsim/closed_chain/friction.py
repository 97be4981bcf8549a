"""The friction laws of spec §4.3 / §7.3 as generalised forces of the closed-chain tree.

The laws are :mod:`hipsim.physics.laws`'; here they act on the tree's own
body motions, mapped to its joints by Pinocchio's Jacobians. The inverse
dynamics (:mod:`~hipsim.closed_chain.dynamics`) adds them to the tree's
torques; the plant (:mod:`~hipsim.closed_chain.plant`) subtracts them.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from ..exceptions import ArgumentError
from ..physics import laws
from ..physics.transmission import radians_per_travel
from ..physics.vectors import stack
from .build import ClosedChainModel, require_layout, require_params
from .constraints import configurations

__all__ = ["friction_forces", "friction_from_jacobians", "platform_frames", "platform_z_axes"]


def platform_frames(chain: ClosedChainModel) -> list:
    """The frames of the platforms' bodies, platform 1 first."""
    model = chain.model
    return [model.frames[model.getFrameId(f"platform_{j}")] for j in (1, 2)]


def platform_z_axes(data, frames) -> np.ndarray:
    """The platforms' z axes in world axes, (2, 3), from the joint placements in ``data``."""
    return np.array([data.oMi[frame.parentJoint].rotation @ frame.placement.rotation[:, 2] for frame in frames])


def friction_from_jacobians(chain: ClosedChainModel, v, Fe, platform_J, lever_J, platform_z=None) -> np.ndarray:
    """Generalised forces the actuators must supply against friction, shape (n, nv) (spec §4.3, §7.3).

    The friction laws are :mod:`hipsim.physics.laws`'; here they act on the
    tree's own body motions, mapped to its joints by Pinocchio's Jacobians.
    platform_J: (n, 2, 3, 3) angular Jacobians of the platforms on their own
    joints [rx, ry, rz]; lever_J: (n, 2, 3, 3, 2) of the levers on [u1, u2],
    or None when the U and S joints are frictionless; platform_z: (n, 2, 3)
    the platforms' z axes, needed only by the axial-only thrust bearing.
    """
    params, layout = require_params(chain), require_layout(chain)
    fr = params.friction
    n = len(v)
    Q = np.zeros((n, chain.model.nv))

    # Central chain: hip joint and thrust bearing, a moment on platform j. Components first: (xyz, n, j).
    omega = np.moveaxis(np.einsum("njab,njb->nja", platform_J, v[:, layout.platform_v]), -1, 0)
    z = None if platform_z is None else np.moveaxis(platform_z, -1, 0)
    moment = stack(laws.central_friction_moment(fr, omega, z, Fe[:, None], params.platform_mass * params.gravity))
    if lever_J is not None:
        omega_lever = np.moveaxis(
            np.einsum("njiab,njib->njia", lever_J, v[:, layout.ujoint_v]), -1, 0
        )  # (xyz, n, j, i)
        # U joint: the lever relative to the slider; S joint: relative to the platform, and oppositely on it.
        u_moment, s_moment = (stack(m) for m in laws.lever_joint_friction(fr, omega_lever, omega[..., None]))
        moment -= s_moment.sum(axis=-1)
        Q[:, layout.ujoint_v] += np.einsum("njiab,anji->njib", lever_J, u_moment + s_moment)
    Q[:, layout.platform_v] += np.einsum("njab,anj->njb", platform_J, moment)

    # Slider guides (two per carriage) and the screw on the motor shaft, as carriage forces.
    Ld = v[:, layout.slider_v]
    motor_speed = radians_per_travel(chain.lead) * Ld
    guide = 2.0 * laws.guide_friction(fr, Ld, motor_speed)
    screw = laws.screw_friction(fr, motor_speed)
    Q[:, layout.slider_v] += guide + radians_per_travel(chain.lead) * screw
    return Q


def friction_forces(chain: ClosedChainModel, q, v, Fe, data=None) -> np.ndarray:
    """Generalised forces the actuators must supply against friction at (q, v) (spec §4.3, §7.3).

    The law :func:`~hipsim.closed_chain.dynamics.inverse_dynamics` adds to the tree's torques: in a
    forward simulation they enter with the opposite sign,
    M a + h = S F − friction_forces + J_cᵀ λ.

    Args:
        chain: the hip model from :func:`~hipsim.closed_chain.build.load_model`.
        q: configuration (nq,) or configurations (N, nq).
        v: velocities, same leading shape, (nv,) or (N, nv).
        Fe: hydraulic load magnitude in [N], a scalar or (N,).
        data: a ``pin.Data`` of ``chain.model`` to compute in (its kinematics are
            overwritten); None to make one.

    Returns:
        Shape (nv,) or (N, nv), in [N] on the sliders and [N·m] on the revolute joints.
    """
    layout = require_layout(chain)
    q, single = configurations(chain, q)
    v = np.atleast_2d(np.asarray(v, dtype=float))
    if v.shape != (len(q), chain.model.nv):
        raise ArgumentError("v", v, f"velocities of shape {(len(q), chain.model.nv)}")
    Fe = np.broadcast_to(np.asarray(Fe, dtype=float), (len(q),))
    model = chain.model
    data = model.createData() if data is None else data
    angular = np.empty((len(q), 3, model.nv))
    fr = require_params(chain).friction
    axial = fr.thrust_bearing_axial_only
    frames = platform_frames(chain) if axial else None
    platform_z = np.empty((len(q), 2, 3)) if axial else None
    for k, qk in enumerate(q):
        pin.computeJointJacobians(model, data, qk)
        angular[k] = data.J[3:]
        if platform_z is not None:  # the axial-only bearing
            platform_z[k] = platform_z_axes(data, frames)
    platform_J = np.moveaxis(angular[:, :, layout.platform_v], 1, 2)
    lever_J = np.moveaxis(angular[:, :, layout.ujoint_v], 1, 3) if laws.lever_joint_friction_on(fr) else None
    out = friction_from_jacobians(chain, v, Fe, platform_J, lever_J, platform_z)
    return out[0] if single else out
