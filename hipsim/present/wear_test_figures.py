"""The wear test's figure: measured against predicted volume per station, cumulative and per interval between stops."""

from __future__ import annotations

import numpy as np

__all__ = ["WEAR_TEST_CAPTIONS", "plot_measured_predicted"]

WEAR_TEST_CAPTIONS = {
    "measured_predicted": "Left: each station's soak-corrected volume lost since its first stop (dots: weighed) and the "
    "volume predicted over the motion it had (line), the fitted steady-state rate dashed. Right: per interval between "
    "stops, measured (filled) and predicted (hatched) volume.",
}


def plot_measured_predicted(result):
    """Cumulative and per-interval volumes, measured and predicted, every station on one chart."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(10.0, 4.2), layout="constrained")
    left, right = fig.subplots(1, 2)
    n = len(result.stations)
    width = 0.8 / max(n, 1)
    for i, s in enumerate(result.stations):
        rate = s.rate
        colour = f"C{i}"
        x = np.asarray(rate.cycles, dtype=float) / 1e6
        kind, k = (result.given.kind, result.given.k) if result.given else ("local", s.fitted.k("local"))
        predicted = s.exposure.predicted_mm3(k, kind, np.asarray(rate.cycles, dtype=float))
        left.plot(x, rate.volume_mm3, "o", color=colour, label=f"station {rate.station}: measured")
        left.plot(x, predicted, "-", color=colour, label=f"station {rate.station}: predicted")
        start = list(rate.cycles).index(rate.from_cycle)
        xs = x[start:]
        y0 = np.mean(np.asarray(rate.volume_mm3)[start:]) - rate.rate_mm3_per_Mc * np.mean(xs)
        left.plot(xs, y0 + rate.rate_mm3_per_Mc * xs, "--", color=colour, lw=0.8)
        rows = s.intervals
        centres = np.arange(len(rows)) + (i - (n - 1) / 2) * width
        right.bar(centres - width / 4, [r.measured_mm3 for r in rows], width / 2, color=colour)
        right.bar(
            centres + width / 4, [r.predicted_mm3 for r in rows], width / 2, color="white", edgecolor=colour, hatch="//"
        )
    left.set_xlabel("cycles [Mc]")
    left.set_ylabel("volume lost [mm³]")
    left.legend(fontsize=8)
    left.grid(alpha=0.3)
    first = result.stations[0].intervals if result.stations else ()
    right.set_xticks(
        np.arange(len(first)), [f"{r.first_cycle / 1e6:.3g}–{r.last_cycle / 1e6:.3g}" for r in first], rotation=45
    )
    right.set_xlabel("interval [Mc]")
    right.set_ylabel("volume per interval [mm³]")
    right.grid(alpha=0.3, axis="y")
    return fig
