"""What the wear test reports (``hipsim wear --weighings``: ``wear_test.json`` and ``--summary-format json``) as
typed records, made from a :class:`~hipsim.wear.test_result.WearTest` and each station's context.

:func:`wear_test_summary` gives the document: the verdict first
(:func:`~hipsim.wear.test_result.wear_verdict`, a :class:`hipsim.records.Verdict`), the density, the weighings' file, the given factor and the reference
motion, then per station (its name the key) the measured rate, the k of both kinds fitted over its motion (and what
they predict for the reference motion), the given factor's prediction, the intervals between stops, its motion error
and friction; the differences between stations; the fitted k(CS) law.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from ..records import Record, Verdict, optional
from .accumulate import IntervalRow
from .factors import FittedFactors, MotionIntegrals
from .gravimetric import RateDifference, StationRate
from .test_context import FrictionState, MotionError, StationContext
from .test_result import StationWear, WearTest

__all__ = [
    "DifferenceSummary",
    "FittedSummary",
    "FrictionSummary",
    "GivenFactorSummary",
    "Predicts",
    "RateSummary",
    "StationWearSummary",
    "WearLawSummary",
    "WearTestSummary",
    "wear_test_summary",
]


@dataclass(frozen=True)
class RateSummary(Record):
    """One station's measured rate: its soak control, stops, the fit's first stop and how it was chosen, the rate
    before it, the rate in [mg/Mc] and [mm³/Mc] with their 95 % intervals, the slope's standard error and degrees of
    freedom, the stops' cycles, losses [mg] and volumes [mm³], the stops named as outliers."""

    station: str
    soak_control: str
    stops: int
    from_cycle: int
    bedding_in: str
    bedding_in_rate_mg_per_Mc: float
    wear_rate_mg_per_Mc: float
    wear_rate_ci95_mg_per_Mc: tuple[float, float]
    wear_rate_mm3_per_Mc: float
    wear_rate_ci95_mm3_per_Mc: tuple[float, float]
    standard_error_mg_per_Mc: float
    degrees_of_freedom: int
    cycles: tuple[int, ...]
    loss_mg: tuple[float, ...]
    volume_mm3: tuple[float, ...]
    outliers: tuple[str, ...]

    @classmethod
    def of(cls, rate: StationRate) -> RateSummary:
        """The record of a :class:`~hipsim.wear.gravimetric.StationRate`."""
        return cls(
            rate.station,
            rate.soak_control,
            len(rate.cycles),
            rate.from_cycle,
            rate.bedding_in,
            rate.bedding_in_rate_mg_per_Mc,
            rate.rate_mg_per_Mc,
            rate.ci95_mg_per_Mc,
            rate.rate_mm3_per_Mc,
            rate.ci95_mm3_per_Mc,
            rate.se_mg_per_Mc,
            rate.dof,
            tuple(int(c) for c in rate.cycles),
            tuple(rate.loss_mg),
            rate.volume_mm3,
            tuple(outlier.describe() for outlier in rate.outliers),
        )


@dataclass(frozen=True)
class DifferenceSummary(Record):
    """Station b's rate minus station a's, in [mg/Mc] and [mm³/Mc] with its 95 % interval; significant when the
    interval excludes 0."""

    a: str
    b: str
    difference_mg_per_Mc: float
    ci95_mg_per_Mc: tuple[float, float]
    difference_mm3_per_Mc: float
    ci95_mm3_per_Mc: tuple[float, float]
    significant: bool

    @classmethod
    def of(cls, d: RateDifference) -> DifferenceSummary:
        """The record of a :class:`~hipsim.wear.gravimetric.RateDifference`."""
        return cls(
            d.a,
            d.b,
            d.difference_mg_per_Mc,
            d.ci95_mg_per_Mc,
            d.difference_mm3_per_Mc,
            d.ci95_mm3_per_Mc,
            d.significant,
        )


@dataclass(frozen=True)
class Predicts(Record):
    """What a station's k of each kind predicts for another motion: [rate, low, high] in [mm³/Mc]."""

    motion: MotionIntegrals
    local_mm3_per_Mc: tuple[float, float, float]
    force_track_mm3_per_Mc: tuple[float, float, float] = field(metadata={"key": "force-track_mm3_per_Mc"})


