"""What a station run reports: its columns, and per platform and angle the RMS and peak error and when it peaks.

The columns (the CSV/Parquet contract ``hipsim stations`` writes and other
commands read): ``t_s``, the carriage commands ``L_11_mm, L_12_mm, L_13_mm``
(in the encoders' reading), each platform's attitude ``alpha_1_deg`` …
``gamma_2_deg``, its error against the desired ``err_alpha_1_deg`` …
``err_gamma_2_deg``, and ``Fe_N`` when the motion carries a load.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..motion.iso_compliance import DEFAULT_TOLERANCES
from ..motion.iso_verdict import ANGLES, StationIso, station_iso
from ..records import Level, Record, Verdict, optional
from ..results import rms_and_signed_peak
from .commands import StationMotion

__all__ = [
    "ANGLES",
    "AngleError",
    "PlatformSummary",
    "SlidersSummary",
    "StationSummary",
    "angle_error",
    "attitude_columns",
    "error_columns",
    "sliders_summary",
    "sliders_verdict",
    "station_columns",
    "station_summary",
    "stations_verdict",
]


def attitude_columns() -> list[str]:
    """``alpha_1_deg`` … ``gamma_2_deg``: platform 1's three angles, then platform 2's."""
    return [f"{a}_{j}_deg" for j in (1, 2) for a in ANGLES]


def error_columns() -> list[str]:
    """``err_alpha_1_deg`` … ``err_gamma_2_deg``."""
    return [f"err_{name}" for name in attitude_columns()]


def station_columns(motion: StationMotion, load: np.ndarray | None = None) -> dict[str, np.ndarray]:
    """The run as named columns in the file's units (s, mm, degrees, N); ``Fe_N`` only with a load."""
    columns = {"t_s": motion.t}
    columns |= {f"L_1{i + 1}_mm": motion.carriages[:, i] * 1e3 for i in range(3)}
    q = np.degrees(motion.attitudes).reshape(len(motion.t), 6)
    e = np.degrees(motion.errors).reshape(len(motion.t), 6)
    columns |= {name: q[:, k] for k, name in enumerate(attitude_columns())}
    columns |= {name: e[:, k] for k, name in enumerate(error_columns())}
    if load is not None:
        columns["Fe_N"] = np.asarray(load, dtype=float)
    return columns


@dataclass(frozen=True)
class AngleError(Record):
    """One angle's error on one platform.

    Attributes:
        rms_deg: RMS of q_j − q_d over the samples in [deg].
        peak_deg: the error of largest magnitude, signed, in [deg].
        peak_at_s: when it occurs in [s] (the first such sample).
    """

    rms_deg: float
    peak_deg: float
    peak_at_s: float


@dataclass(frozen=True)
class PlatformSummary(Record):
    """One platform's errors and its station's ISO 14242-1 verdict.

    Attributes:
        platform: 1 or 2.
        angles: per angle (alpha, beta, gamma) its error.
        controlled: whether the carriages serve this platform.
        iso: the station's ISO verdict (None without a load).
    """

    platform: int
    angles: dict[str, AngleError]
    controlled: bool
    iso: StationIso | None = optional()


@dataclass(frozen=True)
class StationSummary(Record):
    """What ``hipsim stations`` found on the desired motion.

    Attributes:
        control: "1", "2" or "both".
        weights: (w_1, w_2) of ``both``'s sum of squares.
        samples: samples of the run.
        duration_s: from the first sample to the last in [s].
        sum_squared_error_deg2: Σ over samples, platforms and angles of the squared error in [deg²].
        rms_error_deg: RMS over both platforms and angles in [deg].
        platforms: platform 1, then 2.
    """

    control: str
    weights: tuple[float, float]
    samples: int
    duration_s: float
    sum_squared_error_deg2: float
    rms_error_deg: float
    platforms: tuple[PlatformSummary, ...]

    @property
    def worst(self) -> tuple[int, str, AngleError]:
        """(platform, angle, its error) of the largest |peak| over both platforms and angles (the first of equals)."""
        return max(
            ((p.platform, a, v) for p in self.platforms for a, v in p.angles.items()),
            key=lambda item: abs(item[2].peak_deg),
        )

    @property
    def verdicts(self) -> tuple[StationIso, ...]:
        """Each station's ISO verdict, in platform order (none without a load)."""
        return tuple(p.iso for p in self.platforms if p.iso is not None)


def angle_error(t: np.ndarray, values_deg: np.ndarray) -> AngleError:
    """RMS, signed peak and its time of one error series in [deg] over times t in [s]."""
    return AngleError(*rms_and_signed_peak(t, values_deg))


