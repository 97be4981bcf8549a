"""What a tolerance study reports: per control and platform the 95th percentiles of the attitude errors over the
drawn machines, and which tolerances make the follower's error (``hipsim stations --bands``)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..records import Level, Record, Verdict
from .tolerance import ToleranceResult

__all__ = [
    "ControlTolerance",
    "PlatformPercentiles",
    "SensitivityRow",
    "ToleranceSummary",
    "family_shares",
    "tolerance_summary",
    "tolerance_verdict",
]

#: The percentile the study reports.
PERCENTILE = 95.0


@dataclass(frozen=True)
class PlatformPercentiles(Record):
    """One platform's errors over the draws: the 95th percentile of each draw's RMS and of its peak, per angle [deg]."""

    platform: int
    rms_p95_deg: tuple[float, float, float]
    peak_p95_deg: tuple[float, float, float]


@dataclass(frozen=True)
class SensitivityRow(Record):
    """One per-chain value's share of the follower's expected mean square error (first order).

    Attributes:
        value: the value's name; chain: "ji", "centre j" or "intermediate" (the stack-up's seat); family: its tolerance family.
        rms_deg: the RMS error per angle α, β, γ in [deg] its band alone gives.
        share: its fraction of the expected mean square, summed over the angles.
    """

    value: str
    chain: str
    family: str
    rms_deg: tuple[float, float, float]
    share: float


@dataclass(frozen=True)
class ControlTolerance(Record):
    """One control's study: both platforms' percentiles, the sensitivity table (largest first), the families' shares."""

    control: str
    platforms: tuple[PlatformPercentiles, PlatformPercentiles]
    sensitivity: tuple[SensitivityRow, ...]
    family_share: dict[str, float]


@dataclass(frozen=True)
class ToleranceSummary(Record):
    """A tolerance study: the draws, the bands, and per control what it found.

    Attributes:
        draws: machines drawn; seed: their seed; samples_per_draw: samples of the motion each ran.
        bands_mm: the half band per family in [mm].
        controls: per control studied its results.
    """

    draws: int
    seed: int
    samples_per_draw: int
    bands_mm: dict[str, float]
    controls: tuple[ControlTolerance, ...]


def family_shares(rows: Sequence[SensitivityRow]) -> dict[str, float]:
    """Each tolerance family's share of the expected mean square (the sum of its values' shares), largest first."""
    shares: dict[str, float] = {}
    for row in rows:
        shares[row.family] = shares.get(row.family, 0.0) + row.share
    return dict(sorted(shares.items(), key=lambda item: -item[1]))


def _triple(values: np.ndarray) -> tuple[float, float, float]:
    return float(values[0]), float(values[1]), float(values[2])


def _row(row: Mapping[str, Any]) -> SensitivityRow:
    return SensitivityRow(row["value"], row["chain"], row["family"], _triple(np.asarray(row["rms_deg"])), row["share"])


def tolerance_summary(result: ToleranceResult, samples_per_draw: int) -> ToleranceSummary:
    """The study's summary: per control and platform the 95th percentiles over the draws in [deg].

    Args:
        result: the draws (:func:`hipsim.stations.tolerance.tolerance_draws`).
        samples_per_draw: samples of the motion each drawn machine ran.
    """
    rms95 = np.degrees(result.percentile("rms", PERCENTILE))
    peak95 = np.degrees(result.percentile("peak", PERCENTILE))
    controls = []
    for c, control in enumerate(result.controls):
        platforms = tuple(PlatformPercentiles(j + 1, _triple(rms95[c, j]), _triple(peak95[c, j])) for j in range(2))
        rows = tuple(_row(row) for row in result.sensitivity[control])
        controls.append(ControlTolerance(control, platforms, rows, family_shares(rows)))  # type: ignore[arg-type]
    return ToleranceSummary(
        draws=int(result.rms.shape[0]),
        seed=result.seed,
        samples_per_draw=samples_per_draw,
        bands_mm={k: v * 1e3 for k, v in result.bands.items()},
        controls=tuple(controls),
    )


def tolerance_verdict(summary: ToleranceSummary) -> Verdict:
    """A tolerance study's verdict: NOT MADE, always (it reports the errors' spread over the machines drawn and what
    makes it; no acceptance limit is set for those errors)."""
    controls = ", ".join(c.control for c in summary.controls) or "none"
    return Verdict(
        Level.NOT_MADE,
        f"manufacturing tolerances: the attitude errors of {summary.draws} machine(s) drawn within the bands "
        f"(--control {controls}), their {PERCENTILE:g}th percentiles and each tolerance's share",
        "the errors against an acceptance limit (none is set)",
        {"draws": float(summary.draws)},
    )