@dataclass(frozen=True)
class FittedSummary(Record):
    """A station's k of both kinds in [mm³/(N·m)] with their 95 % intervals, over its own motion; and what they
    predict for the reference motion (when one was given)."""

    station: str
    motion: MotionIntegrals
    k_local_mm3_per_Nm: float
    k_local_ci95: tuple[float, float]
    k_force_track_mm3_per_Nm: float
    k_force_track_ci95: tuple[float, float]
    predicts: Predicts | None = optional()

    @classmethod
    def of(cls, fitted: FittedFactors, other: MotionIntegrals | None) -> FittedSummary:
        """The record of :class:`~hipsim.wear.factors.FittedFactors` (``other``: the reference motion, or None)."""
        predicts = None
        if other is not None:
            values = fitted.predict(other)
            predicts = Predicts(other, values["local"], values["force-track"])
        return cls(
            fitted.station,
            fitted.motion,
            fitted.k("local"),
            fitted.ci95("local"),
            fitted.k("force-track"),
            fitted.ci95("force-track"),
            predicts,
        )


@dataclass(frozen=True)
class FrictionSummary(Record):
    """The monitor's last word on a station (:class:`~hipsim.wear.test_context.FrictionState`) and its sentence."""

    source: str
    snapshots: int
    last_cycle: int
    hip_mu_change: float
    hip_mu_change_std: float
    own_station: bool
    flag: str
    summary: str

    @classmethod
    def of(cls, f: FrictionState) -> FrictionSummary:
        """The record of a :class:`~hipsim.wear.test_context.FrictionState`."""
        return cls(
            f.source, f.snapshots, f.last_cycle, f.hip_mu_change, f.hip_mu_change_std, f.own, f.flag, f.describe()
        )


@dataclass(frozen=True)
class StationWearSummary(Record):
    """One station: its measured rate's keys, its motion's source, its fitted k, the given factor's prediction over
    the steady state [mm³/Mc] (null without one) and whether it lies in the measured interval, the factor the
    intervals used, the intervals between stops, its motion error and friction (null: not known)."""

    rate: RateSummary = field(metadata={"flatten": True})  # field() itself: mypy then knows it has no default
    motion: str
    fitted: FittedSummary
    predicted_mm3_per_Mc: float
    prediction_within_ci95: bool | None
    interval_law: str
    intervals: tuple[IntervalRow, ...]
    motion_error: MotionError | None
    friction: FrictionSummary | None


def _station(s: StationWear, reference: MotionIntegrals | None, context: StationContext | None) -> StationWearSummary:
    return StationWearSummary(
        RateSummary.of(s.rate),
        s.exposure.source,
        FittedSummary.of(s.fitted, reference),
        s.predicted_mm3_per_Mc,
        s.within,
        s.interval_law,
        s.intervals,
        None if context is None else context.motion,
        None if context is None or context.friction is None else FrictionSummary.of(context.friction),
    )


@dataclass(frozen=True)
class GivenFactorSummary(Record):
    """A wear factor given to predict with: its value in [mm³/(N·m)] and kind."""

    k_mm3_per_Nm: float
    kind: str


@dataclass(frozen=True)
class WearLawSummary(Record):
    """The k(CS) law fitted from the stations: each station's work-weighted cross-shear and local k [mm³/(N·m)]."""

    cross_shear: tuple[float, ...]
    k_mm3_per_Nm: tuple[float, ...]


@dataclass(frozen=True)
class WearTestSummary(Record):
    """A wear test's result (module docstring): the verdict (ALIKE, DIFFERENT, NOT MADE with one station), the
    density in [mg/mm³] and how it was stated, the weighings' file, the given factor, the reference motion, per station
    its result, the differences between stations, the fitted k(CS) law."""

    verdict: Verdict
    density_mg_per_mm3: float
    density: str
    weighings: str
    wear_factor: GivenFactorSummary | None
    reference_motion: MotionIntegrals | None
    stations: dict[str, StationWearSummary]
    differences: tuple[DifferenceSummary, ...]
    fitted_wear_law: WearLawSummary | None


def wear_test_summary(result: WearTest, contexts: tuple[StationContext, ...] = ()) -> WearTestSummary:
    """The summary of a wear test (module docstring), each station with its context when given."""
    by_name = {c.station: c for c in contexts}
    g, law, given = result.gravimetry, result.fitted_law, result.given
    return WearTestSummary(
        result.verdict,
        g.density_mg_per_mm3,
        g.density_stated,
        g.source,
        None if given is None else GivenFactorSummary(given.k, given.kind),
        result.reference,
        {s.rate.station: _station(s, result.reference, by_name.get(s.rate.station)) for s in result.stations},
        tuple(DifferenceSummary.of(d) for d in g.differences),
        None if law is None else WearLawSummary(tuple(law.cross_shear.tolist()), tuple(law.k.tolist())),
    )
