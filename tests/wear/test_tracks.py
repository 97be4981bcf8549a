"""hipsim.wear.tracks: markers on rings by hand; slide tracks checked as a rigid turn (each starts at its marker, stays
on the unit sphere, and keeps its angle to every other marker), over the first cycle only."""

from __future__ import annotations

import math

import numpy as np
from numpy.testing import assert_allclose

from hipsim.motion.trajectories import iso14242
from hipsim.wear.kinematics import CupSetup
from hipsim.wear.tracks import cycle_tracks, default_markers


def test_markers_one_at_the_pole_and_per_ring_on_each_ring():
    markers = default_markers()
    assert markers.shape == (1 + 3 * 8, 3)
    assert_allclose(markers[0], [0.0, 0.0, 1.0])
    s = math.sqrt(0.5)
    assert_allclose(markers[1 + 2 * 8], [s, 0.0, s], atol=1e-15)  # the 45° ring's first marker, at φ = 0
    assert_allclose(
        markers[1 + 2], [0.0, math.sin(math.radians(15)), math.cos(math.radians(15))], atol=1e-15
    )  # φ = 90°
    assert_allclose(np.linalg.norm(markers, axis=1), 1.0, rtol=1e-15)
    assert default_markers((10.0,), per_ring=4).shape == (4, 3)  # no pole unless asked for


def test_slide_tracks_are_a_rigid_turn_of_the_markers_over_the_first_cycle():
    motion = iso14242(rate=100, cycles=2)  # t = 0, 0.01, ... 1.99 s
    tracks = cycle_tracks(motion, 1.0, CupSetup())
    K = 101  # samples up to the first at t ≥ 1 s, that one included
    assert tracks.slide.shape == (25, K, 3) and tracks.force.shape == (K, 3)
    assert_allclose(tracks.load, motion.Fe[:K])
    assert_allclose(tracks.slide[:, 0], tracks.markers, atol=1e-12)  # h = R_rel(0)·w₀ is w₀ at the start
    assert_allclose(np.linalg.norm(tracks.slide, axis=-1), 1.0, rtol=1e-12)
    angles = np.einsum("ak,bk->ab", tracks.markers, tracks.markers)
    for k in (1, 37, K - 1):
        assert_allclose(tracks.slide[:, k] @ tracks.slide[:, k].T, angles, atol=1e-12)
    assert np.ptp(tracks.slide[0, :, 0]) > 0.1  # the pole marker does move: the check above is not vacuous


def test_markers_given_are_tracked():
    tracks = cycle_tracks(iso14242(rate=50), 1.0, CupSetup(), markers=np.array([[1.0, 0.0, 0.0]]))
    assert tracks.slide.shape[0] == 1
    assert_allclose(tracks.slide[0, 0], [1.0, 0.0, 0.0], atol=1e-12)


def test_the_first_cycle_of_a_source_starting_late_and_the_samples_drawn(monkeypatch):
    """A source (not a trajectory) starting at t = 5 s: its first cycle; a cycle of one step keeps two samples; a
    cycle longer than the motion keeps all; at most MAX_DRAWN samples drawn, every ⌈K/MAX_DRAWN⌉-th."""
    import hipsim.wear.tracks as tracks_module
    from hipsim.motion.sources import SampledSource
    from hipsim.motion.trajectories import Trajectory

    base = iso14242(rate=100, cycles=2)
    late = Trajectory(base.t + 5.0, base.q, base.qd, base.qdd, base.Fe, "late")
    tracks = cycle_tracks(SampledSource(late), 1.0, CupSetup())
    assert tracks.force.shape == (101, 3)
    assert_allclose(tracks.load, base.Fe[:101])
    assert cycle_tracks(late, 0.005, CupSetup()).force.shape == (2, 3)  # t₁ − t₀ reaches the cycle: samples 0, 1
    assert cycle_tracks(late, 5.0, CupSetup()).force.shape == (200, 3)  # no sample reaches it: the whole motion
    monkeypatch.setattr(tracks_module, "MAX_DRAWN", 10)
    thin = cycle_tracks(late, 1.0, CupSetup())  # 101 samples, every 11th: 0, 11, … 99
    assert_allclose(thin.load, base.Fe[0:101:11])
