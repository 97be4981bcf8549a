"""Visual inspection in meshcat: the machine moving through a trajectory, live or as one offline page.

What is shown is the Pinocchio model's *closed* configuration
(:func:`hipsim.closed_chain.kinematics`): at every frame the tree's joint
values make all six lever tips meet their platform joints, so a closure that
goes wrong is visible at a glance. Frames are the closed samples themselves,
never an interpolation between them (the offline page holds each sample until
the next one).

A few lines show any configuration or trajectory::

    import numpy as np
    import hipsim
    from hipsim.present.viewer import Viewer

    with Viewer(human=True) as viewer:               # a meshcat server on 127.0.0.1
        viewer.url                                   # open it in a browser
        viewer.show_orientation(np.radians(20), 0.0, 0.0)
        viewer.play(hipsim.iso14242(rate=200), loop=False, forces=True)
        page = viewer.record(hipsim.iso14242(rate=200))  # one offline HTML page

    Viewer(serve=False).record(trajectory)           # the page only, no server

Where the scene goes, the live server on 127.0.0.1 or the self-contained
offline page (``#t=0.25`` after its address opens it paused at 0.25 s), is
:mod:`hipsim.present.meshcat_output`.

Shown with ``forces``: the motor thrust 2πτ/p on each screw's carriage (magenta,
along the screw, leaving the carriage in the direction of the force) and the
force each lever exerts on its platform at the spherical joint (cyan), from
the closed-chain inverse dynamics, drawn at a stated scale in mm per N. With
``singularity`` the six levers take the colour of the singularity measure
(the inverse condition number of J, one value for the whole machine): red at
0 (singular), yellow at 0.25, lime green at 0.5 and above.

With ``human=True`` example-robot-data's human model stands beside the
machine, its right hip turning exactly as the platforms do: how the machine's
angles map onto the hip is :mod:`hipsim.present.human`.

Not thread-safe: use one Viewer from one thread at a time.
"""

from __future__ import annotations

import math
import time
import warnings
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

import numpy as np
import pinocchio as pin

from ..exceptions import ArgumentError, HipsimError, PoseError
from ..files import write_atomic
from .human import HIP_JOINTS, HUMAN_PELVIS_POSITION, HUMAN_PELVIS_ROTATION, human_hip_angles, load_human
from .meshcat_output import DiscreteAnimation, LiveWindow, OfflineWindow, Server, TeeWindow, offline_page
from ..machine.parameters import Parameters, load_parameters
from ..motion.trajectories import Trajectory, interpolator

__all__ = ["DEFAULT_FPS", "Motion", "Viewer", "describe", "force_scale_for", "singularity_colour"]

#: Frames per second of the animation (live and recorded) unless told otherwise.
DEFAULT_FPS = 30.0
#: Longest force arrow the automatic scale allows, in [m].
LONGEST_ARROW = 0.3
#: Force scales the automatic choice picks from, in [m per N] (1 mm/N and down in 1-2-5 steps).
_SCALES = tuple(m * 10.0**-e for e in range(3, 8) for m in (1.0, 0.5, 0.2))
#: Colours (RGB, 0..1) of the force arrows.
MOTOR_FORCE_COLOUR = (0.85, 0.10, 0.80)
JOINT_FORCE_COLOUR = (0.05, 0.75, 0.85)
#: Singularity colour map: (inverse condition number, RGB) stops, clamped beyond the ends.
SINGULARITY_STOPS = ((0.0, (0.85, 0.10, 0.10)), (0.25, (0.95, 0.85, 0.10)), (0.5, (0.45, 0.90, 0.10)))

_MACHINE_ROOT = "hipsim/machine"
_HUMAN_ROOT = "hipsim/human"
_FORCES_ROOT = "hipsim/forces"

# Camera: orbit target and camera position in world axes [m].
_CAMERA = {False: ((0.0, 0.0, 0.62), (1.0, 1.2, 1.15)), True: ((0.0, 0.45, 0.72), (2.1, 0.95, 1.25))}


