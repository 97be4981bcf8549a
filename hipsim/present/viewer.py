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
:mod:`hipsim.present.meshcat_output`; the frames are
:mod:`hipsim.present.motion_frames`, the scene's nodes, arrows and colours
:mod:`hipsim.present.meshcat_scene`, the legend and the description
:mod:`hipsim.present.viewer_text`.

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

from collections.abc import Callable
from typing import Any

import numpy as np

from ..clock import SYSTEM_CLOCK, Clock
from ..exceptions import ArgumentError, HipsimError
from ..machine.parameters import Parameters, load_parameters
from ..motion.trajectories import Trajectory
from .human import human_hip_angles
from .meshcat_output import DiscreteAnimation, LiveWindow, OfflineWindow, Server, TeeWindow, offline_page
from .meshcat_scene import FORCES_ROOT, Scene, arrow_scale, force_scale_for, import_meshcat, singularity_colour
from .motion_frames import Motion, closed_motion
from .viewer_text import description_lines, legend_lines

__all__ = ["DEFAULT_FPS", "Motion", "Viewer", "describe", "force_scale_for", "singularity_colour"]

#: Frames per second of the animation (live and recorded) unless told otherwise.
DEFAULT_FPS = 30.0


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

    def __init__(
        self,
        params: Parameters | None = None,
        human: bool = False,
        *,
        serve: bool = True,
        force_scale: float | None = None,
    ):
        meshcat = import_meshcat()

        from ..closed_chain.build import load_model

        self.params = load_parameters() if params is None else params
        self.chain = load_model(self.params)
        self.human = bool(human)
        self.force_scale = force_scale
        self._server = None
        self._window: Any = None
        try:
            self._offline = OfflineWindow()
            if serve:
                self._server = Server()
                self._window = TeeWindow(LiveWindow(self._server.zmq_url, self._server.web_url), self._offline)
            else:
                self._window = self._offline
            self.vis = meshcat.Visualizer(window=self._window)
            self.scene = Scene(self.vis, self.chain, self.params, self.human)
            self.show(self._home())
        except BaseException:
            self.close()
            raise

    def _home(self) -> np.ndarray:
        from ..closed_chain.closure import kinematics

        zero = Trajectory(np.zeros(1), np.zeros((1, 3)), np.zeros((1, 3)), np.zeros((1, 3)), np.zeros(1), name="home")
        return kinematics(self.chain, zero).q[0]

    def set_camera(self, target, position) -> None:
        """Look from ``position`` at ``target`` (world axes, [m]); the view then orbits about the target.

        meshcat's camera always looks at (and orbits about) the origin of its
        scene, so the scene (the hipsim nodes and the floor grid) is shifted
        by −target in the viewer; the model's own coordinates do not change.
        """
        self.scene.set_camera(target, position)

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

    def motion(
        self,
        trajectory: Trajectory,
        *,
        fps: float = DEFAULT_FPS,
        speed: float = 1.0,
        forces: bool = False,
        singularity: bool = False,
    ) -> Motion:
        """The closed frames that show ``trajectory`` at ``fps`` frames per second, played ``speed`` times real time.

        The trajectory is resampled at fps/speed samples per second of its time
        (whole periods when it is periodic, so that a loop is seamless) and the
        chain closed at every sample with Pinocchio (closure gap ≤ 1e-12 m).
        See :func:`hipsim.present.motion_frames.closed_motion`.

        Raises:
            PoseError: a sample is out of reach or singular.
        """
        return closed_motion(
            self.chain, self.params, trajectory, fps=fps, speed=speed, forces=forces, singularity=singularity
        )

    def _scale(self, motion: Motion) -> float:
        """The arrow scale of a motion with forces in [m per N]."""
        return arrow_scale(motion, self.force_scale)

    # -- showing ------------------------------------------------------------------------

    def show(self, q) -> None:
        """Show one tree configuration q (shape (nq,)); the human's hip follows platform 1's orientation.

        The configuration is shown as given: close it first (:meth:`show_orientation`)
        to see the machine assembled.
        """
        q = np.asarray(q, dtype=float)
        if q.shape != (self.chain.model.nq,):
            raise ArgumentError("q", q, f"a configuration of size nq = {self.chain.model.nq}")
        R = self.scene.platform_rotation(q)
        self.scene.show(q, human_hip_angles(R))

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

        one = Trajectory(
            np.zeros(1),
            np.array([[alpha, beta, gamma]], dtype=float),
            np.zeros((1, 3)),
            np.zeros((1, 3)),
            np.zeros(1),
            name="orientation",
        )
        q = kinematics(self.chain, one).q[0]
        self.show(q)
        return q

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
        clock: Clock = SYSTEM_CLOCK,
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
            clock: the clock that paces the frames (:mod:`hipsim.clock`; a test passes its own).

        Returns:
            The motion shown.
        """
        motion = (
            trajectory
            if isinstance(trajectory, Motion)
            else self.motion(trajectory, fps=fps, speed=speed, forces=forces, singularity=singularity)
        )
        scale = self._scale(motion) if motion.F_act is not None else 0.0
        n = len(motion)
        frame_rate = motion.fps
        while True:
            start = clock.monotonic()
            shown = -1
            while True:
                k = int((clock.monotonic() - start) * frame_rate)
                if k >= n:
                    if not loop and shown != n - 1:
                        k = n - 1  # a run that ends rests on its last frame, even if the clock skipped it
                    else:
                        break
                if k != shown:
                    self.scene.show_frame(motion, k, scale)
                    shown = k
                    if on_frame is not None:
                        on_frame(k, motion)
                next_time = start + (k + 1) / frame_rate
                clock.sleep(max(0.0, next_time - clock.monotonic()))
            if not loop:
                return motion

    def show_frame(self, motion: Motion, k: int) -> None:
        """Show frame ``k`` of ``motion`` (a :class:`Motion` from :meth:`motion`), with its arrows and colours."""
        if not 0 <= k < len(motion):
            raise HipsimError(f"frame {k} is not in the motion's {len(motion)} frames")
        self.scene.show_frame(motion, k, self._scale(motion) if motion.F_act is not None else 0.0)

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
        motion = (
            trajectory
            if isinstance(trajectory, Motion)
            else self.motion(trajectory, fps=fps, speed=speed, forces=forces, singularity=singularity)
        )
        animation = self._animation(motion)
        from meshcat.commands import SetAnimation

        self._offline.send(SetAnimation(animation, play=True, repetitions=float("inf")))
        try:
            return offline_page(self._offline.commands(), title or f"hipsim: {motion.name}", self._legend(motion))
        finally:
            self._offline.tree.animation = None

    def _animation(self, motion: Motion):
        forces = motion.forces()
        scale = self._scale(motion) if forces is not None else 0.0
        # Show the first frame: the scene then holds each node's scale (animations keep the scale they find).
        self.scene.show_frame(motion, 0, scale)
        self.scene.colour_levers(None)
        animation = DiscreteAnimation(default_framerate=motion.fps)
        lever_paths = self.scene.lever_paths()
        for k in range(len(motion)):
            poses = self.scene.poses(
                motion.q[k],
                motion.hip[k],
                forces[0][k] if forces is not None else None,
                forces[1][k] if forces is not None else None,
                scale,
            )
            with animation.at_frame(self.vis, k) as frame:
                for path, T, s in poses:
                    frame[path].set_transform(T)
                    if s is not None and path.startswith(FORCES_ROOT):
                        frame[path].set_property("scale", "vector3", [float(v) for v in s])
                if motion.cond_inv is not None:
                    rgb = [float(v) for v in singularity_colour(motion.cond_inv[k])]
                    for path in lever_paths:
                        frame[path].set_property("material.color", "color", rgb)
        return animation

    def _legend(self, motion: Motion) -> list[str]:
        return legend_lines(motion, self._scale(motion) if motion.F_act is not None else None, self.human)

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

    def __enter__(self) -> Viewer:
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def __del__(self):
        try:
            self.close()
        except Exception:  # interpreter shutdown
            pass


def describe(viewer: Viewer, motion: Motion) -> list[str]:
    """Plain-text lines saying what ``viewer`` shows of ``motion`` (frames, closure gap, arrows, colours, human)."""
    return description_lines(motion, viewer._scale(motion) if motion.F_act is not None else None, viewer.human)
