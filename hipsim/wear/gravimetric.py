"""Wear rates from weighings (ISO 14242-2): per station the slope of its soak-corrected loss, with its 95 % interval.

Per station (:class:`~hipsim.wear.weighings.StationWeighings`):

- loss at each stop: the cup's mass loss since the first stop plus its soak
  control's gain (fluid uptake); volume = loss / density;
- rate: the least-squares slope of loss against cycles (in Mc), its standard
  error s/√Σ(x − x̄)² and 95 % interval from Student's t with n − 2 degrees of
  freedom (at least three stops; two give a rate without an interval);
- bedding-in: the first stops wear faster. Given ``from_cycle``, the rate is
  fitted over the stops from that cycle on. Otherwise it is found from the
  data: while the stop before the fitted ones lies below the 99 % prediction
  interval of the line through the stops after it (and at least three stops
  remain), that stop is bedding-in; the earlier wear is then reported apart
  (its own mean rate);
- outliers: stops of the fit whose externally studentized residual t exceeds
  the Bonferroni bound (Student's t at 1 − :data:`OUTLIER_ALPHA`/(2n), n − 3
  degrees of freedom: a stop this far off is due to noise in at most 5 % of
  tests) are named (cycle, residual in mg, t). They stay in the fit: a lab
  decides, not the program;
- the difference of two stations' rates: its standard error √(se_a² + se_b²),
  Welch–Satterthwaite degrees of freedom, 95 % interval.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from itertools import combinations

import numpy as np

from ..exceptions import ArgumentError
from .weighings import StationWeighings, Weighings

__all__ = [
    "DENSITY_UHMWPE",
    "OUTLIER_ALPHA",
    "Gravimetry",
    "Outlier",
    "RateDifference",
    "StationRate",
    "gravimetry",
    "LineFit",
    "line_fit",
    "rate_difference",
    "station_rate",
]

#: UHMWPE's density in [mg/mm³] (0.93–0.94 by grade): the default, stated in every output.
DENSITY_UHMWPE = 0.935
#: Densities outside (0, 25] mg/mm³ are refused (25: denser than any implant material).
DENSITY_RANGE = (0.0, 25.0)
#: The family-wise level of the outlier test (Bonferroni over the fit's stops).
OUTLIER_ALPHA = 0.05
#: The prediction interval's level for finding bedding-in (stricter than 95 % so that balance noise alone rarely
#: makes a bedding-in).
BEDDING_LEVEL = 0.99
MC = 1e6


def _t_quantile(p: float, dof: float) -> float:
    """Student's t quantile (SciPy's stats imported when first needed: it costs a quarter of a second)."""
    from scipy import stats

    return float(stats.t.ppf(p, dof))


@dataclass(frozen=True)
class LineFit:
    """y = intercept + slope·x by least squares: slope, its standard error, degrees of freedom and residuals."""

    slope: float
    intercept: float
    se: float
    dof: int
    residuals: tuple[float, ...]
    leverage: tuple[float, ...]
    s: float

    def interval(self, level: float = 0.95) -> tuple[float, float]:
        """The slope's two-sided interval (NaN without degrees of freedom)."""
        if self.dof < 1:
            return (math.nan, math.nan)
        half = float(_t_quantile(0.5 + level / 2, self.dof)) * self.se
        return (self.slope - half, self.slope + half)


def line_fit(x: np.ndarray, y: np.ndarray) -> LineFit:
    """The least-squares line through (x, y), at least two points with two distinct x."""
    x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
    n = x.size
    xm = x.mean()
    sxx = float(np.sum((x - xm) ** 2))
    slope = float(np.sum((x - xm) * (y - y.mean())) / sxx)
    intercept = float(y.mean() - slope * xm)
    residuals = y - intercept - slope * x
    dof = n - 2
    s = math.sqrt(float(residuals @ residuals) / dof) if dof > 0 else math.nan
    leverage = 1.0 / n + (x - xm) ** 2 / sxx
    return LineFit(slope, intercept, s / math.sqrt(sxx), dof, tuple(residuals), tuple(leverage), s)


