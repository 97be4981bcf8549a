"""Figures of the workspace analysis: the singularity map with the trajectory on it, and the platform-offset sweep."""

from __future__ import annotations

import math

import numpy as np

from ..design.workspace import OffsetSweep, SingularityMap

__all__ = ["plot_offset_sweep", "plot_singularity_map"]


def plot_singularity_map(smap: SingularityMap, levels: tuple[float, ...] = (0.1, 0.2, 0.3, 0.4, 0.5, 0.6)):
    """One panel per γ: the singularity measure over α × β, the trajectory drawn on it.

    The full path is drawn thin on every panel; the samples whose γ is nearest
    that panel's γ are drawn bold, and the trajectory's worst sample is starred.
    A last panel shows the measure along the trajectory over time.

    Args:
        smap: the map (from :func:`singularity_map`).
        levels: contour lines to draw, inverse condition numbers.

    Returns:
        A matplotlib Figure (Agg; save it with :func:`hipsim.present.figures.save_figure`).
    """
    from matplotlib.figure import Figure

    n = smap.gamma_deg.size
    path, m = smap.trajectory_q_deg, smap.margin  # both given with a trajectory, else both None
    panels = n + (1 if path is not None else 0)
    columns = min(3, panels)
    rows = math.ceil(panels / columns)
    fig = Figure(figsize=(5.2 * columns, 3.6 * rows + 0.8), layout="constrained")
    axes = fig.subplots(rows, columns, squeeze=False).ravel()
    finite = smap.cond_inv[np.isfinite(smap.cond_inv)]
    vmax = float(finite.max()) if finite.size else 1.0
    extent = _extent(smap.alpha_deg, smap.beta_deg)
    if path is not None:
        nearest = np.argmin(np.abs(path[:, 2, None] - smap.gamma_deg[None, :]), axis=1)
    image = None
    for g in range(n):
        ax = axes[g]
        ax.set_facecolor("0.82")  # NaN (out of reach) stays transparent: grey shows through
        image = ax.imshow(
            np.ma.masked_invalid(smap.cond_inv[g]),
            origin="lower",
            extent=extent,
            aspect="auto",
            cmap="viridis",
            vmin=0.0,
            vmax=vmax,
            interpolation="nearest",
        )
        if finite.size and np.ptp(finite) > 0:
            contours = ax.contour(
                smap.alpha_deg, smap.beta_deg, smap.cond_inv[g], levels=list(levels), colors="white", linewidths=0.6
            )
            ax.clabel(contours, fontsize=7, fmt="%.1f")
        if path is not None:
            ax.plot(path[:, 0], path[:, 1], color="white", lw=0.8, ls="--", alpha=0.8, label="trajectory (all γ)")
            if np.any(nearest == g):
                mine = np.where(nearest == g, path[:, 1], np.nan)
                ax.plot(
                    path[:, 0],
                    mine,
                    color="tab:red",
                    lw=2.0,
                    label=f"trajectory where γ is nearest {smap.gamma_deg[g]:g}°",
                )
            m = smap.margin
            if m is not None and m.index >= 0 and nearest[m.index] == g:
                ax.plot(
                    m.q_deg[0],
                    m.q_deg[1],
                    marker="*",
                    ms=14,
                    color="tab:orange",
                    mec="black",
                    label=f"min {m.cond_inv_min:.3f} at t = {m.t_s:.3f} s",
                )
            ax.legend(loc="lower left", fontsize=7, framealpha=0.85)
        ax.set_title(f"γ = {smap.gamma_deg[g]:g}° (internal/external rotation)", fontsize=10)
        ax.set_xlabel("α flexion/extension [deg]")
        ax.set_ylabel("β abduction/adduction [deg]")
    if path is not None and m is not None:
        ax = axes[n]
        ax.plot(smap.trajectory_t_s, m.cond_inv, color="tab:blue", label="inverse condition number of J")
        if m.index >= 0:
            ax.plot(
                m.t_s,
                m.cond_inv_min,
                marker="*",
                ms=14,
                color="tab:orange",
                mec="black",
                label=f"min {m.cond_inv_min:.3f} at t = {m.t_s:.3f} s",
            )
        ax.set_ylim(0.0, max(vmax, np.nanmax(m.cond_inv) if np.any(np.isfinite(m.cond_inv)) else 1.0) * 1.05)
        ax.set_xlabel("time t [s]")
        ax.set_ylabel("inverse condition number of J [–]")
        ax.set_title(f"along the trajectory: {m.trajectory}", fontsize=10)
        ax.grid(alpha=0.3)
        ax.legend(loc="lower right", fontsize=7)
    for ax in axes[panels:]:
        ax.set_visible(False)
    if image is not None:
        bar = fig.colorbar(image, ax=axes[:n].tolist(), shrink=0.9)
        bar.set_label("inverse condition number of J (0 singular, 1 isotropic); grey: out of reach")
    fig.suptitle(f"Singularity map, platform offset δ = {smap.delta_deg:g}°")
    return fig


