"""Points of the cup: the default grid over the hemisphere with each cell's area, or a user's points, and their tangent bases.

A cup point is a unit vector w in the cup frame; the cup is the hemisphere
w_z ≥ 0. The default grid takes the midpoints of ``n_theta`` bands of polar
angle θ ∈ [0°, 90°] and ``n_phi`` sectors of azimuth φ ∈ [0°, 360°): the
midpoint rule on the sphere of radius r, each cell's area r²·sin θ·Δθ·Δφ.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..exceptions import ArgumentError

__all__ = ["CupPoints", "cup_grid", "cup_points", "tangent_basis"]

#: How far from 1 a given point's length may be (points written with six decimals are within 1e-6).
UNIT_TOLERANCE = 1e-3
#: The finest default grid taken: 1000 × 2000 cells (2·10⁶ points).
MAX_GRID = (1000, 2000)


@dataclass(frozen=True, eq=False)
class CupPoints:
    """Points of the cup.

    Attributes:
        w: unit vectors in the cup frame, (P, 3).
        area_mm2: each point's cell area in [mm²] on the head's sphere, (P,); None for points given one by one.
        shape: (n_theta, n_phi) of a grid (w in row-major order, θ first), or None.
        theta, phi: the grid's polar angles and azimuths in [rad], (n_theta,), (n_phi,), or None.
    """

    w: np.ndarray
    area_mm2: np.ndarray | None = None
    shape: tuple[int, int] | None = None
    theta: np.ndarray | None = None
    phi: np.ndarray | None = None

    def __len__(self) -> int:
        return self.w.shape[0]


def cup_grid(n_theta: int = 90, n_phi: int = 180, radius_mm: float = 14.0) -> CupPoints:
    """The default grid (module docstring).

    Args:
        n_theta: bands of polar angle over [0°, 90°].
        n_phi: sectors of azimuth over [0°, 360°).
        radius_mm: the head's radius r in [mm], for the cells' areas.
    """
    for name, value, most in (("n_theta", n_theta, MAX_GRID[0]), ("n_phi", n_phi, MAX_GRID[1])):
        if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or not 1 <= value <= most:
            raise ArgumentError(name, value, f"a whole number of cells from 1 to {most}")
    d_theta, d_phi = (math.pi / 2) / n_theta, (2 * math.pi) / n_phi
    theta = (np.arange(n_theta) + 0.5) * d_theta
    phi = (np.arange(n_phi) + 0.5) * d_phi
    th, ph = np.meshgrid(theta, phi, indexing="ij")
    w = np.stack([np.sin(th) * np.cos(ph), np.sin(th) * np.sin(ph), np.cos(th)], axis=-1).reshape(-1, 3)
    area = (radius_mm**2 * np.sin(th) * d_theta * d_phi).reshape(-1)
    return CupPoints(w, area, (int(n_theta), int(n_phi)), theta, phi)


def cup_points(xyz: np.ndarray, source: str = "points") -> CupPoints:
    """A user's points, checked: unit vectors (to :data:`UNIT_TOLERANCE`) on the cup (z ≥ 0), normalised.

    Args:
        xyz: the points, (P, 3).
        source: where they came from, for messages.

    Raises:
        ArgumentError: a point off the unit sphere or off the cup, naming its row (1-based).
    """
    xyz = np.asarray(xyz, dtype=float)
    if xyz.ndim != 2 or xyz.shape[1] != 3 or xyz.shape[0] < 1:
        raise ArgumentError(source, xyz, "points as rows of x, y, z")
    bad = np.flatnonzero(~np.all(np.isfinite(xyz), axis=1))
    if bad.size:
        raise ArgumentError(f"{source}, row {bad[0] + 1}", tuple(float(x) for x in xyz[bad[0]]), "finite x, y, z")
    length = np.linalg.norm(xyz, axis=1)
    bad = np.flatnonzero(np.abs(length - 1.0) > UNIT_TOLERANCE)
    if bad.size:
        raise ArgumentError(
            f"{source}, row {bad[0] + 1}",
            tuple(float(x) for x in xyz[bad[0]]),
            f"a point on the unit sphere (|w| = 1 within {UNIT_TOLERANCE:g}; this one has |w| = {length[bad[0]]:.6g})",
        )
    w = xyz / length[:, None]
    bad = np.flatnonzero(w[:, 2] < -UNIT_TOLERANCE)
    if bad.size:
        raise ArgumentError(
            f"{source}, row {bad[0] + 1}", tuple(float(x) for x in xyz[bad[0]]), "a point of the cup (z ≥ 0)"
        )
    return CupPoints(w)


def tangent_basis(w: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Unit tangents t1, t2 at each unit w, (P, 3) each, with t1 × t2 = w; t1 from the axis least along w."""
    axis = np.zeros_like(w)
    axis[np.arange(w.shape[0]), np.argmin(np.abs(w), axis=1)] = 1.0
    t1 = axis - np.sum(axis * w, axis=1)[:, None] * w
    t1 /= np.linalg.norm(t1, axis=1)[:, None]
    return t1, np.cross(w, t1)