def _below_prediction(x: np.ndarray, y: np.ndarray, k: int) -> bool:
    """Whether stop k lies below the BEDDING_LEVEL prediction interval of the line through the stops after it."""
    xs, ys = x[k + 1 :], y[k + 1 :]
    fit = line_fit(xs, ys)
    if fit.dof < 1 or not fit.s > 0:
        return False
    xm, sxx = xs.mean(), float(np.sum((xs - xs.mean()) ** 2))
    half = (
        float(_t_quantile(0.5 + BEDDING_LEVEL / 2, fit.dof))
        * fit.s
        * math.sqrt(1 + 1 / xs.size + (x[k] - xm) ** 2 / sxx)
    )
    return bool(y[k] < fit.intercept + fit.slope * x[k] - half)


@dataclass(frozen=True)
class Outlier:
    """A stop whose residual stands out: named, kept in the fit."""

    station: str
    cycle: int
    residual_mg: float
    t: float

    def describe(self) -> str:
        return (
            f"station {self.station} at {self.cycle / MC:.4g} Mc: {self.residual_mg:+.3g} mg off its line "
            f"(t = {self.t:+.2f}), kept in the fit"
        )


@dataclass(frozen=True)
class StationRate:
    """One station's wear rate (module docstring); the mm³ values are the mg ones over ``density_mg_per_mm3``.

    Attributes:
        station, soak_control: the station and its soak control.
        cycles, loss_mg: the stops and their soak-corrected loss in [mg].
        from_cycle: the first stop of the fit (steady state).
        bedding_in: how the fit's start was chosen: ``"none"`` (from the first stop), ``"detected"`` or ``"given"``.
        bedding_in_rate_mg_per_Mc: the mean rate before ``from_cycle`` in [mg/Mc], NaN without bedding-in.
        rate_mg_per_Mc, se_mg_per_Mc, dof: the slope, its standard error, its degrees of freedom.
        ci95_mg_per_Mc: (low, high), NaN with two stops.
        density_mg_per_mm3: the density used.
        outliers: stops named as outliers (kept).
    """

    station: str
    soak_control: str
    cycles: tuple[int, ...]
    loss_mg: tuple[float, ...]
    from_cycle: int
    bedding_in: str
    bedding_in_rate_mg_per_Mc: float
    rate_mg_per_Mc: float
    se_mg_per_Mc: float
    dof: int
    ci95_mg_per_Mc: tuple[float, float]
    density_mg_per_mm3: float
    outliers: tuple[Outlier, ...]

    @property
    def rate_mm3_per_Mc(self) -> float:
        return self.rate_mg_per_Mc / self.density_mg_per_mm3

    @property
    def ci95_mm3_per_Mc(self) -> tuple[float, float]:
        low, high = self.ci95_mg_per_Mc
        return (low / self.density_mg_per_mm3, high / self.density_mg_per_mm3)

    @property
    def volume_mm3(self) -> tuple[float, ...]:
        """The volume lost by each stop in [mm³]."""
        return tuple(loss / self.density_mg_per_mm3 for loss in self.loss_mg)


def station_rate(
    weighed: StationWeighings, density_mg_per_mm3: float = DENSITY_UHMWPE, from_cycle: int | None = None
) -> StationRate:
    """One station's rate (module docstring).

    Args:
        weighed: the station's stops.
        density_mg_per_mm3: the cup's density in [mg/mm³].
        from_cycle: fit the stops from this cycle on (the steady state); None: bedding-in found from the data.

    Raises:
        ArgumentError: a density outside (0, 25] mg/mm³, or fewer than two stops from ``from_cycle`` on.
    """
    _check_density(density_mg_per_mm3)
    x, y = weighed.cycles / MC, weighed.loss_mg
    if from_cycle is not None:
        start = int(np.searchsorted(weighed.cycles, from_cycle))
        if weighed.cycles.size - start < 2:
            raise ArgumentError(
                "--from", from_cycle, f"a cycle with at least two of station {weighed.station}'s stops from it on"
            )
        how = "given" if start > 0 else "none"
    else:
        start = 0
        while x.size - (start + 1) >= 3 and _below_prediction(x, y, start):
            start += 1
        how = "detected" if start > 0 else "none"
    fit = line_fit(x[start:], y[start:])
    outliers = []
    if fit.dof >= 2:
        residuals, leverage = np.array(fit.residuals), np.array(fit.leverage)
        sse = float(residuals @ residuals)
        bound = float(_t_quantile(1 - OUTLIER_ALPHA / (2 * residuals.size), fit.dof - 1))
        for k, (e, h) in enumerate(zip(residuals, leverage, strict=True)):
            s_without = math.sqrt(max(sse - e * e / (1 - h), 0.0) / (fit.dof - 1)) if h < 1 else math.nan
            t = e / (s_without * math.sqrt(1 - h)) if s_without > 0 else (math.inf if e else 0.0)
            if abs(t) > bound:
                outliers.append(Outlier(weighed.station, int(weighed.cycles[start + k]), float(e), float(t)))
    bedding_rate = math.nan
    if start > 0:
        bedding_rate = float((y[start] - y[0]) / (x[start] - x[0]))
    return StationRate(
        weighed.station,
        weighed.soak_control,
        tuple(int(c) for c in weighed.cycles),
        tuple(float(v) for v in y),
        int(weighed.cycles[start]),
        how,
        bedding_rate,
        fit.slope,
        fit.se,
        fit.dof,
        fit.interval(),
        density_mg_per_mm3,
        tuple(outliers),
    )