# ---------------------------------------------------------------------------
# Small pure helpers
# ---------------------------------------------------------------------------


def _import_meshcat():
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


def _scale_text(scale: float) -> str:
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
# The frames to show
# ---------------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class Motion:
    """The closed samples a viewer shows, with what is drawn on them.

    Attributes:
        t: trajectory time of each frame in [s], shape (N,).
        fps: frames per second of the display.
        speed: playback speed (1 = real time).
        angles: platform angles [α, β, γ] in [rad] as the machine turns them
            (angle_signs applied), shape (N, 3).
        q: closed tree configurations, shape (N, nq).
        residual: largest closure gap of each frame in [m], shape (N,).
        F_act: actuator force on each carriage in [N], shape (N, 3), or None.
        F_joint: force each lever exerts on its platform at a_ji, world axes,
            in [N], shape (N, 2, 3, 3), or None.
        cond_inv: singularity measure per frame, shape (N,), or None.
        hip: the human's right-hip joint values [right_hip_Z, right_hip_X,
            right_hip_Y] in [rad], shape (N, 3).
        periodic: the frames tile a period (the animation loops seamlessly).
        name: where the trajectory came from.
    """

    t: np.ndarray
    fps: float
    speed: float
    angles: np.ndarray
    q: np.ndarray
    residual: np.ndarray
    F_act: np.ndarray | None
    F_joint: np.ndarray | None
    cond_inv: np.ndarray | None
    hip: np.ndarray
    periodic: bool
    name: str

    def __len__(self) -> int:
        return self.t.size

    @property
    def rate(self) -> float:
        """Frames per second of trajectory time, fps/speed."""
        return self.fps / self.speed

    @property
    def duration(self) -> float:
        """Trajectory time the frames cover in [s] (a whole period when periodic)."""
        return len(self) / self.rate if self.periodic else float(self.t[-1] - self.t[0])


def _resample(trajectory: Trajectory, rate: float) -> tuple[Trajectory, bool]:
    """The trajectory at ``rate`` samples per second of its time (whole periods if periodic)."""
    t = trajectory.t
    if t.size < 2:
        return trajectory, False
    dt = (t[-1] - t[0]) / (t.size - 1)
    if trajectory.periodic:
        period = t[-1] - t[0] + dt
        n = max(2, int(round(period * rate)))
        times = t[0] + np.arange(n) * (period / n)
    else:
        n = max(2, int(math.floor((t[-1] - t[0]) * rate + 1e-9)) + 1)
        times = t[0] + np.arange(n) / rate
    # Sample times that are samples of the trajectory are taken as they are; others are interpolated.
    index = np.clip(np.round((times - t[0]) / dt).astype(int), 0, t.size - 1)
    if np.allclose(t[index], times, rtol=0.0, atol=1e-9 * dt):
        return trajectory.slice(index), trajectory.periodic
    return interpolator(trajectory)(times), trajectory.periodic


def _check_reach(params: Parameters, trajectory: Trajectory) -> None:
    """A pose out of reach named as `torques` names it: by its sample's time (and file line), not a frame's.

    The frames shown lie between the trajectory's samples; a pose out of reach
    among the samples is found there first. Near-singular poses are left to
    the frames, which may show them.
    """
    from ..analytic.inverse_kinematics import kinematics as analytic_kinematics

    heights = np.asarray(analytic_kinematics(params, trajectory, on_error="flag").L).reshape(len(trajectory), -1)
    reached = np.all(np.isfinite(heights), axis=1)
    if not reached.all():
        k = int(np.argmin(reached))
        try:
            analytic_kinematics(params, trajectory.slice(slice(k, k + 1)))  # the analytic model's message for that sample
        except PoseError as error:
            raise PoseError(error.reason, error.time, k, source=error.source) from None


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
            return {"uuid": self.uuid, "type": "ConeGeometry", "radius": self.radius, "height": self.height, "radialSegments": self.segments}

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


