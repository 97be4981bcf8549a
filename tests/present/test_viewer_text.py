"""What a viewer shows, in words (hipsim.present.viewer_text): the legend's and the description's lines, each there
only when its part is shown, with the numbers taken from the frames."""

from __future__ import annotations

import numpy as np

from hipsim.present.motion_frames import Motion
from hipsim.present.viewer_text import description_lines, legend_lines


def motion(forces: bool, cond: bool) -> Motion:
    n = 3
    F_act = np.array([[10.0, -250.4, 3.0], [0.0, 0.0, 0.0], [1.0, 2.0, 3.0]])
    F_joint = np.zeros((n, 2, 3, 3))
    F_joint[1, 0, 2] = [30.0, 40.0, 0.0]  # |F| = 50 N, the largest
    return Motion(
        t=np.array([0.0, 0.1, 0.2]),
        fps=10.0,
        speed=1.0,
        angles=np.zeros((n, 3)),
        q=np.zeros((n, 7)),
        residual=np.array([1e-13, 4e-13, 2e-13]),
        F_act=F_act if forces else None,
        F_joint=F_joint if forces else None,
        cond_inv=np.array([0.31, np.nan, 0.4567]) if cond else None,
        hip=np.zeros((n, 3)),
        periodic=False,
        name="walk <1>",
    )


def test_the_description_says_frames_gap_forces_and_measure():
    lines = description_lines(motion(True, True), 0.002, human=True)
    assert (
        lines[0] == "walk <1>: 0.2 s in 3 frames at 10 fps, speed 1x; largest closure gap of the frames shown 4.0e-13 m"
    )
    assert lines[1].startswith("arrows at 2 mm per N: magenta") and "(peak 250 N)" in lines[1]
    assert lines[1].endswith("(peak 50 N)")  # the largest lever force by its length, not a component
    assert lines[2].endswith("here 0.310 to 0.457")  # NaN frames left out
    assert lines[3].startswith("human model: its right hip")


def test_only_what_is_shown_is_described():
    assert len(description_lines(motion(False, False), None, human=False)) == 1
    assert len(description_lines(motion(True, False), None, human=False)) == 1  # forces without a scale: no arrows


def test_the_legend_escapes_the_name_and_lists_the_same_parts():
    lines = legend_lines(motion(True, True), 0.002, human=False)
    assert lines[0].startswith("hipsim: walk &lt;1&gt;, 0.2 s in 3 frames at 10 fps, speed 1&times;")
    assert lines[1].startswith("arrows (2 mm per N)") and lines[2].startswith("levers: singularity measure")
    assert len(legend_lines(motion(False, False), 0.002, human=True)) == 2
