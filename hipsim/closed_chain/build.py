"""Loading the closed-chain model: a URDF tree and its loop closures as Pinocchio objects, and the hip simulator's joint map (spec §6).

The kinematic tree comes from the URDF that :mod:`hipsim.machine.model_files`
expands from the parameter set; the six lever-tip ↔ platform-joint loops come
from ``models/hip_simulator.yaml`` and become 3-D point constraints
(``pin.RigidConstraintModel``, CONTACT_3D, LOCAL). :func:`load_model` adds the
hip's joint map (:class:`HipLayout`) that the solver
(:mod:`~hipsim.closed_chain.closure`, :mod:`~hipsim.closed_chain.dynamics`) reads.
Each model owns its solver's per-thread state (:class:`~hipsim.closed_chain.solver.ClosedChainSolver`).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import pinocchio as pin
import yaml

from ..exceptions import ModelError
from ..machine.chains import STACKUP_CLOSURE, STACKUP_JOINTS
from ..machine.model_files import closure_declaration, closure_file_path, urdf_text
from ..machine.parameters import Parameters, load_parameters
from ..physics.transmission import radians_per_travel
from .solver import ClosedChainSolver

__all__ = [
    "ClosedChainModel",
    "HipLayout",
    "controlled_platform",
    "load_closed_chain",
    "load_model",
    "require_layout",
    "require_params",
]


@dataclass(frozen=True, eq=False)
class HipLayout:
    """Where the hip simulator's joints, bodies and closures sit in the Pinocchio model.

    All index arrays are velocity indices (the hip's joints are all 1-DoF, so
    they are configuration indices too).
    """

    platform_v: np.ndarray  # (2, 3): platform j's [rx, ry, rz] joints, i.e. [α, β, γ]
    slider_v: np.ndarray  # (3,)
    ujoint_v: np.ndarray  # (2, 3, 2): lever ji's [u1, u2]
    closure: np.ndarray  # (2, 3): closure index of lever ji
    slider_offset: np.ndarray  # (3,): L_1i - L_2i in [m], read from the tree
    leg_v: np.ndarray  # (15,) or (18,): the leg coordinates (sliders, universal joints, the stack-up's slides)
    groups: np.ndarray  # (10·(njoints−1), 3): dynamic parameters of platforms, levers, carriages
    initial_guess: np.ndarray  # (nq,): levers upright, tips at platform 1's height
    #: With a stack-up: the spline's axial slide and the shaft end's X, Y slides (STACKUP_JOINTS); else empty.
    stackup_v: np.ndarray = dataclasses.field(default_factory=lambda: np.zeros(0, dtype=int))


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
        solver: the closure solver's per-thread state for this model (made
            per model, not copied by ``dataclasses.replace``).
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
    layout: HipLayout | None = None
    solver: ClosedChainSolver = field(init=False, repr=False)

    def __post_init__(self):
        object.__setattr__(self, "solver", ClosedChainSolver(self))

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


def _read_closures(path: str | Path | dict) -> dict:
    if isinstance(path, dict):  # a declaration already read (closure_declaration)
        content = path
        path = "the closure declaration"
    else:
        content = _load_yaml(path)
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


def _load_yaml(path: str | Path):
    try:
        with open(path, encoding="utf-8") as stream:
            content = yaml.safe_load(stream)
    except OSError as error:
        raise ModelError(f"cannot read closure file {path}: {error}") from None
    except yaml.YAMLError as error:
        raise ModelError(f"{path}: not valid YAML ({error})") from None
    return content


def load_closed_chain(
    urdf: str | Path,
    closure_file: str | Path | dict,
    *,
    gravity: float = 9.81,
    lead: float | None = None,
    rotor_inertia: float | None = None,
) -> ClosedChainModel:
    """Build a closed-chain model from a URDF and a closure file (Gepetto's extended-URDF layout).

    Args:
        urdf: URDF text, or the path of a URDF file.
        closure_file: YAML (or its content, parsed) with ``closed_loop`` (frame pairs), ``type``
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
    where = "the closure declaration" if isinstance(closure_file, dict) else closure_file
    constraint_models = pin.StdVec_RigidConstraintModel()
    for (name1, name2), kind in zip(content["closed_loop"], content["type"]):
        frames = []
        for name in (name1, name2):
            if not model.existFrame(name):
                raise ModelError(f"{where}: closure frame '{name}' is not in the URDF")
            frames.append(model.frames[model.getFrameId(name)])
        contact = {"3d": pin.ContactType.CONTACT_3D, "6d": pin.ContactType.CONTACT_6D}.get(str(kind).lower())
        if contact is None:
            raise ModelError(f"{where}: closure type '{kind}' of {name1}-{name2} is not '3d' or '6d'")
        constraint = pin.RigidConstraintModel(
            contact,
            model,
            frames[0].parentJoint,
            frames[0].placement,
            frames[1].parentJoint,
            frames[1].placement,
            pin.ReferenceFrame.LOCAL,
        )
        constraint.name = f"{name1}-{name2}"
        constraint_models.append(constraint)

    actuated = tuple(str(name) for name in content["name_mot"])
    actuated_v = []
    for name in actuated:
        if not model.existJointName(name):
            raise ModelError(f"{where}: actuated joint '{name}' is not in the URDF")
        joint = model.joints[model.getJointId(name)]
        if joint.nv != 1:
            raise ModelError(f"{where}: actuated joint '{name}' has {joint.nv} DoF, expected 1")
        actuated_v.append(joint.idx_v)

    transmission = content.get("transmission") or {}
    if lead is None or rotor_inertia is None:
        try:
            leads = {float(transmission[n]["lead_m"]) for n in actuated if n in transmission}
            inertias = {float(transmission[n]["rotor_inertia_kgm2"]) for n in actuated if n in transmission}
        except (KeyError, TypeError, ValueError) as error:
            message = f"{where}: transmission needs lead_m and rotor_inertia_kgm2 per joint ({error})"
            raise ModelError(message) from None
        if len(leads) > 1 or len(inertias) > 1:
            raise ModelError(f"{where}: actuated joints with different transmissions are not supported")
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
        # With a stack-up, the seat closure too (the shipped file holds the drawing's six).
        closure_declaration(params) if params.chains.stacked else closure_file_path(),
        gravity=params.gravity,
        lead=params.lead,
        rotor_inertia=params.screw_inertia,
    )
    layout = _hip_layout(chain, params)
    return dataclasses.replace(chain, params=params, layout=layout)


