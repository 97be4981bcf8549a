"""The figure of a design sweep: its variants on two objectives, the Pareto front drawn through them."""

from __future__ import annotations

from typing import Sequence

import numpy as np

__all__ = ["plot_pareto"]

_RATING_STYLE = {
    "pass": ("tab:green", "passes the rating"),
    "fail": ("tab:red", "fails the rating"),
    "unchecked": ("tab:blue", "no rating checked"),
}


def plot_pareto(
    x: np.ndarray, y: np.ndarray, front: np.ndarray, names: tuple[str, str], maximise: tuple[bool, bool],
    ratings: Sequence[str], title: str = "",
):
    """The variants on two objectives, coloured by their rating, the Pareto front joined and ringed.

    Args:
        x, y: the objectives per variant, (n,), in the units their names give; NaN (no metrics) is not drawn.
        front: (n,) True for the variants on the front (:func:`hipsim.design.sweep.pareto_front`).
        names: the two columns.
        maximise: per objective, True if larger is better (the axis label says which).
        ratings: per variant "pass", "fail", "unchecked" or "" (no metrics).
        title: above the plot.

    Returns:
        A matplotlib Figure (Agg; save it with :func:`hipsim.present.figures.save_figure`).
    """
    from matplotlib.figure import Figure

    x, y, front = np.asarray(x, dtype=float), np.asarray(y, dtype=float), np.asarray(front, dtype=bool)
    ratings = np.asarray(ratings, dtype=object)
    fig = Figure(figsize=(7.5, 5.5), layout="constrained")
    ax = fig.subplots()
    for rating, (colour, label) in _RATING_STYLE.items():
        chosen = (ratings == rating) & np.isfinite(x) & np.isfinite(y)
        if np.any(chosen):
            ax.scatter(x[chosen], y[chosen], s=10, color=colour, alpha=0.55, linewidths=0, label=f"{label} ({np.count_nonzero(chosen)})")
    if np.any(front):
        order = np.argsort(x[front])
        ax.plot(x[front][order], y[front][order], color="black", lw=1.0, zorder=3)
        ax.scatter(x[front], y[front], s=36, facecolors="none", edgecolors="black", linewidths=1.2, zorder=4,
                   label=f"Pareto front ({np.count_nonzero(front)})")  # fmt: skip
    for setter, name, larger in ((ax.set_xlabel, names[0], maximise[0]), (ax.set_ylabel, names[1], maximise[1])):
        setter(f"{name} ({'larger' if larger else 'smaller'} is better)")
    ax.grid(alpha=0.3)
    ax.legend(loc="best", fontsize=8)
    if title:
        ax.set_title(title, fontsize=10)
    return fig
