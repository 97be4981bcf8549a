"""``hipsim torques``: slider motion and motor torques along a trajectory, streamed to CSV or Parquet, and a summary."""

from __future__ import annotations

import argparse
import math
import sys

from ..analysis.registry import engine_entry, engine_names
from ..present.tables import format_table
from .common import add_machine_options, add_summary_format, load_pinocchio_kernels, parameters, print_json, progress
from .feasible import add_strict_option
from .motion_options import add_trajectory_options, cycle_period, load_source, span

__all__ = ["add_parser", "format_summary", "run"]


def add_parser(subparsers) -> argparse.ArgumentParser:
    """Register ``torques`` on the main parser's subcommands."""
    torques = subparsers.add_parser(
        "torques",
        help="slider motion and motor torques along a trajectory -> CSV + summary",
        description="Slider positions, velocities and accelerations, motor torques split into platforms, levers, "
        "sliders, screws and friction, motor speeds and the singularity measure along a trajectory. "
        "Writes the CSV of spec §7.5 and prints a summary.",
    )
    add_machine_options(torques)
    add_trajectory_options(torques)
    torques.add_argument(
        "--engine",
        choices=engine_names(),
        default="analytic",
        help="which model computes the torques (default analytic; mujoco needs the mujoco extra)",
    )
    torques.add_argument(
        "--out",
        default="hipsim_torques.csv",
        metavar="FILE",
        help="CSV to write (default hipsim_torques.csv); a .parquet name writes Apache Parquet (the same columns, the parameter set "
        "and hipsim version in its metadata); - for CSV on standard output",
    )
    add_summary_format(torques)
    torques.add_argument(
        "--flag-bad-poses",
        action="store_true",
        help="carry on through poses out of reach or singular and mark them in a 'flagged' column instead of stopping",
    )
    add_strict_option(torques)
    torques.set_defaults(run=run)
    return torques


def format_summary(summary, cycle=None) -> str:
    """The torque run summary (:class:`hipsim.results.RunSummary`) as plain-text tables; ``cycle`` the cycle of the
    smallest singularity measure (:class:`hipsim.cli.documents.CycleOf`), None for a run of one cycle."""
    out = [
        f"model: {summary.model}   trajectory: {summary.trajectory} ({summary.samples} samples)",
        f"parameters: {summary.parameters}",
        "",
    ]
    if summary.flagged_samples:
        out += [
            f"WARNING: {summary.flagged_samples} samples out of reach or singular (flagged in the CSV, left out below)",
            "",
        ]
    rows = [
        [f"S{name}", s.L_max_mm, s.L_min_mm, s.stroke_mm, s.Ld_max_mm_s, s.Ldd_max_mm_s2]
        for name, s in summary.sliders.items()
    ]
    out.append(
        format_table(
            ["slider", "L max [mm]", "L min [mm]", "stroke [mm]", "|Ld| max [mm/s]", "|Ldd| max [mm/s²]"],
            rows,
            "Sliders",
        )
    )
    out.append("")
    header = ["motor", "platforms", "levers", "sliders", "screws", "friction", "peak", "RMS", "speed [rpm]"]
    rows = [
        [
            f"M{i}",
            *(getattr(m, f"{p}_max_Nmm") for p in ("tau_m", "tau_l", "tau_s", "tau_L", "tau_f")),
            m.tau_peak_Nmm,
            m.tau_rms_Nmm,
            m.speed_peak_rpm,
        ]
        for i, m in summary.motors.items()
    ]
    out.append(format_table(header, rows, "Motor torques [N·mm] (max |part|; peak and RMS of the total)"))
    if summary.joints is not None:
        out.append("")
        rows = [[name, j.peak_N, j.rms_N] for name, j in summary.joints.items()]
        out.append(
            format_table(
                ["joint", "peak [N]", "RMS [N]"], rows, "Joint forces (spherical joints a_ji, central joints o_j)"
            )
        )
    where = f"t = {summary.cond_inv_min_t_s:.6g} s"
    if cycle is not None:
        where += f" (cycle {cycle.cond_inv_min_cycle}, {cycle.cond_inv_min_t_in_cycle_s:.4g} s into it)"
    out += [
        "",
        f"smallest singularity measure (inverse condition number of J): {summary.cond_inv_min:.4f} at {where}",
    ]
    return "\n".join(out)


def _cycle_of(time: float, trajectory, period: float | None):
    """Which cycle (from 1) a time in [s] falls in and how far into it (:class:`hipsim.cli.documents.CycleOf`), when
    the run spans more than one cycle (a trajectory or a source); None otherwise."""
    from .documents import CycleOf

    start = float(trajectory.t[0]) if hasattr(trajectory, "t") else trajectory.time(0)
    if period is None or span(trajectory) <= period * (1 + 1e-9):
        return None
    # A hair over whole cycles: a time printed as 395.0 s is the start of cycle 396, not the end of 395.
    cycle = math.floor((time - start) / period + 1e-9)
    return CycleOf(cycle + 1, max(0.0, time - start - cycle * period))


def _file_metadata(params) -> dict[str, str]:
    """A results file's key-value metadata: the hipsim version and the parameter set as a parameter file's text."""
    from ..machine.toml_writer import parameter_toml
    from ..version import __version__

    return {
        "hipsim.version": __version__,
        "hipsim.parameters_source": str(params.source),
        "hipsim.parameters": parameter_toml(params),
    }


