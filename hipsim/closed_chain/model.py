"""The machine as a Pinocchio closed-chain model (spec §6): kinematics and inverse dynamics.

The kinematic tree comes from the URDF that :mod:`hipsim.model_files` expands
from the parameter set; the six lever-tip ↔ platform-joint loops come from
``models/hip_simulator.yaml`` and become 3-D point constraints
(``pin.RigidConstraintModel``, CONTACT_3D, LOCAL). Everything here is
computed with Pinocchio's kinematics, Jacobians and RNEA, independently of
the analytic formulas of :mod:`hipsim.kinematics` / :mod:`hipsim.dynamics`,
so that the two can check each other.

Closed-chain kinematics (:func:`kinematics`). The platform angles are known
along the trajectory, so the unknowns are the leg coordinates (3 sliders,
12 universal-joint angles). Per sample:

* the configuration is predicted from the previous sample by a third-order
  Taylor step (jerk from the last two accelerations) and corrected by Newton
  steps that reuse the previous sample's inverse K⁻¹ (below; a chord method:
  no new factorisation while it contracts); a damped Gauss–Newton
  (Levenberg–Marquardt) on the 15 leg coordinates with fresh Jacobians takes
  over on the first sample and whenever the chord steps stall;
* with K = [P₁; J_c] (P₁ selects platform 1's three angle coordinates, J_c
  the 18×21 closure Jacobian) the velocities solve K v = [q̇; 0] and the
  accelerations K a = [q̈; −J̇_c v], J̇_c v from the closure frames' classical
  accelerations at a = 0, built from the world joint Jacobians J and v (J̇ is
  the sum of cross products J̇·v = Σ_{j before k} (S_j v_j) × (S_k v_k) along
  each frame's chain, Pinocchio's own definition of it). Platform 2's
  coordinates come out equal to platform 1's (its three closures force the
  same orientation) and are then set to the given values exactly.

Closed-chain inverse dynamics (:func:`inverse_dynamics`): the tree's
generalised forces by part, each exact — RNEA of the tree with only one group
of bodies' inertias (platforms, levers, carriages; RNEA is linear in them for
a fixed motion, gravity included), the armature term for the screws, and the
friction generalised forces of spec §4.3 / §7.3 — then, per sample, the
actuator forces of Sᵀ F + J_cᵀ λ = τ from the K⁻¹ the kinematics computed
(a 3×3 solve: see :func:`hipsim.closed_chain.closure_kernel.actuator_and_closure_forces`).
The parts therefore add up to the total to rounding.
:func:`trajectory_dynamics` does both in one pass, reusing the Jacobians.

Speed. A sample's work is two Pinocchio calls: forward kinematics at the
prediction and the joint Jacobians at the corrected configuration. Their
results are read through NumPy views that Pinocchio keeps
current in its Data (``data.oMi``, ``data.J``; see
:class:`_Workspace`), not through per-closure property reads, which cost a
Python call and a copy each; the closures' frames, gaps and Jacobian, the
predictor, the chord step, K⁻¹ and the drift are compiled arithmetic on them
(:mod:`~hipsim.closed_chain.closure_kernel`), writing into arrays the solver
keeps. Pinocchio's own ``RigidConstraintModel.calc`` and
``getConstraintsJacobian`` serve the public helpers below and the tests that
hold the compiled route equal to them. The tree's torques are computed for a
whole chunk of samples at once by ``pin.rneaInParallel`` (one thread).
``scripts/bench.py --only servo`` times a sample next to its floor, the two
Pinocchio calls alone; the README's Speed section has the figures.

Sign conventions: J_c is the derivative of R₁ᵀ(p₁ − p₂) with frame 1 the lever
tip and frame 2 the platform joint; λ_ji is the force the platform exerts on
lever ji at a_ji, in the lever-tip frame (the lever exerts −λ on the platform).
"""

from __future__ import annotations

import math
import threading
import weakref
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import pinocchio as pin
import yaml

from ..physics import laws
from ..physics.friction import central_chain_friction
from ..physics.orientation import angular_velocity_map, inverse_condition_number, rotation_matrix
from ..physics.transmission import angle_from_travel, radians_per_travel, travel_per_radian
from ..physics.vectors import stack
from ..arrays import check_shapes
from ..exceptions import ArgumentError, ClosureError, ModelError, PoseError, TrajectoryError
from ..machine.model_files import closure_file_path, urdf_text
from ..machine.parameters import Parameters, load_parameters
from ..motion.trajectories import trajectory_arrays
from ..results import JointForces, Torques
from . import closure_kernel

__all__ = [
    "ClosedChainModel",
    "Continuation",
    "ClosedChainDynamics",
    "ClosedKinematics",
    "closure_residuals",
    "constraint_jacobian",
    "constraint_rank",
    "friction_forces",
    "inverse_dynamics",
    "kinematics",
    "load_closed_chain",
    "load_model",
    "platform_joint_positions",
    "trajectory_dynamics",
    "warm_up",
]

# Samples per batch of the inverse-dynamics solve: bounds the memory of the
# stacked (n, 21, 21) K⁻¹ while keeping the batched RNEA and solve efficient.
_CHUNK = 512
#: Threads of Pinocchio's batched RNEA (``pin.rneaInParallel``): one. It is used for its batching
#: (one call a chunk instead of one a sample); a second thread would save ~1 µs a sample on an idle
#: machine but compete with the loop's other process or thread wherever one runs (sweeps, servers).
_RNEA_THREADS = 1
#: The body groups' trees of each loaded model (see :func:`_group_trees`).
_GROUP_TREES: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()
#: Per thread, each loaded model's workspace and batched RNEAs (see :func:`_this_thread`).
_THREADS = threading.local()


# ---------------------------------------------------------------------------
# Loading
# ---------------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class _HipLayout:
    """Where the hip simulator's joints, bodies and closures sit in the Pinocchio model.

    All index arrays are velocity indices (the hip's joints are all 1-DoF, so
    they are configuration indices too).
    """

    platform_v: np.ndarray  # (2, 3): platform j's [rx, ry, rz] joints, i.e. [α, β, γ]
    slider_v: np.ndarray  # (3,)
    ujoint_v: np.ndarray  # (2, 3, 2): lever ji's [u1, u2]
    closure: np.ndarray  # (2, 3): closure index of lever ji
    slider_offset: np.ndarray  # (3,): L_1i - L_2i in [m], read from the tree
    leg_v: np.ndarray  # (15,): the leg coordinates (sliders and universal joints)
    groups: np.ndarray  # (10·(njoints−1), 3): dynamic parameters of platforms, levers, carriages
    initial_guess: np.ndarray  # (nq,): levers upright, tips at platform 1's height


@dataclass(frozen=True, eq=False)
class ClosedChainModel:
    """A kinematic tree with loop closures, ready for Pinocchio.

    Attributes:
        model: the tree; ``model.gravity`` and ``model.armature`` are set.
        visual_model: its visual geometry.
        constraint_models: one ``pin.RigidConstraintModel`` per closure
            (frame 1 first, LOCAL), as a ``StdVec_RigidConstraintModel``.
        closure_frames: the (frame 1, frame 2) names of each closure.
        actuated_joints: names of the actuated joints.
        actuated_v: their velocity indices, shape (n_act,).
        lead: screw lead p in [m per motor turn] (motor torque = p/2π · joint
            force); None if the closure file gives no transmission.
        rotor_inertia: screw rotor inertia I_L in [kg·m²] (armature
            I_L·(2π/p)² on each actuated joint); None without transmission.
        params: the parameter set the model was built from, if any.
        urdf: the URDF text the tree was built from.
        layout: the hip simulator's joint map (None for another machine).
    """

    model: pin.Model
    visual_model: pin.GeometryModel
    constraint_models: Any
    closure_frames: tuple[tuple[str, str], ...]
    actuated_joints: tuple[str, ...]
    actuated_v: np.ndarray
    lead: float | None
    rotor_inertia: float | None
    params: Parameters | None
    urdf: str
    layout: _HipLayout | None = None

    @property
    def n_closures(self) -> int:
        """Number of loop closures."""
        return len(self.closure_frames)


