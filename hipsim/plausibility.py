"""Is a number what its label says? The ranges of a hip simulator's data, and the unit slips a lab makes.

A unit slip reads as valid numbers: milliseconds under ``t_s`` make a 1 s
gait a 1000 s one, a load in kN under ``Fe_N`` a 3 N load, a data sheet's
N·mm under ``_Nm`` a 380 N·m motor. Every reader (trajectory files, load
files, rig logs and snapshots, drive files and catalogues, parameter files)
holds its numbers against the same ranges here, so the same slip gets the
same answer whichever command reads the file:

- a **clear slip** (the value is out of every plausible range, and the
  factor of a unit, most often 1000, brings it inside) is returned as its
  reason in words (the value and the unit it looks like), which the caller
  raises as its own :class:`~hipsim.exceptions.HipsimError` subclass naming
  the file and the column or key;
- a **doubtful** value (outside the usual range, with no unit that explains
  it) is a warning, one line, returned to the caller.

Comparisons against a limit allow for rounding: :func:`beyond` counts a
value within a relative :data:`REL_TOL` of its limit as at the limit, not
past it (a load mapped onto 300–3000 N peaks at 3000.0000000000005 N).

This module is part of the foundation (it imports no other hipsim module:
NumPy and the standard library only), so the machine's and the motion's
readers, which may not import each other, share it.
"""

from __future__ import annotations

import math
from datetime import UTC, datetime

import numpy as np

__all__ = [
    "ANGLE_RANGE_DEG",
    "EPOCH_FLOOR_S",
    "LOAD_PEAK_N",
    "LOAD_WARNING_N",
    "MOTION_SPAN_S",
    "MS_STEP_S",
    "REL_TOL",
    "SMALL_RANGE_DEG",
    "DRIVE_RANGES",
    "beyond",
    "below",
    "drive_slip",
    "epoch_warning",
    "factor_name",
    "load_slip",
    "one_radians_slip",
    "radians_slip",
    "time_slip",
    "unit_slip",
]

#: Relative tolerance of a comparison with a limit: a value within it of its limit is at the limit.
REL_TOL = 1e-9

#: Time stamps whose first value is beyond this in [s] (3 March 1973) are Unix epoch times, read relative to the first.
EPOCH_FLOOR_S = 1e8

#: A median sample step at least this long in [s] (2 Hz) is no gait recording: with a thousandth of it plausible, milliseconds.
MS_STEP_S = 0.5

#: The shortest and longest plausible motion in [s]: a gait cycle of a runner to an endurance log of a day.
MOTION_SPAN_S = (0.05, 86400.0)

#: The peak loads of a hip simulator's tests in [N]: ISO 14242-1's 300 to 3000 N, up to 5000 N for heavier patients' cycles.
LOAD_PEAK_N = (300.0, 5000.0)

#: A load peak below this in [N] is warned of (a light test, or a unit slip).
LOAD_WARNING_N = 100.0

#: The smallest and largest range in [deg] of an angle over a gait cycle (ISO 14242-1: 7° to 43°; 180° for any rig motion).
ANGLE_RANGE_DEG = (5.0, 180.0)

#: When every angle spans less than this in [deg] and the widest would be a gait's as radians, they are radians.
SMALL_RANGE_DEG = 1.0

_DEG_PER_RAD = 180.0 / math.pi


#: The plausible range in SI of a drive's figures for a machine of this size (a 100 W to 2 kW servo, a ball screw):
#: field base name → (low, high, SI unit). A value out of it that a factor of 1000 brings in is a unit slip.
DRIVE_RANGES = {
    "s1_torque": (0.01, 100.0, "N·m"),
    "peak_torque": (0.01, 300.0, "N·m"),
    "rated_torque": (0.01, 100.0, "N·m"),
    "max_speed": (100.0 * math.pi / 30.0, 30000.0 * math.pi / 30.0, "rad/s"),
    "lead": (1e-3, 0.1, "m"),
    "stroke": (0.01, 3.0, "m"),
    "torque_constant": (0.02, 20.0, "N·m/A"),
    "preload": (20.0, 50000.0, "N"),
}


