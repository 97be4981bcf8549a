"""The view command's own logic (hipsim.cli.view): frame-by-frame stepping (next, back through the start, quit, the
end of input, looping at the end) with a stand-in viewer, and the refusals before any viewer starts. The viewer and
its page: present/test_viewer.py."""

from __future__ import annotations

import io
import math
from types import SimpleNamespace

import numpy as np
import pytest

from hipsim.cli.view import run_view, step_through
from hipsim.exceptions import HipsimError


class Shown:
    def __init__(self):
        self.frames: list[int] = []

    def show_frame(self, motion, k):
        self.frames.append(k)


class Frames(SimpleNamespace):
    def __len__(self):
        return len(self.t)


def frames(n=3) -> Frames:
    return Frames(t=np.arange(n) * 0.1, angles=np.radians(np.tile([10.0, -2.0, 5.0], (n, 1))))


def test_back_from_the_first_frame_is_the_last_and_q_stops():
    viewer, out = Shown(), io.StringIO()
    step_through(viewer, frames(), io.StringIO("b\n\n\n\nquit\n"), out)
    assert viewer.frames == [0, 2, 0, 1, 2]
    lines = out.getvalue().splitlines()
    assert lines[0] == "step mode: Enter = next frame, b = back, q = quit"
    assert lines[2] == "frame 3/3  t = 0.2000 s  α =   10.00°  β =  -2.00°  γ =   5.00°"


def test_the_end_of_input_stops_and_without_looping_so_does_the_last_frame():
    viewer = Shown()
    step_through(viewer, frames(), io.StringIO("\n"), io.StringIO())
    assert viewer.frames == [0, 1]  # then no more lines
    viewer = Shown()
    seen: list[int] = []
    step_through(
        viewer, frames(), io.StringIO("\n" * 10), io.StringIO(), loop=False, on_frame=lambda k, m: seen.append(k)
    )
    assert viewer.frames == seen == [0, 1, 2]


@pytest.mark.parametrize(
    ("given", "message"),
    [
        ({"speed": 0.0}, "--speed must be a positive number"),
        ({"speed": math.inf}, "--speed"),
        ({"fps": -1.0}, "--fps must be a positive number"),
        ({"html": "v.html", "step": True}, "--frame-by-frame applies to the live viewer, not to --html"),
    ],
)
def test_refusals_before_any_viewer(given, message):
    with pytest.raises(HipsimError, match=message):
        run_view(None, None, **given)  # type: ignore[arg-type]