def _read_urdf(urdf: str | Path) -> str:
    if isinstance(urdf, Path) or not str(urdf).lstrip().startswith("<"):
        try:
            return Path(urdf).read_text(encoding="utf-8")
        except OSError as error:
            raise ModelError(f"cannot read URDF {urdf}: {error}") from None
    return str(urdf)


def _read_closures(path: str | Path) -> dict:
    try:
        with open(path, encoding="utf-8") as stream:
            content = yaml.safe_load(stream)
    except OSError as error:
        raise ModelError(f"cannot read closure file {path}: {error}") from None
    except yaml.YAMLError as error:
        raise ModelError(f"{path}: not valid YAML ({error})") from None
    if not isinstance(content, dict):
        raise ModelError(f"{path}: expected a mapping with keys closed_loop, type, name_mot")
    for key in ("closed_loop", "type", "name_mot"):
        if key not in content:
            raise ModelError(f"{path}: missing key '{key}'")
    pairs, types = content["closed_loop"], content["type"]
    if not isinstance(pairs, list) or not all(isinstance(p, list) and len(p) == 2 for p in pairs):
        raise ModelError(f"{path}: closed_loop must be a list of [frameA, frameB] pairs")
    if not isinstance(types, list) or len(types) != len(pairs):
        raise ModelError(f"{path}: type must list one of '3d'/'6d' per closed_loop pair ({len(pairs)})")
    return content


def load_closed_chain(
    urdf: str | Path,
    closure_file: str | Path,
    *,
    gravity: float = 9.81,
    lead: float | None = None,
    rotor_inertia: float | None = None,
) -> ClosedChainModel:
    """Build a closed-chain model from a URDF and a closure file (Gepetto's extended-URDF layout).

    Args:
        urdf: URDF text, or the path of a URDF file.
        closure_file: YAML with ``closed_loop`` (frame pairs), ``type``
            ('3d' or '6d' per pair) and ``name_mot`` (actuated joints); an
            optional ``transmission`` gives per actuated joint ``lead_m`` [m]
            and ``rotor_inertia_kgm2`` [kg·m²].
        gravity: g in [m/s²], along -Z.
        lead: screw lead in [m per motor turn]; overrides the file's.
        rotor_inertia: screw rotor inertia in [kg·m²]; overrides the file's.

    Returns:
        The model (without the hip layout; :func:`load_model` adds it).

    Raises:
        ModelError: naming the missing frame, joint or key.
    """
    text = _read_urdf(urdf)
    try:
        model = pin.buildModelFromXML(text)
        visual_model = pin.buildGeomFromUrdfString(model, text, pin.GeometryType.VISUAL)
    except (RuntimeError, ValueError) as error:
        raise ModelError(f"Pinocchio cannot parse the URDF: {error}") from None
    model.gravity = pin.Motion(np.array([0.0, 0.0, -gravity]), np.zeros(3))

    content = _read_closures(closure_file)
    constraint_models = pin.StdVec_RigidConstraintModel()
    for (name1, name2), kind in zip(content["closed_loop"], content["type"]):
        frames = []
        for name in (name1, name2):
            if not model.existFrame(name):
                raise ModelError(f"{closure_file}: closure frame '{name}' is not in the URDF")
            frames.append(model.frames[model.getFrameId(name)])
        contact = {"3d": pin.ContactType.CONTACT_3D, "6d": pin.ContactType.CONTACT_6D}.get(str(kind).lower())
        if contact is None:
            raise ModelError(f"{closure_file}: closure type '{kind}' of {name1}-{name2} is not '3d' or '6d'")
        constraint = pin.RigidConstraintModel(
            contact, model, frames[0].parentJoint, frames[0].placement,
            frames[1].parentJoint, frames[1].placement, pin.ReferenceFrame.LOCAL,
        )  # fmt: skip
        constraint.name = f"{name1}-{name2}"
        constraint_models.append(constraint)

    actuated = tuple(str(name) for name in content["name_mot"])
    actuated_v = []
    for name in actuated:
        if not model.existJointName(name):
            raise ModelError(f"{closure_file}: actuated joint '{name}' is not in the URDF")
        joint = model.joints[model.getJointId(name)]
        if joint.nv != 1:
            raise ModelError(f"{closure_file}: actuated joint '{name}' has {joint.nv} DoF, expected 1")
        actuated_v.append(joint.idx_v)

    transmission = content.get("transmission") or {}
    if lead is None or rotor_inertia is None:
        try:
            leads = {float(transmission[n]["lead_m"]) for n in actuated if n in transmission}
            inertias = {float(transmission[n]["rotor_inertia_kgm2"]) for n in actuated if n in transmission}
        except (KeyError, TypeError, ValueError) as error:
            message = f"{closure_file}: transmission needs lead_m and rotor_inertia_kgm2 per joint ({error})"
            raise ModelError(message) from None
        if len(leads) > 1 or len(inertias) > 1:
            raise ModelError(f"{closure_file}: actuated joints with different transmissions are not supported")
        lead = lead if lead is not None else (leads.pop() if leads else None)
        rotor_inertia = rotor_inertia if rotor_inertia is not None else (inertias.pop() if inertias else None)
    if lead is not None and rotor_inertia is not None:
        armature = model.armature.copy()
        armature[actuated_v] = rotor_inertia * radians_per_travel(lead) ** 2
        model.armature = armature

    return ClosedChainModel(
        model=model,
        visual_model=visual_model,
        constraint_models=constraint_models,
        closure_frames=tuple((str(a), str(b)) for a, b in content["closed_loop"]),
        actuated_joints=actuated,
        actuated_v=np.array(actuated_v, dtype=int),
        lead=lead,
        rotor_inertia=rotor_inertia,
        params=None,
        urdf=text,
    )


def load_model(params: Parameters | None = None) -> ClosedChainModel:
    """The hip simulator as a Pinocchio closed-chain model, built from one parameter set.

    Args:
        params: the machine, SI; None for the published machine.

    Returns:
        The model with the hip layout, gravity params.gravity, and armature
        I_L·(2π/p)² on the three sliders.
    """
    params = load_parameters() if params is None else params
    chain = load_closed_chain(
        urdf_text(params),
        closure_file_path(),
        gravity=params.gravity,
        lead=params.lead,
        rotor_inertia=params.screw_inertia,
    )
    layout = _hip_layout(chain, params)
    return ClosedChainModel(**{**chain.__dict__, "params": params, "layout": layout})