def drive_slip(field: str, values_si, given_unit: str, factor: float = 1.0) -> str | None:
    """Why a drive figure (in SI) looks like another unit than its key's, or None.

    Args:
        field: the field's base name (a key of :data:`DRIVE_RANGES`; others pass).
        values_si: the value(s) in SI, as converted from the key's unit.
        given_unit: the key's unit as written (``Nm``, ``Nmm``, ``rpm``, ``mm``), for the message.
        factor: SI per unit of ``given_unit`` (1e-3 for ``Nmm``), to show the value as written.

    Returns:
        The reason in words, naming the factor (the caller names the file and key and raises).
    """
    if field not in DRIVE_RANGES:
        return None
    low, high, unit = DRIVE_RANGES[field]
    values = np.atleast_1d(np.asarray(values_si, dtype=float))
    values = values[values > 0]
    if values.size == 0:
        return None
    worst = float(values.max()) if values.max() > high else float(values.min())
    slip = unit_slip(worst, low, high)
    if slip is None:
        return None
    shown = f"{worst / factor:.4g} {given_unit}"
    plausible = f"{low:.3g} to {high:.3g} {unit}"
    return (
        f"{shown} is {factor_name(slip)} a plausible figure for this machine's drive ({plausible}): "
        f"a unit slip by {factor_name(slip).split()[0]} (N·mm under an _Nm key, N·m under _Nmm, m under _mm, krpm under _rpm?): "
        "check the key's unit against the data sheet"
    )


def beyond(value, limit, rel: float = REL_TOL):
    """``value > limit``, allowing a relative ``rel`` of rounding: a value at its limit within rounding is not beyond it.

    Args:
        value: the value(s) needed (any unit, the limit's).
        limit: the ceiling (a number or an array broadcasting with ``value``).
        rel: the relative tolerance.

    Returns:
        A bool (or a bool array for arrays).
    """
    value, limit = np.asarray(value, dtype=float), np.asarray(limit, dtype=float)
    out = value > limit + rel * np.abs(limit)
    return bool(out) if out.ndim == 0 else out


def below(value, floor, rel: float = REL_TOL):
    """``value < floor``, allowing a relative ``rel`` of rounding (as :func:`beyond`, for a floor)."""
    value, floor = np.asarray(value, dtype=float), np.asarray(floor, dtype=float)
    out = value < floor - rel * np.abs(floor)
    return bool(out) if out.ndim == 0 else out


def unit_slip(value: float, low: float, high: float, factors=(1e3, 1e-3)) -> float | None:
    """The factor f (of ``factors``) for which ``value`` is out of [low, high] but ``value / f`` inside it, else None.

    Args:
        value: a magnitude, as read (in SI, or in the unit its label says).
        low, high: its plausible range, in the same unit.
        factors: the unit factors to try (1000: N·mm read as N·m, ms read as s, …).
    """
    value = abs(float(value))
    if low <= value <= high or not math.isfinite(value) or value == 0.0:
        return None
    for factor in factors:
        if low <= value / factor <= high:
            return factor
    return None


def factor_name(factor: float) -> str:
    """'1000 times' or '1/1000 of' (a ratio in words, 4 significant digits)."""
    if factor >= 1:
        return f"{factor:.4g} times"
    return f"1/{1 / factor:.4g} of"


def time_slip(t: np.ndarray, unit: str) -> str | None:
    """Why times (converted to [s] from ``unit``) are in another unit than labelled, or None when they are plausible.

    Milliseconds read as seconds give a median step of :data:`MS_STEP_S` or
    more (a gait sampled at 2 Hz or less); seconds read as milliseconds a
    motion shorter than :data:`MOTION_SPAN_S`'s 50 ms. Either is a clear slip
    when the factor of 1000 brings the motion's span into :data:`MOTION_SPAN_S`.

    Args:
        t: times in [s], (N,), increasing (N ≥ 2).
        unit: the unit they were read in: "s" or "ms".

    Returns:
        The reason in words (the caller names the file and column and raises), or None.
    """
    t = np.asarray(t, dtype=float)
    if t.size < 2:
        return None
    span = float(t[-1] - t[0])
    step = float(np.median(np.diff(t)))
    low, high = MOTION_SPAN_S
    if unit == "s" and step >= MS_STEP_S and low <= span * 1e-3 <= high:
        return (
            f"the times look like milliseconds: a sample every {step:.4g} s over {span:.4g} s is no gait recording "
            f"({span * 1e-3:.4g} s in ms); give the times in s (or, for a trajectory file, map the column with :ms)"
        )
    if unit == "ms" and span < low and low <= span * 1e3 <= high:
        return (
            f"the times look like seconds: read as ms the motion lasts {span * 1e3:.4g} ms ({1 / step:.4g} Hz "
            f"sampling); label the time column in s (drop ':ms')"
        )
    return None