class _Bands:
    """Adds the 95 % band columns to each piece of the run, from the parameter file's covariance (in order of the pieces)."""

    def __init__(self, params, source, covariance):
        self.params, self.source, self.covariance, self.done, self.widest = params, source, covariance, 0, 0.0

    def __call__(self, columns):
        import numpy as np

        from ..rig.identification.uncertainty import band_columns

        n = len(columns["t_s"])
        piece = self.source.piece(self.done, self.done + n)
        self.done += n
        extra = band_columns(self.params, piece, self.covariance, columns)
        with np.errstate(invalid="ignore"):
            widths = [np.nanmax(extra[f"tau_{i}_hi95_Nmm"] - columns[f"tau_{i}_Nmm"], initial=0.0) for i in (1, 2, 3)]
        self.widest = max(self.widest, *widths)
        return dict(columns) | extra


def _bands(args, params, source):
    """The band adder when ``--params`` names a file with an identified covariance, else None."""
    from ..analysis.streaming import as_source
    from ..rig.identification.uncertainty import read_covariance

    covariance = read_covariance(getattr(args, "params", None), params)
    return None if covariance is None else _Bands(params, as_source(source), covariance)


#: The most samples of a file without load run again with the ISO load, for the friction it would add.
_NO_LOAD_SAMPLES = 20_000


def no_load_note(args, params, source) -> str | None:
    """For a file with no load: the friction parts' peaks now, and with ISO 14242-1's load over the file as one cycle.

    Runs the analytic model twice on (at most :data:`_NO_LOAD_SAMPLES` of) the file's samples; None when
    the file has a load (no :class:`hipsim.motion.build.NoLoadWarning` while reading it).
    """
    import numpy as np

    from ..analysis.runs import analyse
    from ..exceptions import HipsimError
    from ..motion.build import NoLoadWarning
    from ..motion.trajectories import Trajectory, iso14242_load

    if not any(issubclass(category, NoLoadWarning) for category, _ in getattr(args, "trajectory_warnings", ())):
        return None
    motion = source.motion.piece(0, min(len(source), _NO_LOAD_SAMPLES))
    cycle = span(source)
    if not cycle > 0:
        return None
    loaded = Trajectory(
        motion.t, motion.q, motion.qd, motion.qdd, iso14242_load((motion.t - motion.t[0]) / cycle), motion.name
    )
    try:
        bare = np.abs(analyse(params, motion).torques.friction).max(axis=0) * 1e3
        iso = np.abs(analyse(params, loaded).torques.friction).max(axis=0) * 1e3
    except HipsimError:  # a pose out of reach: the run itself names it (or flags it)
        return None
    return (
        f"{source.name}: no load, so the friction parts peak at {bare.min():.3g}–{bare.max():.3g} N·mm per motor; "
        f"with ISO 14242-1's load (300–3000 N, the file's {cycle:.4g} s as one cycle) they would peak at "
        f"{iso.min():.3g}–{iso.max():.3g} N·mm"
    )


def run(args) -> int:
    """Stream the run to ``--out`` and print its summary."""
    from ..analysis.streaming import stream_run
    from ..files import ColumnWriter, check_output, is_stdout
    from .feasible import FeasibilityWatch, limits, report_crossings

    check_output(args.out)  # an unusable output is refused before the computing
    params = parameters(args)
    source = load_source(args)
    note = no_load_note(args, params, source) if args.trajectory else None
    if note is not None:
        print(f"hipsim: warning: {note}", file=sys.stderr)
    if engine_entry(args.engine).warm_up:
        load_pinocchio_kernels()
    watch = FeasibilityWatch(limits(params))
    bands = _bands(args, params, source)

    def write(columns) -> None:
        if bands is not None:
            columns = bands(columns)
        writer.write(columns)
        watch.add(columns)

    with ColumnWriter(args.out, _file_metadata(params)) as writer:
        summary = stream_run(
            params,
            source,
            model=args.engine,
            on_error="flag" if args.flag_bad_poses else "raise",
            write=write,
            progress=progress(f"{args.engine} model"),
        )
        if args.strict and watch.crossings() and not is_stdout(args.out):
            writer.abort()  # --strict: a crossed limit is an error, and an error writes nothing
            return report_crossings(watch.crossings(), True)
        path = writer.close()
    cycle = _cycle_of(summary.cond_inv_min_t_s, source, cycle_period(args, source))
    report = sys.stderr if is_stdout(args.out) else sys.stdout  # the CSV has standard output
    kind = "Parquet" if writer.parquet else "CSV"
    if args.summary_format == "json":
        from .documents import TorquesRun

        written = {"parquet": str(path)} if writer.parquet else {"csv": str(path)}
        print_json(TorquesRun(summary, cycle, **written).to_json(), report)
    else:
        print(format_summary(summary, cycle), file=report)
        if bands is not None:
            print(
                f"\nthe model's 95 % band on the motor torques (tau_i_lo95_Nmm, tau_i_hi95_Nmm): the uncertainty of the "
                f"identified parameters in {args.params}, half-width up to {bands.widest:.3g} N·mm; not a band for measured "
                "torques, which add the sensors' noise and the model's own error (hipsim compare gives that prediction band)",
                file=report,
            )
        where = "the CSV to standard output" if is_stdout(args.out) else path
        print(
            f"\nwrote {where} ({summary.samples} rows, {len(writer.names or ())} columns{', Parquet' if kind == 'Parquet' else ''})",
            file=report,
        )
    return report_crossings(watch.crossings(), args.strict)
