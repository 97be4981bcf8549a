"""The machine as a MuJoCo model (MJCF): the URDF's tree, the six closures as ``connect`` equalities.

:func:`mjcf_text` converts the very URDF that
:func:`hipsim.machine.model_files.urdf_text` expands from a parameter set, and
the closure declaration of :func:`hipsim.machine.model_files.closure_declaration`,
into MJCF:

* URDF links become bodies, joints become MuJoCo joints (revolute → hinge,
  prismatic → slide), inertials become explicit body inertia, visuals become
  visual-only geoms (no collision, no mass) with the URDF's materials, so the
  scene is the one the meshcat viewer draws. MuJoCo refuses a moving body
  without mass, and the URDF spells a universal joint and a spherical joint
  as revolute chains through massless links (the U joint's cross, the
  platform's gimbal links); each such link is merged into the body it
  carries, its joint moving along: MuJoCo applies a body's joints in order,
  each about its own anchor, which is exactly the chain. The cross's ball
  rides on the lever body (a sphere on every later joint's axis, so it looks
  the same). Massless leaves on fixed joints (the closure frames
  ``lever_ji_tip``, ``platform_j_joint_i``) become sites. The result has the
  21 joints of the Pinocchio model with the same names and meaning.
* With a stack-up (``[geometry] spline_seat_mm``), the URDF's intermediate chain
  (:func:`hipsim.machine.chains.per_chain_urdf`: 24 joints) has two massless links
  that carry no single moving body: the spline's slide (m_1 and the shaft's end
  hang from it) and the shaft end's slides (only the seat frame). MuJoCo gets them
  as bodies of :data:`~hipsim.mujoco_engine.machine.PLACEHOLDER_MASS` (1 mg): the inverse
  dynamics take it out exactly (:mod:`~hipsim.mujoco_engine.dynamics`); in the plant it
  is the only difference from the massless shaft of the other models (its inertia
  force, 1e-6 kg times the shaft end's ~0.1 m/s², is some 1e-7 N).
* Each ``3d`` closure becomes a ``connect`` equality between its two sites.
* Each actuated joint (a slider) gets the screw's rotor inertia as joint
  armature I_L·(2π/p)² and a ``motor`` actuator whose control is the motor
  torque in N·m and whose gear is 2π/p (the lead): force = (2π/p)·torque;
  ``ctrlrange`` is the torque limit when it is finite.
* A keyframe ``iso_start`` at the built-in ISO 14242-1 cycle's first sample:
  the closed configuration and velocity (closure gap below 1e-13 m, solved
  with MuJoCo's own constraint rows) and the inverse-dynamics motor torques as
  controls, so that a simulation started there follows the cycle at first.

hipsim writes the MJCF text itself and compiles that very text: MuJoCo's own
writer (``MjSpec.to_xml``) keeps six significant digits, which moves joints by
up to 1e-6 m and opens the closures as much.

Settings (:class:`MjcfSettings`), and why:

* ``timestep = 0.5 ms``, ``integrator = RK4``: the servo settings of the
  parameter file (1 kHz servo, RK4 0.5 ms), the fourth-order method the other
  plants use.
* ``solref = (4·timestep, 1)`` with RK4, ``(2·timestep, 1)`` otherwise
  (:func:`default_solref`): the closures' error dynamics critically damped, as
  fast as the integrator resolves them.
* ``solimp = (0.9999, 0.9999, 0.001, 0.5, 2)``: the largest impedance MuJoCo
  accepts (mjMAXIMP), i.e. the least compliant constraint. A loop closure is
  a machine part, not a contact: no softness is wanted. With 0.99 the gaps
  and the tracking difference to the rigid Pinocchio plant grow a hundredfold.
* Dense Jacobians (21 DoF), Newton solver (equality constraints only: one
  Newton iteration solves them), contacts off (the geoms only draw).

The friction of spec §4.3 (load-dependent Coulomb moments) has no MJCF
element: the plant and the inverse dynamics add it as forces
(:mod:`hipsim.mujoco_engine.plant`). Units: SI (m, kg, kg·m², rad, N, N·m).

Example:
    >>> import hipsim
    >>> from hipsim.mujoco_engine.mjcf import mjcf_text
    >>> xml = mjcf_text(hipsim.load_parameters())   # doctest: +SKIP
"""

from __future__ import annotations

import io
import math
import os
import xml.etree.ElementTree as ET
from collections import defaultdict
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import yourdfpy

