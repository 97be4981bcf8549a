"""The rig log the models take: one type, handed out in windows, whether held in memory or read from its file in pieces.

A :class:`Log` is motion with its derivatives, load and motor torques, filtered
alike, and what a reader should know of it (its name, rate, cutoff, where the
motion came from). Its samples come in windows (:meth:`Log.windows`): a log
held in memory (:class:`MeasuredLog`, from arrays or :func:`load_log`) is its
own one window; a log read from its file in pieces (:class:`LogPieces`, for
logs of any length in constant memory) hands out overlapping windows that give
the whole log's values to round-off. Comparisons and fits
(:func:`hipsim.rig.compare`, :func:`hipsim.rig.identify`) go through the
windows, so they take either without asking which.
"""

from __future__ import annotations

import math
import tempfile
from abc import ABC, abstractmethod
from collections.abc import Iterator, Mapping
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ...analytic.forward_kinematics import forward_kinematics
from ...arrays import check_shapes
from ...exceptions import ArgumentError, PoseError, TrajectoryError
from ...machine.parameters import Parameters, load_parameters
from ...motion.trajectories import ANGLE_NAMES, Trajectory
from .reader import RigLogFile
from .smoothing import DEFAULT_CUTOFF, edge_samples, filter_halo, lowpass, minimum_samples, reversal_half, smooth_motion

__all__ = [
    "DEFAULT_CUTOFF",
    "DEFAULT_TOLERANCE_DEG",
    "PIECE",
    "Log",
    "LogInfo",
    "LogPieces",
    "MeasuredLog",
    "load_log",
]

#: Largest disagreement in [deg] allowed between the attitude sensor and the encoders' forward kinematics.
DEFAULT_TOLERANCE_DEG = 0.5
#: Samples per piece of a log compared in pieces (:class:`LogPieces`): some 70 MB of the model's working arrays.
PIECE = 20_000
#: How much an interpolating quintic spline's response to one sample shrinks per sample (its B-spline's root of largest modulus < 1).
SPLINE_DECAY = 0.4305753470999737
#: Samples beyond which that response is below round-off twice over (2⁻¹⁰⁶): a piece's spline reaches this far. Twice,
#: because a piece's end condition errs by as much as the second derivative of noisy samples, many times the angles.
SPLINE_HALO = int(math.ceil(106 * math.log(2) / -math.log(SPLINE_DECAY))) + 4


@dataclass(frozen=True)
class LogInfo:
    """A log's description (:meth:`Log.info`): what a comparison reports of its log.

    Attributes:
        name: the log's name (its file).
        rate: sample rate in [Hz].
        cutoff: the low-pass cutoff in [Hz], or None.
        motion_from: "angles" or "encoders".
        notes: how the log was read.
    """

    name: str
    rate: float
    cutoff: float | None
    motion_from: str
    notes: tuple[str, ...]


class Log(ABC):
    """The rig log the models take (module docstring): its samples in windows.

    Attributes every log has: ``name`` (its file), ``rate`` (sample rate in
    [Hz]), ``t`` (sample times in [s], (N,)), ``cutoff`` (the low-pass cutoff in [Hz], or None), ``motion_from``
    ("angles", "encoders" or "exact"), ``notes`` (how it was read), ``edge``
    (samples at each end that the filter left unreliable).
    """

    name: str
    cutoff: float | None
    motion_from: str
    notes: tuple[str, ...]
    edge: int

    @abstractmethod
    def __len__(self) -> int:
        """Samples in the log."""

    # Properties, not plain annotations: the variants compute them (a subclass may not
    # override a writeable attribute with a read-only property).
    @property
    @abstractmethod
    def rate(self) -> float:
        """Sample rate in [Hz]."""

    @property
    @abstractmethod
    def t(self) -> np.ndarray:
        """Sample times in [s], (N,)."""

    @property
    def usable(self) -> slice:
        """The samples between the filter's edges."""
        return slice(self.edge, len(self) - self.edge)

    @abstractmethod
    def windows(self) -> Iterator[tuple[MeasuredLog, slice, int]]:
        """The log in windows.

        Yields:
            (window, core, start): a window of the log as a :class:`MeasuredLog`
            (with as much of the log around its core as the filters need), the
            core's samples in it (a slice), and the log's index of the core's
            first sample. The cores tile the log.
        """

    @abstractmethod
    def filtered_angles(self, most: int | None = None) -> tuple[np.ndarray, np.ndarray]:
        """Times in [s] and low-passed angles in [rad] of the usable samples, every k-th so that at most ``most`` are kept (None: all)."""

    def info(self) -> LogInfo:
        """The log's description."""
        return LogInfo(self.name, self.rate, self.cutoff, self.motion_from, self.notes)

    def close(self) -> None:  # noqa: B027 - a hook: a log in memory holds nothing to drop
        """Drop what the log holds outside memory (nothing, for a log in memory)."""

    def __enter__(self):
        return self

    def __exit__(self, *exc) -> None:
        self.close()


