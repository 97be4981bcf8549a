"""A wear test's result per station: measured (weighings), fitted (k of both kinds), predicted (over its own motion).

Made from a :class:`~hipsim.wear.gravimetric.Gravimetry` and, per station, an
:class:`~hipsim.wear.accumulate.Exposure` (its motion over the test). Per
station: the measured rate; its k of both kinds fitted over its steady-state
motion, and what that k predicts for a reference motion (the built-in ISO
cycle, or any); with a given factor (its kind named), the predicted rate over
the steady-state interval beside the measured one; predicted against measured
volume per interval between stops (the given factor, else the station's own
fitted local k, which matches the total by construction and shows the shape).

The verdict (:func:`wear_verdict`) comes first on every page: DIFFERENT when
some pair of stations' rates differs (its 95 % interval excludes 0), else ALIKE
(ONE STATION when only one was weighed);
then, with a given factor, per station whether its prediction lies in the
measured rate's 95 % interval.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..records import Level
from .accumulate import Exposure, IntervalRow, interval_table
from .factors import FittedFactors, MotionIntegrals, fit_factors, fitted_wear_law, predicted_rate
from .gravimetric import Gravimetry, StationRate
from .laws import CrossShearLaw

__all__ = ["GivenFactor", "StationWear", "WearTest", "WearVerdict", "wear_test", "wear_verdict"]


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
class WearVerdict:
    """The verdict: a word (ALIKE or DIFFERENT, the stations' rates) and its lines."""

    word: str
    lines: tuple[str, ...]

    @property
    def level(self) -> Level:
        """ALIKE, DIFFERENT, or NOT MADE for ONE STATION (for :func:`hipsim.records.exit_status`)."""
        return {"ALIKE": Level.ALIKE, "DIFFERENT": Level.DIFFERENT}.get(self.word, Level.NOT_MADE)


@dataclass(frozen=True)
class WearTest:
    """A test's wear result (module docstring)."""

    gravimetry: Gravimetry
    stations: tuple[StationWear, ...]
    given: GivenFactor | None
    reference: MotionIntegrals | None
    fitted_law: CrossShearLaw | None
    verdict: WearVerdict


def wear_verdict(gravimetry: Gravimetry, stations: tuple[StationWear, ...], given: GivenFactor | None) -> WearVerdict:
    """The verdict (module docstring): a pure function of the numbers."""
    lines = []
    different = [d for d in gravimetry.differences if d.significant]
    for d in gravimetry.differences:
        low, high = d.ci95_mm3_per_Mc
        lines.append(
            f"station {d.b} − station {d.a}: {d.difference_mm3_per_Mc:+.3g} mm³/Mc, 95 % [{low:+.3g}, {high:+.3g}]: "
            + ("the rates differ" if d.significant else "no difference shown")
        )
    if given is not None:
        for s in stations:
            low, high = s.rate.ci95_mm3_per_Mc
            state = {True: "within", False: "outside", None: "no interval to hold it against"}[s.within]
            lines.append(
                f"station {s.rate.station}: predicted {s.predicted_mm3_per_Mc:.3g} mm³/Mc ({given.describe()}), "
                f"measured {s.rate.rate_mm3_per_Mc:.3g} [{low:.3g}, {high:.3g}]: {state}"
            )
    if not gravimetry.differences:
        return WearVerdict("ONE STATION", ("one station weighed: no other to compare its rate with", *lines))
    return WearVerdict("DIFFERENT" if different else "ALIKE", tuple(lines))


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
    return WearTest(gravimetry, stations, given, reference, table, wear_verdict(gravimetry, stations, given))
