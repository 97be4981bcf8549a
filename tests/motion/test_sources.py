"""Trajectory sources handed out in pieces (hipsim.motion.sources), pinned on tiny tables written here (motion_support)."""

from __future__ import annotations

import numpy as np
from motion_support import LOAD, N, Q, T, csv_file, error_of

from hipsim.motion.build import SampledMotion
from hipsim.motion.readers import read_trajectory
from hipsim.motion.sources import MAX_STREAMED_SAMPLES, CycleSource, FileSource, SampledSource, pieces
from hipsim.motion.trajectories import Trajectory, iso14242_at


def test_the_built_in_cycle_in_pieces():
    source = CycleSource(rate=100.0, cycles=0.5, frequency=2.0)
    assert (len(source), source.periodic, source.name) == (25, False, "ISO 14242-1")
    assert (source.rate, source.frequency) == (100.0, 2.0)
    assert source.time(7) == 0.07
    piece = source.piece(20, 40)
    expected = iso14242_at(np.arange(20, 25) / 100.0, 2.0)
    np.testing.assert_array_equal(piece.t, expected.t)
    np.testing.assert_array_equal(piece.q, expected.q)
    np.testing.assert_array_equal(piece.Fe, expected.Fe)
    whole = CycleSource(rate=50, cycles=2)
    assert (len(whole), whole.periodic, whole.rate, whole.frequency) == (100, True, 50.0, 1.0)
    assert CycleSource().rate == 1000.0 and len(CycleSource()) == 1000 and CycleSource().periodic
    assert MAX_STREAMED_SAMPLES == 100_000_000
    error = error_of(lambda: CycleSource(rate=1e6, cycles=101))
    assert "at most 100,000,000 are run in one go" in str(error)


def test_a_trajectory_in_memory_in_pieces():
    whole = Trajectory(T, Q, 2 * Q, 3 * Q, LOAD, name="mine", periodic=True, lines=np.arange(3, 3 + N))
    source = SampledSource(whole)
    assert (len(source), source.name, source.periodic, source.time(3)) == (N, "mine", True, 0.03)
    piece = source.piece(2, 5)
    np.testing.assert_array_equal(piece.t, T[2:5])
    np.testing.assert_array_equal(piece.qd, 2 * Q[2:5])
    np.testing.assert_array_equal(piece.lines, [5, 6, 7])
    assert list(pieces(source, 3)) == [(0, 3), (3, 6), (6, 8)]
    assert list(pieces(source, 8)) == [(0, 8)]
    assert list(pieces(source, 100)) == [(0, 8)]


def test_a_file_in_pieces_is_the_file_read_whole(tmp_path):
    path = csv_file(tmp_path / "a.csv")
    source = FileSource.read(path)
    whole = read_trajectory(path)
    assert (len(source), source.name, source.periodic) == (N, path, False)
    assert source.time(5) == 0.05
    piece = source.piece(3, 6)
    np.testing.assert_array_equal(piece.qdd, whole.qdd[3:6])
    np.testing.assert_array_equal(piece.lines, [5, 6, 7])
    got = source.trajectory()
    np.testing.assert_array_equal(got.qd, whole.qd)
    assert got.name == path
    resampled = FileSource.read(path, resample=200.0)
    assert len(resampled) == 15 and resampled.time(3) == 0.015
    assert isinstance(FileSource(source.motion).motion, SampledMotion)