@dataclass(frozen=True, eq=False)
class MeasuredLog(Log):
    """A log held in memory: smooth motion with derivatives, and torques; its whole self is its one window.

    Build it with :func:`hipsim.rig.load_log` from a file, or directly
    from arrays (e.g. a simulation's exact states, with ``cutoff=None``).

    Attributes:
        trajectory: the motion (angles, rates, accelerations) and the load.
        tau: measured motor torques in [N·m], (N, 3), filtered like the motion.
        cutoff: the low-pass cutoff in [Hz] the motion and torques went
            through, or None for exact (unfiltered) signals.
        name: the log's name (its file), for messages and reports.
        motion_from: "angles", "encoders", or "exact".
        notes: what a reader should know about how the log was read.
        lines: the file line of each sample, (N,), or None.
        edge: samples at each end that the filter left unreliable; comparisons
            and fits use the samples between them (:attr:`usable`), but the
            model runs over all, so that its torques can be filtered alike.
        sample_rate: the sample rate in [Hz]; None for the times' (a piece of
            a long log carries the whole log's, so every piece filters alike).
    """

    trajectory: Trajectory
    tau: np.ndarray
    cutoff: float | None = None
    name: str = "log"
    motion_from: str = "exact"
    notes: tuple[str, ...] = ()
    lines: np.ndarray | None = field(default=None)
    edge: int = 0
    sample_rate: float | None = None

    def __post_init__(self):
        n = len(self.trajectory)
        if not (0 <= self.edge and 2 * self.edge < n):
            raise TrajectoryError(f"edge of {self.edge} samples leaves nothing of {n}", source=self.name)
        check_shapes(self, {"tau": (n, 3)} | ({"lines": (n,)} if self.lines is not None else {}))
        if self.cutoff is not None and not (math.isfinite(self.cutoff) and self.cutoff > 0):
            raise TrajectoryError(f"cutoff must be a positive frequency in Hz, got {self.cutoff!r}", source=self.name)
        if not np.all(np.isfinite(self.tau)):
            raise TrajectoryError("torques are not finite", source=self.name)

    def __len__(self) -> int:
        return len(self.trajectory)

    @property
    def t(self) -> np.ndarray:
        """Sample times in [s], (N,)."""
        return self.trajectory.t

    @property
    def rate(self) -> float:
        """Sample rate in [Hz]."""
        if self.sample_rate is not None:
            return self.sample_rate
        t = self.trajectory.t
        return (t.size - 1) / (t[-1] - t[0])

    def windows(self) -> Iterator[tuple[MeasuredLog, slice, int]]:
        """The log itself, whole: one window."""
        yield self, slice(0, len(self)), 0

    def filtered_angles(self, most: int | None = None) -> tuple[np.ndarray, np.ndarray]:
        """Times in [s] and low-passed angles in [rad] of the usable samples, every k-th so that at most ``most`` are kept (None: all)."""
        first, stop = self.usable.start, self.usable.stop
        stride = 1 if most is None else max(1, -(-(stop - first) // most))
        keep = slice(first, stop, stride)
        return self.trajectory.t[keep], self.trajectory.q[keep]


def load_log(
    path: str | Path,
    params: Parameters | None = None,
    torque_constant: float | None = None,
    cutoff: float | None = DEFAULT_CUTOFF,
    tolerance_deg: float = DEFAULT_TOLERANCE_DEG,
    columns: str | Mapping[str, str] | None = None,
) -> MeasuredLog:
    """Read a rig log and make it ready for the models.

    Args:
        path: the log: CSV, TDMS or HDF5 (columns in :mod:`hipsim.rig.logs.reader`).
        params: the machine (for the encoders' forward kinematics); None for the published one.
        torque_constant: the motors' torque constant in [N·m/A], for logs of motor currents.
        cutoff: low-pass cutoff in [Hz] for motion, load and torques; None for
            none (signals already clean: the angles are then only splined).
        tolerance_deg: largest disagreement in [deg] between the attitude
            sensor's angles and the encoders' when the log has both (the
            encoders are used; beyond this the log is refused).
        columns: a TDMS or HDF5 log's column map (``NAME=GROUP/CHANNEL,…``; :mod:`hipsim.channels`), or None.

    Returns:
        The log, filtered and differentiated; its first and last
        :func:`~hipsim.rig.logs.smoothing.edge_samples` samples are marked as the filter's edges.

    Raises:
        TrajectoryError: naming the file, line and column: the reader's
            errors, encoder heights no pose reaches, a disagreement of the two
            motion sources, a log too short to filter.
    """
    with LogPieces(path, params, torque_constant, cutoff, tolerance_deg, columns=columns) as pieces:
        return pieces.whole()


class LogPieces(Log):
    """A rig log read from its file in overlapping pieces, each made ready for the models as :func:`load_log` makes the whole.

    The file is scanned once (:class:`~hipsim.rig.logs.reader.RigLogFile`:
    every check, the times kept); encoder heights are turned into angles piece
    by piece, each piece continuing from the last pose of the one before, and
    the attitude sensor checked against them. :meth:`windows` then hands out
    the log a piece (``piece`` samples) at a time with :attr:`halo` samples of
    the log on either side: the low-pass, the spline, the model's low-pass and
    the reversal windows of a piece so see the log around it as the whole log
    does. The halo is two of the filter's transients
    (:func:`~hipsim.rig.logs.smoothing.filter_halo`: its impulse response below
    round-off), the quintic spline's reach (its influence shrinks by
    :data:`SPLINE_DECAY` a sample) and a reversal window: the pieces then give
    the whole log's values to round-off (the forward kinematics, started from
    another pose, and the filters, started in another state, round differently
    in the last digits).

    Args:
        path, params, torque_constant, cutoff, tolerance_deg, columns: as :func:`load_log`.
        piece: samples per piece (at least what the filter needs).
        raw: the file already scanned (:class:`~hipsim.rig.logs.reader.RigLogFile`, e.g. with kept columns or a
            window of its lines), or None to scan ``path``.

    Raises:
        TrajectoryError: as :func:`load_log`.
    """

    def __init__(
        self,
        path: str | Path,
        params: Parameters | None = None,
        torque_constant: float | None = None,
        cutoff: float | None = DEFAULT_CUTOFF,
        tolerance_deg: float = DEFAULT_TOLERANCE_DEG,
        piece: int = PIECE,
        raw: RigLogFile | None = None,
        columns: str | Mapping[str, str] | None = None,
    ):
        if isinstance(piece, bool) or not isinstance(piece, int) or piece < 1:
            raise ArgumentError("piece", piece, "a positive number of samples")
        self.params = params if params is not None else load_parameters()
        # The scan's blocks no larger than a piece; a file scanned already (with the reader's options) is taken as is.
        given = raw is not None
        self.raw = raw = (
            raw if raw is not None else RigLogFile(path, torque_constant, block=max(piece, 1000), columns=columns)
        )
        try:
            self._describe(torque_constant, cutoff, tolerance_deg, piece)
        except BaseException:  # refused: the store this one opened is dropped now, not at the garbage collector's turn
            if not given:
                raw.close()
            raise

    def _describe(self, torque_constant: float | None, cutoff: float | None, tolerance_deg: float, piece: int) -> None:
        """The notes, edge, halo and piece size; the encoders' angles checked and stored (arguments: :class:`LogPieces`'s)."""
        raw = self.raw
        self.name, self._rate, self.cutoff, self.source = Path(raw.source).name, raw.rate, cutoff, raw.source
        notes = []
        if raw.ignored:
            notes.append(f"columns not used: {', '.join(raw.ignored)}")
        if raw.torque_from == "currents":
            notes.append(f"torques from the motor currents × {torque_constant:g} N·m/A")
        elif torque_constant is not None:
            notes.append("the log gives torques: the torque constant was not needed")
        if cutoff is None:
            self.edge, self.halo, smallest = 0, SPLINE_HALO, 6
        else:
            lowpass(raw.t, self.rate, cutoff, raw.source)  # refuses a log too short to filter, before any work
            self.edge = edge_samples(self.rate, cutoff)
            self.halo = 2 * filter_halo(self.rate, cutoff) + SPLINE_HALO + reversal_half(self.rate, cutoff) + 2
            smallest = minimum_samples(self.rate, cutoff)
        self.piece = max(piece, smallest)
        self._q = None
        if raw.has_heights:
            self.motion_from = "encoders"
            self._q = tempfile.TemporaryFile()
            worst = first = None  # (difference in deg, sample, angle) at worst and first beyond the tolerance
            q0 = None
            for a, b in self._cores():
                part = raw.piece(a, b)
                start = (part.angles[0] if part.angles is not None else None) if q0 is None else q0
                assert part.heights is not None  # raw.has_heights: every piece has them
                try:
                    q = forward_kinematics(self.params, part.heights, part.t, q0=start)
                except PoseError as error:
                    raise TrajectoryError(
                        f"encoder heights L_11_mm … at {error}", source=raw.source, line=int(part.lines[error.index])
                    ) from None
                q0 = q[-1]
                np.ascontiguousarray(q).tofile(self._q)
                if part.angles is not None:
                    difference = np.degrees(np.abs(q - part.angles))
                    k, j = np.unravel_index(np.argmax(difference), difference.shape)
                    if worst is None or difference[k, j] > worst[0]:
                        worst = (float(difference[k, j]), a + int(k), int(j))
                    beyond = np.argwhere(difference > tolerance_deg)
                    if first is None and beyond.size:
                        k, j = beyond[0]
                        first = (float(difference[k, j]), a + int(k), int(j))
            if first is not None and worst is not None:  # worst is set with first
                raise TrajectoryError(
                    f"the attitude sensor and the encoders disagree by {first[0]:.3g}° in {ANGLE_NAMES[first[2]]} "
                    f"(tolerance {tolerance_deg:g}°; {worst[0]:.3g}° at worst, line {int(raw.lines[worst[1]])}): "
                    "check the sensor's mounting, zero and sign conventions, or the machine's parameters",
                    source=raw.source,
                    line=int(raw.lines[first[1]]),
                    column=f"{ANGLE_NAMES[first[2]]}_{raw.angle_unit}",
                )
            if worst is not None:
                notes.append(
                    f"encoders used; the attitude sensor agrees within {worst[0]:.3g}° (tolerance {tolerance_deg:g}°)"
                )
        else:
            self.motion_from = "angles"
        if cutoff is not None:
            notes.append(
                f"low-passed at {cutoff:g} Hz (zero-phase Butterworth); the first and last {self.edge / self.rate:.3g} s are the filter's edges"
            )
        self.notes = tuple(notes)

    def __len__(self) -> int:
        return len(self.raw)

    @property
    def sha256(self) -> str:
        """The file's SHA-256 (hex), of the bytes its one read parsed."""
        return self.raw.sha256

    @property
    def size(self) -> int:
        """The file's size in [bytes]."""
        return self.raw.size

    @property
    def rate(self) -> float:
        """Sample rate in [Hz], the file's."""
        return self._rate

    @property
    def t(self) -> np.ndarray:
        """Sample times in [s], (N,)."""
        return self.raw.t

    def close(self) -> None:  # a hook: a log in memory holds nothing to drop
        """Drop the temporary stores."""
        self.raw.close()
        if self._q is not None:
            self._q.close()

    def _cores(self):
        n = len(self)
        for a in range(0, n, self.piece):
            yield a, min(a + self.piece, n)

    def _angles(self, lo: int, hi: int) -> np.ndarray:
        if self._q is None:
            angles = self.raw.piece(lo, hi).angles
            assert angles is not None  # no encoder heights: the log gives the attitude sensor's angles
            return angles
        self._q.seek(lo * 24)
        return np.fromfile(self._q, dtype=float, count=3 * (hi - lo)).reshape(-1, 3)

    def _window(self, lo: int, hi: int, edge: int) -> MeasuredLog:
        raw = self.raw.piece(lo, hi)
        trajectory = smooth_motion(raw.t, self._angles(lo, hi), raw.Fe, self.cutoff, self.name, rate=self.rate)
        tau = raw.tau if self.cutoff is None else lowpass(raw.tau, self.rate, self.cutoff, self.source)
        return MeasuredLog(
            trajectory, tau, self.cutoff, self.name, self.motion_from, self.notes, raw.lines, edge, self.rate
        )

    def whole(self) -> MeasuredLog:
        """The whole log at once: what :func:`load_log` returns."""
        return self._window(0, len(self), self.edge)

    def windows(self):
        """The log in pieces.

        Yields:
            (window, core, start): a piece with its halo as a :class:`MeasuredLog` (no edges),
            the piece's samples in it (a slice), and the log's index of the piece's first sample.
        """
        n = len(self)
        for a, b in self._cores():
            lo, hi = max(0, a - self.halo), min(n, b + self.halo)
            yield self._window(lo, hi, 0), slice(a - lo, b - lo), a

    def filtered_angles(self, most: int | None = None) -> tuple[np.ndarray, np.ndarray]:
        """Times in [s] and low-passed angles in [rad] of the usable samples, every k-th so that at most ``most`` are kept (None: all)."""
        first, stop = self.usable.start, self.usable.stop
        stride = 1 if most is None else max(1, -(-(stop - first) // most))
        times, angles = [], []
        n = len(self)
        for a, b in self._cores():
            lo, hi = max(0, a - self.halo), min(n, b + self.halo)
            q = self._angles(lo, hi)
            if self.cutoff is not None:
                q = lowpass(q, self.rate, self.cutoff, self.source)
            start = max(a, first)
            start += (first - start) % stride
            keep = np.arange(start, min(b, stop), stride)
            times.append(self.raw.t[keep])
            angles.append(q[keep - lo])
        return np.concatenate(times), np.concatenate(angles)
