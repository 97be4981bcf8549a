"""The hip simulator (and the human beside it) as meshcat nodes: built once, then posed frame by frame.

A :class:`Scene` loads the Pinocchio model's visuals (and, if asked,
example-robot-data's human) into a meshcat Visualizer, sets the background
and the camera, and then turns one frame (a closed configuration, the hip
angles, the forces) into node transforms. It also draws what the models do
not have: the force arrows (a cylinder and a cone, at a scale in mm per N)
and the levers' singularity colours.

Where the commands go, a live server or an offline page, is the
Visualizer's window (:mod:`hipsim.present.meshcat_output`).
"""

from __future__ import annotations

import warnings
from typing import Any

import numpy as np
import pinocchio as pin

from ..exceptions import ArgumentError
from ..machine.parameters import Parameters
from .human import HIP_JOINTS, HUMAN_PELVIS_POSITION, HUMAN_PELVIS_ROTATION, load_human
from .motion_frames import Motion

__all__ = [
    "JOINT_FORCE_COLOUR",
    "LONGEST_ARROW",
    "MOTOR_FORCE_COLOUR",
    "SINGULARITY_STOPS",
    "Scene",
    "arrow_scale",
    "force_scale_for",
    "import_meshcat",
    "singularity_colour",
]

#: Longest force arrow the automatic scale allows, in [m].
LONGEST_ARROW = 0.3
#: Force scales the automatic choice picks from, in [m per N] (1 mm/N and down in 1-2-5 steps).
_SCALES = tuple(m * 10.0**-e for e in range(3, 8) for m in (1.0, 0.5, 0.2))
#: Colours (RGB, 0..1) of the force arrows.
MOTOR_FORCE_COLOUR = (0.85, 0.10, 0.80)
JOINT_FORCE_COLOUR = (0.05, 0.75, 0.85)
#: Singularity colour map: (inverse condition number, RGB) stops, clamped beyond the ends.
SINGULARITY_STOPS = ((0.0, (0.85, 0.10, 0.10)), (0.25, (0.95, 0.85, 0.10)), (0.5, (0.45, 0.90, 0.10)))

MACHINE_ROOT = "hipsim/machine"
HUMAN_ROOT = "hipsim/human"
FORCES_ROOT = "hipsim/forces"

# Camera: orbit target and camera position in world axes [m], without and with the human.
_CAMERA = {False: ((0.0, 0.0, 0.62), (1.0, 1.2, 1.15)), True: ((0.0, 0.45, 0.72), (2.1, 0.95, 1.25))}


# ---------------------------------------------------------------------------
# Small pure helpers
# ---------------------------------------------------------------------------


def import_meshcat():
    """meshcat (and Pinocchio's meshcat visualiser), without the DeprecationWarning meshcat 0.3 triggers in pyzmq."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)
        import meshcat
        import meshcat.animation
        import meshcat.commands
        import meshcat.geometry
        import pinocchio.visualize  # noqa: F401 - imports meshcat too

    return meshcat


def singularity_colour(cond_inv) -> np.ndarray:
    """RGB (0..1) of the singularity measure: red 0 (singular), yellow 0.25, green ≥ 0.5.

    Args:
        cond_inv: inverse condition number(s) of J; NaN counts as 0.

    Returns:
        Shape (..., 3).
    """
    c = np.nan_to_num(np.asarray(cond_inv, dtype=float), nan=0.0)
    stops = np.array([s for s, _ in SINGULARITY_STOPS])
    colours = np.array([rgb for _, rgb in SINGULARITY_STOPS])
    return np.stack([np.interp(c, stops, colours[:, k]) for k in range(3)], axis=-1)


def force_scale_for(peak_force: float, longest: float = LONGEST_ARROW) -> float:
    """The arrow scale in [m per N]: the largest of 1, 0.5, 0.2, 0.1, … mm/N that keeps the longest arrow ≤ ``longest``."""
    for scale in _SCALES:
        if peak_force * scale <= longest:
            return scale
    return _SCALES[-1]


def arrow_scale(motion: Motion, force_scale: float | None = None) -> float:
    """The arrow scale of a motion with forces in [m per N]: ``force_scale``, or if None one for its peak force."""
    if force_scale is not None:
        return force_scale
    forces = motion.forces()
    if forces is None:
        raise ArgumentError("motion", motion.name, "a motion with forces, or a force_scale")
    F_act, F_joint = forces
    peak = max(float(np.abs(F_act).max()), float(np.linalg.norm(F_joint, axis=-1).max()))
    return force_scale_for(peak)


def scale_text(scale: float) -> str:
    """An arrow scale in [m per N] as text in mm per N."""
    return f"{scale * 1e3:g} mm per N"


def _rotation_y_to(d: np.ndarray) -> np.ndarray:
    """A rotation taking the Y axis (meshcat's cylinder and cone axis) onto the unit vector d."""
    d = d / np.linalg.norm(d)
    y = np.array([0.0, 1.0, 0.0])
    c = float(y @ d)
    if c < -1.0 + 1e-12:
        return np.diag([1.0, -1.0, -1.0])
    v = np.cross(y, d)
    K = np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])
    return np.eye(3) + K + K @ K / (1.0 + c)


