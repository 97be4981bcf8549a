"""Trajectory sources: a motion handed out a piece at a time, so that a run of any length fits in constant memory.

Every source has a ``name``, ``periodic`` (the samples cover whole periods),
``len()`` (the number of samples), ``time(k)`` (sample k's time in [s]) and
``piece(start, stop) -> Trajectory`` (samples start … stop−1, not periodic).
A piece equals that part of the whole trajectory to the last digit: the
built-in cycle is exact at every sample, and a file's derivatives come from
the one spline through all its samples (:class:`hipsim.motion.build.SampledMotion`).
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import Protocol

import numpy as np

from .trajectories import Trajectory, iso14242_at, iso14242_samples

__all__ = ["CycleSource", "FileSource", "SampledSource", "TrajectorySource", "pieces"]

#: Most samples a built-in cycle handed out in pieces may have (some 28 h at 1 kHz; the times alone take 800 MB).
MAX_STREAMED_SAMPLES = 100_000_000


class TrajectorySource(Protocol):
    """What a run in pieces needs of a motion (module docstring)."""

    name: str
    periodic: bool

    def __len__(self) -> int: ...

    def time(self, k: int) -> float: ...

    def piece(self, start: int, stop: int) -> Trajectory: ...


class CycleSource:
    """The built-in ISO 14242-1 cycle (spec §7.2), generated piece by piece: what :func:`hipsim.iso14242` gives, in parts.

    Args:
        rate: sample rate in [Hz].
        cycles: number of cycles (whole or not).
        frequency: cycle frequency in [Hz].
    """

    name = "ISO 14242-1"

    def __init__(self, rate: float = 1000.0, cycles: float = 1, frequency: float = 1.0):
        self._n, self.periodic = iso14242_samples(rate, cycles, frequency, MAX_STREAMED_SAMPLES, "are run in one go")
        self.rate, self.frequency = float(rate), float(frequency)

    def __len__(self) -> int:
        return self._n

    def time(self, k: int) -> float:
        """Sample k's time in [s]."""
        return float(np.float64(k) / self.rate)

    def piece(self, start: int, stop: int) -> Trajectory:
        """Samples ``start`` … ``stop``−1."""
        return iso14242_at(np.arange(start, min(stop, self._n)) / self.rate, self.frequency)


class SampledSource:
    """A trajectory already in memory, handed out in pieces.

    Args:
        trajectory: the whole trajectory.
    """

    def __init__(self, trajectory: Trajectory):
        self.trajectory, self.name, self.periodic = trajectory, trajectory.name, trajectory.periodic

    def __len__(self) -> int:
        return len(self.trajectory)

    def time(self, k: int) -> float:
        """Sample k's time in [s]."""
        return float(self.trajectory.t[k])

    def piece(self, start: int, stop: int) -> Trajectory:
        """Samples ``start`` … ``stop``−1."""
        return self.trajectory.slice(slice(start, stop))


class FileSource:
    """A trajectory file read once, its samples differentiated piece by piece through the one spline of the whole file.

    Args:
        motion: the file's samples, from :func:`hipsim.motion.readers.read_trajectory` with ``lazy=True``
            (or :meth:`read`).
    """

    def __init__(self, motion):
        self.motion = motion
        self.name, self.periodic = motion.source, motion.periodic

    @classmethod
    def read(cls, path, **options) -> FileSource:
        """Read ``path`` with :func:`hipsim.motion.readers.read_trajectory`'s options, checks and errors."""
        from .readers import read_trajectory

        return cls(read_trajectory(path, **options, lazy=True))

    def __len__(self) -> int:
        return len(self.motion)

    def time(self, k: int) -> float:
        """Sample k's time in [s]."""
        return float(self.motion.t[k])

    def piece(self, start: int, stop: int) -> Trajectory:
        """Samples ``start`` … ``stop``−1 (the file's lines kept, for messages)."""
        return self.motion.piece(start, stop)

    def trajectory(self) -> Trajectory:
        """The whole trajectory, as :func:`hipsim.motion.readers.read_trajectory` gives it."""
        return self.motion.trajectory()


def pieces(source: TrajectorySource, size: int) -> Iterator[tuple[int, int]]:
    """(start, stop) of consecutive pieces of at most ``size`` samples covering the source."""
    n = len(source)
    for start in range(0, n, size):
        yield start, min(start + size, n)
