"""What one learning step reports: errors per platform and angle, convergence, the update, each station's ISO verdict.

Typed records, made by :func:`hipsim.learning.step.learning_step`; ``to_json()``
gives the document ``hipsim learn`` and ``hipsim simulate --learn`` print.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from ..exceptions import TrajectoryError
from ..motion.iso_compliance import DEFAULT_TOLERANCES, Tolerances, iso_check

__all__ = [
    "Convergence",
    "LearnSummary",
    "PlatformErrors",
    "StationVerdict",
    "UpdateChange",
    "platform_errors",
    "station_verdict",
]

ANGLES = ("alpha", "beta", "gamma")


def _triple(values) -> tuple[float, float, float]:
    a, b, c = (float(v) for v in values)
    return a, b, c


@dataclass(frozen=True)
class PlatformErrors:
    """One platform's measured error q_d − q over the cycle, per angle (α, β, γ), in [deg] and [s]."""

    platform: int
    controlled: bool
    rms_deg: tuple[float, float, float]
    peak_deg: tuple[float, float, float]
    peak_at_s: tuple[float, float, float]

    @property
    def rms_total_deg(self) -> float:
        """√(mean over the three angles of their mean squares) in [deg]."""
        return math.sqrt(sum(r * r for r in self.rms_deg) / 3.0)


def platform_errors(t: np.ndarray, errors: np.ndarray, learned_from: tuple[int, ...]) -> tuple[PlatformErrors, ...]:
    """Each platform with finite errors (N, 2, 3) [rad] at times t (N,) [s]: its RMS and peak per angle."""
    out = []
    for j in (1, 2):
        e = np.degrees(errors[:, j - 1])
        if not np.all(np.isfinite(e)):
            continue
        peak = np.argmax(np.abs(e), axis=0)
        out.append(
            PlatformErrors(
                j,
                j in learned_from,
                _triple(np.sqrt(np.mean(e**2, axis=0))),
                _triple(e[peak, range(3)]),
                _triple(t[peak]),
            )
        )
    return tuple(out)


@dataclass(frozen=True)
class Convergence:
    """The monotone-convergence figure ‖Q(I − L·P)‖ < 1 on the model and, where measurable, on the log's drive.

    Attributes:
        model: the figure on the model (|1 − γ|).
        data: the figure with the drive's response measured in the log, or None (no commands logged).
        data_at_Hz: the harmonic where the data's figure is worst, or None.
        note: what the data figure rests on, in words.
    """

    model: float
    data: float | None
    data_at_Hz: float | None
    note: str

    @property
    def converges(self) -> bool:
        """Both figures (those known) below 1."""
        return self.model < 1.0 and (self.data is None or self.data < 1.0)


@dataclass(frozen=True)
class UpdateChange:
    """What the update changed, per carriage, in [mm]: the change of the command, and the whole learned correction."""

    change_rms_mm: tuple[float, float, float]
    change_peak_mm: tuple[float, float, float]
    learned_rms_mm: tuple[float, float, float]
    learned_peak_mm: tuple[float, float, float]


@dataclass(frozen=True)
class StationVerdict:
    """The ISO 14242-1 check of the motion a station went through (its measured attitude), not of the desired one.

    Attributes:
        platform: 1 or 2.
        verdict: "PASS", "FAIL" or "not made".
        failing: the quantities out of tolerance.
        worst_deg: the worst deviation of α, β, γ from the waveform in [deg] (NaN when not made).
        reason: why no verdict was made, else "".
    """

    platform: int
    verdict: str
    failing: tuple[str, ...]
    worst_deg: tuple[float, float, float]
    reason: str = ""


def station_verdict(
    platform: int,
    t: np.ndarray,
    q: np.ndarray,
    load: np.ndarray,
    source: str,
    tolerances: Tolerances = DEFAULT_TOLERANCES,
) -> StationVerdict:
    """The verdict on platform ``platform``'s measured motion q (N, 3) [rad] over one period (wrapped), load (N,) [N];
    platform 0 for the desired motion itself."""
    what = f"station {platform}" if platform else "the desired motion"
    try:
        check = iso_check(t, q, load, tolerances, source=f"{source}, {what}", periodic=True)
    except TrajectoryError as error:
        # str(): the message on one line (hipsim.exceptions.printable), as every refusal prints it.
        return StationVerdict(platform, "not made", (), (math.nan,) * 3, str(error))
    return StationVerdict(
        platform, "PASS" if check.passed else "FAIL", tuple(check.failing), _triple(check.worst(a) for a in ANGLES)
    )


@dataclass(frozen=True)
class LearnSummary:
    """One learning step: the cycle it learned from and the command it made.

    Attributes:
        cycle: the cycle's number (0 for the model's own command, before any run); None when not known (a log).
        control, weights, gain, q_cutoff_Hz, drive_lag_ms: the law.
        period_s: the cycle's period; samples: per period; periods: the log's periods averaged per phase (0: none).
        commands_logged: the log had the commands (else the encoders stood for them).
        errors: each measured platform's error in the cycle learned from (empty for cycle 0).
        convergence: the convergence figures.
        update: what the update changed (None for cycle 0).
        stations: each measured station's ISO 14242-1 verdict on its motion (empty without a load or for cycle 0).
        desired: the same check of the desired motion itself (platform 0), so that a station that tracks a motion
            which is not the ISO waveform is not read as a failing station; None without a load.
    """

    cycle: int | None
    control: str
    weights: tuple[float, float]
    gain: float
    q_cutoff_Hz: float | None
    drive_lag_ms: float
    period_s: float
    samples: int
    periods: int
    commands_logged: bool
    errors: tuple[PlatformErrors, ...]
    convergence: Convergence
    update: UpdateChange | None
    stations: tuple[StationVerdict, ...]
    desired: StationVerdict | None = None

    def controlled_rms_deg(self) -> float:
        """The RMS error over the learned platforms' angles in [deg] (NaN without errors)."""
        chosen = [e for e in self.errors if e.controlled]
        if not chosen:
            return math.nan
        return math.sqrt(sum(e.rms_total_deg**2 for e in chosen) / len(chosen))

    def to_json(self) -> dict:
        """The record as a JSON-ready document (NaN as None is left to the writer)."""
        return dataclasses.asdict(self) | {"converges": self.convergence.converges}