from ..exceptions import ArgumentError, ModelError
from ..files import write_atomic
from ..machine.model_files import closure_declaration, urdf_text
from ..machine.parameters import Parameters, load_parameters
from ..physics.transmission import radians_per_travel
from ._dependency import mujoco
from .dynamics import inverse_dynamics
from .machine import PLACEHOLDER_MASS, STACKUP_BODIES, MujocoMachine
from .trajectory import kinematics

__all__ = [
    "INTEGRATORS",
    "KEYFRAME",
    "MjcfSettings",
    "compile_mjcf",
    "default_solref",
    "keyframe_gap",
    "mjcf_text",
    "write_mjcf",
]

#: Name of the keyframe at the ISO cycle's first sample.
KEYFRAME = "iso_start"

_VISUAL_GROUP = 1  # MuJoCo's viewer shows groups 0-2; the closure sites go in 4 (hidden unless asked)
_SITE_GROUP = 4

#: mjMAXIMP: the largest impedance MuJoCo accepts.
_MAX_IMPEDANCE = 0.9999


@dataclass(frozen=True)
class MjcfSettings:
    """The simulation settings written into the MJCF.

    Attributes:
        timestep: integration step in [s].
        integrator: one of :data:`INTEGRATORS`, as MJCF spells them.
        solref: (time constant [s], damping ratio) of the closures' error
            dynamics; None for :func:`default_solref`.
        solimp: (d0, d_width, width [m], midpoint, power) of the closures'
            impedance; d near 1 is a stiff constraint.
    """

    timestep: float = 0.5e-3
    integrator: str = "RK4"
    solref: tuple[float, float] | None = None
    solimp: tuple[float, ...] = (_MAX_IMPEDANCE, _MAX_IMPEDANCE, 0.001, 0.5, 2.0)

    def __post_init__(self):
        if not (math.isfinite(self.timestep) and self.timestep > 0):
            raise ArgumentError("timestep", self.timestep, "a positive number of seconds")
        if self.integrator not in INTEGRATORS:
            raise ArgumentError("integrator", self.integrator, f"one of {', '.join(INTEGRATORS)}")

    @property
    def closure_solref(self) -> tuple[float, float]:
        """solref of the closures: the given one, or :func:`default_solref` at this step and integrator."""
        return self.solref if self.solref is not None else default_solref(self.timestep, self.integrator)


def default_solref(timestep: float, integrator: str) -> tuple[float, float]:
    """The closures' (time constant [s], damping ratio): critically damped, 4 steps with RK4, 2 otherwise.

    Two steps is the shortest time constant MuJoCo lets a semi-implicit Euler
    step use (``refsafe``); it gives the smallest closure gaps with Euler and
    the implicit integrators, whose tracking error does not depend on it. With
    RK4 four steps resolve the closure's error dynamics better: along 0.2 s of
    the ISO cycle under the augmented PD at 0.5 ms the angles then agree with
    the Pinocchio plant to 4.6e-7° (2.1e-6° with two steps), for a gap of
    9e-9 m (2e-9 m).
    """
    return (4.0 if integrator == "RK4" else 2.0) * timestep, 1.0


#: The integrators MJCF names (option/integrator).
INTEGRATORS = ("Euler", "RK4", "implicitfast", "implicit")


def _text(values) -> str:
    """Numbers as MJCF text, each the shortest that reads back as the same double.

    MuJoCo's own writer (``MjSpec.to_xml``) keeps six significant digits, which
    moves the joints by up to 1e-6 m and opens the closures as much: hipsim
    therefore writes the MJCF itself and compiles that very text.
    """
    return " ".join(_number(float(v)) for v in np.atleast_1d(values))


def _number(value: float) -> str:
    if value == int(value) and abs(value) < 1e15:
        return str(int(value))  # "1", not "1.0"; and "-0.0" becomes "0"
    return repr(value)


def _quat(rotation: np.ndarray) -> np.ndarray:
    quat = np.empty(4)
    mujoco.mju_mat2Quat(quat, np.ascontiguousarray(rotation, dtype=float).ravel())
    return quat


def _place(element, pose: np.ndarray) -> None:
    """Set an element's pos and quat from a 4×4 pose in its body's frame (left out where zero / identity)."""
    if np.any(pose[:3, 3] != 0.0):
        element.set("pos", _text(pose[:3, 3]))
    if np.any(pose[:3, :3] != np.eye(3)):
        element.set("quat", _text(_quat(pose[:3, :3])))


def _origin(element) -> np.ndarray:
    """The 4×4 origin of a URDF element (identity where the URDF gives none)."""
    return np.eye(4) if element.origin is None else np.asarray(element.origin, dtype=float)


