"""The figure of a design sweep (hipsim.present.sweep_figures): what is drawn where, read back from the figure's
artists (nothing rendered), and the labels of the Pareto points."""

from __future__ import annotations

import numpy as np

from hipsim.present.sweep_figures import MAX_LABELS, design_label, plot_pareto


def test_pareto_points_carry_their_design_values():
    x = np.array([1.0, 2.0, 3.0, 2.5, 4.0])
    y = np.array([3.0, 2.0, 1.0, 2.5, 0.5])
    front = np.array([True, True, True, False, True])
    labels = [design_label({"lever.length_mm": 300.0 + 10 * k, "screw.lead_mm": 10.0}) for k in range(5)]
    fig = plot_pareto(x, y, front, ("a", "b"), (False, False), ["pass"] * 5, labels=labels)
    texts = {t.get_text() for t in fig.axes[0].texts}
    assert texts == {labels[k] for k in (0, 1, 2, 4)} and labels[0] == "length_mm 300, lead_mm 10"


def test_points_by_rating_the_front_joined_in_order_and_nan_left_out():
    x = np.array([3.0, 1.0, 2.0, np.nan, 4.0])
    y = np.array([1.0, 3.0, 2.0, 5.0, np.nan])
    front = np.array([True, True, True, False, False])
    ratings = ["pass", "fail", "pass", "pass", "unchecked"]
    fig = plot_pareto(x, y, front, ("mass_kg", "torque_Nm"), (False, True), ratings, title="t")
    ax = fig.axes[0]
    legend = [t.get_text() for t in ax.get_legend().get_texts()]
    # the NaN variants are counted nowhere; "unchecked" has none left, so no entry
    assert legend == ["passes the rating (2)", "fails the rating (1)", "Pareto front (3)"]
    (line,) = ax.get_lines()
    assert line.get_xdata().tolist() == [1.0, 2.0, 3.0] and line.get_ydata().tolist() == [3.0, 2.0, 1.0]
    assert ax.get_xlabel() == "mass_kg (smaller is better)" and ax.get_ylabel() == "torque_Nm (larger is better)"
    assert ax.get_title() == "t" and not ax.texts  # no labels asked for


def test_a_long_front_is_labelled_every_kth_point():
    n = 2 * MAX_LABELS + 1  # 33 points: every 3rd, 11 labels
    x = np.arange(n, dtype=float)[::-1]
    fig = plot_pareto(
        x, -x, np.ones(n, bool), ("a", "b"), (False, False), ["pass"] * n, labels=[f"d{k}" for k in range(n)]
    )
    texts = [t.get_text() for t in fig.axes[0].texts]
    assert texts[-1] == "one Pareto point in 3 labelled"
    assert texts[:-1] == [f"d{k}" for k in range(n - 1, -1, -3)]  # in order of x, from the smallest
    at_limit = plot_pareto(
        x[:MAX_LABELS],
        x[:MAX_LABELS],
        np.ones(MAX_LABELS, bool),
        ("a", "b"),
        (False, False),
        ["pass"] * MAX_LABELS,
        labels=["l"] * MAX_LABELS,
    )
    assert len(at_limit.axes[0].texts) == MAX_LABELS  # at the limit: every point, no note


def test_a_design_label_drops_the_section_and_keeps_four_digits():
    assert design_label({"platform.home_offset_deg": 29.99999, "screw.lead_mm": 0.012345}) == (
        "home_offset_deg 30, lead_mm 0.01235"
    )
    assert design_label({}) == ""
