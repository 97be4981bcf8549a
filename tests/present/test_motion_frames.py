"""The frames a viewer shows (hipsim.present.motion_frames): a Motion's rate and duration, the resampling at the
display's rate (samples taken as they are where they fall on it), and the refusals before any chain is closed.
Closed frames on the machine: present/test_viewer.py."""

from __future__ import annotations

import math

import numpy as np
import pytest

from hipsim.exceptions import ArgumentError, PoseError
from hipsim.machine.parameters import load_parameters
from hipsim.motion.trajectories import Trajectory, iso14242
from hipsim.present.motion_frames import Motion, _resample, closed_motion


def motion(n=4, periodic=True, fps=30.0, speed=0.5, forces=True) -> Motion:
    t = np.arange(n) / 60.0
    return Motion(
        t=t,
        fps=fps,
        speed=speed,
        angles=np.zeros((n, 3)),
        q=np.zeros((n, 7)),
        residual=np.array([1e-13, 3e-13, 2e-13, 0.0])[:n],
        F_act=np.ones((n, 3)) if forces else None,
        F_joint=np.ones((n, 2, 3, 3)),
        cond_inv=None,
        hip=np.zeros((n, 3)),
        periodic=periodic,
        name="m",
    )


def test_the_rate_is_fps_over_speed_and_a_period_lasts_its_frames():
    m = motion()
    assert m.rate == 60.0 and len(m) == 4
    assert m.duration == pytest.approx(4 / 60.0)  # a period: the frames tile it
    assert motion(periodic=False).duration == pytest.approx(3 / 60.0)  # from the first frame to the last
    assert m.forces() is not None and motion(forces=False).forces() is None  # both or neither


def test_a_periodic_trajectory_resampled_on_its_own_samples_takes_them_as_they_are():
    iso = iso14242(rate=100.0)  # 100 samples over 1 s
    samples, periodic = _resample(iso, 25.0)
    assert periodic and len(samples) == 25
    np.testing.assert_array_equal(samples.q, iso.q[::4])  # every 4th sample, not interpolated
    between, _ = _resample(iso, 30.0)  # 30 frames of a period: between the samples
    assert len(between) == 30 and between.t[1] == pytest.approx(1 / 30, rel=1e-12)


def test_an_open_trajectory_keeps_its_last_sample_on_the_grid():
    iso = iso14242(rate=100.0)
    part = Trajectory(iso.t[:51], iso.q[:51], iso.qd[:51], iso.qdd[:51], iso.Fe[:51], "part", False)  # 0 … 0.5 s
    samples, periodic = _resample(part, 10.0)
    assert not periodic and samples.t.tolist() == pytest.approx([0.0, 0.1, 0.2, 0.3, 0.4, 0.5])
    few, _ = _resample(part, 1.0)  # 0.5 s is shorter than a frame's step: its first and last samples
    assert few.t.tolist() == [0.0, 0.5]
    one = part.slice(slice(0, 1))
    assert _resample(one, 10.0) == (one, False)


@pytest.mark.parametrize(("fps", "speed"), [(0.0, 1.0), (30.0, 0.0), (math.inf, 1.0), (30.0, math.nan)])
def test_fps_and_speed_must_be_positive_and_finite(fps, speed):
    with pytest.raises(ArgumentError, match="fps, speed"):
        closed_motion(None, load_parameters(), iso14242(rate=10.0), fps=fps, speed=speed)


def test_a_pose_out_of_reach_is_named_by_its_sample_before_any_chain_is_closed():
    iso = iso14242(rate=10.0)
    q = iso.q.copy()
    q[3, 2] = math.radians(170.0)  # γ far beyond the levers' reach
    far = Trajectory(iso.t, q, iso.qd, iso.qdd, iso.Fe, "far.csv", True)
    with pytest.raises(PoseError) as caught:
        closed_motion(None, load_parameters(), far, fps=10.0)
    assert caught.value.index == 3 and caught.value.time == pytest.approx(0.3)