# ---------------------------------------------------------------------------
# The viewer
# ---------------------------------------------------------------------------


class Viewer:
    """The hip simulator (and optionally the human model) in meshcat.

    Args:
        params: the machine; None for the published one.
        human: also show example-robot-data's human model beside the machine,
            its right hip turning as the platforms do.
        serve: start a meshcat server on 127.0.0.1 for a browser to watch
            (``url``); False builds scenes for :meth:`record` only.
        force_scale: arrow scale in [m per N]; None picks one per motion
            (:func:`force_scale_for`).

    Raises:
        ModelError: the human model is asked for and not installed.
        HipsimError: the meshcat server does not start.
    """

    def __init__(self, params: Parameters | None = None, human: bool = False, *, serve: bool = True, force_scale: float | None = None):
        meshcat = _import_meshcat()
        from pinocchio.visualize import MeshcatVisualizer

        from ..closed_chain.build import load_model

        self.params = load_parameters() if params is None else params
        self.chain = load_model(self.params)
        self.human = bool(human)
        self.force_scale = force_scale
        self._server = None
        self._window = None
        try:
            self._offline = OfflineWindow()
            if serve:
                self._server = Server()
                self._window = TeeWindow(LiveWindow(self._server.zmq_url, self._server.web_url), self._offline)
            else:
                self._window = self._offline
            self.vis = meshcat.Visualizer(window=self._window)

            model, visual = self.chain.model, self.chain.visual_model
            self._machine = MeshcatVisualizer(model, None, visual)
            self._machine.initViewer(viewer=self.vis)
            self._machine.loadViewerModel(rootNodeName=_MACHINE_ROOT)
            self._machine_data = model.createData()
            self._machine_gdata = visual.createData()
            # Geometry attached to the base never moves: send only the rest.
            self._moving = [(k, f"{_MACHINE_ROOT}/visuals/{g.name}") for k, g in enumerate(visual.geometryObjects) if g.parentJoint != 0]
            self._levers = [
                k for k, g in enumerate(visual.geometryObjects)
                if g.name.startswith("lever_") and model.names[g.parentJoint].startswith("u2_")
            ]  # fmt: skip
            self._lever_colour: tuple | None = None
            self._forces_visible: bool | None = None
            self._arrows_ready = False
            self._frames_ids = self._frame_ids()
            if self.human:
                self._setup_human(MeshcatVisualizer)
            self._setup_scene()
            self.show(self._home())
        except BaseException:
            self.close()
            raise

    # -- set-up -----------------------------------------------------------------

    def _frame_ids(self) -> dict[str, int]:
        model = self.chain.model
        names = [f"slider_{i}" for i in (1, 2, 3)]
        ids = {name: model.getJointId(name) for name in names}
        for j in (1, 2):
            for i in (1, 2, 3):
                ids[f"tip_{j}{i}"] = model.getFrameId(f"lever_{j}{i}_tip")
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
        self._human_viz.loadViewerModel(rootNodeName=_HUMAN_ROOT)
        # The right leg moves: geometry below right_hip_Z.
        leg = set(model.subtrees[model.getJointId(HIP_JOINTS[0])])
        self._human_moving = [
            (k, f"{_HUMAN_ROOT}/visuals/{g.name}", np.asarray(g.meshScale, dtype=float))
            for k, g in enumerate(visual.geometryObjects) if g.parentJoint in leg
        ]  # fmt: skip
        self._human_q0 = pin.neutral(model)
        # Draw the whole body once at its neutral pose, then place the pelvis in the world.
        pin.forwardKinematics(model, self._human_data, self._human_q0)
        self._human_viz.display(self._human_q0)
        self.vis[_HUMAN_ROOT].set_transform(_homogeneous(HUMAN_PELVIS_ROTATION, HUMAN_PELVIS_POSITION))

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

        for name, rgb in self._arrow_names():
            self.vis[f"{_FORCES_ROOT}/{name}/shaft"].set_object(mg.Cylinder(1.0, _SHAFT_RADIUS), material(rgb))
            self.vis[f"{_FORCES_ROOT}/{name}/head"].set_object(Cone(_HEAD_LENGTH, _HEAD_RADIUS), material(rgb))
        self._arrows_ready = True

    @staticmethod
    def _arrow_names():
        names = [(f"screw_{i}", MOTOR_FORCE_COLOUR) for i in (1, 2, 3)]
        names += [(f"joint_{j}{i}", JOINT_FORCE_COLOUR) for j in (1, 2) for i in (1, 2, 3)]
        return names

    def _home(self) -> np.ndarray:
        from ..closed_chain.closure import kinematics

        zero = Trajectory(np.zeros(1), np.zeros((1, 3)), np.zeros((1, 3)), np.zeros((1, 3)), np.zeros(1), name="home")
        return kinematics(self.chain, zero).q[0]

    # -- properties ----------------------------------------------------------------

    @property
    def url(self) -> str | None:
        """The address to open in a browser (http://127.0.0.1:PORT/static/), None without a server."""
        return self._server.web_url if self._server is not None else None

    @property
    def server_pid(self) -> int | None:
        """Process id of the meshcat server, None without one."""
        return self._server.pid if self._server is not None else None

    # -- computing what to show ---------------------------------------------------------

    def motion(self, trajectory: Trajectory, *, fps: float = DEFAULT_FPS, speed: float = 1.0, forces: bool = False, singularity: bool = False) -> Motion:
        """The closed frames that show ``trajectory`` at ``fps`` frames per second, played ``speed`` times real time.

        The trajectory is resampled at fps/speed samples per second of its time
        (whole periods when it is periodic, so that a loop is seamless) and the
        chain closed at every sample with Pinocchio (closure gap ≤ 1e-12 m).

        Raises:
            PoseError: a sample is out of reach or singular.
        """
        from ..closed_chain.closure import kinematics
        from ..closed_chain.dynamics import trajectory_dynamics

        if not (fps > 0 and speed > 0 and math.isfinite(fps) and math.isfinite(speed)):
            raise ArgumentError("fps, speed", (fps, speed), "positive numbers")
        rate = fps / speed
        _check_reach(self.params, trajectory)
        samples, periodic = _resample(trajectory, rate)
        F_act = F_joint = cond_inv = None
        if forces:
            kin, torques = trajectory_dynamics(self.chain, samples)
            F_act = np.array(torques.F_act)
            F_joint = self._platform_forces(kin.q, np.asarray(torques.lambdas))
        else:
            kin = kinematics(self.chain, samples)
        if singularity:
            cond_inv = np.array(kin.cond_inv)
        from ..analytic.inverse_kinematics import rotation_matrix

        hip = human_hip_angles(rotation_matrix(np.asarray(kin.angles)))
        return Motion(
            t=np.array(samples.t), fps=float(fps), speed=float(speed), angles=np.array(kin.angles), q=np.array(kin.q),
            residual=np.array(kin.residual), F_act=F_act, F_joint=F_joint, cond_inv=cond_inv, hip=hip,
            periodic=periodic, name=trajectory.name,
        )  # fmt: skip

    def _platform_forces(self, Q: np.ndarray, lambdas: np.ndarray) -> np.ndarray:
        """World force of each lever on its platform, −R_tip·λ, shape (N, 2, 3, 3)."""
        model, data = self.chain.model, self._machine_data
        out = np.empty_like(lambdas)
        for k, q in enumerate(Q):
            pin.framesForwardKinematics(model, data, q)
            for j in range(2):
                for i in range(3):
                    out[k, j, i] = -data.oMf[self._frames_ids[f"tip_{j + 1}{i + 1}"]].rotation @ lambdas[k, j, i]
        return out

    def _scale(self, motion: Motion) -> float:
        if self.force_scale is not None:
            return self.force_scale
        peak = max(float(np.abs(motion.F_act).max()), float(np.linalg.norm(motion.F_joint, axis=-1).max()))
        return force_scale_for(peak)

    # -- poses of everything in one frame ------------------------------------------------

    def _poses(self, q: np.ndarray, hip: np.ndarray | None, F_act=None, F_joint=None, scale: float = 0.0):
        """[(path, 4x4 transform without scale, scale (3,) or None)] of every moving node at q."""
        model, data, visual, gdata = self.chain.model, self._machine_data, self.chain.visual_model, self._machine_gdata
        pin.framesForwardKinematics(model, data, q)
        pin.updateGeometryPlacements(model, data, visual, gdata)
        poses = [(path, gdata.oMg[k].homogeneous, None) for k, path in self._moving]
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
                poses += self._arrow_poses(f"screw_{i + 1}", tail, np.array([0.0, 0.0, F_act[i]]), scale)
            for j in range(2):
                for i in range(3):
                    tail = data.oMf[self._frames_ids[f"joint_{j + 1}{i + 1}"]].translation
                    poses += self._arrow_poses(f"joint_{j + 1}{i + 1}", tail, F_joint[j, i], scale)
        return poses

    @staticmethod
    def _arrow_poses(name, tail, force, scale):
        shaft, length, head = _arrow_pose(np.asarray(tail, dtype=float), np.asarray(force, dtype=float), scale)
        return [(f"{_FORCES_ROOT}/{name}/shaft", shaft, np.array([1.0, length, 1.0])), (f"{_FORCES_ROOT}/{name}/head", head, None)]

    def _send(self, poses) -> None:
        for path, T, s in poses:
            if s is not None:
                T = T @ np.diag(np.append(s, 1.0))
            self.vis[path].set_transform(T)

    def _colour_levers(self, rgb) -> None:
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
            self.vis[_FORCES_ROOT].set_property("visible", visible)
            self._forces_visible = visible

    # -- showing ------------------------------------------------------------------------

    def show(self, q) -> None:
        """Show one tree configuration q (shape (nq,)); the human's hip follows platform 1's orientation.

        The configuration is shown as given: close it first (:meth:`show_orientation`)
        to see the machine assembled.
        """
        q = np.asarray(q, dtype=float)
        if q.shape != (self.chain.model.nq,):
            raise ArgumentError("q", q, f"a configuration of size nq = {self.chain.model.nq}")
        pin.forwardKinematics(self.chain.model, self._machine_data, q)
        R = self._machine_data.oMi[self._frames_ids["platform"]].rotation
        self._send(self._poses(q, human_hip_angles(R)))
        self._show_forces(False)
        self._colour_levers(None)

    def show_orientation(self, alpha: float, beta: float, gamma: float) -> np.ndarray:
        """Close the chain at one platform orientation and show it.

        Args:
            alpha, beta, gamma: flexion/extension, abduction/adduction and
                rotation in [rad], as a trajectory gives them (the parameter
                set's angle_signs apply).

        Returns:
            The closed configuration q, shape (nq,).

        Raises:
            PoseError: the orientation is out of reach or singular.
        """
        from ..closed_chain.closure import kinematics

        one = Trajectory(np.zeros(1), np.array([[alpha, beta, gamma]], dtype=float), np.zeros((1, 3)), np.zeros((1, 3)), np.zeros(1), name="orientation")
        q = kinematics(self.chain, one).q[0]
        self.show(q)
        return q

    def _show_frame(self, motion: Motion, k: int, scale: float) -> None:
        forces = motion.F_act is not None
        if forces:
            self._setup_arrows()
        self._send(self._poses(motion.q[k], motion.hip[k], motion.F_act[k] if forces else None, motion.F_joint[k] if forces else None, scale))
        self._show_forces(forces)
        self._colour_levers(singularity_colour(motion.cond_inv[k]) if motion.cond_inv is not None else None)

    def play(
        self,
        trajectory: Trajectory | Motion,
        speed: float = 1.0,
        loop: bool = True,
        *,
        forces: bool = False,
        singularity: bool = False,
        fps: float = DEFAULT_FPS,
        on_frame: Callable[[int, Motion], None] | None = None,
    ) -> Motion:
        """Play a trajectory in the live viewer, in real time (``speed`` × real time), once or looping.

        Frames are closed samples at ``fps``; when sending falls behind the clock,
        frames are skipped, never slowed. Stop a loop with Ctrl-C
        (KeyboardInterrupt reaches the caller).

        Args:
            trajectory: a Trajectory, or a :class:`Motion` from :meth:`motion`
                (then speed, forces, singularity and fps are the motion's).
            speed: playback speed, 1 = real time, 0.25 = four times slower.
            loop: start again at the end, until interrupted.
            forces, singularity: draw force arrows / colour the levers (module docstring).
            fps: frames per second.
            on_frame: called with (frame index, motion) after each frame is sent.

        Returns:
            The motion shown.
        """
        motion = trajectory if isinstance(trajectory, Motion) else self.motion(trajectory, fps=fps, speed=speed, forces=forces, singularity=singularity)
        scale = self._scale(motion) if motion.F_act is not None else 0.0
        n = len(motion)
        frame_rate = motion.fps
        while True:
            start = time.monotonic()
            shown = -1
            while True:
                k = int((time.monotonic() - start) * frame_rate)
                if k >= n:
                    if not loop and shown != n - 1:
                        k = n - 1  # a run that ends rests on its last frame, even if the clock skipped it
                    else:
                        break
                if k != shown:
                    self._show_frame(motion, k, scale)
                    shown = k
                    if on_frame is not None:
                        on_frame(k, motion)
                next_time = start + (k + 1) / frame_rate
                time.sleep(max(0.0, next_time - time.monotonic()))
            if not loop:
                return motion

    def show_frame(self, motion: Motion, k: int) -> None:
        """Show frame ``k`` of ``motion`` (a :class:`Motion` from :meth:`motion`), with its arrows and colours."""
        if not 0 <= k < len(motion):
            raise HipsimError(f"frame {k} is not in the motion's {len(motion)} frames")
        self._show_frame(motion, k, self._scale(motion) if motion.F_act is not None else 0.0)

    # -- recording --------------------------------------------------------------------------

    def record(
        self,
        trajectory: Trajectory | Motion,
        fps: float = DEFAULT_FPS,
        speed: float = 1.0,
        *,
        forces: bool = False,
        singularity: bool = False,
        title: str | None = None,
    ) -> str:
        """The motion as one self-contained offline HTML page (meshcat's recorded animation, looping).

        Each animation frame is a closed sample, held until the next one (no
        in-between poses). The page needs no network; append ``#t=SECONDS`` to
        its address to open it paused at that time of the animation.

        Args:
            trajectory: a Trajectory, or a :class:`Motion` from :meth:`motion`
                (then fps, speed, forces and singularity are the motion's).
            fps: animation frames per second.
            speed: playback speed of the page (0.5 = half speed).
            forces, singularity: as in :meth:`play` (the lever colours animate in the page too).
            title: the page's title; default from the trajectory.

        Returns:
            The HTML text.
        """
        motion = trajectory if isinstance(trajectory, Motion) else self.motion(trajectory, fps=fps, speed=speed, forces=forces, singularity=singularity)
        animation = self._animation(motion)
        from meshcat.commands import SetAnimation

        self._offline.send(SetAnimation(animation, play=True, repetitions=float("inf")))
        try:
            return offline_page(self._offline.commands(), title or f"hipsim: {motion.name}", self._legend(motion))
        finally:
            self._offline.tree.animation = None

    def _animation(self, motion: Motion):
        forces = motion.F_act is not None
        scale = self._scale(motion) if forces else 0.0
        # Show the first frame: the scene then holds each node's scale (animations keep the scale they find).
        self._show_frame(motion, 0, scale)
        self._colour_levers(None)
        animation = DiscreteAnimation(default_framerate=motion.fps)
        lever_paths = [f"{_MACHINE_ROOT}/visuals/{self.chain.visual_model.geometryObjects[g].name}/<object>" for g in self._levers]
        for k in range(len(motion)):
            poses = self._poses(motion.q[k], motion.hip[k], motion.F_act[k] if forces else None, motion.F_joint[k] if forces else None, scale)
            with animation.at_frame(self.vis, k) as frame:
                for path, T, s in poses:
                    frame[path].set_transform(T)
                    if s is not None and path.startswith(_FORCES_ROOT):
                        frame[path].set_property("scale", "vector3", [float(v) for v in s])
                if motion.cond_inv is not None:
                    rgb = [float(v) for v in singularity_colour(motion.cond_inv[k])]
                    for path in lever_paths:
                        frame[path].set_property("material.color", "color", rgb)
        return animation

    def _legend(self, motion: Motion) -> list[str]:
        import html

        lines = [f"hipsim: {html.escape(motion.name)}, {motion.duration:.3g} s in {len(motion)} frames at {motion.fps:g} fps, speed {motion.speed:g}&times;"]
        if motion.F_act is not None:
            scale = self._scale(motion)
            lines.append(
                f"arrows ({_scale_text(scale)}): <span style='color:#d91acc'>&#9632;</span> motor thrust 2πτ/p on each screw's carriage, "
                f"<span style='color:#0dbfd9'>&#9632;</span> force of each lever on its platform"
            )
        if motion.cond_inv is not None:
            lines.append(
                "levers: singularity measure (inverse condition number of J) "
                "<span style='color:#d91a1a'>&#9632;</span> 0 singular, <span style='color:#f2d91a'>&#9632;</span> 0.25, "
                "<span style='color:#73e61a'>&#9632;</span> &ge; 0.5"
            )
        if self.human:
            lines.append("human: the right hip turns as the platforms do (α flexion, β adduction, γ internal rotation)")
        return lines

    # -- ending -------------------------------------------------------------------------------

    def close(self) -> None:
        """Stop the meshcat server (if any). Safe to call twice."""
        window = getattr(self, "_window", None)
        if window is not None:
            window.close()
            self._window = None
        server = getattr(self, "_server", None)
        if server is not None:
            server.close()
            self._server = None

    def __enter__(self) -> "Viewer":
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def __del__(self):
        try:
            self.close()
        except Exception:  # noqa: BLE001 - interpreter shutdown
            pass


