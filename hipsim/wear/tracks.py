"""Paths on the cup over one cycle, for figures: the slide tracks of marker points of the head, and the force track.

A head point h (fixed in the head frame) is at R_relᵀ·h in the cup frame; a
marker is the head point over the cup point w₀ at the cycle's start
(h = R_rel(0)·w₀), and its slide track is the curve it draws on the cup, as
Calonius & Saikko draw them. The force track is the path of the contact centre n.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..motion.sources import SampledSource, TrajectorySource
from ..motion.trajectories import Trajectory
from .kinematics import CupSetup, relative_motion

__all__ = ["Tracks", "default_markers", "cycle_tracks"]

#: Most samples of a cycle kept for drawing.
MAX_DRAWN = 2000


@dataclass(frozen=True, eq=False)
class Tracks:
    """Paths over the first cycle, in the cup frame.

    Attributes:
        markers: the markers' cup points at the start, unit, (M, 3).
        slide: the markers' slide tracks, unit vectors, (M, K, 3).
        force: the contact centre n, (K, 3).
        load: the load in [N] along it, (K,).
    """

    markers: np.ndarray
    slide: np.ndarray
    force: np.ndarray
    load: np.ndarray


def default_markers(rings_deg=(0.0, 15.0, 30.0, 45.0), per_ring: int = 8) -> np.ndarray:
    """Markers on rings of polar angle [deg] about the cup's pole, ``per_ring`` on each (one at the pole), (M, 3)."""
    rows = []
    for ring in rings_deg:
        th = math.radians(ring)
        count = 1 if ring == 0 else per_ring
        for j in range(count):
            ph = 2 * math.pi * j / count
            rows.append([math.sin(th) * math.cos(ph), math.sin(th) * math.sin(ph), math.cos(th)])
    return np.array(rows)


def cycle_tracks(
    motion: Trajectory | TrajectorySource, cycle_time_s: float, setup: CupSetup, markers: np.ndarray | None = None
) -> Tracks:
    """The slide tracks of ``markers`` (default :func:`default_markers`) and the force track over the motion's first cycle."""
    source = SampledSource(motion) if isinstance(motion, Trajectory) else motion
    n = len(source)
    t0 = source.time(0)
    stop = n
    for k in range(1, n):  # the first cycle's samples (a log may hold many)
        if source.time(k) - t0 >= cycle_time_s:
            stop = k + 1
            break
    part = source.piece(0, stop)
    stride = max(1, -(-len(part) // MAX_DRAWN))
    part = part.slice(slice(0, None, stride))
    motion_ = relative_motion(part, setup)
    markers = default_markers() if markers is None else np.asarray(markers, dtype=float)
    heads = markers @ motion_.rotation[0].T  # h = R_rel(0)·w₀, row by row
    slide = np.einsum("kji,mj->mki", motion_.rotation, heads)  # R_relᵀ·h
    return Tracks(markers, slide, motion_.n, part.Fe)
