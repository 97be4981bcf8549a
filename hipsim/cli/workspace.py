"""``hipsim workspace``: the singularity map and the platform-offset sweep, as figures, JSON and a text summary."""

from __future__ import annotations

import argparse
import json
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, TextIO

from ..exceptions import HipsimError
from .common import add_machine_options, add_summary_format, numbers, parameters
from .motion_options import add_trajectory_options, load_trajectory

if TYPE_CHECKING:  # the computing modules load when the command runs, not with the parser
    from numpy.typing import ArrayLike

    from ..design.workspace import OffsetSweep, SingularityMap
    from ..machine.parameters import Parameters
    from ..motion.trajectories import Trajectory

__all__ = ["WorkspaceRun", "add_parser", "format_workspace_summary", "run", "run_workspace"]


def add_parser(subparsers) -> argparse.ArgumentParser:
    """Register ``workspace`` on the main parser's subcommands."""
    workspace = subparsers.add_parser(
        "workspace",
        help="singularity map over orientations, and the platform-offset sweep",
        description="Maps the singularity measure (inverse condition number of J) over flexion/extension x "
        "abduction/adduction at a few rotations with the trajectory drawn on it, and sweeps the platform offset δ "
        "showing the trajectory's singularity margin, peak torque and slider stroke.",
    )
    add_machine_options(workspace)
    add_trajectory_options(workspace)
    workspace.add_argument(
        "--out", default="hipsim_workspace", metavar="DIR", help="folder to write (default hipsim_workspace)"
    )
    workspace.add_argument(
        "--gamma", metavar="LIST", help="rotations γ in degrees, comma-separated (default -12,-8,-4,0,4)"
    )
    workspace.add_argument("--deltas", metavar="A:B:STEP", help="offsets δ to sweep in degrees (default -90:90:1)")
    add_summary_format(workspace)
    workspace.set_defaults(run=run)
    return workspace


@dataclass(frozen=True, eq=False)
class WorkspaceRun:
    """What :func:`run_workspace` computed and wrote.

    Attributes:
        map: the singularity map with the trajectory's margin.
        sweep: the platform offset sweep.
        files: every file written (PNG and SVG of each figure, summary JSON).
    """

    map: SingularityMap
    sweep: OffsetSweep
    files: tuple[Path, ...]


def format_workspace_summary(smap: SingularityMap, sweep: OffsetSweep | None = None) -> str:
    """A short plain-text summary: the trajectory's margin, the map's reach, the sweep table.

    The sweep table lists the built machine's δ, the best δ by singularity margin
    and by peak torque, and every 10th δ, so it stays short on a fine sweep.
    """
    import numpy as np

    lines = [
        f"singularity map: δ = {smap.delta_deg:g}°, {smap.alpha_deg.size} α × {smap.beta_deg.size} β × {smap.gamma_deg.size} γ = {smap.orientations:,} orientations"
    ]
    for g, fraction, values in zip(smap.gamma_deg, smap.reachable_fraction(), smap.cond_inv):
        finite = values[np.isfinite(values)]
        low = f"{finite.min():.3f} … {finite.max():.3f}" if finite.size else "—"
        lines.append(f"  γ = {g:+6.1f}°: {100 * fraction:5.1f} % within reach, inverse condition number {low}")
    m = smap.margin
    if m is not None:
        if m.index < 0:
            lines.append(f"trajectory {m.trajectory}: every sample out of reach")
        else:
            a, b, g = m.q_deg
            lines.append(
                f"trajectory {m.trajectory}: smallest inverse condition number {m.cond_inv_min:.4f} at t = {m.t_s:.4g} s "
                f"(α = {a:.2f}°, β = {b:.2f}°, γ = {g:.2f}°)"
            )
            if not m.clear:
                lines.append(
                    f"  WARNING: {m.out_of_reach} samples out of reach, {m.singular} singular, "
                    f"{m.crossings} singularities crossed between samples"
                )
    if sweep is not None:
        lines += ["", f"platform offset sweep ({sweep.trajectory}):", _sweep_table(sweep)]
    return "\n".join(lines)