def _hip_layout(chain: ClosedChainModel, params: Parameters) -> _HipLayout:
    model = chain.model

    def joint(name: str) -> int:
        if not model.existJointName(name):
            raise ModelError(f"the hip simulator URDF has no joint '{name}'")
        return model.getJointId(name)

    if any(model.joints[k].nq != 1 or model.joints[k].nv != 1 for k in range(1, model.njoints)):
        raise ModelError("the hip simulator's tree must consist of 1-DoF joints")

    def idx(name: str) -> int:
        return model.joints[joint(name)].idx_v

    platform_v = np.array([[idx(f"platform_{j}_r{axis}") for axis in "xyz"] for j in (1, 2)])
    slider_v = np.array([idx(f"slider_{i}") for i in (1, 2, 3)])
    ujoint_v = np.array([[[idx(f"u1_{j}{i}"), idx(f"u2_{j}{i}")] for i in (1, 2, 3)] for j in (1, 2)])
    closure = np.empty((2, 3), dtype=int)
    for j in (1, 2):
        for i in (1, 2, 3):
            pair = (f"lever_{j}{i}_tip", f"platform_{j}_joint_{i}")
            if pair not in chain.closure_frames:
                raise ModelError(f"the closure file has no closure {pair[0]}-{pair[1]}")
            closure[j - 1, i - 1] = chain.closure_frames.index(pair)
    if sorted(chain.actuated_v) != sorted(slider_v) or chain.n_closures != 6:
        raise ModelError("the hip simulator needs six closures and the three sliders as actuated joints")

    placement_z = np.array([[model.jointPlacements[joint(f"u1_{j}{i}")].translation[2] for i in (1, 2, 3)] for j in (1, 2)])
    leg_v = np.array(sorted(set(slider_v) | set(ujoint_v.ravel())))

    # Dynamic parameters (10 per joint, Pinocchio's regressor order) of each body group.
    members = (set(platform_v[:, 0]), set(ujoint_v[:, :, 1].ravel()), set(slider_v))
    groups = np.zeros((10 * (model.njoints - 1), 3))
    for k in range(1, model.njoints):
        parameters = model.inertias[k].toDynamicParameters()
        owner = [g for g, member in enumerate(members) if model.joints[k].idx_v in member]
        if owner:
            groups[10 * (k - 1) : 10 * k, owner[0]] = parameters
        elif np.any(parameters != 0.0):
            raise ModelError(f"body of joint '{model.names[k]}' has inertia but belongs to no part of the torque")

    initial_guess = pin.neutral(model)
    initial_guess[slider_v] = params.heights[0] - params.lever_length
    return _HipLayout(
        platform_v=platform_v,
        slider_v=slider_v,
        ujoint_v=ujoint_v,
        closure=closure,
        slider_offset=placement_z[0] - placement_z[1],
        leg_v=leg_v,
        groups=groups,
        initial_guess=initial_guess,
    )


# ---------------------------------------------------------------------------
# Configuration-level helpers
# ---------------------------------------------------------------------------


class _Workspace:
    """Pinocchio data and the constraint datas of one computation (not shared between threads).

    The solver reads Pinocchio's results through NumPy views that Pinocchio
    keeps current in its Data (the joint Jacobians ``data.J``,
    the joint placements ``data.oMi``): a property read costs a Python call
    and a copy, some 0.5 µs, and a sample would need dozens. The views live
    as long as this workspace's Data, which they point into.
    """

    def __init__(self, chain: ClosedChainModel):
        self.model = chain.model
        self.data = chain.model.createData()
        self.cms = chain.constraint_models
        self.cds = pin.StdVec_RigidConstraintData()
        for cm in self.cms:
            self.cds.append(cm.createData())
        # Python lists of references into the vectors: indexing a StdVec per access is slow.
        self.cd_list = list(self.cds)
        self.pairs = list(zip(self.cms, self.cd_list))
        n, nv = len(self.cd_list), chain.model.nv
        # The joints supporting each closure frame, frame 1 then frame 2, as 0/1 over the velocity indices:
        # the columns of the world Jacobians that move that frame's body.
        self.support_masks = np.zeros((2 * n, nv))
        for c, cm in enumerate(self.cms):
            for end, joint in enumerate((cm.joint1_id, cm.joint2_id)):
                for k in self.model.supports[joint][1:]:  # the universe (0) has no velocity
                    self.support_masks[2 * c + end, self.model.joints[k].idx_v] = 1.0
        # Each closure's two joints, and its frames' placements in them (closure_kernel.closure_frames).
        self.closure_joints = np.array([[cm.joint1_id, cm.joint2_id] for cm in self.cms])
        self.closure_placements = np.array([[cm.joint1_placement.homogeneous, cm.joint2_placement.homogeneous] for cm in self.cms])
        self.joint_rotations, self.joint_origins = _joint_placement_views(self.model, self.data)
        self.J = self.data.J
        self.tips = np.empty((n, 4, 4))  # frame 1's world placement per closure, at the last place()
        self.p2 = np.empty((n, 3))  # frame 2's world origin per closure [m], at the last place()
        self.gaps = np.empty(3 * n)  # the closure gaps [m] at the last place()
        self.J_c = np.empty((3 * n, nv))
        # closure_kernel.closure_frames' arguments, in its order (None without live views of data.oMi).
        self.frame_args = (
            None if self.joint_rotations is None
            else (self.joint_rotations, self.joint_origins, self.closure_joints, self.closure_placements, self.tips, self.p2, self.gaps)
        )  # fmt: skip

    def place(self, q: np.ndarray, jacobians: bool = True) -> float:
        """Forward kinematics, joint Jacobians (unless not asked for) and the closures' frames and gaps at q; returns |gaps|² [m²]."""
        if jacobians:
            pin.computeJointJacobians(self.model, self.data, q)
        else:
            pin.forwardKinematics(self.model, self.data, q)
        return closure_kernel.closure_frames(*self.frame_arguments())

    def frame_arguments(self) -> tuple:
        """closure_kernel.closure_frames' arguments at the placed q: the views of ``data.oMi``, or copies of it without them."""
        if self.joint_rotations is not None:
            return self.frame_args
        rotations, origins = _joint_placement_copies(self.data)
        return (rotations, origins, self.closure_joints, self.closure_placements, self.tips, self.p2, self.gaps)

    def residual(self) -> np.ndarray:
        """The closure gaps d = R₁ᵀ(p₂ − p₁) of every closure, stacked, in [m] (after :meth:`place`; overwritten by the next).

        Pinocchio's relative placement c1Mc2's translation, whose derivative is
        −J_c (J_c differentiates p₁ − p₂): a Newton step on the gaps is q + K⁻¹·[0; d].
        """
        return self.gaps

    def jacobian(self) -> np.ndarray:
        """The stacked closure Jacobian J_c (after :meth:`place` with the Jacobians; overwritten by the next call)."""
        closure_kernel.closure_jacobian(self.J, self.support_masks, self.tips, self.p2, self.J_c)
        return self.J_c

    def tip_frames(self) -> np.ndarray:
        """Frame 1's homogeneous placement of every closure (its axes and origin in the world), (n, 4, 4) (after :meth:`place`; overwritten by the next)."""
        return self.tips

    def calc_constraints(self) -> None:
        """Pinocchio's own closure computations (``RigidConstraintModel.calc``) at the placed q: the reference the views are checked against."""
        for cm, cd in self.pairs:
            cm.calc(self.model, self.data, cd)

    def pinocchio_jacobian(self) -> np.ndarray:
        """Pinocchio's stacked closure Jacobian (``getConstraintsJacobian``) at the placed q (after :meth:`place` with the Jacobians)."""
        self.calc_constraints()
        return pin.getConstraintsJacobian(self.model, self.data, self.cms, self.cds)


