"""A wear test's result per station: measured (weighings), fitted (k of both kinds), predicted (over its own motion).

Made from a :class:`~hipsim.wear.gravimetric.Gravimetry` and, per station, an
:class:`~hipsim.wear.accumulate.Exposure` (its motion over the test). Per
station: the measured rate; its k of both kinds fitted over its steady-state
motion, and what that k predicts for a reference motion (the built-in ISO
cycle, or any); with a given factor (its kind named), the predicted rate over
the steady-state interval beside the measured one; predicted against measured
volume per interval between stops (the given factor, else the station's own
fitted local k, which matches the total by construction and shows the shape).

The verdict (:func:`wear_verdict`, a :class:`hipsim.records.Verdict`) comes
first on every page: DIFFERENT when some pair of stations' rates differs (its
95 % interval excludes 0), else ALIKE; NOT MADE when only one station was
weighed (the page and the terminal say ONE STATION: the comparison needs two).
Under it (:func:`verdict_lines`) each pair's difference and, with a given
factor, per station whether its prediction lies in the measured rate's 95 %
interval (shown, not judged).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..records import Level, Verdict
from .accumulate import Exposure, IntervalRow, interval_table
from .factors import FittedFactors, MotionIntegrals, fit_factors, fitted_wear_law, predicted_rate
from .gravimetric import Gravimetry, RateDifference, StationRate
from .laws import CrossShearLaw

__all__ = ["ONE_STATION", "GivenFactor", "StationWear", "WearTest", "verdict_lines", "wear_test", "wear_verdict"]

#: The word the page and the terminal say for the verdict NOT MADE: one station weighed, no other to compare with.
ONE_STATION = "ONE STATION"


@dataclass(frozen=True)
class GivenFactor:
    """A wear factor as given: its value in [mm³/(N·m)] and its kind (``local`` or ``force-track``)."""

    k: float
    kind: str

    def describe(self) -> str:
        return f"k = {self.k:.4g} mm³/(N·m), {self.kind}"


@dataclass(frozen=True)
class StationWear:
    """One station's measured, fitted and predicted wear.

    Attributes:
        rate: the measured rate.
        exposure: its motion over the test.
        fitted: its k of both kinds over its steady-state motion.
        predicted_mm3_per_Mc: the given factor's rate over the steady-state interval (NaN without one).
        intervals: per interval between stops, measured and predicted volume.
        interval_law: the factor the intervals' prediction used, in words.
    """

    rate: StationRate
    exposure: Exposure
    fitted: FittedFactors
    predicted_mm3_per_Mc: float
    intervals: tuple[IntervalRow, ...]
    interval_law: str

    @property
    def within(self) -> bool | None:
        """Whether the given factor's prediction lies in the measured rate's 95 % interval (None without one)."""
        low, high = self.rate.ci95_mm3_per_Mc
        if not math.isfinite(self.predicted_mm3_per_Mc) or not (math.isfinite(low) and math.isfinite(high)):
            return None
        return bool(low <= self.predicted_mm3_per_Mc <= high)


@dataclass(frozen=True)
class WearTest:
    """A test's wear result (module docstring)."""

    gravimetry: Gravimetry
    stations: tuple[StationWear, ...]
    given: GivenFactor | None
    reference: MotionIntegrals | None
    fitted_law: CrossShearLaw | None
    verdict: Verdict
    lines: tuple[str, ...]

    @property
    def word(self) -> str:
        """The verdict's word on the page and in the terminal: its level's, ONE STATION for NOT MADE."""
        return ONE_STATION if self.verdict.level == Level.NOT_MADE else self.verdict.level.value


def _difference_line(d: RateDifference) -> str:
    low, high = d.ci95_mm3_per_Mc
    return f"station {d.b} − station {d.a}: {d.difference_mm3_per_Mc:+.3g} mm³/Mc, 95 % [{low:+.3g}, {high:+.3g}]: " + (
        "the rates differ" if d.significant else "no difference shown"
    )