def _geometry(visual) -> tuple[str, list[float]]:
    """MJCF geom type and size of a URDF visual (URDF sizes are full lengths, MuJoCo's halves)."""
    g = visual.geometry
    if g.sphere is not None:
        return "sphere", [g.sphere.radius]
    if g.cylinder is not None:
        return "cylinder", [g.cylinder.radius, g.cylinder.length / 2.0]
    if g.box is not None:
        return "box", [s / 2.0 for s in g.box.size]
    raise ModelError(f"visual '{visual.name}': only spheres, cylinders and boxes are converted to MJCF")


def _is_massless(link) -> bool:
    return link.inertial is None or (link.inertial.mass == 0.0 and not np.any(link.inertial.inertia))


class _Converter:
    """URDF (as yourdfpy parses it) → MJCF bodies, joints, geoms and sites under ``worldbody``."""

    def __init__(self, root: ET.Element, robot):
        self.links = {link.name: link for link in robot.links}
        self.children = defaultdict(list)
        for joint in robot.joints:
            self.children[joint.parent].append(joint)
        self.asset = ET.SubElement(root, "asset")
        self.materials = set()
        for material in robot.materials:
            if material.color is not None:
                self.materials.add(material.name)
                ET.SubElement(self.asset, "material", name=material.name, rgba=_text(material.color.rgba))
        self.worldbody = ET.SubElement(root, "worldbody")
        roots = set(self.links) - {joint.child for joint in robot.joints}
        if len(roots) != 1:
            raise ModelError(f"the URDF must have one root link, found {sorted(roots)}")
        self.root = roots.pop()

    def run(self) -> ET.Element:
        if not _is_massless(self.links[self.root]):
            raise ModelError(f"root link '{self.root}' has mass: it is the fixed base and becomes MuJoCo's world")
        self._visit(self.links[self.root], self.worldbody, np.eye(4))
        return self.worldbody

    def _visuals(self, link, body: ET.Element, pose: np.ndarray) -> None:
        for visual in link.visuals:
            kind, size = _geometry(visual)
            geom = ET.SubElement(body, "geom", name=visual.name or "", type=kind, size=_text(size))
            if not visual.name:
                del geom.attrib["name"]
            _place(geom, pose @ _origin(visual))
            if visual.material is not None and visual.material.name in self.materials:
                geom.set("material", visual.material.name)
            elif visual.material is not None and visual.material.color is not None:
                geom.set("rgba", _text(visual.material.color.rgba))
            # Drawing only: no contacts, no mass (the bodies' inertia is the URDF's).
            geom.set("contype", "0")
            geom.set("conaffinity", "0")
            geom.set("group", str(_VISUAL_GROUP))
            geom.set("mass", "0")

    def _visit(self, link, body: ET.Element, pose: np.ndarray) -> None:
        """Add ``link`` (whose frame sits at ``pose`` in ``body``) and, recursively, what hangs from it."""
        self._visuals(link, body, pose)
        for joint in self.children[link.name]:
            child = self.links[joint.child]
            if joint.type == "fixed":
                if not _is_massless(child) or self.children[child.name]:
                    raise ModelError(
                        f"fixed joint '{joint.name}': only a massless leaf (a frame) can be fixed to a body"
                    )
                site = ET.SubElement(body, "site", name=child.name, size="0.005", group=str(_SITE_GROUP))
                _place(site, pose @ _origin(joint))
                self._visuals(child, body, pose @ _origin(joint))
                continue
            chain = [joint]
            while _is_massless(child):
                # A massless link between two joints: merge it into the body it carries.
                onward = self.children[child.name]
                if len(onward) == 1 and onward[0].type != "fixed":
                    chain.append(onward[0])
                    child = self.links[onward[0].child]
                elif child.name in STACKUP_BODIES:  # the stack-up's slides: MuJoCo needs a mass (PLACEHOLDER_MASS)
                    break
                else:
                    raise ModelError(f"link '{child.name}' has no mass and does not carry exactly one moving body")
            self._body(chain, body, pose, child)

    def _body(self, chain, parent: ET.Element, pose: np.ndarray, link) -> None:
        """The body of ``link`` moved by the joints of ``chain`` (outermost first)."""
        # after[k]: pose of the body's frame in the frame of joint k's child link, at zero joint values.
        after = [np.eye(4)]
        for joint in reversed(chain[1:]):
            after.insert(0, _origin(joint) @ after[0])
        frame = pose
        for joint in chain:
            frame = frame @ _origin(joint)
        body = ET.SubElement(parent, "body", name=link.name)
        _place(body, frame)
        self._inertia(body, link)
        for joint, placement in zip(chain, after):
            inverse = np.linalg.inv(placement)  # the joint's frame in the body's frame
            kind = {"revolute": "hinge", "continuous": "hinge", "prismatic": "slide"}.get(joint.type)
            if kind is None:
                raise ModelError(f"joint '{joint.name}' of type {joint.type} is not converted to MJCF")
            axis = inverse[:3, :3] @ np.asarray(joint.axis, dtype=float)
            element = ET.SubElement(body, "joint", name=joint.name, type=kind, axis=_text(axis / np.linalg.norm(axis)))
            if np.any(inverse[:3, 3] != 0.0):
                element.set("pos", _text(inverse[:3, 3]))
            # No limits, as in the Pinocchio model: the closures keep every joint in range.
            element.set("limited", "false")
        for k, (joint, placement) in enumerate(zip(chain[:-1], after[:-1])):
            merged = self.links[joint.child]
            self._check_round(merged, chain[k + 1 :])
            self._visuals(merged, body, np.linalg.inv(placement))
        self._visit(link, body, np.eye(4))

    @staticmethod
    def _check_round(link, onward) -> None:
        """A merged link's visuals turn with the body it joins: allowed only where that changes nothing."""
        for visual in link.visuals:
            centre = _origin(visual)[:3, 3]
            on_axes = all(
                np.linalg.norm(
                    np.cross(centre - _origin(j)[:3, 3], _origin(j)[:3, :3] @ np.asarray(j.axis, dtype=float))
                )
                < 1e-12
                for j in onward
            )
            if visual.geometry.sphere is None or not on_axes:
                raise ModelError(f"visual '{visual.name}' of massless link '{link.name}' would turn with the next body")

    @staticmethod
    def _inertia(body: ET.Element, link) -> None:
        if _is_massless(link):  # one of STACKUP_BODIES
            inertia = _text([PLACEHOLDER_MASS * 1e-4] * 3)
            ET.SubElement(body, "inertial", pos="0 0 0", mass=_text(PLACEHOLDER_MASS), diaginertia=inertia)
            return
        inertial = link.inertial
        origin = _origin(inertial)
        tensor = origin[:3, :3] @ np.asarray(inertial.inertia, dtype=float) @ origin[:3, :3].T
        element = ET.SubElement(body, "inertial", pos=_text(origin[:3, 3]), mass=_text(inertial.mass))
        if np.count_nonzero(tensor - np.diag(np.diag(tensor))) == 0:
            element.set("diaginertia", _text(np.diag(tensor)))
        else:
            element.set(
                "fullinertia",
                _text([tensor[0, 0], tensor[1, 1], tensor[2, 2], tensor[0, 1], tensor[0, 2], tensor[1, 2]]),
            )


