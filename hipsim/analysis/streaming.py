"""Runs of any length in constant memory: a model run piece by piece, its columns streamed out, its summary gathered.

:func:`stream_run` runs one model along a :mod:`~hipsim.motion.sources`
source a piece (``chunk`` samples) at a time, hands each piece's CSV columns
to ``write`` and adds it to a :class:`~hipsim.results.Summary`; memory is set
by the piece, not by the run. :class:`PieceRunner` runs one piece (``hipsim
check`` runs five models side by side with it).

The pieces give the one-piece results to the last digit: each piece is run as
the engine's :class:`~hipsim.engine.PieceNeeds` ask. The analytic model runs
each piece with the sample before it (and the first piece of a periodic motion
with the last sample, the wrap-around), so the detection of a singularity
crossed between two samples sees the same neighbours. The Pinocchio model
closes the chain from the previous samples' solution: its state, a
:class:`~hipsim.closed_chain.closure.Continuation`, carries that solution from
one piece to the next, so its pieces too give the one-piece results bit for bit.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping

import numpy as np

from ..engine import PieceNeeds
from ..exceptions import ArgumentError, PoseError
from ..machine.parameters import Parameters
from ..motion.sources import SampledSource, TrajectorySource, pieces
from ..motion.trajectories import Trajectory
from ..results import Run, RunSummary, Summary
from .registry import make_engine

__all__ = ["CHUNK", "PieceRunner", "as_source", "stream_run"]

#: Samples per piece unless an engine asks for fewer: some 60 MB of the analytic model's working arrays, a few ms of its time.
CHUNK = PieceNeeds().chunk


def _join(before: Trajectory, piece: Trajectory) -> Trajectory:
    return Trajectory(
        np.concatenate([before.t, piece.t]),
        np.vstack([before.q, piece.q]),
        np.vstack([before.qd, piece.qd]),
        np.vstack([before.qdd, piece.qdd]),
        np.concatenate([before.Fe, piece.Fe]),
        piece.name,
    )


class PieceRunner:
    """One engine along one source, piece by piece, each piece as the engine's :class:`~hipsim.engine.PieceNeeds` ask (module docstring).

    Args:
        params: the machine.
        source: the motion.
        model, on_error, lever_spin: as :func:`hipsim.analyse`.

    Attributes:
        engine: the :class:`~hipsim.engine.Engine` run.
        state: what the engine carries from the last piece run to the next.
    """

    def __init__(self, params, source: TrajectorySource, model: str, on_error: str = "raise", lever_spin: bool = False):
        self.engine = make_engine(model, params, on_error=on_error, lever_spin=lever_spin)
        self.source, self.state = source, None

    def run(self, start: int, piece: Trajectory) -> Run:
        """The engine along ``piece``, the samples from ``start`` on."""
        n, needs = len(self.source), self.engine.pieces
        if start > 0 and needs.overlap:
            before = self.source.piece(max(0, start - needs.overlap), start)
        elif start == 0 and needs.wraps_around and self.source.periodic:
            before = self.source.piece(n - 1, n)  # the wrap-around: sample 0 follows the last
        else:
            return self._run(piece, piece, start)
        try:
            return self._run(_join(before, piece), piece, start - len(before)).slice(slice(len(before), None))
        except PoseError as error:
            if start == 0 and error.index < 0:  # the wrap-around sample itself is bad: reported where it is, later
                return self._run(piece, piece, start)
            raise

    def _run(self, trajectory: Trajectory, piece: Trajectory, offset: int) -> Run:
        """Run, a pose error's index made the run's and its file line added."""
        try:
            self.state = self.engine.piece_state(offset, self.state)
            return self.engine.run(trajectory, self.state)
        except PoseError as error:
            line = error.line if error.line is not None else piece.line_at(error.time)
            raise PoseError(error.reason, error.time, error.index + offset, source=error.source, line=line) from None


def as_source(motion) -> TrajectorySource:
    """A source of ``motion``: a Trajectory in memory wrapped, a source as it is."""
    return SampledSource(motion) if isinstance(motion, Trajectory) else motion


def stream_run(
    params: Parameters,
    source: TrajectorySource | Trajectory,
    model: str = "analytic",
    *,
    on_error: str = "raise",
    lever_spin: bool = False,
    chunk: int | None = None,
    write: Callable[[Mapping[str, np.ndarray]], None] | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> RunSummary:
    """Run a model along a source in pieces: each piece's columns to ``write``, the summary of the whole returned.

    Args:
        params: the machine.
        source: the motion (a :mod:`~hipsim.motion.sources` source, or a Trajectory).
        model: as :func:`hipsim.analyse`.
        on_error: as :func:`hipsim.analyse`; with "flag" every piece has the ``flagged`` column.
        lever_spin: as :func:`hipsim.analyse`.
        chunk: samples per piece; None: the engine's own (:attr:`hipsim.engine.PieceNeeds.chunk`).
        write: called with each piece's :meth:`~hipsim.results.Run.columns`, in order.
        progress: called with (samples done, samples in all) after each piece.

    Returns:
        The summary :meth:`hipsim.Run.summary` gives of the whole run.

    Raises:
        PoseError: the first pose out of reach or singular (index and time of the whole run),
            or every sample flagged.
    """
    source = as_source(source)
    if chunk is not None and (isinstance(chunk, bool) or not isinstance(chunk, int) or chunk < 1):
        raise ArgumentError("chunk", chunk, "a positive number of samples")
    runner = PieceRunner(params, source, model, on_error, lever_spin)
    if chunk is None:
        chunk = runner.engine.pieces.chunk
    summary: Summary | None = None
    n = len(source)
    for start, stop in pieces(source, chunk):
        run = runner.run(start, source.piece(start, stop))
        if summary is None:  # whether there are joint forces: what the model gives
            summary = Summary(run.model, params, source.name, run.joint_forces is not None)
        summary.add(run)
        if write is not None:
            columns = run.columns()
            if on_error == "flag":
                columns.setdefault("flagged", run.flagged.astype(float))
            write(columns)
        if progress is not None:
            progress(stop, n)
    if summary is None or not summary.kept:
        raise PoseError(
            f"all {n} samples are out of reach or singular; nothing to compute", source.time(0), 0, source=source.name
        )
    return summary.result()
