"""Does a wear test's gravimetric result make sense? The weighings' regression held to the fits' gates.

The gates of :mod:`hipsim.fit_checks`, applied to each station's line of
soak-corrected loss against cycles (:mod:`hipsim.wear.gravimetric`):

- **residuals against the balance noise** (:func:`residual_findings`, with
  :func:`hipsim.fit_checks.residual_gate` and its 3 times): each station's
  residual standard deviation against the noise of a loss. A loss is two
  readings apart from the first stop's (the cup's and its soak control's), so
  a stated balance noise σ (``--balance-noise``, one reading's standard
  deviation) gives √2·σ. Without it the noise is the other stations' median
  residual (one balance, one lab: the stations share the noise), so a station
  scattering 3 times its neighbours is named; one station alone is not held,
  nor stations with under :data:`NEIGHBOUR_MIN_DOF` = 6 degrees of freedom
  (8 stops: with fewer, two honest stations differ 3-fold too often);
- **a rate a hip cup cannot have** (:func:`rate_findings`): a steady rate whose
  95 % interval lies wholly below 0 (the cup gains mass after the soak
  correction: the soak control's sign, or the cup and its soak control
  swapped), or one beyond :data:`RATE_MAX_MM3_PER_MC` = 300 mm³/Mc (the
  highest rates measured on hip simulators, gamma-in-air UHMWPE against
  rough heads, are 50–150 mm³/Mc; twice that is a slip: masses in µg, a cup
  swapped at a stop);
- **a mass that is not a cup's in mg** (:func:`mass_findings`): a reading
  outside :data:`CUP_MASS_RANGE_MG` = 1 g to 1 kg (a polyethylene cup weighs
  10–60 g, a metal or ceramic one up to 200 g): below, the column holds grams;
  above, micrograms;
- **a swap a quick test can name** (:func:`swap_findings`): two stations'
  masses (or a station's and its soak control's) exchanged at one stop, named
  when exchanging them back removes more than
  :data:`hipsim.fit_checks.PATTERN_GAIN` (half) of the two lines' squared
  residual (a real swap of two cups removes nearly all of it);
- **the same cup twice** (:func:`duplicate_stations`): two stations with the
  same masses at every stop (rows pasted under a second name) count one cup
  twice; refused.

Each is a pure function returning its findings in words;
:func:`check_gravimetry` collects them as a :class:`~hipsim.fit_checks.FitCheck`.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from itertools import combinations

import numpy as np

from ..fit_checks import PATTERN_GAIN, RESIDUAL_FACTOR, FitCheck, residual_gate
from .gravimetric import MC, Gravimetry, StationRate, line_fit
from .weighings import StationWeighings, Weighings

__all__ = [
    "BALANCE_NOISE_RANGE",
    "CUP_MASS_RANGE_MG",
    "NEIGHBOUR_MIN_DOF",
    "RATE_MAX_MM3_PER_MC",
    "check_gravimetry",
    "duplicate_stations",
    "mass_findings",
    "rate_findings",
    "residual_findings",
    "swap_findings",
]

#: A steady rate beyond this in [mm³/Mc] is not a hip cup's (the highest measured: 50–150 mm³/Mc).
RATE_MAX_MM3_PER_MC = 300.0
#: A cup's mass in [mg] lies in [1 g, 1 kg]: below, grams in the mg column; above, micrograms.
CUP_MASS_RANGE_MG = (1e3, 1e6)
#: Without a stated balance noise, stations are held to each other only with this many degrees of freedom each
#: (8 stops; ISO 14242-2 weighs 11 by 5 Mc): two honest stations of 6 then differ 3-fold in 1.7 % of tests, of 3
#: (5 stops) in 10 %.
NEIGHBOUR_MIN_DOF = 6
#: ``--balance-noise`` in [mg]: hard range (0, 100], one reading's standard deviation.
BALANCE_NOISE_RANGE = (0.0, 100.0)


def residual_findings(
    rates: Sequence[StationRate], balance_noise_mg: float | None = None, factor: float = RESIDUAL_FACTOR
) -> str | None:
    """Stations whose residual standard deviation exceeds ``factor`` times a loss's noise, in words, or None.

    Args:
        rates: the stations' rates; a station with fewer than three fitted stops (no residual) is skipped.
        balance_noise_mg: one reading's standard deviation in [mg]; a loss's noise is √2 times it. None: each
            station is held to the median residual of the others (none with a single station), among the stations
            with at least :data:`NEIGHBOUR_MIN_DOF` degrees of freedom.
        factor: the gate (:data:`hipsim.fit_checks.RESIDUAL_FACTOR`); a ratio equal to it passes.
    """
    held = [rate for rate in rates if rate.dof >= (1 if balance_noise_mg is not None else NEIGHBOUR_MIN_DOF)]
    names, residual, noise = [], [], []
    for rate in held:
        s = rate.se_mg_per_Mc * math.sqrt(_sxx(rate))
        if balance_noise_mg is not None:
            reference = math.sqrt(2.0) * balance_noise_mg
        else:
            others = [other.se_mg_per_Mc * math.sqrt(_sxx(other)) for other in held if other is not rate]
            if not others:
                continue
            reference = float(np.median(others))
        names.append(f"station {rate.station}")
        residual.append(s)
        noise.append(reference)
    if not names:
        return None
    found = residual_gate(residual, noise, names, "mg", factor)
    if found is None:
        return None
    against = (
        f"√2 × the balance noise {balance_noise_mg:g} mg"
        if balance_noise_mg is not None
        else "the other stations' median residual"
    )
    return f"{found}, against {against} (a stop misread, cups mixed up, or a balance out of its calibration?)"


def _sxx(rate: StationRate) -> float:
    """Σ(x − x̄)² of the fitted stops, x in [Mc]: the residual standard deviation is se·√Sxx."""
    x = np.array([c for c in rate.cycles if c >= rate.from_cycle], dtype=float) / MC
    return float(np.sum((x - x.mean()) ** 2))


def rate_findings(rate: StationRate, rate_max_mm3_per_Mc: float = RATE_MAX_MM3_PER_MC) -> str | None:
    """A rate a hip cup cannot have, with its likely cause, or None.

    Negative: the 95 % interval's upper end below 0 (a rate of exactly 0 at its end passes); without an
    interval (two stops), the rate itself below 0. Too high: beyond ``rate_max_mm3_per_Mc`` (equal passes).
    """
    rate_mm3 = rate.rate_mm3_per_Mc
    high = rate.ci95_mm3_per_Mc[1]
    upper = high if math.isfinite(high) else rate_mm3
    if upper < 0:
        return (
            f"station {rate.station}: steady rate {rate_mm3:.3g} mm³/Mc, below 0 (the cup gains mass after the soak "
            f"correction): the soak control's sign (a soak column holding a loss, not a mass?) or the cup and its "
            f"soak control '{rate.soak_control}' swapped"
        )
    if rate_mm3 > rate_max_mm3_per_Mc:
        return (
            f"station {rate.station}: steady rate {rate_mm3:.4g} mm³/Mc, beyond {rate_max_mm3_per_Mc:g} mm³/Mc "
            "(hip cups wear under 150): masses in µg rather than mg, or cups swapped at a stop?"
        )
    return None


def mass_findings(weighed: StationWeighings, mass_range_mg: tuple[float, float] = CUP_MASS_RANGE_MG) -> str | None:
    """A station's (or its soak control's) mass outside a cup's, with the unit it looks like, or None (ends pass)."""
    low, high = mass_range_mg
    for what, masses in ((f"station {weighed.station}", weighed.mass_mg), (weighed.soak_control, weighed.soak_mg)):
        m = float(np.min(masses))
        if m < low:
            return f"{what} weighs {m:g} mg, under {low:g} mg (a cup weighs 10 to 200 g): masses in g, not mg?"
        m = float(np.max(masses))
        if m > high:
            return f"{what} weighs {m:g} mg, over {high:g} mg (a cup weighs 10 to 200 g): masses in µg, not mg?"
    return None


