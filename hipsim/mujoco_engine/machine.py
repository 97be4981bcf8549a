"""The compiled MuJoCo model of the machine and where its parts sit; its closure rows.

:class:`MujocoMachine` wraps a ``mujoco.MjModel`` built from the MJCF of
:mod:`hipsim.mujoco_engine.mjcf`: the indices of the platforms' angle
coordinates, the sliders, the universal joints and the six ``connect``
closures, one massive copy per body group (for the torque parts of
:mod:`~hipsim.mujoco_engine.dynamics`), and the closure residual and Jacobian
J_c read from MuJoCo's constraint rows (``efc_pos``, ``efc_J`` after
``mj_fwdPosition``).

Sign conventions: the connect rows are the derivative of p₁ − p₂ (world
axes), p₁ the lever tip, p₂ the platform joint.
"""

from __future__ import annotations

import copy

import numpy as np

from ..exceptions import ModelError
from ..machine.chains import STACKUP_CLOSURE, STACKUP_JOINTS
from ..machine.parameters import Parameters
from ..physics.transmission import lead_from_ratio
from ._dependency import mujoco

__all__ = ["PLACEHOLDER_MASS", "STACKUP_BODIES", "MujocoMachine", "closure_gaps", "constraint_jacobian"]

#: The stack-up's massless links that carry no single moving body (:func:`hipsim.machine.chains.per_chain_urdf`):
#: the spline's slide (m_1 and the shaft's end hang from it) and the shaft end's slides (only the seat's frame).
STACKUP_BODIES = ("spline_1", "spline_1_slide_y")
#: The mass MuJoCo is given for each of :data:`STACKUP_BODIES`, in [kg] (it refuses a moving body without one);
#: the inverse dynamics take it out again (:attr:`MujocoMachine.placeholders`).
PLACEHOLDER_MASS = 1e-6


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
        stacked = params.chains.stacked
        if model.neq != 6 + stacked or np.any(model.eq_type != mujoco.mjtEq.mjEQ_CONNECT):
            raise ModelError(
                "the hip simulator's MuJoCo model needs its six connect equalities (seven with a stack-up)"
            )
        names = [mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_EQUALITY, k) for k in range(model.neq)]
        pairs = [[f"lever_{j}{i}_tip-platform_{j}_joint_{i}" for i in (1, 2, 3)] for j in (1, 2)]
        seat = ["{}-{}".format(*STACKUP_CLOSURE)] if stacked else []
        missing = sorted(set(sum(pairs, seat)) - set(names))
        if missing:
            raise ModelError(f"the MuJoCo model has no closure {missing[0]}")
        self.closure = np.array([[names.index(name) for name in row] for row in pairs])
        self.lead = lead_from_ratio(float(model.actuator_gear[0, 0]))
        self.data = mujoco.MjData(model)
        # One model per body group, the other groups massless: mj_rne on it gives that group's share.
        #: With a stack-up, the dof of the spline's axial slide (m_1's centre rides it: the load F_e acts on it), else None.
        self.stackup_dof = model.jnt_dofadr[joint(STACKUP_JOINTS[0])] if stacked else None
        #: The stack-up's bodies of PLACEHOLDER_MASS (empty without a stack-up).
        self.placeholders = {body(name) for name in STACKUP_BODIES} if stacked else set()
        if stacked:
            # MuJoCo scales a closure row's softness by a per-body mean mobility (body_invweight0): the shaft end's,
            # 1/(3·1 mg) from its light horizontal slides, would make the seat's vertical row, which lifts m_1, some
            # 1e6 times too soft. It moves vertically with m_1's slide: that body's mobility is the right scale.
            model.body_invweight0[body(STACKUP_BODIES[1]), 0] = model.body_invweight0[body(STACKUP_BODIES[0]), 0]
        self.group_models = []
        carriages = {model.body_parentid[b] for b in self.lever_body.ravel()}
        members = (set(self.platform_body), set(self.lever_body.ravel()), carriages)
        if set().union(*members) | self.placeholders != set(range(1, model.nbody)):
            raise ModelError("every moving body must be a platform, a lever or a carriage")
        #: The placeholder bodies' own model (the others massless), whose mj_rne the inverse dynamics take out; None without.
        self.placeholder_model = None
        for member in (*members, self.placeholders) if stacked else members:
            group = copy.deepcopy(model)
            for b in range(1, model.nbody):
                if b not in member:
                    group.body_mass[b] = 0.0
                    group.body_inertia[b] = 0.0
            group.dof_armature[:] = 0.0
            if member is self.placeholders:
                self.placeholder_model = (group, mujoco.MjData(group))
            else:
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