def describe(viewer: Viewer, motion: Motion) -> list[str]:
    """Plain-text lines saying what ``viewer`` shows of ``motion`` (frames, closure gap, arrows, colours, human)."""
    lines = [
        f"{motion.name}: {motion.duration:.4g} s in {len(motion)} frames at {motion.fps:g} fps, speed {motion.speed:g}x; "
        f"largest closure gap of the frames shown {float(motion.residual.max()):.1e} m"
    ]
    if motion.F_act is not None:
        lines.append(
            f"arrows at {_scale_text(viewer._scale(motion))}: magenta = motor thrust 2πτ/p on each screw's carriage "
            f"(peak {float(np.abs(motion.F_act).max()):.0f} N), cyan = force of each lever on its platform "
            f"(peak {float(np.linalg.norm(motion.F_joint, axis=-1).max()):.0f} N)"
        )
    if motion.cond_inv is not None:
        lines.append(
            "levers coloured by the singularity measure (inverse condition number of J): red 0, yellow 0.25, lime green >= 0.5; "
            f"here {float(np.nanmin(motion.cond_inv)):.3f} to {float(np.nanmax(motion.cond_inv)):.3f}"
        )
    if viewer.human:
        lines.append("human model: its right hip turns as the platforms do (alpha flexion, beta adduction, gamma internal rotation)")
    return lines
