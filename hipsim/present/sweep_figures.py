"""The figure of a design sweep: its variants on two objectives, the Pareto front drawn through them, its points labelled."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

__all__ = ["MAX_LABELS", "design_label", "plot_pareto"]

#: At most this many Pareto points are labelled with their design values; a longer front is labelled every k-th point.
MAX_LABELS = 16

_RATING_STYLE = {
    "pass": ("tab:green", "passes the rating"),
    "fail": ("tab:red", "fails the rating"),
    "unchecked": ("tab:blue", "no rating checked"),
}


def plot_pareto(
    x: np.ndarray,
    y: np.ndarray,
    front: np.ndarray,
    names: tuple[str, str],
    maximise: tuple[bool, bool],
    ratings: Sequence[str],
    title: str = "",
    labels: Sequence[str] | None = None,
):
    """The variants on two objectives, coloured by their rating, the Pareto front joined and ringed.

    Args:
        x, y: the objectives per variant, (n,), in the units their names give; NaN (no metrics) is not drawn.
        front: (n,) True for the variants on the front (:func:`hipsim.design.sweep.pareto_front`).
        names: the two columns.
        maximise: per objective, True if larger is better (the axis label says which).
        ratings: per variant "pass", "fail", "unchecked" or "" (no metrics).
        title: above the plot.
        labels: (n,) each variant's design values as text (:func:`design_label`); the Pareto points are
            labelled with theirs. None: no labels.

    Returns:
        A matplotlib Figure (Agg; save it with :func:`hipsim.present.figures.save_figure`).
    """
    from matplotlib.figure import Figure

    x, y, front = np.asarray(x, dtype=float), np.asarray(y, dtype=float), np.asarray(front, dtype=bool)
    rating_cells = np.asarray(ratings, dtype=object)
    fig = Figure(figsize=(7.5, 5.5), layout="constrained")
    ax = fig.subplots()
    for rating, (colour, label) in _RATING_STYLE.items():
        chosen = (rating_cells == rating) & np.isfinite(x) & np.isfinite(y)
        if np.any(chosen):
            ax.scatter(
                x[chosen],
                y[chosen],
                s=10,
                color=colour,
                alpha=0.55,
                linewidths=0,
                label=f"{label} ({np.count_nonzero(chosen)})",
            )
    if np.any(front):
        order = np.argsort(x[front])
        ax.plot(x[front][order], y[front][order], color="black", lw=1.0, zorder=3)
        ax.scatter(
            x[front],
            y[front],
            s=36,
            facecolors="none",
            edgecolors="black",
            linewidths=1.2,
            zorder=4,
            label=f"Pareto front ({np.count_nonzero(front)})",
        )
    if labels is not None and np.any(front):
        _label_front(ax, x, y, front, labels)
    for setter, name, larger in ((ax.set_xlabel, names[0], maximise[0]), (ax.set_ylabel, names[1], maximise[1])):
        setter(f"{name} ({'larger' if larger else 'smaller'} is better)")
    ax.grid(alpha=0.3)
    ax.legend(loc="best", fontsize=8)
    if title:
        ax.set_title(title, fontsize=10)
    return fig


def design_label(values: dict[str, float]) -> str:
    """A variant's design values as a point label: "length_mm 330, lead_mm 10" (the key without its section)."""
    return ", ".join(f"{key.split('.')[-1]} {value:.4g}" for key, value in values.items())


def _label_front(ax, x, y, front, labels) -> None:
    """Each Pareto point's design values beside it, alternately above and below so neighbours do not overlap."""
    indices = np.flatnonzero(front & np.isfinite(x) & np.isfinite(y))
    indices = indices[np.argsort(x[indices])]
    step = max(1, int(np.ceil(len(indices) / MAX_LABELS)))
    for n, k in enumerate(indices[::step]):
        ax.annotate(
            labels[k],
            (x[k], y[k]),
            xytext=(6, 8 if n % 2 == 0 else -12),
            textcoords="offset points",
            fontsize=6.5,
            color="0.15",
            zorder=5,
        )
    if step > 1:
        ax.text(
            0.99,
            0.01,
            f"one Pareto point in {step} labelled",
            transform=ax.transAxes,
            ha="right",
            va="bottom",
            fontsize=7,
            color="0.3",
        )