def _joint_placement_copies(data) -> tuple[np.ndarray, np.ndarray]:
    """The joints' world rotations (njoints, 3, 3) and origins (njoints, 3) [m], copied out of ``data.oMi``."""
    return np.array([M.rotation for M in data.oMi]), np.array([M.translation for M in data.oMi])


def _joint_placement_views(model, data) -> tuple[np.ndarray | None, np.ndarray | None]:
    """The joints' world rotations (njoints, 3, 3) and origins (njoints, 3) [m] as NumPy views into ``data.oMi``, or (None, None).

    Pinocchio keeps ``data.oMi`` as one contiguous std::vector of SE3 (the
    rotation's nine entries column by column, then the translation), and its
    bindings hand out each element's rotation and translation as views into
    it. Two strided arrays over the first element's views then cover every
    joint and stay current as Pinocchio updates the placements: the compiled
    solver reads them with no Python call per joint. The layout is checked
    (addresses, and the values after a forward kinematics); where it is not
    the expected one, (None, None) and the solver copies (slower, same result).
    """
    from numpy.lib.stride_tricks import as_strided

    def address(array: np.ndarray) -> int:
        return array.__array_interface__["data"][0]

    rotation, translation = data.oMi[0].rotation, data.oMi[0].translation
    if model.njoints < 2 or rotation.strides != (8, 24) or translation.strides != (8,):
        return None, None
    stride = address(data.oMi[1].rotation) - address(rotation)
    if any(address(data.oMi[j].rotation) != address(rotation) + j * stride or address(data.oMi[j].translation) != address(rotation) + j * stride + 72
           for j in range(model.njoints)):  # fmt: skip
        return None, None
    rotations = as_strided(rotation, shape=(model.njoints, 3, 3), strides=(stride, 8, 24), writeable=False)
    origins = as_strided(translation, shape=(model.njoints, 3), strides=(stride, 8), writeable=False)
    pin.forwardKinematics(model, data, pin.randomConfiguration(model, -np.ones(model.nq), np.ones(model.nq)))
    copies = _joint_placement_copies(data)
    if not (np.array_equal(rotations, copies[0]) and np.array_equal(origins, copies[1])):
        return None, None
    return rotations, origins


