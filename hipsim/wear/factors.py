"""Wear factors of both kinds, named, and fitted from a test's measured rates.

Two definitions are in use, and the same number means different things:

- **local** (Archard, pin-on-disc): the depth rate is k·p·v at each point, so
  V = ∫_cup k·W dA per cycle (:class:`~hipsim.wear.laws.WearFactor`): a
  pin-on-disc k, or a k(CS) table (``--wear-law``);
- **force-track** (global, a simulator's, Saikko): V = k·∫F ds along the force
  track per cycle, the track integral of load (:class:`ForceTrackFactor`).

On the built-in ISO cycle ΣW·dA = 36.5 N·m and ∫F ds = 28.3 N·m, so
k = 8×10⁻⁸ mm³/(N·m) gives 2.92 mm³/Mc as a local factor and 2.26 mm³/Mc as a
force-track one. A value is never taken without its kind.

Fitted (:func:`fit_factors`): a station's k of each kind is its measured rate
over the integral of its own motion per cycle (mean over the test's motion),
with the rate's 95 % interval carried over (the motion taken as exact); it
predicts another motion's rate as k times that motion's integral.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..exceptions import ArgumentError
from ..records import Record
from .laws import MC, CrossShearLaw, WearFactor
from .maps import WearMaps

__all__ = [
    "KINDS",
    "FittedFactors",
    "ForceTrackFactor",
    "MotionIntegrals",
    "fit_factors",
    "fitted_wear_law",
    "kind_of",
    "motion_integrals",
    "parse_wear_factor",
    "predicted_rate",
]

#: The kinds a wear factor is given with: ``local`` (Archard, V = ∫k·W dA) and ``force-track`` (Saikko, V = k·∫F ds).
KINDS = ("local", "force-track")
#: Wear factors outside [0, 1e-3] mm³/(N·m) are refused (UHMWPE's are 1e-8 to 1e-5).
K_RANGE = (0.0, 1e-3)


@dataclass(frozen=True)
class ForceTrackFactor:
    """Saikko's global wear factor k in [mm³/(N·m)]: V = k·∫F ds along the force track, per cycle.

    The volume is the cup's; spread over the cup in proportion to the work W (where a point wears, the local law
    says; how much in all, this one), so the maps and tables have a depth per point.
    """

    k: float

    def __post_init__(self):
        if isinstance(self.k, bool) or not (math.isfinite(self.k) and self.k >= 0):
            raise ArgumentError("wear factor", self.k, "a wear factor k ≥ 0 in mm³/(N·m)")

    def describe(self) -> str:
        return f"force-track (global, Saikko: V = k·∫F ds), k = {self.k:.4g} mm³/(N·m)"

    def depth_mm(self, maps: WearMaps) -> np.ndarray:
        area = maps.points.area_mm2
        if area is None:
            raise ArgumentError(
                "points",
                "points given one by one",
                "a cup grid (a force-track factor spreads the cup's volume by the work)",
            )
        total = float(np.sum(maps.work_N_per_mm * area))  # ΣW·dA in [N·mm]
        volume = self.k * maps.force_track_load_Nm  # [mm³] per cycle
        return maps.work_N_per_mm * (volume / total if total > 0 else 0.0)


def parse_wear_factor(text: str) -> WearFactor | ForceTrackFactor:
    """``K:KIND`` → the factor: ``8e-8:local`` or ``8e-8:force-track``; a bare value is refused.

    Raises:
        ArgumentError: naming ``--wear-factor``: no kind, an unknown kind, a value not a number or outside [0, 1e-3].
    """
    value, _, kind = text.partition(":")
    expected = (
        "K:KIND in mm³/(N·m), KIND local (Archard, pin-on-disc: V = ∫k·W dA) or force-track (Saikko, simulator: "
        "V = k·∫F ds), e.g. 8e-8:force-track; a value without its kind is ambiguous"
    )
    if kind not in KINDS:
        raise ArgumentError("--wear-factor", text, expected)
    try:
        k = float(value)
    except ValueError:
        raise ArgumentError("--wear-factor", text, expected) from None
    low, high = K_RANGE
    if not (math.isfinite(k) and low <= k <= high):
        raise ArgumentError("--wear-factor", text, f"k in [{low:g}, {high:g}] mm³/(N·m)")
    return WearFactor(k) if kind == "local" else ForceTrackFactor(k)


def kind_of(law) -> str:
    """The kind of a law: ``local``, ``force-track``, or ``contact-area``."""
    if isinstance(law, ForceTrackFactor):
        return "force-track"
    if isinstance(law, WearFactor | CrossShearLaw):
        return "local"
    return "contact-area"


@dataclass(frozen=True)
class MotionIntegrals(Record):
    """A motion's per-cycle integrals the factors multiply, in [N·m]: ΣW·dA (local) and ∫F ds (force-track), and its
    work-weighted cross-shear."""

    load_slide_integral_Nm: float
    force_track_load_Nm: float
    cross_shear_work_weighted: float
    name: str = ""

    def integral(self, kind: str) -> float:
        return self.load_slide_integral_Nm if kind == "local" else self.force_track_load_Nm


def motion_integrals(maps: WearMaps) -> MotionIntegrals:
    """The integrals of one motion's maps (a grid's: the cells' areas are needed).

    Raises:
        ArgumentError: points without areas.
    """
    area = maps.points.area_mm2
    if area is None:
        raise ArgumentError("points", "points given one by one", "a cup grid (ΣW·dA needs the cells' areas)")
    work = maps.work_N_per_mm
    loaded = maps.loaded
    weights = work[loaded] * area[loaded]
    cs = float(np.average(maps.cross_shear[loaded], weights=weights)) if weights.sum() > 0 else math.nan
    return MotionIntegrals(float(np.sum(work * area)) / 1000.0, maps.force_track_load_Nm, cs, maps.name)


def predicted_rate(k: float, kind: str, integrals: MotionIntegrals) -> float:
    """The rate k predicts for a motion in [mm³/Mc]: k·(its integral per cycle)·10⁶."""
    return k * integrals.integral(kind) * MC


@dataclass(frozen=True)
class FittedFactors:
    """One station's wear factors of both kinds, fitted from its rate and its own motion (module docstring).

    Attributes:
        station: the station.
        motion: the integrals of its motion per cycle (the test's mean).
        rate_mm3_per_Mc, ci95_mm3_per_Mc: its measured rate and interval.
        k_local, ci95_local: the local k in [mm³/(N·m)] and its interval.
        k_force_track, ci95_force_track: the force-track k and its interval.
    """

    station: str
    motion: MotionIntegrals
    rate_mm3_per_Mc: float
    ci95_mm3_per_Mc: tuple[float, float]

    def k(self, kind: str) -> float:
        return self.rate_mm3_per_Mc / (self.motion.integral(kind) * MC)

    def ci95(self, kind: str) -> tuple[float, float]:
        scale = 1.0 / (self.motion.integral(kind) * MC)
        return (self.ci95_mm3_per_Mc[0] * scale, self.ci95_mm3_per_Mc[1] * scale)

    def predict(self, other: MotionIntegrals) -> dict[str, tuple[float, float, float]]:
        """Per kind: the rate (and interval) this station's k predicts for another motion in [mm³/Mc]."""
        out = {}
        for kind in KINDS:
            low, high = self.ci95(kind)
            rate = predicted_rate(self.k(kind), kind, other)
            out[kind] = (rate, predicted_rate(low, kind, other), predicted_rate(high, kind, other))
        return out


def fit_factors(
    station: str, rate_mm3_per_Mc: float, ci95: tuple[float, float], motion: MotionIntegrals
) -> FittedFactors:
    """A station's k of both kinds (module docstring).

    Raises:
        ArgumentError: a motion with no work (its integrals 0).
    """
    if not (motion.load_slide_integral_Nm > 0 and motion.force_track_load_Nm > 0):
        raise ArgumentError(
            f"station {station}'s motion", motion.name, "a loaded motion that slides (ΣW·dA and ∫F ds > 0)"
        )
    return FittedFactors(station, motion, rate_mm3_per_Mc, ci95)


#: Stations whose work-weighted CS differ by less than this give no k(CS) table (one CS, one k).
CS_APART = 0.01


def fitted_wear_law(fits: tuple[FittedFactors, ...]) -> CrossShearLaw | None:
    """A ``--wear-law`` table from the stations' local k at their work-weighted CS, when their CS differ by at least
    :data:`CS_APART` (else None): a line through the points, held beyond them, as the law's table reads."""
    points = sorted((fit.motion.cross_shear_work_weighted, fit.k("local")) for fit in fits)
    if len(points) < 2 or any(b[0] - a[0] < CS_APART for a, b in zip(points, points[1:], strict=False)):
        return None
    cs, k = np.array(points).T
    if np.any(k < 0):
        return None
    return CrossShearLaw(cs, k, "fitted from the weighings")