def _document(params: Parameters, settings: MjcfSettings) -> ET.Element:
    """The MJCF document without keyframe: options, assets, tree, closures, actuators."""
    root = ET.Element("mujoco", model="hip_simulator")
    ET.SubElement(root, "compiler", angle="radian", autolimits="false")
    option = ET.SubElement(
        root,
        "option",
        timestep=_text(settings.timestep),
        integrator=settings.integrator,
        gravity=_text([0.0, 0.0, -params.gravity]),
        jacobian="dense",
        solver="Newton",
    )
    ET.SubElement(option, "flag", contact="disable")
    robot = yourdfpy.URDF.load(io.StringIO(urdf_text(params)), build_scene_graph=False, load_meshes=False).robot
    worldbody = _Converter(root, robot).run()
    _add_camera(worldbody, params)

    declaration = closure_declaration(params)
    equality = ET.SubElement(root, "equality")
    for (site1, site2), kind in zip(declaration["closed_loop"], declaration["type"]):
        if str(kind).lower() != "3d":
            raise ModelError(
                f"closure {site1}-{site2}: type '{kind}' is not converted to MJCF (only '3d' point closures)"
            )
        ET.SubElement(
            equality,
            "connect",
            name=f"{site1}-{site2}",
            site1=site1,
            site2=site2,
            solref=_text(settings.closure_solref),
            solimp=_text(settings.solimp),
        )
    gear = radians_per_travel(params.lead)
    limit = params.control.torque_limit
    joints = {element.get("name"): element for element in worldbody.iter("joint")}
    actuator = ET.SubElement(root, "actuator")
    for number, joint_name in enumerate(declaration["name_mot"], start=1):
        if joint_name not in joints:
            raise ModelError(f"actuated joint '{joint_name}' is not in the URDF")
        # The screw's rotor, seen from the slider: I_L·(2π/p)².
        joints[joint_name].set("armature", _text(params.screw_inertia * gear**2))
        motor = ET.SubElement(actuator, "motor", name=f"motor_{number}", joint=joint_name, gear=_text(gear))
        if math.isfinite(limit):
            motor.set("ctrllimited", "true")
            motor.set("ctrlrange", _text([-limit, limit]))
        else:
            motor.set("ctrllimited", "false")
    return root