def _block_triangular_order(pattern: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Row and column orders that make square matrices of this sparsity block lower triangular, and where the blocks start.

    The block triangular form of Dulmage and Mendelsohn: a perfect matching of
    rows to columns (a diagonal without structural zeros), then the strongly
    connected components of the graph "row i involves the column matched to
    row k", in an order where each comes after those it involves.

    Args:
        pattern: (n, n) booleans, True where the matrices may be nonzero.

    Returns:
        rows, columns: the orders, (n,) each; starts: each block's first index and n at the end.
        One block (the original order) where no perfect matching exists.
    """
    from scipy.sparse import csr_matrix
    from scipy.sparse.csgraph import connected_components, maximum_bipartite_matching

    n = len(pattern)
    match = maximum_bipartite_matching(csr_matrix(pattern), perm_type="column")  # the column matched to each row
    if (match < 0).any():
        return np.arange(n), np.arange(n), np.array([0, n])
    involves = pattern[:, match]
    count, component = connected_components(csr_matrix(involves), directed=True, connection="strong")
    needs = [set(component[involves[component == c].any(axis=0)]) - {c} for c in range(count)]
    order: list[int] = []
    while len(order) < count:  # the components' graph has no cycles: each pass places at least one
        order += [c for c in range(count) if c not in order and needs[c] <= set(order)]
    rows = np.concatenate([np.flatnonzero(component == c) for c in order])
    starts = np.cumsum([0] + [int(np.sum(component == c)) for c in order])
    return rows, match[rows], starts


def _k_order(ws: _Workspace, platform1: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The block order of K's block B for :func:`closure_kernel.velocity`: J_c's rows, the velocity indices of B's columns, the blocks' starts.

    Closure c's three rows of J_c can only be nonzero in the columns of the
    joints that support its two frames (``support_masks``). For the hip the
    blocks are each platform-1 lever's slider and universal joint (3×3, three
    of them), then platform 2's levers and spherical joint together (9×9).
    """
    others = np.setdiff1d(np.arange(ws.model.nv), platform1)
    reach = ws.support_masks[0::2] + ws.support_masks[1::2] > 0  # (closures, nv)
    rows, columns, starts = _block_triangular_order(np.repeat(reach[:, others], 3, axis=0))
    return rows, others[columns], starts


def _configurations(chain: ClosedChainModel, q) -> tuple[np.ndarray, bool]:
    q = np.asarray(q, dtype=float)
    single = q.ndim == 1
    q = np.atleast_2d(q)
    if q.shape[1] != chain.model.nq:
        raise ArgumentError("q", q, f"configurations of size nq = {chain.model.nq}")
    return q, single


def closure_residuals(chain: ClosedChainModel, q) -> np.ndarray:
    """How far each closure is from closed: p₂ − p₁ in world axes.

    Args:
        chain: the model.
        q: a configuration (nq,) or configurations (N, nq).

    Returns:
        Shape (n_closures, 3) or (N, n_closures, 3), in [m].
    """
    q, single = _configurations(chain, q)
    ws = _Workspace(chain)
    out = np.empty((len(q), chain.n_closures, 3))
    for k, qk in enumerate(q):
        ws.place(qk)
        ws.calc_constraints()
        out[k] = [cd.oMc2.translation - cd.oMc1.translation for cd in ws.cd_list]
    return out[0] if single else out


def constraint_jacobian(chain: ClosedChainModel, q) -> np.ndarray:
    """The closure Jacobian J_c (legacy LOCAL convention: d/dt of R₁ᵀ(p₁ − p₂)).

    Args:
        chain: the model.
        q: a configuration (nq,).

    Returns:
        Shape (3·n_closures, nv) for point closures, in [m/rad] or [1].
    """
    ws = _Workspace(chain)
    ws.place(np.asarray(q, dtype=float))
    return ws.pinocchio_jacobian()


def constraint_rank(chain: ClosedChainModel, q, rtol: float = 1e-9) -> int:
    """Rank of the closure Jacobian J_c at q (singular values above rtol · the largest).

    Args:
        chain: the model.
        q: a configuration (nq,).
        rtol: relative threshold on the singular values.

    Returns:
        The rank; nv − rank is the mobility at q (3 for the hip simulator).
    """
    sigma = np.linalg.svd(constraint_jacobian(chain, q), compute_uv=False)
    return int(np.sum(sigma > rtol * sigma[0]))


def platform_joint_positions(chain: ClosedChainModel, q) -> np.ndarray:
    """World positions of the platforms' spherical joints a_ji (frames platform_j_joint_i).

    Args:
        chain: the hip model.
        q: a configuration (nq,) or configurations (N, nq).

    Returns:
        Shape (2, 3, 3) or (N, 2, 3, 3): [platform j, joint i, xyz] in [m].
    """
    layout = _require_layout(chain)
    q, single = _configurations(chain, q)
    ws = _Workspace(chain)
    out = np.empty((len(q), 2, 3, 3))
    for k, qk in enumerate(q):
        ws.place(qk)
        ws.calc_constraints()
        for j in range(2):
            for i in range(3):
                out[k, j, i] = ws.cd_list[layout.closure[j, i]].oMc2.translation
    return out[0] if single else out


def _require_layout(chain: ClosedChainModel) -> _HipLayout:
    if chain.layout is None:
        raise ModelError("this function needs the hip simulator model from load_model()")
    return chain.layout


# ---------------------------------------------------------------------------
# Closed-chain kinematics
# ---------------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class ClosedKinematics:
    """The closed configuration of the whole tree along a trajectory.

    Attributes:
        t: sample times in [s], shape (N,).
        angles: platform angles [α, β, γ] in [rad] as used (angle_signs
            applied), shape (N, 3); angle_rates [rad/s], angle_accels [rad/s²] likewise.
        q: tree configurations in [m, rad], shape (N, nq).
        v: tree velocities in [m/s, rad/s], shape (N, nv), with J_c v = 0.
        a: tree accelerations in [m/s², rad/s²], shape (N, nv), with J_c a + J̇_c v = 0.
        L, Ld, Ldd: slider heights [m], rates [m/s], accelerations [m/s²] of
            U-joint centre b_ji, shape (N, 2, 3) [platform j, screw i].
        J: the slider Jacobian L̇ = J·ω of the closed chain in [m], shape (N, 3, 3),
            from the velocity closure (independent of the analytic J).
        cond_inv: its inverse condition number (singularity measure), shape (N,).
        residual: largest closure gap of each sample in [m], shape (N,).
        iterations: configuration evaluations spent on each sample, shape (N,).
    """

    t: np.ndarray
    angles: np.ndarray
    angle_rates: np.ndarray
    angle_accels: np.ndarray
    q: np.ndarray
    v: np.ndarray
    a: np.ndarray
    L: np.ndarray
    Ld: np.ndarray
    Ldd: np.ndarray
    J: np.ndarray
    cond_inv: np.ndarray
    residual: np.ndarray
    iterations: np.ndarray

    def __post_init__(self):
        nq, nv = np.shape(self.q)[1], np.shape(self.v)[1]
        check_shapes(
            self,
            {
                "t": ("N",), "angles": ("N", 3), "angle_rates": ("N", 3), "angle_accels": ("N", 3),
                "q": ("N", nq), "v": ("N", nv), "a": ("N", nv),
                "L": ("N", 2, 3), "Ld": ("N", 2, 3), "Ldd": ("N", 2, 3),
                "J": ("N", 3, 3), "cond_inv": ("N",), "residual": ("N",), "iterations": ("N",),
            },
            samples=len(self.t),
        )  # fmt: skip


class _Closer:
    """Solves the closed configuration sample after sample (one trajectory, one workspace)."""

    def __init__(self, chain: ClosedChainModel, tol: float, max_iter: int):
        self.layout = _require_layout(chain)
        resources = _this_thread(chain)
        self.ws = resources.workspace
        self.tol2, self.max_iter = tol * tol, max_iter
        nv = chain.model.nv
        self.platforms = self.layout.platform_v.ravel()
        # K = [P₁; J_c]'s selection P₁: platform 1's coordinates, and the others.
        self.platform1 = self.layout.platform_v[0]
        self.order = resources.k_order()
        self.K_inv = np.empty((nv, nv))  # K⁻¹ at the last closed sample: the chord method's Jacobian
        self.have_K_inv = False
        self.prediction = np.empty(nv)  # where the loop puts a sample's predicted q
        self._scratch = np.empty(nv)  # a second iterate for chord steps beyond the first
        self.evaluations = 0
        # closure_kernel.closed_sample's arguments after the gaps' limit, up to the sample's own (fixed for a run).
        ws, layout = self.ws, self.layout
        self.constants = (ws.J, ws.support_masks, ws.J_c, self.platform1, *self.order, layout.platform_v[1], layout.slider_v)
        self.keep_nothing = (np.empty((0, nv, nv)), np.empty((0, 3, nv)), np.empty((0, len(ws.cms), 3, 3)), -1)  # sample()'s keep without dynamics

    def _evaluate(self, q: np.ndarray, jacobians: bool = True) -> float:
        """|gaps|² at q [m²]; q's placements, gaps (and Jacobians) are left in the workspace."""
        self.evaluations += 1
        return self.ws.place(q, jacobians)

    def close(self, q: np.ndarray, angles: np.ndarray, out: np.ndarray) -> None:
        """Move q's leg coordinates until every closure holds, into ``out``.

        q: a configuration whose platform coordinates are ``angles`` already
        (both platforms', in ``platform_v.ravel()`` order); it is left as it
        is. On return ``out`` holds the closed configuration and the workspace
        its placements, Jacobians and gaps. Raises ClosureError (with the gap
        left) if the loops cannot be closed.
        """
        if not self.have_K_inv:
            size = self._evaluate(q)
            out[:] = q if size <= self.tol2 else self._levenberg_marquardt(q, size)
            return
        ws, tol2 = self.ws, self.tol2
        # A prediction is seldom closed already: its Jacobians would go unused.
        size = self._evaluate(q, jacobians=False)
        # Chord steps: Newton with the previous sample's K⁻¹, while it contracts well. The
        # first goes straight into out (the usual case: one step closes the chain to round-off).
        trial, other = out, self._scratch
        for step in range(6):
            if size <= tol2:
                if step == 0:
                    pin.computeJointJacobians(ws.model, ws.data, q)
                if q is not out:
                    out[:] = q
                return
            # The kernel of sample()'s usual course (gaps at q again, the same bits; limit −1: always step).
            closure_kernel.gaps_and_chord_step(*ws.frame_arguments(), q, self.K_inv, self.platforms, angles, -1.0, trial)
            size_trial = self._evaluate(trial)
            if size_trial > 0.01 * size:  # the gap must shrink tenfold per step, else fresh Jacobians
                out[:] = self._levenberg_marquardt(q, self._evaluate(q))
                return
            q, size = trial, size_trial
            trial, other = other, trial
        out[:] = self._levenberg_marquardt(q, size)

    def sample(self, prediction, angles, out, rates, accels, V, A, row: int, J_rates, residual, k: int, keep) -> None:
        """Close sample k from its prediction into ``out`` and compute its rates: the solver's step per sample.

        Args:
            prediction: the predicted configuration, (nq,), platform coordinates at ``angles`` (left as it is).
            angles: both platforms' coordinates at k (``platform_v.ravel()`` order) [rad].
            out: the closed configuration's row, Q[row].
            rates, accels: platform angle rates [rad/s] and accelerations [rad/s²] of every sample, (samples, 3).
            V, A, row: where the tree velocity and acceleration go, V[row], A[row].
            J_rates, residual, k: where ∂L̇/∂q̇ and the largest closure gap [m] go, J_rates[k], residual[k].
            keep: ``(K_invs, angular, tip_rotations, slot)`` where closure_kernel.store keeps what
                the inverse dynamics reuse (slot < 0: nothing).

        Raises:
            ClosureError: the loops cannot be closed, or the pose is singular.
        """
        ws, tol2 = self.ws, self.tol2
        args = (rates, accels, V, A, row, J_rates, residual, k, self.K_inv, *keep)
        frames = ws.frame_args if ws.joint_rotations is not None else None  # the usual course reads Pinocchio's placements through the views
        if self.have_K_inv and frames is not None:
            # close()'s usual course in two Pinocchio and two compiled calls: forward kinematics at
            # the prediction, one chord step (into out), the Jacobians there; anything else goes to close().
            pin.forwardKinematics(ws.model, ws.data, prediction)
            size = closure_kernel.gaps_and_chord_step(*frames, prediction, self.K_inv, self.platforms, angles, tol2, out)
            if size > tol2:
                pin.computeJointJacobians(ws.model, ws.data, out)
                status, _ = closure_kernel.closed_sample(*frames, min(tol2, 0.01 * size), *self.constants, *args)
                if status != closure_kernel.OPEN:
                    self.evaluations += 2
                    self._check(status)
                    return
        self.close(prediction, angles, out)
        status, _ = closure_kernel.closed_sample(*ws.frame_arguments(), math.inf, *self.constants, *args)
        self._check(status)

    def _check(self, status: int) -> None:
        """Raise for closure_kernel.rates' failure codes; on success keep K⁻¹ for the next sample's chord steps."""
        if status == closure_kernel.SINGULAR:
            raise ClosureError("singular pose: the closure Jacobian loses rank (spec §3)")
        if status == closure_kernel.LEVER_DOWN:
            raise ClosureError("a lever is horizontal or points down (singular pose, spec §3)")
        self.have_K_inv = True

    def _levenberg_marquardt(self, q: np.ndarray, cost: float) -> np.ndarray:
        """Damped Gauss–Newton on the 15 leg coordinates with fresh Jacobians, from q whose gaps (|gaps|² = cost) the workspace holds."""
        legs = self.layout.leg_v
        damping = 1e-6
        for iteration in range(self.max_iter):
            if cost <= self.tol2:
                return q
            J = self.ws.jacobian()[:, legs]
            H, g = J.T @ J, J.T @ self.ws.gaps
            while True:
                step = np.linalg.solve(H + damping * np.eye(len(legs)), g)
                trial = q.copy()
                trial[legs] += step  # d(q + δ) ≈ d − J_c·δ: the gaps fall along −J_c
                cost_trial = self._evaluate(trial)
                if cost_trial < cost:
                    q, cost = trial, cost_trial
                    damping = max(damping / 4.0, 1e-12)
                    break
                damping *= 8.0
                if damping > 1e8 or np.abs(step).max() < 1e-15:
                    raise ClosureError(
                        f"cannot close the loops: the closure gap stays at {math.sqrt(cost):.3g} m "
                        "(the pose is out of the levers' reach)", math.sqrt(cost), iteration + 1,
                    )
        if cost <= self.tol2:
            return q
        raise ClosureError(f"cannot close the loops in {self.max_iter} iterations (gap {math.sqrt(cost):.3g} m)", math.sqrt(cost), self.max_iter)


@dataclass(eq=False)
class Continuation:
    """Where a run in pieces left the closure solver, so that the next piece goes on as one run would.

    The solver starts each sample from a prediction made of the previous
    samples and its chord steps reuse the previous sample's K⁻¹: a piece that
    started cold would close the chain to the same tolerance but not to the
    same bits. Pass one (initially empty) object to successive pieces in time
    order; each run updates it in place.

    Attributes:
        samples: samples closed so far.
        t: times of the last (up to) two samples in [s], (m,).
        q, v, a: their configurations, velocities and accelerations, (m, nq), (m, nv), (m, nv).
        K_inv: the solver's chord Jacobian at the last sample.
    """

    samples: int = 0
    t: np.ndarray | None = None
    q: np.ndarray | None = None
    v: np.ndarray | None = None
    a: np.ndarray | None = None
    K_inv: np.ndarray | None = None


def kinematics(chain: ClosedChainModel, traj, *, tol: float = 1e-12, max_iter: int = 50) -> ClosedKinematics:
    """Close the chain along a platform trajectory, with Pinocchio only.

    Args:
        chain: the hip model from :func:`load_model`.
        traj: a Trajectory-like object: t (N,) in [s]; q, qd, qdd (N, 3):
            [α, β, γ] in [rad], [rad/s], [rad/s²]. The parameter set's
            angle_signs multiply them first (as the analytic model does).
        tol: closure gap accepted in [m] (bound on the norm of all gaps stacked).
        max_iter: damped Gauss–Newton iterations allowed per sample.

    Returns:
        The closed configurations, velocities and accelerations.

    Raises:
        PoseError: at the first sample whose pose is out of reach or singular.
        TrajectoryError: the arrays have the wrong shapes.
    """
    return _close_chain(chain, traj, tol, max_iter, Fe=None)[0]


def _close_chain(
    chain: ClosedChainModel, traj, tol: float, max_iter: int, Fe, parts: bool = True, continuation: Continuation | None = None
) -> tuple[ClosedKinematics, Any]:
    """The kinematics loop; with a load Fe it also runs the inverse dynamics on the fly."""
    layout = _require_layout(chain)
    t, q_in, qd_in, qdd_in = trajectory_arrays(traj)
    signs = chain.params.angle_signs if chain.params is not None else np.ones(3)
    angles, rates, accels = (np.ascontiguousarray(x * signs) for x in (q_in, qd_in, qdd_in))
    both = np.tile(angles, 2)  # both platforms' coordinates, in platform_v.ravel() order
    n, nq, nv = len(t), chain.model.nq, chain.model.nv
    residual = np.empty(n)  # the largest closure gap per sample [m]
    iterations = np.empty(n, dtype=int)
    J_rates = np.empty((n, 3, 3))  # ∂L̇/∂(angle rates) of the sliders
    closer = _Closer(chain, tol, max_iter)
    # The samples before this piece (if any) come first, so that the predictor sees one run.
    go_on = continuation if continuation is not None and continuation.samples else None
    before = len(go_on.t) if go_on else 0
    T = np.concatenate([go_on.t, t]) if go_on else t
    Q, V, A = np.empty((before + n, nq)), np.empty((before + n, nv)), np.empty((before + n, nv))
    if go_on:
        Q[:before], V[:before], A[:before] = go_on.q, go_on.v, go_on.a
        closer.K_inv[:] = go_on.K_inv
        closer.have_K_inv = True
    # The closer leaves Pinocchio's data at the closed q: the dynamics reuse its Jacobians.
    dynamics = _InverseDynamics(chain, Q[before:], V[before:], A[before:], Fe, parts) if Fe is not None else None
    # Bound once: at some 30,000 samples a second, each attribute read in the loop (~30 ns) shows.
    platforms, predict, prediction, sample, ws = closer.platforms, closure_kernel.predict, closer.prediction, closer.sample, closer.ws
    keep = closer.keep_nothing
    for k in range(n):
        row = before + k  # this sample's row in Q, V, A and T, after the previous piece's last samples
        angles_k = both[k]
        if row:
            predict(T, Q, V, A, row, platforms, angles_k, prediction)
        else:
            prediction[:] = layout.initial_guess
            prediction[platforms] = angles_k
        if dynamics is not None:
            keep = dynamics.keep(k)
        evaluations = closer.evaluations
        try:
            sample(prediction, angles_k, Q[row], rates, accels, V, A, row, J_rates, residual, k, keep)
        except (ClosureError, np.linalg.LinAlgError) as error:
            raise PoseError(str(error), float(t[k]), k, source=getattr(traj, "name", None)) from None
        iterations[k] = closer.evaluations - evaluations
        if dynamics is not None:
            dynamics.stored(k, ws)

    if continuation is not None and n:
        last = slice(max(0, before + n - 2), before + n)
        continuation.samples += n
        continuation.t, continuation.q, continuation.v, continuation.a = T[last].copy(), Q[last].copy(), V[last].copy(), A[last].copy()
        continuation.K_inv = closer.K_inv.copy()
    Q, V, A = Q[before:], V[before:], A[before:]
    sliders = layout.slider_v
    offset = np.stack([np.zeros(3), layout.slider_offset])[None]
    # L̇ = J_rates·q̇ and ω = T(q)·q̇, so J = J_rates·T⁻¹ (T⁻¹ in closed form: LAPACK's batched
    # solve on 3×3 matrices cost 0.5 µs a sample, 2 % of the whole). The product is three
    # elementwise terms, not einsum, whose rounding depends on the array's length: a run in
    # pieces must give the one-piece bits.
    T_inverse_rows = laws.inverse_transpose(np.moveaxis(angular_velocity_map(angles), (1, 2), (0, 1)))  # T⁻ᵀ's rows b, each (xyz, n)
    T_inverse = np.stack([np.stack(row, axis=-1) for row in T_inverse_rows], axis=-1)  # (n, c, b) = T⁻¹
    J = sum(J_rates[:, :, c, None] * T_inverse[:, None, c, :] for c in range(3))
    kin = ClosedKinematics(
        t=t,
        angles=angles,
        angle_rates=rates,
        angle_accels=accels,
        q=Q,
        v=V,
        a=A,
        L=Q[:, None, sliders] - offset,
        Ld=np.repeat(V[:, None, sliders], 2, axis=1),
        Ldd=np.repeat(A[:, None, sliders], 2, axis=1),
        J=J,
        cond_inv=inverse_condition_number(J),
        residual=residual,
        iterations=iterations,
    )
    return kin, (dynamics.result(kin) if dynamics is not None else None)


# ---------------------------------------------------------------------------
# Closed-chain inverse dynamics
# ---------------------------------------------------------------------------


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


class _BatchedRNEA:
    """Pinocchio's batched RNEA (``pin.rneaInParallel``) of one tree, and where its joints sit in the hip model's velocity vector.

    Each holds its own ``pin.ModelPool`` (the tree's Data): not shared between threads.

    Args:
        model: the tree; None for a group without bodies (massless levers, say), whose torques are zero.
        columns: the hip model's velocity index of each of the tree's joints, in the tree's order.
    """

    def __init__(self, model, columns: np.ndarray):
        self.pool = pin.ModelPool(model, _RNEA_THREADS) if model is not None else None
        self.columns = columns

    def __call__(self, q: np.ndarray, v: np.ndarray, a: np.ndarray, out: np.ndarray) -> None:
        """Write the tree's torques at samples (rows of) q, v, a into ``out``'s columns, (m, nv); the other columns are zeroed."""
        if self.pool is None:
            out[:] = 0.0
        elif len(self.columns) == out.shape[1]:  # the hip model's whole tree
            pin.rneaInParallel(_RNEA_THREADS, self.pool, q.T, v.T, a.T, out.T)
        else:
            columns = self.columns
            tau = np.empty((len(q), len(columns)))
            pin.rneaInParallel(_RNEA_THREADS, self.pool, q[:, columns].T, v[:, columns].T, a[:, columns].T, tau.T)
            out[:] = 0.0
            out[:, columns] = tau


def _group_trees(chain: ClosedChainModel) -> list[tuple[Any, np.ndarray]]:
    """Per body group (platforms, levers, carriages): a tree with only that group's inertias, and its joints' velocity indices.

    RNEA is linear in the bodies' inertias for a given motion, so the tree
    with only one group's inertias (and no armature: the screws' term is added
    apart) gives that group's part of the torques. A group's torques depend
    only on the joints that support its bodies, so its tree keeps just those
    (``pin.buildReducedModel`` locks the others, whose bodies carry no
    inertia there): 6 joints for the platforms, 15 for the levers, 3 for the
    carriages, against 21 for each. Built once per loaded model.
    """
    trees = _GROUP_TREES.get(chain)
    if trees is None:
        model, groups = chain.model, _require_layout(chain).groups
        trees = []
        for g in range(groups.shape[1]):
            members = [k for k in range(1, model.njoints) if np.any(groups[10 * (k - 1) : 10 * k, g] != 0.0)]
            if not members:
                trees.append((None, np.zeros(0, dtype=int)))
                continue
            member = model.copy()
            member.armature = np.zeros(model.nv)
            for k in range(1, model.njoints):
                if k not in members:
                    member.inertias[k] = pin.Inertia.Zero()
            kept = {int(j) for k in members for j in model.supports[k]}
            locked = [k for k in range(1, model.njoints) if k not in kept]
            reduced = pin.buildReducedModel(member, locked, pin.neutral(model)) if locked else member
            trees.append((reduced, np.array([model.joints[model.getJointId(name)].idx_v for name in reduced.names[1:]])))
        _GROUP_TREES[chain] = trees
    return trees


class _ThreadResources:
    """What the solver of one model needs in one thread, made once: its workspace, K's block order and its batched RNEAs (Pinocchio Data is not shared between threads)."""

    def __init__(self, chain: ClosedChainModel):
        self.chain, self.workspace, self._rneas, self._k_order = chain, _Workspace(chain), {}, None

    def k_order(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """K's block order (:func:`_k_order`) with P₁ on platform 1's coordinates: ~0.7 ms of SciPy graph work, once."""
        if self._k_order is None:
            self._k_order = _k_order(self.workspace, _require_layout(self.chain).platform_v[0])
        return self._k_order

    def rneas(self, parts: bool) -> list[_BatchedRNEA]:
        """The body groups' batched RNEAs (parts), or the whole tree's, armature included."""
        if parts not in self._rneas:
            chain = self.chain
            trees = _group_trees(chain) if parts else [(chain.model, np.arange(chain.model.nv))]
            self._rneas[parts] = [_BatchedRNEA(model, columns) for model, columns in trees]
        return self._rneas[parts]


def _this_thread(chain: ClosedChainModel) -> _ThreadResources:
    """This thread's :class:`_ThreadResources` for ``chain`` (a run reuses the last run's: some 0.3 ms saved each)."""
    cache = getattr(_THREADS, "resources", None)
    if cache is None:
        cache = _THREADS.resources = weakref.WeakKeyDictionary()
    resources = cache.get(chain)
    if resources is None:
        resources = cache[chain] = _ThreadResources(chain)
    return resources


def _platform_frames(chain: ClosedChainModel) -> list:
    """The frames of the platforms' bodies, platform 1 first."""
    model = chain.model
    return [model.frames[model.getFrameId(f"platform_{j}")] for j in (1, 2)]


def _platform_z_axes(data, frames) -> np.ndarray:
    """The platforms' z axes in world axes, (2, 3), from the joint placements in ``data``."""
    return np.array([data.oMi[frame.parentJoint].rotation @ frame.placement.rotation[:, 2] for frame in frames])


def _friction_forces(chain: ClosedChainModel, v, Fe, platform_J, lever_J, platform_z=None) -> np.ndarray:
    """Generalised forces the actuators must supply against friction, shape (n, nv) (spec §4.3, §7.3).

    The friction laws are :mod:`hipsim.physics.laws`'; here they act on the
    tree's own body motions, mapped to its joints by Pinocchio's Jacobians.
    platform_J: (n, 2, 3, 3) angular Jacobians of the platforms on their own
    joints [rx, ry, rz]; lever_J: (n, 2, 3, 3, 2) of the levers on [u1, u2],
    or None when the U and S joints are frictionless; platform_z: (n, 2, 3)
    the platforms' z axes, needed only by the axial-only thrust bearing.
    """
    params, layout = chain.params, chain.layout
    fr = params.friction
    n = len(v)
    Q = np.zeros((n, chain.model.nv))

    # Central chain: hip joint and thrust bearing, a moment on platform j. Components first: (xyz, n, j).
    omega = np.moveaxis(np.einsum("njab,njb->nja", platform_J, v[:, layout.platform_v]), -1, 0)
    z = None if platform_z is None else np.moveaxis(platform_z, -1, 0)
    moment = stack(laws.central_friction_moment(fr, omega, z, Fe[:, None], params.platform_mass * params.gravity))
    if lever_J is not None:
        omega_lever = np.moveaxis(np.einsum("njiab,njib->njia", lever_J, v[:, layout.ujoint_v]), -1, 0)  # (xyz, n, j, i)
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

    The law :func:`inverse_dynamics` adds to the tree's torques: in a
    forward simulation they enter with the opposite sign,
    M a + h = S F − friction_forces + J_cᵀ λ.

    Args:
        chain: the hip model from :func:`load_model`.
        q: configuration (nq,) or configurations (N, nq).
        v: velocities, same leading shape, (nv,) or (N, nv).
        Fe: hydraulic load magnitude in [N], a scalar or (N,).
        data: a ``pin.Data`` of ``chain.model`` to compute in (its kinematics are
            overwritten); None to make one.

    Returns:
        Shape (nv,) or (N, nv), in [N] on the sliders and [N·m] on the revolute joints.
    """
    layout = _require_layout(chain)
    q, single = _configurations(chain, q)
    v = np.atleast_2d(np.asarray(v, dtype=float))
    if v.shape != (len(q), chain.model.nv):
        raise ArgumentError("v", v, f"velocities of shape {(len(q), chain.model.nv)}")
    Fe = np.broadcast_to(np.asarray(Fe, dtype=float), (len(q),))
    model = chain.model
    data = model.createData() if data is None else data
    angular = np.empty((len(q), 3, model.nv))
    axial = chain.params.friction.thrust_bearing_axial_only
    frames = _platform_frames(chain) if axial else None
    platform_z = np.empty((len(q), 2, 3)) if axial else None
    for k, qk in enumerate(q):
        pin.computeJointJacobians(model, data, qk)
        angular[k] = data.J[3:]
        if axial:
            platform_z[k] = _platform_z_axes(data, frames)
    platform_J = np.moveaxis(angular[:, :, layout.platform_v], 1, 2)
    lever_J = np.moveaxis(angular[:, :, layout.ujoint_v], 1, 3) if laws.lever_joint_friction_on(chain.params.friction) else None
    out = _friction_forces(chain, v, Fe, platform_J, lever_J, platform_z)
    return out[0] if single else out


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
        self.chain, self.layout, self.model = chain, _require_layout(chain), chain.model
        self.parts_asked = bool(parts)
        # The whole tree (armature included) for the total, or one tree per body group for the parts.
        self.rneas = _this_thread(chain).rneas(parts)
        self.q, self.v, self.a = q, v, a
        n, nv = len(v), chain.model.nv
        self.Fe = np.broadcast_to(np.asarray(Fe, dtype=float), (n,))
        self.lever_friction = laws.lever_joint_friction_on(chain.params.friction)
        # The axial-only thrust bearing needs each platform's z axis, read from the placements.
        self.platform_frames = _platform_frames(chain) if chain.params.friction.thrust_bearing_axial_only else None
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

    def stored(self, k: int, ws: _Workspace) -> None:
        """Sample k is kept (closure_kernel.store, with the workspace still placed at it): solve the chunk once it is full."""
        slot = k - self.start
        if self.platform_z is not None:
            self.platform_z[slot] = _platform_z_axes(ws.data, self.platform_frames)
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
        friction = _friction_forces(self.chain, v, self.Fe[start:stop], platform_J, lever_J, platform_z)
        if self.parts_asked:
            rhs[3] = self.model.armature * a
            rhs[4] = friction
        else:
            rhs[0] += friction
        tau = np.moveaxis(rhs, 0, 2)  # (m, nv, parts)
        closure_kernel.actuator_and_closure_forces(K_inv, tau, self.chain.actuated_v, self.parts[start:stop], self.lambdas[start:stop].reshape(m, -1))
        self.start = stop

    def result(self, kin: ClosedKinematics) -> ClosedChainDynamics:
        params, closure = self.chain.params, self.layout.closure
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
        torques = Torques(
            total=total,
            platforms=tau_m, levers=tau_l, sliders=tau_s, screws=tau_L, friction=tau_f,
            motor_speed=motor_speed,
            friction_moment=np.linalg.norm(central_chain_friction(params.friction, params.platform_mass * params.gravity, omega, self.Fe, rotation_matrix(kin.angles)), axis=-1),
            # By virtual power the motors' friction share times their speed is the whole friction loss.
            friction_power=np.sum(tau_f * motor_speed, axis=1),
        )
        joint_forces = JointForces(Fa=np.linalg.norm(lambdas, axis=-1), Fo=np.linalg.norm(centre, axis=-1))
        return ClosedChainDynamics(torques=torques, F_act=self.parts.sum(axis=2), lambdas=lambdas, joint_forces=joint_forces)


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
        chain: the hip model from :func:`load_model`.
        kin: the closed motion from :func:`kinematics`.
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
    closer = _Closer(chain, tol=math.inf, max_iter=0)
    ws, n, nv = closer.ws, len(kin.q), chain.model.nv
    V, A, J_rates, residual = np.empty((1, nv)), np.empty((1, nv)), np.empty((n, 3, 3)), np.empty(n)
    rates, accels = np.ascontiguousarray(kin.angle_rates), np.ascontiguousarray(kin.angle_accels)
    for k, q in enumerate(kin.q):
        pin.computeJointJacobians(ws.model, ws.data, q)
        status, _ = closure_kernel.closed_sample(
            *ws.frame_arguments(), math.inf, *closer.constants, rates, accels, V, A, 0, J_rates, residual, k, closer.K_inv, *dynamics.keep(k)
        )  # fmt: skip
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

    trajectory_dynamics(load_model(load_parameters()), iso14242_at([0.0, 0.001, 0.002]))


def trajectory_dynamics(
    chain: ClosedChainModel, traj, *, tol: float = 1e-12, max_iter: int = 50, parts: bool = True,
    continuation: Continuation | None = None,
) -> tuple[ClosedKinematics, ClosedChainDynamics]:
    """:func:`kinematics` and :func:`inverse_dynamics` in one pass, with the trajectory's own load.

    Faster than the two calls: the dynamics reuse the Jacobians the
    kinematics computed at each closed configuration.

    Args:
        chain: the hip model from :func:`load_model`.
        traj: a Trajectory-like object with t, q, qd, qdd (see
            :func:`kinematics`) and Fe (N,) in [N].
        tol: closure gap accepted in [m], as in :func:`kinematics`.
        max_iter: damped Gauss–Newton iterations allowed per sample.
        parts: split the torques into their parts (as :func:`inverse_dynamics`).
        continuation: for a run in pieces, one :class:`Continuation` passed to
            every piece in time order: the pieces then give the one-piece
            results bit for bit.

    Returns:
        The closed motion and the torques.
    """
    return _close_chain(chain, traj, tol, max_iter, Fe=traj.Fe, parts=parts, continuation=continuation)
