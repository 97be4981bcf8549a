"""What ``hipsim workspace`` reports (``workspace.json``, ``--summary-format json``): the map's grid and reach, the
trajectory's margin from singularities, the platform-offset sweep, as typed records.

No verdict: the command judges nothing (a trajectory that crosses a singularity is reported by its counts).
"""

from __future__ import annotations

from dataclasses import dataclass

from ..records import Record
from .workspace import OffsetRow, OffsetSweep, SingularityMap, TrajectoryMargin

__all__ = ["Grid", "MarginSummary", "WorkspaceSummary", "margin_summary", "workspace_summary"]


@dataclass(frozen=True)
class Grid(Record):
    """The map's grid: α and β as [first, last, count] in [deg], the γ of each panel in [deg]."""

    alpha_deg: tuple[float, float, int]
    beta_deg: tuple[float, float, int]
    gamma_deg: tuple[float, ...]


@dataclass(frozen=True)
class MarginSummary(Record):
    """The trajectory's smallest inverse condition number, the time [s] and gait angles [deg] where it falls, and its
    samples out of reach, singular, and the singularities crossed between samples."""

    cond_inv_min: float
    t_s: float
    q_deg: tuple[float, float, float]
    out_of_reach_samples: int
    singular_samples: int
    singularity_crossings: int


def margin_summary(margin: TrajectoryMargin) -> MarginSummary:
    """The record of a :class:`~hipsim.design.workspace.TrajectoryMargin` (NaN where no sample is reachable)."""
    q = [float(x) for x in margin.q_deg]
    return MarginSummary(
        float(margin.cond_inv_min),
        float(margin.t_s),
        (q[0], q[1], q[2]),
        int(margin.out_of_reach),
        int(margin.singular),
        int(margin.crossings),
    )


@dataclass(frozen=True)
class WorkspaceSummary(Record):
    """``workspace.json``: the parameters' source, the trajectory, the built offset δ [deg], the grid, the fraction of
    each γ panel within reach (by γ as printed), the trajectory's margin, and the offset sweep per δ."""

    parameters: str
    trajectory: str
    delta_deg: float
    grid: Grid
    reachable_fraction: dict[str, float]
    trajectory_margin: MarginSummary
    offset_sweep: tuple[OffsetRow, ...]


def _axis(values) -> tuple[float, float, int]:
    return float(values[0]), float(values[-1]), int(values.size)


def workspace_summary(smap: SingularityMap, sweep: OffsetSweep) -> WorkspaceSummary:
    """The summary of a map made along a trajectory (it has its margin) and of the offset sweep along it.

    Raises:
        ValueError: a map made without a trajectory.
    """
    if smap.margin is None:
        raise ValueError("workspace_summary: the map was made without a trajectory (no margin to report)")
    fractions = smap.reachable_fraction().round(6).tolist()
    return WorkspaceSummary(
        smap.source,
        smap.margin.trajectory,
        float(smap.delta_deg),
        Grid(_axis(smap.alpha_deg), _axis(smap.beta_deg), tuple(float(g) for g in smap.gamma_deg)),
        {f"{g:g}": float(f) for g, f in zip(smap.gamma_deg, fractions, strict=True)},
        margin_summary(smap.margin),
        sweep.rows(),
    )