def epoch_warning(t0: float) -> str | None:
    """The note for times that are Unix epoch time stamps (read relative to the first), or None.

    Args:
        t0: the first time in [s].
    """
    if not (math.isfinite(t0) and t0 >= EPOCH_FLOOR_S):
        return None
    try:
        when = datetime.fromtimestamp(t0, tz=UTC).strftime("%Y-%m-%d %H:%M:%S UTC")
    except (OverflowError, OSError, ValueError):
        return None
    return f"the times are Unix time stamps (from {when}): read relative to the first, {t0:.17g} s"


def load_slip(peak: float, unit: str = "N") -> tuple[str | None, str | None]:
    """A load's peak in [N] against a hip simulator's test loads: (error, warning), each a reason or None.

    Args:
        peak: the load's largest value in [N], as read.
        unit: the unit it was read in ("N", "kN", "%BW"), for the advice.

    Returns:
        (error, None) for a clear slip (a factor of 1000 brings the peak into
        :data:`LOAD_PEAK_N`), (None, warning) for a doubtful peak (below
        :data:`LOAD_WARNING_N`, or above :data:`LOAD_PEAK_N`'s top), else (None, None).
    """
    low, high = LOAD_PEAK_N
    if not (math.isfinite(peak) and peak > 0.0):
        return None, None
    slip = unit_slip(peak, low, high)
    if slip == 1e-3 and unit == "N":
        return (
            f"the load looks like kN: its peak is {peak:.4g} N, 1/1000 of a hip simulator's test loads "
            f"(ISO 14242-1: {low:g} to 3000 N); give it in N, or label it :kN",
            None,
        )
    if slip == 1e3 and unit == "kN":
        return (
            f"the load looks like N read as kN: its peak is {peak:.4g} N, 1000 times a hip simulator's test loads "
            f"(ISO 14242-1: {low:g} to 3000 N); label it :N",
            None,
        )
    if slip == 1e3:
        return (
            f"the load peaks at {peak:.4g} N, 1000 times a hip simulator's test loads (ISO 14242-1: {low:g} to 3000 N): "
            "check its unit",
            None,
        )
    if peak < LOAD_WARNING_N:
        return None, (
            f"the load peaks at {peak:.4g} N, far below a hip simulator's test loads (ISO 14242-1: {low:g} to 3000 N): is it in N?"
        )
    if peak > high:
        return None, f"the load peaks at {peak:.4g} N, above any hip simulator's test load ({high:g} N): check its unit"
    return None, None


def radians_slip(spans_deg: np.ndarray) -> tuple[int, float] | None:
    """Angles read in degrees that are radians: (the widest angle's index, its span as radians in [deg]), or None.

    Clear when every angle spans less than :data:`SMALL_RANGE_DEG` and the widest,
    read as radians, spans a gait cycle's range (:data:`ANGLE_RANGE_DEG`).

    Args:
        spans_deg: each angle's range (max − min) in [deg] as read.
    """
    spans = np.asarray(spans_deg, dtype=float)
    if spans.size == 0 or not np.all(np.isfinite(spans)):
        return None
    k = int(np.argmax(spans))
    as_radians = float(spans[k]) * _DEG_PER_RAD
    if spans[k] < SMALL_RANGE_DEG and ANGLE_RANGE_DEG[0] <= as_radians <= ANGLE_RANGE_DEG[1]:
        return k, as_radians
    return None


def one_radians_slip(spans_deg: np.ndarray) -> list[tuple[int, float]]:
    """Single angles read in degrees that look like radians beside others that are degrees: (index, span as radians in [deg]).

    An angle spanning under :data:`SMALL_RANGE_DEG` (but moving) while the widest spans a gait's range
    (:data:`ANGLE_RANGE_DEG`): one column exported in radians among degrees, or scaled (a doubtful value:
    the caller warns, naming the span as radians). A still angle (span 0) is a planar model's.

    Args:
        spans_deg: each angle's range (max − min) in [deg] as read.
    """
    spans = np.asarray(spans_deg, dtype=float)
    if spans.size < 2 or not np.all(np.isfinite(spans)) or spans.max() < ANGLE_RANGE_DEG[0]:
        return []
    return [(k, float(v) * _DEG_PER_RAD) for k, v in enumerate(spans) if 0.0 < v < SMALL_RANGE_DEG]