def station_summary(
    motion: StationMotion, load: np.ndarray | None = None, source: str = "trajectory", periodic: bool = False
) -> StationSummary:
    """Per platform and angle the RMS and peak error in [deg] and the time of the peak; each station's ISO verdict.

    Args:
        motion: the run.
        load: the axial load in [N], (N,), for the ISO 14242-1 check of each station's motion; None: no check.
        source: the desired motion's name.
        periodic: the samples cover whole periods (the ISO check then wraps around).
    """
    e = np.degrees(motion.errors)
    platforms = []
    for j in range(2):
        angles = {a: angle_error(motion.t, e[:, j, k]) for k, a in enumerate(ANGLES)}
        iso = None
        if load is not None:
            iso = station_iso(
                f"m_{j + 1}",
                motion.t,
                motion.attitudes[:, j],
                motion.desired,
                load,
                DEFAULT_TOLERANCES,
                f"{source}, station {j + 1}",
                periodic,
            )
        platforms.append(PlatformSummary(j + 1, angles, motion.control in (str(j + 1), "both"), iso))
    squared = float(np.sum(e**2))
    return StationSummary(
        control=motion.control,
        weights=(float(motion.weights[0]), float(motion.weights[1])),
        samples=len(motion.t),
        duration_s=float(motion.t[-1] - motion.t[0]) if len(motion.t) > 1 else 0.0,
        sum_squared_error_deg2=squared,
        rms_error_deg=math.sqrt(squared / max(1, e.size)),
        platforms=tuple(platforms),
    )


def stations_verdict(summary: StationSummary) -> Verdict:
    """The verdict of a station run: FAIL when a station's ISO 14242-1 verdict fails, PASS when every one made
    passes, NOT MADE without one (no load, no whole cycle). Judged: each station's motion (see
    :mod:`hipsim.motion.iso_verdict`); not judged: the attitude errors themselves, which carry no acceptance limit."""
    j, angle, worst = summary.worst
    numbers = {"worst_peak_deg": abs(worst.peak_deg), "worst_peak_at_s": worst.peak_at_s}
    numbers["rms_error_deg"] = summary.rms_error_deg
    not_judged = "the attitude errors against an acceptance limit (none is set)"
    made = [(p.platform, p.iso) for p in summary.platforms if p.iso is not None and p.iso.verdict != Level.NOT_MADE]
    if not made:
        return Verdict(Level.NOT_MADE, "no whole ISO 14242-1 cycle with a load to check", not_judged, numbers)
    for platform, iso in made:
        numbers |= {f"worst_{a}_{platform}_deg": v for a, v in (iso.worst_deg or {}).items()}
    level = Level.FAIL if any(iso.verdict == Level.FAIL for _, iso in made) else Level.PASS
    judged = "ISO 14242-1 (tolerances assumed): " + ", ".join(f"station {p} {iso.verdict.value}" for p, iso in made)
    # A station that tracks a non-ISO motion perfectly passes on its share (motion.iso_verdict); the headline says
    # so, so that its PASS is not read as "this station's motion is the ISO waveform".
    off = [max(iso.desired.worst_deg.values()) for _, iso in made if iso.desired is not None and not iso.desired.iso]
    if off:
        judged += (
            f"; the desired motion is not the ISO 14242-1 waveform (worst {max(off):.3g}° off): each station is "
            "judged on its tracking of it"
        )
    return Verdict(level, judged, not_judged, numbers)


@dataclass(frozen=True)
class SlidersSummary(Record):
    """Both platforms' attitudes from a log's carriages: how far apart they turn.

    Attributes:
        log: the log's path.
        samples: its samples.
        platform_difference_rms_deg: RMS of q_1 − q_2 per angle α, β, γ in [deg].
        platform_difference_peak_deg: the largest |q_1 − q_2| per angle in [deg].
    """

    log: str
    samples: int
    platform_difference_rms_deg: tuple[float, float, float]
    platform_difference_peak_deg: tuple[float, float, float]


def sliders_summary(log: str, attitudes: np.ndarray) -> SlidersSummary:
    """How far apart the two platforms turn, from their attitudes (N, 2, 3) in [rad]."""
    difference = np.degrees(attitudes[:, 0] - attitudes[:, 1])
    rms = np.sqrt((difference**2).mean(axis=0))
    peak = np.abs(difference).max(axis=0)
    return SlidersSummary(
        log,
        len(attitudes),
        (float(rms[0]), float(rms[1]), float(rms[2])),
        (float(peak[0]), float(peak[1]), float(peak[2])),
    )


def sliders_verdict(sliders: SlidersSummary) -> Verdict:
    """The verdict of the attitudes from a log's carriages: NOT MADE (how far apart the platforms turn has no limit)."""
    return Verdict(
        Level.NOT_MADE,
        f"both platforms' attitudes from the carriages of {sliders.log} ({sliders.samples} samples): how far apart "
        "they turn",
        "the attitudes against an acceptance limit (none is set)",
    )
