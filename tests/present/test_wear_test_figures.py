"""The wear test's figure (hipsim.present.wear_test_figures): measured and predicted volumes per station, the
steady-state rate's line through the stops it was fitted on, the intervals' bars; from a small fake test here."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from hipsim.present.wear_test_figures import plot_measured_predicted


def station(number, volumes, k_seen):
    cycles = [0.0, 0.5e6, 1.0e6, 1.5e6]
    rate = SimpleNamespace(station=number, cycles=cycles, volume_mm3=volumes, from_cycle=0.5e6, rate_mm3_per_Mc=4.0)

    def predicted(k, kind, at):
        k_seen.append((k, kind))
        return 2.0 * np.asarray(at) / 1e6

    intervals = [
        SimpleNamespace(first_cycle=0.0, last_cycle=0.5e6, measured_mm3=1.0, predicted_mm3=1.5),
        SimpleNamespace(first_cycle=0.5e6, last_cycle=1.0e6, measured_mm3=2.0, predicted_mm3=1.0),
    ]
    return SimpleNamespace(
        rate=rate,
        exposure=SimpleNamespace(predicted_mm3=predicted),
        fitted=SimpleNamespace(k=lambda kind: 7.0),
        intervals=intervals,
    )


def test_the_rate_line_runs_through_the_stops_it_was_fitted_on():
    seen: list = []
    result = SimpleNamespace(stations=[station(1, [0.0, 1.0, 3.0, 5.0], seen)], given=None)
    left, right = plot_measured_predicted(result).axes
    measured, predicted, rate = left.get_lines()
    assert measured.get_xdata().tolist() == [0.0, 0.5, 1.0, 1.5]  # in Mc
    assert predicted.get_ydata().tolist() == [0.0, 1.0, 2.0, 3.0]
    assert seen == [(7.0, "local")]  # without a given law: the station's own local k
    # from 0.5 Mc on: mean volume 3 at mean 1 Mc, slope 4: the line 4x − 1
    assert rate.get_xdata().tolist() == [0.5, 1.0, 1.5] and rate.get_ydata().tolist() == pytest.approx([1.0, 3.0, 5.0])
    assert [t.get_text() for t in right.get_xticklabels()] == ["0–0.5", "0.5–1"]
    heights = [bar.get_height() for bar in right.patches]
    assert heights == [1.0, 2.0, 1.5, 1.0]  # measured bars, then predicted


def test_a_given_law_predicts_every_station():
    seen: list = []
    given = SimpleNamespace(kind="global", k=3.0)
    result = SimpleNamespace(stations=[station(1, [0.0] * 4, seen), station(2, [0.0] * 4, seen)], given=given)
    fig = plot_measured_predicted(result)
    assert seen == [(3.0, "global")] * 2
    labels = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    assert labels == ["station 1: measured", "station 1: predicted", "station 2: measured", "station 2: predicted"]