def _extent(alpha: np.ndarray, beta: np.ndarray) -> tuple[float, float, float, float]:
    """Image extent so that each pixel is centred on its grid value."""

    def edges(v):
        if v.size == 1:
            return v[0] - 0.5, v[0] + 0.5
        return v[0] - 0.5 * (v[1] - v[0]), v[-1] + 0.5 * (v[-1] - v[-2])

    return (*edges(alpha), *edges(beta))


def plot_offset_sweep(sweep: OffsetSweep):
    """The sweep against δ: smallest singularity measure, peak motor torque, largest slider stroke.

    Infeasible δ (motion out of reach or singular) are shaded; the built machine's δ is marked.

    Args:
        sweep: from :func:`offset_sweep`.

    Returns:
        A matplotlib Figure.
    """
    from matplotlib.figure import Figure

    fig = Figure(figsize=(8.5, 8.5), layout="constrained")
    axes = fig.subplots(3, 1, sharex=True)
    d = sweep.deltas_deg
    built = sweep.delta_built_deg
    series = (
        (sweep.cond_inv_min, "smallest inverse condition\nnumber of J [–]", "linear"),
        (sweep.tau_peak_Nmm, "peak motor torque [N·mm]\n(largest of the three)", "log"),
        (sweep.stroke_max_mm, "largest slider stroke [mm]", "linear"),
    )
    for ax, (values, label, scale) in zip(axes, series):
        ax.plot(d, values, marker=".", ms=3, color="tab:blue", label=f"{sweep.trajectory}")
        ax.set_ylabel(label)
        ax.set_yscale(scale)
        ax.grid(alpha=0.3, which="both")
        ax.axvline(built, color="tab:red", ls="--", lw=1.2, label=f"built machine δ = {built:g}°")
        k = sweep.built_index
        if k is not None and np.isfinite(values[k]):
            ax.plot(d[k], values[k], "o", color="tab:red")
            ax.annotate(
                f"{values[k]:.3g}",
                (d[k], values[k]),
                textcoords="offset points",
                xytext=(6, 6),
                fontsize=8,
                color="tab:red",
            )
        _shade(ax, d, ~sweep.feasible)
    axes[0].set_ylim(bottom=0.0)
    axes[0].legend(loc="upper left", fontsize=8)
    if np.any(~sweep.feasible):
        axes[1].text(
            0.01,
            0.95,
            "shaded: motion out of reach, singular, or passing through a singularity",
            transform=axes[1].transAxes,
            fontsize=8,
            va="top",
        )
    axes[-1].set_xlabel("platform offset δ [deg] (platform joint i at φ_i = θ_i + δ)")
    fig.suptitle(f"Platform offset sweep: {sweep.trajectory}")
    return fig


def _shade(ax, x: np.ndarray, mask: np.ndarray) -> None:
    """Shade the x ranges where mask is True (half a step either side of each point)."""
    if not np.any(mask):
        return
    step = np.median(np.diff(x)) if x.size > 1 else 1.0
    for k in np.flatnonzero(mask):
        ax.axvspan(x[k] - step / 2, x[k] + step / 2, color="tab:red", alpha=0.15, lw=0)