def _add_camera(worldbody: ET.Element, params: Parameters) -> None:
    """A light and the meshcat viewer's default view of the machine, from the front right."""
    target = np.array([0.0, 0.0, 0.69 * params.heights[0]])
    eye = target + np.array([1.0, 1.2, 0.53])
    forward = (target - eye) / np.linalg.norm(target - eye)
    right = np.cross(forward, [0.0, 0.0, 1.0])
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    ET.SubElement(worldbody, "camera", name="overview", pos=_text(eye), xyaxes=_text([*right, *up]))
    ET.SubElement(worldbody, "light", name="top", pos="0 0 3", dir="0 0 -1", directional="true")


def _serialise(root: ET.Element) -> str:
    ET.indent(root, space="  ")
    return ET.tostring(root, encoding="unicode") + "\n"


def mjcf_text(params: Parameters | None = None, settings: MjcfSettings | None = None, keyframe: bool = True) -> str:
    """The MJCF document of a parameter set.

    Args:
        params: the machine, SI; None for the published machine.
        settings: time step, integrator and closure softness; None for the defaults.
        keyframe: add the keyframe :data:`KEYFRAME` at the ISO cycle's first
            sample (its closure solve and inverse dynamics use MuJoCo itself).

    Returns:
        The MJCF text; ``mujoco.MjModel.from_xml_string`` compiles it. The same
        parameters and settings always give the same text.

    Raises:
        ModelError: the URDF or closure file holds something the converter does not handle.
    """
    params = load_parameters() if params is None else params
    settings = MjcfSettings() if settings is None else settings
    root = _document(params, settings)
    root.insert(
        0,
        ET.Comment(
            " The 2(3PUS+S) hip joint simulator, generated by hipsim.mujoco_engine.mjcf from one parameter set; do not edit. "
            "Units: m, kg, kg·m², rad, N; motor controls in N·m. Six connect equalities close the levers onto the "
            f"platforms; keyframe '{KEYFRAME}' is the ISO 14242-1 cycle's first sample. "
        ),
    )
    if keyframe:
        from ..motion.trajectories import iso14242_at

        machine = MujocoMachine(compile_mjcf(_serialise(root)), params)
        start = iso14242_at(np.array([0.0]))
        kin = kinematics(machine, start)
        torques = inverse_dynamics(machine, kin, start.Fe)
        keys = ET.SubElement(root, "keyframe")
        ET.SubElement(
            keys,
            "key",
            name=KEYFRAME,
            time="0",
            qpos=_text(kin.q[0]),
            qvel=_text(kin.v[0]),
            ctrl=_text(torques.torques.total[0]),
        )
    return _serialise(root)


def compile_mjcf(text: str):
    """``mujoco.MjModel`` of an MJCF text, MuJoCo's errors as :class:`~hipsim.exceptions.ModelError`."""
    try:
        return mujoco.MjModel.from_xml_string(text)
    except ValueError as error:
        message = "; ".join(line.strip() for line in str(error).splitlines() if line.strip())
        if "inertia of moving bodies" in message:
            message += (
                " (MuJoCo needs every principal moment of inertia positive: slender-rod levers, "
                "I_l = diag(I_t, I_t, 0), cannot be simulated in MuJoCo)"
            )
        raise ModelError(f"MuJoCo cannot compile the MJCF: {message}") from None


def write_mjcf(
    params: Parameters | None = None,
    path: str | os.PathLike = "hip_simulator.xml",
    settings: MjcfSettings | None = None,
) -> Path:
    """Write the MJCF of a parameter set, atomically.

    Args:
        params: the machine, SI; None for the published machine.
        path: the output file.
        settings: as in :func:`mjcf_text`.

    Returns:
        The path written.
    """
    return write_atomic(path, mjcf_text(params, settings))


def keyframe_gap(model, key: str = KEYFRAME) -> float:
    """Largest closure gap |p₁ − p₂| in [m] at a keyframe of a compiled model (default :data:`KEYFRAME`)."""
    k = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_KEY, key)
    if k < 0:
        raise ModelError(f"the MuJoCo model has no keyframe '{key}'")
    data = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, data, k)
    mujoco.mj_kinematics(model, data)
    sites = data.site_xpos
    return max(float(np.linalg.norm(sites[model.eq_obj1id[e]] - sites[model.eq_obj2id[e]])) for e in range(model.neq))
