"""The paper's Fig. 7 (hipsim.present.fig7): each angle on its panel in the paper's order, every curve on each,
one y-axis; read back from the figure's lines (nothing rendered)."""

from __future__ import annotations

import numpy as np

from hipsim.present.fig7 import PANELS, Curve, plot_fig7


def test_the_panels_are_beta_gamma_alpha_with_every_curve_on_each():
    t = np.array([0.0, 0.5, 1.0])
    a = np.array([[1.0, 2.0, 3.0], [4.0, 5.0, 6.0], [7.0, 8.0, 9.0]])  # columns α, β, γ in [deg]
    curves = [Curve("desired", a), Curve("platform 2", -a, "tab:blue", "--")]
    fig = plot_fig7(t, curves, title="run")
    axes = fig.axes
    assert [ax.get_title(loc="left") for ax in axes] == [name for name, _ in PANELS]
    assert [k for _, k in PANELS] == [1, 2, 0]
    for ax, (_, k) in zip(axes, PANELS):
        desired, measured = ax.get_lines()
        assert desired.get_xdata().tolist() == t.tolist() and desired.get_ydata().tolist() == a[:, k].tolist()
        assert measured.get_ydata().tolist() == (-a[:, k]).tolist()
        assert measured.get_linestyle() == "--" and measured.get_color() == "tab:blue"
    assert axes[0].get_shared_y_axes().joined(axes[0], axes[2])  # one y-axis for the three panels
    assert [t.get_text() for t in axes[0].get_legend().get_texts()] == ["desired", "platform 2"]
    assert axes[-1].get_xlabel() == "t [s]" and fig.get_suptitle() == "run"
    assert plot_fig7(t, curves[:1]).get_suptitle() == ""
