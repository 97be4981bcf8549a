"""The verdict on a model-versus-rig comparison: is every motor's RMS torque error within the accepted share of its
measured RMS torque? A pure function of the comparison (:mod:`hipsim.rig.compare`)."""

from __future__ import annotations

from collections.abc import Mapping

from ..records import Level, Verdict

__all__ = ["acceptance_verdict"]


def acceptance_verdict(relative_rms_error: Mapping[str, float], accept: float | None) -> Verdict:
    """PASS when every motor's RMS error relative to its measured RMS torque is at most ``accept``, FAIL when one is
    above, NOT MADE without a threshold.

    Args:
        relative_rms_error: per motor ("1", "2", "3") its RMS error over its measured RMS torque, a fraction.
        accept: the largest relative RMS error accepted, a fraction (0.05: 5 %); None: no threshold.
    """
    numbers = {f"relative_rms_error_{i}": float(v) for i, v in relative_rms_error.items()}
    not_judged = "the peak errors and the errors per gait phase (shown, not judged)"
    if accept is None:
        return Verdict(Level.NOT_MADE, "no acceptance threshold given (--accept PERCENT)", not_judged, numbers)
    share = f"{100 * accept:g} %"
    failing = [i for i, v in relative_rms_error.items() if not v <= accept]
    if failing:
        judged = f"{len(failing)} of {len(relative_rms_error)} motors exceed the accepted {share} RMS error"
        return Verdict(Level.FAIL, judged, not_judged, numbers | {"accept": accept})
    judged = f"every motor's RMS error is within {share} of its measured RMS torque"
    return Verdict(Level.PASS, judged, not_judged, numbers | {"accept": accept})