def _sweep_table(sweep: OffsetSweep) -> str:
    import numpy as np

    d = sweep.deltas_deg
    feasible = sweep.feasible
    picks = set(range(0, d.size, max(1, d.size // 10))) | {d.size - 1}
    notes: dict[int, list[str]] = {}
    k = sweep.built_index
    if k is not None:
        picks.add(k)
        notes.setdefault(k, []).append("built")
    if np.any(np.isfinite(sweep.cond_inv_min) & feasible):
        k = int(np.nanargmax(np.where(feasible, sweep.cond_inv_min, np.nan)))
        picks.add(k)
        notes.setdefault(k, []).append("largest margin")
    if np.any(feasible):
        k = int(np.nanargmin(np.where(feasible, sweep.tau_peak_Nmm, np.nan)))
        picks.add(k)
        notes.setdefault(k, []).append("lowest peak torque")
    header = f"  {'δ [deg]':>8}  {'min cond_inv':>12}  {'peak torque [N·mm]':>18}  {'max stroke [mm]':>15}  note"
    lines = [header, "  " + "-" * (len(header) - 2)]
    for k in sorted(picks):
        if feasible[k]:
            values = f"{sweep.cond_inv_min[k]:>12.4f}  {sweep.tau_peak_Nmm[k]:>18.1f}  {sweep.stroke_max_mm[k]:>15.1f}"
        else:
            if sweep.out_of_reach[k]:
                reason = f"out of reach at {sweep.out_of_reach[k]} samples"
            elif sweep.singular[k]:
                reason = f"singular at {sweep.singular[k]} samples"
            else:
                reason = f"passes through a singularity {sweep.crossings[k]}×"
            values = f"{sweep.cond_inv_min[k]:>12.2g}  {'—':>18}  {'—':>15}"
            notes.setdefault(k, []).append(reason)
        lines.append(f"  {d[k]:>8.1f}  {values}  {', '.join(notes.get(k, []))}".rstrip())
    return "\n".join(lines)


def run_workspace(
    params: Parameters,
    trajectory: Trajectory | None,
    out_dir: str | Path,
    alpha_deg: ArrayLike | None = None,
    beta_deg: ArrayLike | None = None,
    gamma_deg: ArrayLike | None = None,
    deltas_deg: ArrayLike | None = None,
    progress: bool | None = None,
    stream: TextIO | None = None,
    summary_format: str = "table",
) -> WorkspaceRun:
    """Compute the singularity map and the offset sweep, write their figures, print a summary.

    Writes ``singularity_map.png/.svg``, ``offset_sweep.png/.svg`` and
    ``workspace.json`` (the trajectory's margin and the sweep table) to
    ``out_dir`` (created if missing), each file atomically.

    Args:
        params: the machine.
        trajectory: the motion drawn on the map and swept over δ (angles in
            [rad], load in [N]); None for one ISO 14242-1 cycle at 1 kHz.
        out_dir: folder to write into.
        alpha_deg: flexion/extension grid in [deg]; default :data:`DEFAULT_ALPHA_DEG`.
        beta_deg: abduction/adduction grid in [deg]; default :data:`DEFAULT_BETA_DEG`.
        gamma_deg: internal/external rotations in [deg], one panel each; default :data:`DEFAULT_GAMMA_DEG`.
        deltas_deg: platform offsets δ in [deg]; default :data:`DEFAULT_DELTAS_DEG`.
        progress: progress bars on stderr; None for automatic (large grids only).
        stream: where to print the summary; None for standard output (pass
            ``io.StringIO()`` to capture it).
        summary_format: "table", or "json" to print ``workspace.json``'s document (with the files written) instead.

    Returns:
        The :class:`WorkspaceRun`.
    """
    from ..design.workspace import offset_sweep, singularity_map
    from ..design.workspace_summary import workspace_summary
    from ..files import check_folder, output_folder, write_atomic
    from ..motion.trajectories import iso14242
    from ..present.figures import save_figure
    from ..present.workspace_figures import plot_offset_sweep, plot_singularity_map

    out = Path(out_dir)
    check_folder(out)  # fail now, not after the computing; but make it only when there is something to write
    trajectory = trajectory if trajectory is not None else iso14242()
    smap = singularity_map(params, alpha_deg, beta_deg, gamma_deg, trajectory=trajectory, progress=progress)
    sweep = offset_sweep(params, deltas_deg, trajectory, progress=progress)
    summary = workspace_summary(smap, sweep)  # a map made along a trajectory has its margin
    document = summary.to_json()
    with output_folder(out):  # a failure from here on takes back the folder if this run made it and it is empty
        files = [
            *save_figure(plot_singularity_map(smap), out, "singularity_map"),
            *save_figure(plot_offset_sweep(sweep), out, "offset_sweep"),
        ]
        files.append(write_atomic(out / "workspace.json", json.dumps(document, indent=2) + "\n"))
    stream = stream if stream is not None else sys.stdout
    if summary_format == "json":
        from .documents_more import WorkspaceDocument

        print(json.dumps(WorkspaceDocument(summary, tuple(str(p) for p in files)).to_json(), indent=2), file=stream)
    else:
        print(format_workspace_summary(smap, sweep), file=stream)
        print(f"\nwrote {', '.join(p.name for p in files)} to {out}", file=stream)
    return WorkspaceRun(smap, sweep, tuple(files))


def run(args) -> int:
    """Check the angle options, then map, sweep, write and print (:func:`run_workspace`)."""
    import numpy as np

    params = parameters(args)
    trajectory = load_trajectory(args)
    gamma = (
        np.array(numbers(args.gamma, ",", "--gamma", "comma-separated angles in degrees"))
        if args.gamma is not None
        else None
    )
    if gamma is not None and np.any(np.abs(gamma) > 180):
        raise HipsimError(f"--gamma: angles must lie within ±180°, got '{args.gamma}'")
    deltas = None
    if args.deltas is not None:
        start, stop, step = numbers(args.deltas, ":", "--deltas", "START:STOP:STEP in degrees", count=3)
        if step <= 0 or stop < start:
            raise HipsimError(f"--deltas: expected START <= STOP and STEP > 0, got '{args.deltas}'")
        if max(abs(start), abs(stop)) > 180:
            raise HipsimError(f"--deltas: offsets must lie within ±180°, got '{args.deltas}'")
        if (stop - start) / step > 100_000:
            raise HipsimError(f"--deltas: {args.deltas} asks for more than 100,000 offsets")
        deltas = np.arange(start, stop + step / 2, step)
    run_workspace(
        params, trajectory, Path(args.out), gamma_deg=gamma, deltas_deg=deltas, summary_format=args.summary_format
    )
    return 0