@dataclass(frozen=True)
class RateDifference:
    """Station b's rate minus station a's, with its 95 % interval (Welch–Satterthwaite), in [mg/Mc] and [mm³/Mc]."""

    a: str
    b: str
    difference_mg_per_Mc: float
    ci95_mg_per_Mc: tuple[float, float]
    density_mg_per_mm3: float

    @property
    def difference_mm3_per_Mc(self) -> float:
        return self.difference_mg_per_Mc / self.density_mg_per_mm3

    @property
    def ci95_mm3_per_Mc(self) -> tuple[float, float]:
        return (self.ci95_mg_per_Mc[0] / self.density_mg_per_mm3, self.ci95_mg_per_Mc[1] / self.density_mg_per_mm3)

    @property
    def significant(self) -> bool:
        """The interval excludes 0 (False when it is unknown)."""
        low, high = self.ci95_mg_per_Mc
        return bool(low > 0 or high < 0)


def rate_difference(a: StationRate, b: StationRate) -> RateDifference:
    """b − a (module docstring)."""
    difference = b.rate_mg_per_Mc - a.rate_mg_per_Mc
    se2 = a.se_mg_per_Mc**2 + b.se_mg_per_Mc**2
    interval = (math.nan, math.nan)
    if a.dof >= 1 and b.dof >= 1 and se2 > 0:
        dof = se2**2 / (a.se_mg_per_Mc**4 / a.dof + b.se_mg_per_Mc**4 / b.dof)
        half = float(_t_quantile(0.975, dof)) * math.sqrt(se2)
        interval = (difference - half, difference + half)
    return RateDifference(a.station, b.station, difference, interval, a.density_mg_per_mm3)


@dataclass(frozen=True)
class Gravimetry:
    """A test's gravimetric result: per station its rate, between stations their differences."""

    source: str
    density_mg_per_mm3: float
    density_stated: str
    stations: tuple[StationRate, ...]
    differences: tuple[RateDifference, ...]

    def station(self, name: str) -> StationRate:
        return next(rate for rate in self.stations if rate.station == name)


def _check_density(density: float) -> None:
    low, high = DENSITY_RANGE
    if isinstance(density, bool) or not (math.isfinite(density) and low < density <= high):
        raise ArgumentError("--density", density, f"a density in ({low:g}, {high:g}] mg/mm³")


def gravimetry(
    weighings: Weighings, density_mg_per_mm3: float | None = None, from_cycle: int | None = None
) -> Gravimetry:
    """Every station's rate and every pair's difference (module docstring); density None: UHMWPE's 0.935 mg/mm³."""
    stated = "given" if density_mg_per_mm3 is not None else "UHMWPE, the default"
    density = DENSITY_UHMWPE if density_mg_per_mm3 is None else density_mg_per_mm3
    _check_density(density)
    rates = tuple(station_rate(weighed, density, from_cycle) for weighed in weighings.stations)
    differences = tuple(rate_difference(a, b) for a, b in combinations(rates, 2))
    return Gravimetry(weighings.source, density, f"{density:g} mg/mm³ ({stated})", rates, differences)