def wear_verdict(gravimetry: Gravimetry, given: GivenFactor | None = None) -> Verdict:
    """The verdict on the stations' rates (module docstring): a pure function of their differences.

    DIFFERENT when some pair's difference is significant (its 95 % interval excludes 0), else ALIKE; NOT MADE with
    one station weighed. The numbers: each pair's difference b − a and its interval in [mm³/Mc].

    Args:
        gravimetry: the measured rates and their differences.
        given: the factor the predictions used (None: none), for what is not judged.
    """
    predictions = (
        "each station's prediction with the given factor against its measured rate's 95 % interval (shown, not judged)"
        if given is not None
        else ""
    )
    if not gravimetry.differences:
        not_judged = "the stations' rates against each other: the comparison needs two stations weighed"
        return Verdict(
            Level.NOT_MADE,
            "one station weighed: no other to compare its rate with",
            "; ".join(filter(None, (not_judged, predictions))),
        )
    numbers: dict[str, float] = {}
    for d in gravimetry.differences:
        key = f"station_{d.b}_minus_{d.a}"
        low, high = d.ci95_mm3_per_Mc
        numbers |= {f"{key}_mm3_per_Mc": d.difference_mm3_per_Mc, f"{key}_ci95_low_mm3_per_Mc": low}
        numbers[f"{key}_ci95_high_mm3_per_Mc"] = high
    judged = "each pair of stations' wear rates, its difference's 95 % interval against 0: " + "; ".join(
        _difference_line(d) for d in gravimetry.differences
    )
    level = Level.DIFFERENT if any(d.significant for d in gravimetry.differences) else Level.ALIKE
    return Verdict(level, judged, predictions, numbers)


def verdict_lines(
    gravimetry: Gravimetry, stations: tuple[StationWear, ...], given: GivenFactor | None
) -> tuple[str, ...]:
    """The sentences under the verdict's word (page and terminal): each pair's difference (or that one station was
    weighed) and, with a given factor, each station's prediction against its measured interval."""
    lines = [_difference_line(d) for d in gravimetry.differences]
    if given is not None:
        for s in stations:
            low, high = s.rate.ci95_mm3_per_Mc
            state = {True: "within", False: "outside", None: "no interval to hold it against"}[s.within]
            lines.append(
                f"station {s.rate.station}: predicted {s.predicted_mm3_per_Mc:.3g} mm³/Mc ({given.describe()}), "
                f"measured {s.rate.rate_mm3_per_Mc:.3g} [{low:.3g}, {high:.3g}]: {state}"
            )
    if not gravimetry.differences:
        return ("one station weighed: no other to compare its rate with", *lines)
    return tuple(lines)


def wear_test(
    gravimetry: Gravimetry,
    exposures: dict[str, Exposure],
    given: GivenFactor | None = None,
    reference: MotionIntegrals | None = None,
) -> WearTest:
    """Every station's result (module docstring).

    Args:
        gravimetry: the measured rates.
        exposures: per station name, its motion over the test.
        given: a factor to predict with, or None.
        reference: a motion to say what each fitted k predicts for (e.g. the built-in ISO cycle), or None.
    """
    out = []
    for rate in gravimetry.stations:
        exposure = exposures[rate.station]
        steady = exposure.mean(rate.from_cycle, rate.cycles[-1])
        fitted = fit_factors(rate.station, rate.rate_mm3_per_Mc, rate.ci95_mm3_per_Mc, steady)
        if given is not None:
            predicted = predicted_rate(given.k, given.kind, steady)
            k, kind, law = given.k, given.kind, given.describe()
        else:
            predicted, k, kind = math.nan, fitted.k("local"), "local"
            law = f"the station's own fitted local k = {k:.4g} mm³/(N·m)"
        rows = interval_table(rate.station, rate.cycles, rate.volume_mm3, exposure, k, kind)
        out.append(StationWear(rate, exposure, fitted, predicted, rows, law))
    stations = tuple(out)
    table = fitted_wear_law(tuple(s.fitted for s in stations))
    verdict, lines = wear_verdict(gravimetry, given), verdict_lines(gravimetry, stations, given)
    return WearTest(gravimetry, stations, given, reference, table, verdict, lines)
