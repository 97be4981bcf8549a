"""The paper's Fig. 7 as it draws it: one panel per angle (AA, IER, FE), both platforms in each, one shared y-axis.

From a simulated run (``hipsim simulate --plant-params … --fig7``: the desired
motion and both platforms' true attitudes) or from a rig log
(``hipsim stations --sliders LOG`` with the sensors' columns: each platform's
attitude measured and predicted from the carriages). The panels follow the
paper's order: abduction/adduction (β), internal/external rotation (γ),
flexion/extension (α).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

__all__ = ["PANELS", "Curve", "plot_fig7"]

#: (panel title, angle index in [α, β, γ]) in the paper's order.
PANELS = (
    ("AA (abduction/adduction, β)", 1),
    ("IER (internal/external rotation, γ)", 2),
    ("FE (flexion/extension, α)", 0),
)


@dataclass(frozen=True)
class Curve:
    """One line on every panel: a label, gait angles [deg] (N, 3), and how it is drawn (matplotlib colour and style)."""

    label: str
    angles_deg: np.ndarray
    colour: str = "k"
    style: str = "-"


def plot_fig7(t: np.ndarray, curves: Sequence[Curve], title: str = ""):
    """The three panels over time t [s] (N,), each curve on each; the y-axis shared. Returns a matplotlib Figure."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(10.0, 7.0), layout="constrained")
    axes = fig.subplots(3, 1, sharex=True, sharey=True)
    for ax, (name, k) in zip(axes, PANELS):
        for curve in curves:
            ax.plot(t, curve.angles_deg[:, k], color=curve.colour, ls=curve.style, lw=1.0, label=curve.label)
        ax.set_title(name, fontsize=10, loc="left")
        ax.set_ylabel("angle [°]")
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=8, loc="upper right", ncol=min(4, len(curves)))
    axes[-1].set_xlabel("t [s]")
    if title:
        fig.suptitle(title, fontsize=11)
    return fig