def _hip_layout(chain: ClosedChainModel, params: Parameters) -> HipLayout:
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
    stacked = params.chains.stacked
    stackup_v = np.array([idx(name) for name in STACKUP_JOINTS] if stacked else [], dtype=int)
    if stacked and STACKUP_CLOSURE not in chain.closure_frames:
        raise ModelError("the closure file has no seat closure {}-{}".format(*STACKUP_CLOSURE))
    if sorted(chain.actuated_v) != sorted(slider_v) or chain.n_closures != 6 + stacked:
        raise ModelError(
            "the hip simulator needs six closures (seven with a stack-up) and the three sliders as actuated joints"
        )

    placement_z = np.array(
        [[model.jointPlacements[joint(f"u1_{j}{i}")].translation[2] for i in (1, 2, 3)] for j in (1, 2)]
    )
    leg_v = np.array(sorted(set(slider_v) | set(ujoint_v.ravel()) | set(stackup_v)))

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
    return HipLayout(
        platform_v=platform_v,
        slider_v=slider_v,
        ujoint_v=ujoint_v,
        closure=closure,
        # A per-chain machine reports carriage readings: L_2i = L_1i − (h_1 − h_2), as on the drawing.
        slider_offset=placement_z[0] - placement_z[1]
        if params.geometry is None
        else np.full(3, params.heights[0] - params.heights[1]),
        leg_v=leg_v,
        groups=groups,
        initial_guess=initial_guess,
        stackup_v=stackup_v,
    )


def require_layout(chain: ClosedChainModel) -> HipLayout:
    """The hip simulator's layout of ``chain`` (from :func:`load_model`).

    Raises:
        ModelError: ``chain`` is a general closed-chain model without the hip simulator's layout.
    """
    if chain.layout is None:
        raise ModelError("this function needs the hip simulator model from load_model()")
    return chain.layout


def require_params(chain: ClosedChainModel) -> Parameters:
    """The parameter set ``chain`` was built from (:func:`load_model`).

    Raises:
        ModelError: ``chain`` is a general closed-chain model, built from a URDF without hipsim's parameters.
    """
    if chain.params is None:
        raise ModelError("this function needs a model built from hipsim's parameters (load_model())")
    return chain.params


def controlled_platform(chain: ClosedChainModel) -> int | None:
    """On a per-chain machine, the index (0: m_1, 1: m_2) of the platform whose angles a trajectory gives; None on the drawing.

    The drawing's platforms turn alike, so a trajectory holds both; a per-chain machine's
    ``[geometry] control`` platform is held at the trajectory and the other one is solved
    with the legs (:class:`~hipsim.closed_chain.closure.Closer`).
    """
    params = chain.params
    if params is None or params.geometry is None:
        return None
    return params.geometry.control - 1
