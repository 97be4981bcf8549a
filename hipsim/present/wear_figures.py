"""Figures of ``hipsim wear``: slide tracks and the force track on the cup, maps of sliding, work and cross-shear,
and the difference maps of two runs. The cup is seen from above its pole (orthographic: x, y of the cup frame
times r), its rim the circle."""

from __future__ import annotations

import numpy as np

from ..wear.maps import WearMaps
from ..wear.tracks import Tracks

__all__ = [
    "WEAR_CAPTIONS",
    "plot_cup_maps",
    "plot_difference_maps",
    "plot_force_track",
    "plot_slide_tracks",
    "plot_slide_tracks_pair",
]

#: Each figure's caption, by file stem.
WEAR_CAPTIONS = {
    "slide_tracks": "Slide tracks over one cycle of marker points of the head (dots: where each starts), drawn on the "
    "cup seen from above its pole, and the force track (the contact centre's path, red), as Calonius & Saikko draw them.",
    "cup_maps": "Per cycle, on the cup seen from above its pole: sliding distance s, work W = ∫p·|v| dt and cross-shear CS "
    "(blank where W = 0).",
    "force_track": "The force track on the cup, coloured by the load along it.",
    "difference_maps": "B − A per point of the cup: sliding distance, work and cross-shear.",
}


def _cup_axes(ax, r: float) -> None:
    theta = np.linspace(0, 2 * np.pi, 361)
    ax.plot(r * np.cos(theta), r * np.sin(theta), color="0.3", lw=1.0)
    ax.set_aspect("equal")
    ax.set_xlim(-1.08 * r, 1.08 * r)
    ax.set_ylim(-1.08 * r, 1.08 * r)
    ax.set_xlabel("cup x [mm]")
    ax.set_ylabel("cup y [mm]")


def plot_slide_tracks(tracks: Tracks, r: float, title: str = ""):
    """Slide tracks of the markers and the force track, top view (caption :data:`WEAR_CAPTIONS`)."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(6.4, 6.0), layout="constrained")
    _draw_tracks(fig.subplots(), tracks, r, title or "Slide tracks and force track")
    return fig


def plot_slide_tracks_pair(a: Tracks, b: Tracks, r: float, names: tuple[str, str]):
    """Two runs' slide tracks side by side, A left (caption :data:`WEAR_CAPTIONS`)."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(12.0, 6.0), layout="constrained")
    for ax, tracks, side, name in zip(fig.subplots(1, 2), (a, b), "AB", names, strict=True):
        _draw_tracks(ax, tracks, r, f"{side}: {name}")
    return fig


def _draw_tracks(ax, tracks: Tracks, r: float, title: str) -> None:
    _cup_axes(ax, r)
    for path in tracks.slide:
        ax.plot(r * path[:, 0], r * path[:, 1], color="tab:blue", lw=0.9)
        ax.plot(r * path[0, 0], r * path[0, 1], "o", color="tab:blue", ms=3)
    ax.plot(r * tracks.force[:, 0], r * tracks.force[:, 1], color="tab:red", lw=2.2, label="force track")
    ax.plot([], [], color="tab:blue", label="slide tracks")
    ax.legend(loc="lower right", fontsize=8)
    ax.set_title(title, fontsize=10)


def _grid_mesh(maps: WearMaps, r: float):
    """The grid's cell corners in the top view, (n_theta + 1, n_phi + 1) each."""
    theta, phi = maps.points.theta, maps.points.phi
    assert theta is not None and phi is not None  # a grid's
    d_theta, d_phi = theta[1] - theta[0] if theta.size > 1 else np.pi / 2, phi[1] - phi[0]
    th = np.concatenate([theta - d_theta / 2, [theta[-1] + d_theta / 2]])
    ph = np.concatenate([phi - d_phi / 2, [phi[-1] + d_phi / 2]])
    TH, PH = np.meshgrid(th, ph, indexing="ij")
    return r * np.sin(TH) * np.cos(PH), r * np.sin(TH) * np.sin(PH)


def _map(fig, ax, maps: WearMaps, values: np.ndarray, r: float, label: str, cmap: str, symmetric: bool = False):
    _cup_axes(ax, r)
    finite = values[np.isfinite(values)]
    top = float(np.max(np.abs(finite))) if finite.size else 1.0
    limits = {"vmin": -top, "vmax": top} if symmetric else {}
    if maps.points.shape is not None:
        X, Y = _grid_mesh(maps, r)
        image = ax.pcolormesh(X, Y, values.reshape(maps.points.shape), cmap=cmap, shading="flat", **limits)
    else:
        w = maps.points.w
        image = ax.scatter(r * w[:, 0], r * w[:, 1], c=values, cmap=cmap, s=12, **limits)
    fig.colorbar(image, ax=ax, shrink=0.8, label=label)


def plot_cup_maps(maps: WearMaps, title: str = ""):
    """Maps of sliding distance, work and CS on the cup (caption :data:`WEAR_CAPTIONS`)."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(15.0, 4.8), layout="constrained")
    axes = fig.subplots(1, 3)
    r = maps.setup.radius_mm
    _map(fig, axes[0], maps, maps.sliding_mm, r, "sliding distance s [mm]", "viridis")
    _map(fig, axes[1], maps, maps.work_N_per_mm, r, "work W [N/mm]", "magma")
    _map(fig, axes[2], maps, maps.cross_shear, r, "cross-shear CS", "plasma")
    fig.suptitle(title or f"{maps.name}: per cycle", fontsize=11)
    return fig


def plot_force_track(tracks: Tracks, r: float, title: str = ""):
    """The force track coloured by load (caption :data:`WEAR_CAPTIONS`)."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(6.4, 5.6), layout="constrained")
    ax = fig.subplots()
    _cup_axes(ax, r)
    image = ax.scatter(r * tracks.force[:, 0], r * tracks.force[:, 1], c=tracks.load, cmap="inferno_r", s=6)
    fig.colorbar(image, ax=ax, shrink=0.8, label="load F [N]")
    ax.set_title(title or "Force track", fontsize=10)
    return fig


def plot_difference_maps(a: WearMaps, differences: dict[str, np.ndarray], title: str = ""):
    """B − A maps (caption :data:`WEAR_CAPTIONS`); ``differences`` from :func:`hipsim.wear.summary.difference_maps`."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(15.0, 4.8), layout="constrained")
    axes = fig.subplots(1, 3)
    r = a.setup.radius_mm
    for ax, (key, label) in zip(
        axes, (("sliding_mm", "Δs [mm]"), ("work_N_per_mm", "ΔW [N/mm]"), ("cross_shear", "ΔCS")), strict=True
    ):
        _map(fig, ax, a, differences[key], r, label, "RdBu_r", symmetric=True)
    fig.suptitle(title or "B − A", fontsize=11)
    return fig