def _sse(cycles: np.ndarray, loss: np.ndarray) -> float:
    if cycles.size < 3:
        return 0.0
    fit = line_fit(cycles / MC, loss)
    return float(np.sum(np.square(fit.residuals)))


def _loss(mass: np.ndarray, soak: np.ndarray) -> np.ndarray:
    return (mass[0] - mass) + (soak - soak[0])


def swap_findings(weighings: Weighings, gain: float = PATTERN_GAIN) -> tuple[str, ...]:
    """Masses exchanged at one stop between two stations, or a station and its soak control, in words.

    Each exchange is undone in turn and both lines refitted over all their stops; the best is named when it
    removes more than ``gain`` of the squared residual (strictly: exactly ``gain`` passes).
    """
    found: list[str] = []
    for weighed in weighings.stations:  # the cup and its soak control
        base = _sse(weighed.cycles, weighed.loss_mg)
        best = (base, -1)
        for k in range(weighed.cycles.size):
            mass, soak = weighed.mass_mg.copy(), weighed.soak_mg.copy()
            mass[k], soak[k] = soak[k], mass[k]
            best = min(best, (_sse(weighed.cycles, _loss(mass, soak)), k))
        if base > 0 and best[1] >= 0 and best[0] < (1.0 - gain) * base:
            k = best[1]
            found.append(
                f"station {weighed.station} and its soak control '{weighed.soak_control}' look swapped at cycle "
                f"{weighed.cycles[k]:.0f} (line {weighed.lines[k]})"
            )
    for a, b in combinations(weighings.stations, 2):
        common = np.intersect1d(a.cycles, b.cycles)
        base = _sse(a.cycles, a.loss_mg) + _sse(b.cycles, b.loss_mg)
        pair: tuple[float, float] = (base, -1.0)
        for cycle in common:
            i, j = int(np.searchsorted(a.cycles, cycle)), int(np.searchsorted(b.cycles, cycle))
            mass_a, mass_b = a.mass_mg.copy(), b.mass_mg.copy()
            mass_a[i], mass_b[j] = b.mass_mg[j], a.mass_mg[i]
            sse = _sse(a.cycles, _loss(mass_a, a.soak_mg)) + _sse(b.cycles, _loss(mass_b, b.soak_mg))
            pair = min(pair, (sse, float(cycle)))
        if base > 0 and pair[1] >= 0 and pair[0] < (1.0 - gain) * base:
            found.append(f"stations {a.station} and {b.station} look swapped at cycle {pair[1]:.0f}")
    return tuple(found)


def duplicate_stations(weighings: Weighings) -> str | None:
    """Two stations with the same cycles and the same masses at every stop (one cup given twice), in words, or None."""
    for a, b in combinations(weighings.stations, 2):
        if np.array_equal(a.cycles, b.cycles) and np.array_equal(a.mass_mg, b.mass_mg):
            return (
                f"stations {a.station} and {b.station} have the same masses at every stop (lines {a.lines[0]} and "
                f"{b.lines[0]} on): one cup given twice counts its stops twice; give each cup once"
            )
    return None


def check_gravimetry(weighings: Weighings, result: Gravimetry, balance_noise_mg: float | None = None) -> FitCheck:
    """Every gate of the module on a test's weighings and their rates (the duplicate refusal apart)."""
    findings: list[str] = []
    for weighed in weighings.stations:
        found = mass_findings(weighed)
        if found:
            findings.append(found)
    residual = residual_findings(result.stations, balance_noise_mg)
    if residual:
        findings.append(residual)
    findings += [found for rate in result.stations if (found := rate_findings(rate))]
    findings += swap_findings(weighings)
    return FitCheck("weighings", tuple(findings))
