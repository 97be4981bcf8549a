"""``hipsim view``: the machine moving in meshcat, live on loopback or as one offline page."""

from __future__ import annotations

import argparse
import math
import sys
from typing import TYPE_CHECKING, TextIO

from ..exceptions import HipsimError
from .common import add_machine_options, parameters
from .feasible import add_strict_option
from .motion_options import add_trajectory_options, load_trajectory

if TYPE_CHECKING:  # loaded when the command runs, not with the parser
    from ..machine.parameters import Parameters
    from ..motion.trajectories import Trajectory

__all__ = ["add_parser", "run", "run_view", "step_through"]


def add_parser(subparsers) -> argparse.ArgumentParser:
    """Register ``view`` on the main parser's subcommands."""
    view = subparsers.add_parser(
        "view",
        help="the machine moving through a trajectory in meshcat (live on loopback, or an offline page)",
        description="Starts a meshcat server on 127.0.0.1, prints its URL and plays the Pinocchio model's closed "
        "configurations through the trajectory in real time, looping, until Ctrl-C. With --html, writes the same "
        "animation as one self-contained offline page instead.",
    )
    add_machine_options(view)
    add_trajectory_options(view)
    view.add_argument("--html", metavar="FILE", help="write a self-contained offline page instead of serving")
    view.add_argument("--speed", type=float, default=1.0, metavar="X", help="playback speed (0.25: four times slower)")
    view.add_argument(
        "--frame-by-frame", dest="step", action="store_true", help="one frame per Enter (b: back, q: quit)"
    )
    view.add_argument(
        "--fps",
        type=int,
        default=30,
        metavar="N",
        help="frames per second of playback (default 30); the trajectory is sampled at fps/speed",
    )
    view.add_argument(
        "--forces",
        action="store_true",
        help="arrows for the motor force on each screw and the force at each spherical joint",
    )
    view.add_argument(
        "--singularity",
        action="store_true",
        help="colour the levers by the singularity measure (red singular, green clear)",
    )
    view.add_argument(
        "--human", action="store_true", help="the example-robot-data human model's hip moving beside the machine"
    )
    add_strict_option(view)
    view.set_defaults(run=run)
    return view


def run(args) -> int:
    """Play or write the machine's motion (:func:`run_view`)."""
    from ..analysis.runs import analyse
    from ..files import is_stdout
    from .feasible import check_run, report_crossings

    params, trajectory = parameters(args), load_trajectory(args)
    if report_crossings(check_run(analyse(params, trajectory, on_error="flag"), params), args.strict):
        return 1
    return run_view(
        params,
        trajectory,
        html=args.html,
        speed=args.speed,
        step=args.step,
        forces=args.forces,
        singularity=args.singularity,
        human=args.human,
        fps=args.fps,
        stream=sys.stderr if args.html and is_stdout(args.html) else sys.stdout,
    )


def run_view(
    params: Parameters,
    trajectory: Trajectory,
    html: str | None = None,
    speed: float = 1.0,
    step: bool = False,
    forces: bool = False,
    singularity: bool = False,
    human: bool = False,
    fps: float | None = None,
    stream: TextIO = sys.stdout,
    input: TextIO | None = None,
) -> int:
    """Play the machine live until Ctrl-C (or frame by frame with ``step``), or write the offline page to ``html``.

    Args:
        params: the machine.
        trajectory: the motion.
        html: path of the page to write; None for the live viewer.
        speed: playback speed (1 = real time; 0.25 = four times slower).
        step: one frame per line of ``input`` (live only).
        forces: draw the motor and spherical-joint forces as arrows.
        singularity: colour the levers by the singularity measure.
        human: show the human model's hip moving beside the machine.
        fps: frames per second of playback; None for the viewer's default.
        stream: where messages go.
        input: where step mode reads (default stdin).

    Returns:
        The exit status, 0.
    """
    from ..files import write_atomic
    from ..present.viewer import DEFAULT_FPS, Viewer, describe

    fps = DEFAULT_FPS if fps is None else fps
    if not (speed > 0 and math.isfinite(speed)):
        raise HipsimError(f"--speed must be a positive number, got {speed}")
    if not (fps > 0 and math.isfinite(fps)):
        raise HipsimError(f"--fps must be a positive number, got {fps}")
    if html is not None:
        if step:
            raise HipsimError("--frame-by-frame applies to the live viewer, not to --html")
        with Viewer(params, human, serve=False) as offline:
            motion = offline.motion(trajectory, fps=fps, speed=speed, forces=forces, singularity=singularity)
            page = offline.record(motion)
            notes = describe(offline, motion)
        path = write_atomic(html, page)
        print(f"wrote {path} ({len(page) / 1e6:.1f} MB): {notes[0]}", file=stream)
        for line in notes[1:]:
            print(line, file=stream)
        return 0

    viewer: Viewer | None = None
    try:
        viewer = Viewer(params, human)
        motion = viewer.motion(trajectory, fps=fps, speed=speed, forces=forces, singularity=singularity)
        print(f"meshcat viewer: {viewer.url}  (Ctrl-C to stop)", file=stream, flush=True)
        for line in describe(viewer, motion):
            print(line, file=stream, flush=True)
        if step:
            step_through(viewer, motion, input or sys.stdin, stream)
        else:
            viewer.play(motion, speed=speed, loop=True)
    except KeyboardInterrupt:
        print("stopped", file=stream, flush=True)
    finally:
        if viewer is not None:
            viewer.close()
    return 0


def step_through(viewer, motion, input: TextIO, stream: TextIO, loop: bool = True, on_frame=None) -> None:
    """One frame per line read from ``input``: Enter next, ``b`` back one, ``q`` or end of input stops.

    Each frame's time and angles are printed to ``stream``; ``on_frame(k, motion)``
    is called after each frame is shown.
    """
    import numpy as np

    n, k = len(motion), 0
    print("step mode: Enter = next frame, b = back, q = quit", file=stream, flush=True)
    while True:
        viewer.show_frame(motion, k)
        if on_frame is not None:
            on_frame(k, motion)
        a, b, g = np.degrees(motion.angles[k])
        print(
            f"frame {k + 1}/{n}  t = {motion.t[k]:.4f} s  α = {a:7.2f}°  β = {b:6.2f}°  γ = {g:6.2f}°",
            file=stream,
            flush=True,
        )
        line = input.readline()
        if not line or line.strip().lower().startswith("q"):
            return
        k += -1 if line.strip().lower().startswith("b") else 1
        if k >= n:
            if not loop:
                return
            k = 0
        k %= n
