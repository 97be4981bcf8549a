"""Validation of an identification on held-out logs: the error per gait phase, and whether the log leaves the training envelope.

Per held-out log (:func:`validation_note`): the RMS error of the motor
torques per tenth of the gait cycle (phases from the load's heel strikes,
:mod:`hipsim.motion.gait_events`), identified and starting machines side by
side; and a warning for each range of the log (load, each angle, each angular
speed) that reaches beyond the training logs' by more than
:data:`MARGIN` of the training range: there the identified model extrapolates.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ...exceptions import ArgumentError, HipsimError
from ...motion.gait_events import detect_gait_events, gait_phase
from ..compare import Comparison
from ..logs.log import Log
from .summary import PhaseNote, phase_note

__all__ = ["MARGIN", "Envelope", "ValidationNote", "envelope", "training_envelope", "validation_note"]

#: How far beyond the training range (a fraction of it) a held-out log may reach before the warning.
MARGIN = 0.05
#: Gait-phase bins: tenths of the cycle.
BINS = 10


@dataclass(frozen=True)
class Envelope:
    """Ranges of logs: load in [N] (lo, hi), angles in [deg] (3, 2), angular speeds in [deg/s] (3, 2)."""

    load: tuple[float, float]
    angles: np.ndarray
    speeds: np.ndarray

    def union(self, other: Envelope) -> Envelope:
        return Envelope(
            (min(self.load[0], other.load[0]), max(self.load[1], other.load[1])),
            np.column_stack(
                [np.minimum(self.angles[:, 0], other.angles[:, 0]), np.maximum(self.angles[:, 1], other.angles[:, 1])]
            ),
            np.column_stack(
                [np.minimum(self.speeds[:, 0], other.speeds[:, 0]), np.maximum(self.speeds[:, 1], other.speeds[:, 1])]
            ),
        )

    def beyond(self, training: Envelope) -> list[str]:
        """Where these ranges leave ``training``'s by more than :data:`MARGIN` of its width, in words."""
        out = []

        def check(name, unit, lo, hi, tlo, thi):
            margin = MARGIN * max(thi - tlo, 1e-9)
            if lo < tlo - margin or hi > thi + margin:
                out.append(f"{name} {lo:.4g} to {hi:.4g} {unit} (training {tlo:.4g} to {thi:.4g})")

        check("load", "N", *self.load, *training.load)
        for k, name in enumerate(("alpha", "beta", "gamma")):
            check(name, "°", *self.angles[k], *training.angles[k])
            check(f"{name} speed", "°/s", *self.speeds[k], *training.speeds[k])
        return out


def _core(log: Log):
    """(t, Fe, q, qd) of the log's usable samples, window by window."""
    usable = log.usable
    for window, core, start in log.windows():
        lo, hi = max(start, usable.start), min(start + core.stop - core.start, usable.stop)
        if lo < hi:
            part = slice(core.start + lo - start, core.start + hi - start)
            trajectory = window.trajectory
            yield trajectory.t[part], trajectory.Fe[part], trajectory.q[part], trajectory.qd[part]


def envelope(log: Log) -> Envelope:
    """The ranges a log covers (usable samples)."""
    load, angles, speeds = [np.inf, -np.inf], np.tile([np.inf, -np.inf], (3, 1)), np.tile([np.inf, -np.inf], (3, 1))
    for _, Fe, q, qd in _core(log):
        load = [min(load[0], Fe.min()), max(load[1], Fe.max())]
        a, s = np.degrees(q), np.degrees(qd)
        angles = np.column_stack([np.minimum(angles[:, 0], a.min(axis=0)), np.maximum(angles[:, 1], a.max(axis=0))])
        speeds = np.column_stack([np.minimum(speeds[:, 0], s.min(axis=0)), np.maximum(speeds[:, 1], s.max(axis=0))])
    return Envelope((float(load[0]), float(load[1])), angles, speeds)


def training_envelope(logs: Sequence[Log]) -> Envelope:
    """The union of the training logs' ranges."""
    out = None
    for log in logs:
        e = envelope(log)
        out = e if out is None else out.union(e)
    if out is None:
        raise ArgumentError("logs", list(logs), "at least one training log")
    return out


@dataclass(frozen=True)
class ValidationNote:
    """What a held-out log says beyond the RMS errors.

    Attributes:
        log: its name.
        phase_edges: gait-cycle percentages bounding the bins, (B + 1,), or None without two heel strikes.
        identified_phase_rms, starting_phase_rms: RMS error per bin and motor in [N·mm], (B, 3), or None.
        warnings: the ranges where the log leaves the training envelope.
    """

    log: str
    phase_edges: np.ndarray | None
    identified_phase_rms: np.ndarray | None
    starting_phase_rms: np.ndarray | None
    warnings: tuple[str, ...]

    def text(self) -> str:
        lines = []
        identified, starting = self.identified_phase_rms, self.starting_phase_rms  # given with the edges
        if self.phase_edges is not None and identified is not None and starting is not None:
            lines.append(
                f"RMS error per tenth of the gait cycle from heel strike [N·mm], identified (starting) on {self.log}:"
            )
            for i in range(3):
                lines.append(
                    f"  M{i + 1}: " + " ".join(f"{a:.3g} ({b:.3g})" for a, b in zip(identified[:, i], starting[:, i]))
                )
        else:
            lines.append(f"{self.log}: no two heel strikes in the load, so no error per gait phase")
        for warning in self.warnings:
            lines.append(f"WARNING: {self.log} leaves the training envelope, the prediction extrapolates: {warning}")
        return "\n".join(lines)

    def summary(self) -> PhaseNote:
        """The note as the summary's record: the warnings, and the per-phase errors when the log has them."""
        return phase_note(self.warnings, self.phase_edges, self.identified_phase_rms, self.starting_phase_rms)


def _phase_rms(comparison: Comparison, phase: np.ndarray, edges: np.ndarray) -> np.ndarray:
    error = comparison.error * 1e3
    bins = np.clip(np.searchsorted(edges, phase, side="right") - 1, 0, len(edges) - 2)
    out = np.full((len(edges) - 1, 3), np.nan)
    for b in range(len(edges) - 1):
        chosen = bins == b
        if chosen.any():
            out[b] = np.sqrt(np.mean(error[chosen] ** 2, axis=0))
    return out


def validation_note(identified: Comparison, starting: Comparison, log: Log, training: Envelope) -> ValidationNote:
    """Per-phase errors of one held-out log and its envelope warnings (module docstring)."""
    parts = list(_core(log))
    t = np.concatenate([p[0] for p in parts])
    Fe = np.concatenate([p[1] for p in parts])
    edges = phase_id = phase_start = None
    try:
        events = detect_gait_events(t, Fe, source=log.name)
        edges = np.linspace(0.0, 100.0, BINS + 1)
        phase = gait_phase(identified.t, events)[0]
        phase_id = _phase_rms(identified, phase, edges)
        phase_start = _phase_rms(starting, gait_phase(starting.t, events)[0], edges)
    except HipsimError:
        edges = None
    return ValidationNote(log.name, edges, phase_id, phase_start, tuple(envelope(log).beyond(training)))