def _homogeneous(R: np.ndarray, p: np.ndarray) -> np.ndarray:
    T = np.eye(4)
    T[:3, :3], T[:3, 3] = R, p
    return T


# ---------------------------------------------------------------------------
# Geometry the models do not have: arrows
# ---------------------------------------------------------------------------


def _cone_class():
    import meshcat.geometry as mg

    class Cone(mg.Geometry):
        """three.js ConeGeometry: axis along Y, apex at +height/2."""

        def __init__(self, height: float, radius: float, segments: int = 24):
            super().__init__()
            self.height, self.radius, self.segments = height, radius, segments

        def lower(self, object_data):
            return {
                "uuid": self.uuid,
                "type": "ConeGeometry",
                "radius": self.radius,
                "height": self.height,
                "radialSegments": self.segments,
            }

    return Cone


_SHAFT_RADIUS = 0.007
_HEAD_RADIUS = 0.018
_HEAD_LENGTH = 0.04
_ARROW_OFFSET = 0.055  # [m]: motor force arrows run this far outside the screw axis
_CARRIAGE_MARGIN = 0.04  # [m]: the carriage box reaches this far beyond its two sliders (see the xacro)
_MIN_ARROW = 1e-5  # [m]: shortest shaft drawn (zero scale breaks three.js normals)


def _arrow_pose(tail: np.ndarray, force: np.ndarray, scale: float):
    """(shaft transform without scale, shaft length, head transform) for a force arrow."""
    magnitude = float(np.linalg.norm(force))
    direction = force / magnitude if magnitude > 0 else np.array([0.0, 0.0, 1.0])
    length = max(magnitude * scale, _MIN_ARROW)
    R = _rotation_y_to(direction)
    shaft = _homogeneous(R, tail + 0.5 * length * direction)
    head = _homogeneous(R, tail + (length + 0.5 * _HEAD_LENGTH) * direction)
    return shaft, length, head


def _arrow_poses(name, tail, force, scale):
    shaft, length, head = _arrow_pose(np.asarray(tail, dtype=float), np.asarray(force, dtype=float), scale)
    return [
        (f"{FORCES_ROOT}/{name}/shaft", shaft, np.array([1.0, length, 1.0])),
        (f"{FORCES_ROOT}/{name}/head", head, None),
    ]


def _arrow_names():
    names = [(f"screw_{i}", MOTOR_FORCE_COLOUR) for i in (1, 2, 3)]
    names += [(f"joint_{j}{i}", JOINT_FORCE_COLOUR) for j in (1, 2) for i in (1, 2, 3)]
    return names


# ---------------------------------------------------------------------------
# The scene
# ---------------------------------------------------------------------------


