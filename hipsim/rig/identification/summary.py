"""What an identification reports (``hipsim identify``): typed records of the fit, made where the fit is.

:meth:`hipsim.rig.identification.fit.Identification.summary` makes an
:class:`IdentificationSummary` (file units, torques in [N·mm]): each base
parameter's estimate beside its prior, the ones the logs determine with their
combinations, the parameters held at their starting values and why, the
residuals, and per held-out log the identified and the starting machines' errors
(:class:`~hipsim.rig.compare_summary.MotorError`) with the error per gait phase
and the envelope warnings. ``identify --base`` lists the base parameters
(:class:`BaseListing`). The verdict of the fit is its self-check's
(:func:`hipsim.fit_checks.fit_verdict`).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ...records import Record, optional
from ..compare_summary import MotorError
from .base import BaseParameters

__all__ = [
    "BaseDefinition",
    "BaseListing",
    "EstimateRow",
    "HeldOutLog",
    "HeldRow",
    "IdentificationSummary",
    "IdentifiedRow",
    "PhaseNote",
    "base_listing",
    "phase_note",
]


@dataclass(frozen=True)
class EstimateRow(Record):
    """One base parameter's estimate beside its prior, in file units.

    Attributes:
        name: the standard parameter that names it (``m_L``).
        definition: the combination it stands for.
        key, unit: its standard parameter's file key and unit.
        value, std: posterior mean and standard deviation.
        prior, prior_std: prior mean (the starting machine's) and standard deviation.
        determined: the logs determine it (posterior std at most half the prior's).
        shift_in_prior_std: how far the data moved it from its prior, in prior standard deviations.
    """

    name: str
    definition: str
    key: str
    unit: str
    value: float
    std: float
    prior: float
    prior_std: float
    determined: bool
    shift_in_prior_std: float


@dataclass(frozen=True)
class IdentifiedRow(Record):
    """A base parameter the logs determine: its whole combination, value, standard deviation, relative std (file units)."""

    quantity: str
    key: str
    value: float
    std: float
    unit: str
    relative_std: float


@dataclass(frozen=True)
class HeldRow(Record):
    """A parameter the logs did not determine, its value (file units) and why it kept it."""

    quantity: str
    reason: str
    value: float
    unit: str


@dataclass(frozen=True)
class PhaseNote(Record):
    """What a held-out log says beyond its RMS errors: envelope warnings, and the error per tenth of the gait cycle.

    Attributes:
        envelope_warnings: the ranges where the log leaves the training logs' (the prediction extrapolates there).
        gait_phase_edges_percent: the bins' edges in [%] of the cycle from heel strike (absent without two heel strikes).
        identified_phase_rms_error_Nmm, starting_phase_rms_error_Nmm: RMS error per bin and motor in [N·mm], (B, 3)
            (null for a bin without samples).
    """

    envelope_warnings: tuple[str, ...]
    gait_phase_edges_percent: list[float] | None = optional()
    identified_phase_rms_error_Nmm: list[list[float]] | None = optional()
    starting_phase_rms_error_Nmm: list[list[float]] | None = optional()


@dataclass(frozen=True)
class HeldOutLog(Record):
    """A held-out log predicted by the identified and by the starting machine: per motor ("1", "2", "3") the errors."""

    log: str
    identified: dict[str, MotorError]
    starting: dict[str, MotorError]
    note: PhaseNote | None = optional(flatten=True)


@dataclass(frozen=True)
class IdentificationSummary(Record):
    """An identification (``hipsim identify``): the fit's numbers in file units, torques in [N·mm].

    Attributes:
        logs: the logs fitted, by name.
        starting_parameters: the starting machine's source (the prior's means).
        lever_spin: the model's levers spin as their universal joints impose.
        rows: samples used, all motors.
        condition_number: of the weighted regressor of the determined base parameters.
        residual_rms_Nmm: the fit's RMS residual per motor ("1", "2", "3").
        base_parameters: every base parameter's estimate and prior.
        identified: the base parameters the logs determine.
        held: the parameters kept at their starting values (undetermined, folded in, or without effect).
        active_constraints: the physical-consistency constraints the solution sits on.
        validation: per held-out log (``--validate``), the errors of both machines; absent without one.
    """

    logs: tuple[str, ...]
    starting_parameters: str
    lever_spin: bool
    rows: int
    condition_number: float
    residual_rms_Nmm: dict[str, float]
    base_parameters: tuple[EstimateRow, ...]
    identified: tuple[IdentifiedRow, ...]
    held: tuple[HeldRow, ...]
    active_constraints: tuple[str, ...]
    validation: tuple[HeldOutLog, ...] | None = optional()


def phase_note(
    warnings: Sequence[str],
    edges: np.ndarray | None,
    identified: np.ndarray | None,
    starting: np.ndarray | None,
) -> PhaseNote:
    """A held-out log's note: its envelope warnings, and its per-phase errors when the three arrays are all given."""
    if edges is None or identified is None or starting is None:
        return PhaseNote(tuple(warnings))
    return PhaseNote(
        tuple(warnings),
        [float(x) for x in edges],
        [[float(x) for x in row] for row in identified],
        [[float(x) for x in row] for row in starting],
    )


@dataclass(frozen=True)
class BaseDefinition(Record):
    """A base parameter as ``identify --base`` lists it: its name, key, unit, definition, prior mean and std (file units)."""

    name: str
    key: str
    unit: str
    definition: str
    prior: float
    prior_std: float


@dataclass(frozen=True)
class BaseListing(Record):
    """``hipsim identify --base``: the machine's base parameters, with the prior each starts from."""

    base_parameters: tuple[BaseDefinition, ...]


def base_listing(base: BaseParameters, mean: np.ndarray, std: np.ndarray) -> BaseListing:
    """The base parameters with their prior (``mean``, ``std`` in SI, in the order of ``base``; file units out)."""
    rows = []
    for p, m, d, s in zip(base.parameters, mean, std, base.scale):
        rows.append(BaseDefinition(p.label, p.key, p.unit, p.definition, float(m / s), float(d / s)))
    return BaseListing(tuple(rows))
