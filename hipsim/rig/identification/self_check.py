"""Does an identification make sense? Its residuals, its moves from the prior and its held-out logs, held to the gates.

The gates and their thresholds are :mod:`hipsim.fit_checks`'s (residuals beyond
3 times the noise, a base parameter beyond 5 prior standard deviations). The
noise of a motor's torque is taken as :data:`~hipsim.fit_checks.NOISE_FLOOR`
(5 %) of its RMS over the rows fitted: the rows are low-passed and decimated,
which hides the sensor's white noise, and a model that explains a log leaves
a few per cent (friction it lacks, the filter's edges). A swapped pair of
torque columns leaves 74–80 times a right log's residual, far beyond it.

When a gate fails and the logs are at hand, the measured torques are set
against the starting machine's (:func:`~hipsim.fit_checks.column_pattern`):
a swap, a sign flip or an offset that explains them is named as the likely cause.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from ...fit_checks import NOISE_FLOOR, FitCheck, column_pattern, prior_gate, residual_gate
from ..compare import compare_log
from ..logs.log import Log
from .fit import Identification

__all__ = ["TORQUE_COLUMNS", "check_identification"]

#: The logged torque columns, in the order of the motors.
TORQUE_COLUMNS = ("tau_1", "tau_2", "tau_3")


def _noise(measured_rms) -> np.ndarray:
    return NOISE_FLOOR * np.asarray(measured_rms, dtype=float)


def check_identification(result: Identification, logs: Sequence[Log] = (), validate: Sequence[Log] = ()) -> FitCheck:
    """The gates of :mod:`hipsim.fit_checks` on an identification; the likely cause named from ``logs`` when one fails.

    Args:
        result: the identification (residual and torque RMS per motor in [N·m], its estimates and priors).
        logs: the logs fitted (for the pattern of a failed gate; empty: no pattern is looked for).
        validate: the held-out logs, in the order of ``result.validation`` (for their pattern).

    Returns:
        The check: no findings when every gate passes.
    """
    findings: list[str] = []
    scale = np.asarray(result.torque_rms if result.torque_rms is not None else np.full(3, np.inf))
    residual = residual_gate(np.asarray(result.residual_rms) * 1e3, _noise(scale) * 1e3, TORQUE_COLUMNS, "N·mm")
    if residual:
        findings.append(f"the fit's {residual}" + _pattern(result, logs[:1]))
    moved = prior_gate(
        [e.value for e in result.estimates],
        [e.prior for e in result.estimates],
        [e.prior_std for e in result.estimates],
        [e.name for e in result.estimates],
        "(file units)",
    )
    if moved:
        findings.append(
            f"base parameters {moved}: the logs and the model disagree (a unit, a column, another machine?)"
        )
    for k, (identified, _start) in enumerate(result.validation):
        motors = identified.statistics["motors"]
        error = [motors[str(i + 1)]["rms_error_Nmm"] for i in range(3)]
        measured = [motors[str(i + 1)]["measured_rms_Nmm"] for i in range(3)]
        held = residual_gate(error, _noise(measured), TORQUE_COLUMNS, "N·mm")
        if held:
            name = validate[k].name if k < len(validate) else f"held-out log {k + 1}"
            findings.append(f"held-out {name}: {held}" + _pattern(result, validate[k : k + 1]))
    return FitCheck("identify", tuple(findings))


def _pattern(result: Identification, logs: Sequence[Log]) -> str:
    """' (likely cause: …)' from the first log against the starting machine, or ''."""
    if not logs:
        return ""
    comparison = compare_log(result.start, logs[0], result.lever_spin)
    found = column_pattern(comparison.measured * 1e3, comparison.model["total"] * 1e3, TORQUE_COLUMNS, "N·mm")
    return f" (likely cause in {logs[0].name}: {found})" if found else ""