class Scene:
    """The machine (and optionally the human) as nodes of a meshcat Visualizer, and their poses frame by frame.

    Args:
        vis: the meshcat Visualizer to draw in.
        chain: the closed-chain model (:func:`hipsim.closed_chain.build.load_model`)
            whose visuals are drawn.
        params: the machine ``chain`` was built from.
        human: also draw example-robot-data's human model beside the machine.

    Raises:
        ModelError: the human model is asked for and not installed.
    """

    def __init__(self, vis, chain, params: Parameters, human: bool = False):
        import_meshcat()
        from pinocchio.visualize import MeshcatVisualizer

        self.vis, self.chain, self.params, self.human = vis, chain, params, bool(human)
        model, visual = self.chain.model, self.chain.visual_model
        self._machine = MeshcatVisualizer(model, None, visual)
        self._machine.initViewer(viewer=self.vis)
        self._machine.loadViewerModel(rootNodeName=MACHINE_ROOT)
        self.machine_data = model.createData()
        self._machine_gdata = visual.createData()
        # Geometry attached to the base never moves: send only the rest.
        self._moving = [
            (k, f"{MACHINE_ROOT}/visuals/{g.name}") for k, g in enumerate(visual.geometryObjects) if g.parentJoint != 0
        ]
        self._levers = [
            k
            for k, g in enumerate(visual.geometryObjects)
            if g.name.startswith("lever_") and model.names[g.parentJoint].startswith("u2_")
        ]
        self._lever_colour: tuple | None = None
        self._forces_visible: bool | None = None
        self._arrows_ready = False
        self._frames_ids = self._frame_ids()
        if self.human:
            self._setup_human(MeshcatVisualizer)
        self._setup_scene()

    # -- set-up -----------------------------------------------------------------

    def _frame_ids(self) -> dict[str, int]:
        model = self.chain.model
        names = [f"slider_{i}" for i in (1, 2, 3)]
        ids = {name: model.getJointId(name) for name in names}
        for j in (1, 2):
            for i in (1, 2, 3):
                ids[f"joint_{j}{i}"] = model.getFrameId(f"platform_{j}_joint_{i}")
        ids["platform"] = model.getJointId("platform_1_rx")
        return ids

    def _setup_human(self, visualizer_class) -> None:
        model, visual = load_human()
        self._human_model, self._human_visual = model, visual
        self._human_data, self._human_gdata = model.createData(), visual.createData()
        self._hip_q = np.array([model.joints[model.getJointId(name)].idx_q for name in HIP_JOINTS])
        self._human_viz = visualizer_class(model, None, visual)
        self._human_viz.initViewer(viewer=self.vis)
        self._human_viz.loadViewerModel(rootNodeName=HUMAN_ROOT)
        # The right leg moves: geometry below right_hip_Z.
        leg = set(model.subtrees[model.getJointId(HIP_JOINTS[0])])
        self._human_moving = [
            (k, f"{HUMAN_ROOT}/visuals/{g.name}", np.asarray(g.meshScale, dtype=float))
            for k, g in enumerate(visual.geometryObjects)
            if g.parentJoint in leg
        ]
        self._human_q0 = pin.neutral(model)
        # Draw the whole body once at its neutral pose, then place the pelvis in the world.
        pin.forwardKinematics(model, self._human_data, self._human_q0)
        self._human_viz.display(self._human_q0)
        self.vis[HUMAN_ROOT].set_transform(_homogeneous(HUMAN_PELVIS_ROTATION, HUMAN_PELVIS_POSITION))

    def _setup_scene(self) -> None:
        self.vis["/Background"].set_property("top_color", [1.0, 1.0, 1.0])
        self.vis["/Background"].set_property("bottom_color", [0.80, 0.83, 0.88])
        self.vis["/Axes"].set_property("visible", False)
        target, position = _CAMERA[self.human]
        self.set_camera(target, position)

    def set_camera(self, target, position) -> None:
        """Look from ``position`` at ``target`` (world axes, [m]); the view then orbits about the target.

        meshcat's camera always looks at (and orbits about) the origin of its
        scene, so the scene (the hipsim nodes and the floor grid) is shifted
        by −target in the viewer; the model's own coordinates do not change.
        """
        target, position = np.asarray(target, dtype=float), np.asarray(position, dtype=float)
        shift = _homogeneous(np.eye(3), -target)
        self.vis.set_transform(shift)
        self.vis["/Grid"].set_transform(shift)
        x, y, z = position - target
        # The camera sits in meshcat's Y-up "rotated" frame: world (x, y, z) is (x, z, −y) there.
        self.vis["/Cameras/default/rotated/<object>"].set_property("position", [float(x), float(z), float(-y)])

    def _setup_arrows(self) -> None:
        import meshcat.geometry as mg

        if self._arrows_ready:
            return
        Cone = _cone_class()

        def material(rgb):
            return mg.MeshLambertMaterial(color=int(rgb[0] * 255) << 16 | int(rgb[1] * 255) << 8 | int(rgb[2] * 255))

        for name, rgb in _arrow_names():
            self.vis[f"{FORCES_ROOT}/{name}/shaft"].set_object(mg.Cylinder(1.0, _SHAFT_RADIUS), material(rgb))
            self.vis[f"{FORCES_ROOT}/{name}/head"].set_object(Cone(_HEAD_LENGTH, _HEAD_RADIUS), material(rgb))
        self._arrows_ready = True

    # -- poses of everything in one frame ------------------------------------------------

    def poses(self, q: np.ndarray, hip: np.ndarray | None, F_act=None, F_joint=None, scale: float = 0.0):
        """[(path, 4x4 transform without scale, scale (3,) or None)] of every moving node at q.

        Args:
            q: closed tree configuration, shape (nq,).
            hip: the human's right-hip joint values in [rad], shape (3,), or None.
            F_act: actuator force on each carriage in [N], shape (3,), or None (no arrows).
            F_joint: force of each lever on its platform in [N], shape (2, 3, 3).
            scale: arrow scale in [m per N].
        """
        model, data, visual, gdata = self.chain.model, self.machine_data, self.chain.visual_model, self._machine_gdata
        pin.framesForwardKinematics(model, data, q)
        pin.updateGeometryPlacements(model, data, visual, gdata)
        poses: list[tuple[str, Any, np.ndarray | None]] = [
            (path, gdata.oMg[k].homogeneous, None) for k, path in self._moving
        ]
        if self.human and hip is not None:
            hq = self._human_q0.copy()
            hq[self._hip_q] = hip
            hmodel, hdata = self._human_model, self._human_data
            pin.forwardKinematics(hmodel, hdata, hq)
            pin.updateGeometryPlacements(hmodel, hdata, self._human_visual, self._human_gdata)
            poses += [(path, self._human_gdata.oMg[k].homogeneous, s) for k, path, s in self._human_moving]
        if F_act is not None:
            below = self.params.heights[0] - self.params.heights[1] + _CARRIAGE_MARGIN
            for i in range(3):
                b = data.oMi[self._frames_ids[f"slider_{i + 1}"]].translation
                # Beside the screw, on its outer side, leaving the carriage (drawn from b_1i + 0.04 m
                # down to b_2i − 0.04 m) in the force's direction.
                outward = np.append(b[:2] / np.linalg.norm(b[:2]), 0.0) if np.linalg.norm(b[:2]) > 0 else np.zeros(3)
                tail = b + _ARROW_OFFSET * outward + np.array([0.0, 0.0, _CARRIAGE_MARGIN if F_act[i] >= 0 else -below])
                poses += _arrow_poses(f"screw_{i + 1}", tail, np.array([0.0, 0.0, F_act[i]]), scale)
            for j in range(2):
                for i in range(3):
                    tail = data.oMf[self._frames_ids[f"joint_{j + 1}{i + 1}"]].translation
                    poses += _arrow_poses(f"joint_{j + 1}{i + 1}", tail, F_joint[j, i], scale)
        return poses

    def lever_paths(self) -> list[str]:
        """meshcat paths of the six levers' objects (whose colour shows the singularity measure)."""
        return [
            f"{MACHINE_ROOT}/visuals/{self.chain.visual_model.geometryObjects[g].name}/<object>" for g in self._levers
        ]

    # -- sending ------------------------------------------------------------------------

    def send(self, poses) -> None:
        """Send the transforms of :meth:`poses` (scale folded in)."""
        for path, T, s in poses:
            if s is not None:
                T = T @ np.diag(np.append(s, 1.0))
            self.vis[path].set_transform(T)

    def colour_levers(self, rgb) -> None:
        """Give the six levers a colour (None: their URDF colour); sends only on change."""
        key = None if rgb is None else tuple(np.round(np.asarray(rgb) * 63) / 63)
        if key == self._lever_colour:
            return
        self._lever_colour = key
        for k in self._levers:
            geom = self.chain.visual_model.geometryObjects[k]
            colour = None if key is None else np.array([*key, 1.0])
            self._machine.loadViewerGeometryObject(geom, pin.GeometryType.VISUAL, colour)

    def _show_forces(self, visible: bool) -> None:
        """Show or hide the force arrows; sends only on change (the server keeps every property sent)."""
        if self._arrows_ready and visible != self._forces_visible:
            self.vis[FORCES_ROOT].set_property("visible", visible)
            self._forces_visible = visible

    def show(self, q: np.ndarray, hip: np.ndarray) -> None:
        """Show the machine at configuration q (shape (nq,)) and the human's hip at ``hip`` [rad], without arrows or colours."""
        self.send(self.poses(q, hip))
        self._show_forces(False)
        self.colour_levers(None)

    def show_frame(self, motion: Motion, k: int, scale: float) -> None:
        """Show frame ``k`` of ``motion`` with its arrows (at ``scale`` in [m per N]) and lever colours."""
        forces = motion.forces()
        if forces is not None:
            self._setup_arrows()
        self.send(
            self.poses(
                motion.q[k],
                motion.hip[k],
                forces[0][k] if forces is not None else None,
                forces[1][k] if forces is not None else None,
                scale,
            )
        )
        self._show_forces(forces is not None)
        self.colour_levers(singularity_colour(motion.cond_inv[k]) if motion.cond_inv is not None else None)

    def platform_rotation(self, q: np.ndarray) -> np.ndarray:
        """Rotation of platform 1 in world axes at tree configuration q, shape (3, 3)."""
        pin.forwardKinematics(self.chain.model, self.machine_data, q)
        return self.machine_data.oMi[self._frames_ids["platform"]].rotation
