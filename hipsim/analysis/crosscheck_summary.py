"""What ``hipsim check`` reports: per configuration the models' column-by-column differences, and the verdict (PASS
when every configuration that must agree does, to :data:`hipsim.analysis.crosscheck.TOLERANCE`)."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from ..records import Level, Record
from .crosscheck import TOLERANCE, Comparison

__all__ = ["ColumnDifference", "ConfigurationCheck", "CrossCheckSummary", "crosscheck_summary"]


@dataclass(frozen=True)
class ColumnDifference(Record):
    """One column: the largest absolute difference (the column's unit) and relative to the column's peak."""

    column: str
    max_abs_diff: float
    max_rel_diff: float


@dataclass(frozen=True)
class ConfigurationCheck(Record):
    """One configuration: what is compared, whether it must agree, whether it does, its worst relative difference."""

    name: str
    description: str
    required: bool
    ok: bool
    worst: float
    columns: tuple[ColumnDifference, ...]


@dataclass(frozen=True)
class CrossCheckSummary(Record):
    """The models against each other on one trajectory.

    Attributes:
        trajectory, samples, parameters: the motion, its samples, the machine's origin.
        tolerance: the largest relative difference of models that agree.
        agree: every configuration that must agree does.
        comparisons: each configuration's differences (the informational ones too).
    """

    trajectory: str
    samples: int
    parameters: str
    tolerance: float
    agree: bool
    comparisons: tuple[ConfigurationCheck, ...]

    @property
    def level(self) -> Level:
        """PASS when the models agree where they must, else FAIL (for :func:`hipsim.records.exit_status`)."""
        return Level.PASS if self.agree else Level.FAIL


def crosscheck_summary(
    trajectory: str, samples: int, parameters: str, comparisons: Sequence[Comparison]
) -> CrossCheckSummary:
    """The summary of :func:`hipsim.analysis.crosscheck.compare_models` (or ``compare_mujoco``) on a trajectory."""
    return CrossCheckSummary(
        trajectory=trajectory,
        samples=samples,
        parameters=parameters,
        tolerance=TOLERANCE,
        agree=not any(c.required and not c.ok for c in comparisons),
        comparisons=tuple(
            ConfigurationCheck(
                c.name,
                c.description,
                c.required,
                c.ok,
                c.worst,
                tuple(ColumnDifference(name, a, r) for name, a, r in c.rows),
            )
            for c in comparisons
        ),
    )
