"""``hipsim sweep``: design variants (grid, Latin hypercube, tolerance study, CSV) on dask.distributed → Parquet/CSV, summary, Pareto figure."""

from __future__ import annotations

import argparse
import dataclasses
import sys
import time
from pathlib import Path
from typing import TYPE_CHECKING

from ..analysis.registry import engine_names
from ..exceptions import ArgumentError, HipsimError
from ..present.tables import format_margin, format_table
from .common import add_machine_options, add_provenance_options, page_provenance, parameters, print_json
from .motion_options import add_trajectory_options, load_trajectory

if TYPE_CHECKING:
    from ..design.sweep_summary import SweepResult
    from .documents_more import SweepRun

__all__ = ["add_parser", "run"]

#: The sweep run when no variants are given: lever length × platform offset δ.
DEFAULT_GRID = ("lever.length_mm=300:360:5", "platform.home_offset_deg=20:50:1")
#: Seconds between two writes of the results so far (an interrupted sweep resumes from the last).
CHECKPOINT_S = 60.0

_DESCRIPTION = (
    """\
Runs design variants of the machine along a trajectory (default one ISO 14242-1 cycle at 1 kHz) and writes one row per
variant: peak and RMS torque and peak speed per motor, stroke per slider, the smallest singularity measure, joint forces
(--engine pinocchio) and the rating check against the parameter file's [motor] table or --drive FILE. Variants that cannot
be built or whose motion leaves the workspace are rows too, with their status and reason. The variants are parameter keys
in the file's units (those of --set; a list's number with [i], counted from 1): a grid (--grid), a Latin hypercube
(--sample N --range), a random tolerance study (--sample N --spread) or a CSV of variants (--variants); without any,
the grid """
    + " × ".join(DEFAULT_GRID)
    + """. They run on local worker processes (dask.distributed; --workers) or on a
dask cluster (--scheduler). Output: Parquet or CSV by the suffix of --out, with a fingerprint of the set-up (machine,
trajectory, model, drive); a rerun of the same set-up with the same --out skips the variants already in it and adds the new
ones; a rerun of another set-up into it is refused (give another --out, or --restart to replace it). Exit status: 0 when at least one variant passes the rating (without ratings: when at
least one could be computed), 1 when none does, 2 on bad input."""
)

_EXAMPLES = """\
examples:
  hipsim sweep --grid lever.length_mm=300:360:5 --grid platform.home_offset_deg=20:50:1 --out levers.parquet
  hipsim sweep --sample 2000 --range lever.length_mm=300:360 --range screw.lead_mm=5:20 --pareto tau_peak_max_Nmm,-cond_inv_min
  hipsim sweep --sample 500 --spread lever.length_mm=0.05 --spread platform.home_offset_deg=±0.2 --set motor.peak_torque_Nmm=450
  hipsim sweep --variants candidates.csv --drive my_drive.toml --engine pinocchio
  hipsim sweep --scheduler tcp://10.0.0.5:8786 --sample 100000 --range lever.length_mm=300:360 --out big.parquet
"""


def add_parser(subparsers) -> argparse.ArgumentParser:
    """Register ``sweep`` on the main parser's subcommands."""
    parser = subparsers.add_parser(
        "sweep",
        help="design variants (grid, Latin hypercube, tolerances, CSV) on a dask cluster -> Parquet/CSV, Pareto figure",
        description=_DESCRIPTION,
        epilog=_EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    add_machine_options(parser)
    add_trajectory_options(parser)
    variants = parser.add_argument_group("variants (one kind; default: the grid " + " × ".join(DEFAULT_GRID) + ")")
    variants.add_argument(
        "--grid",
        action="append",
        default=[],
        metavar="KEY=START:STOP:STEP",
        help="a grid axis in the key's file unit, stop included (repeatable: every combination)",
    )
    variants.add_argument(
        "--sample",
        type=int,
        metavar="N",
        help="N random variants: a Latin hypercube over --range, or a tolerance study with --spread",
    )
    variants.add_argument(
        "--range",
        dest="ranges",
        action="append",
        default=[],
        metavar="KEY=LOW:HIGH",
        help="with --sample: a key's range for the Latin hypercube (scipy.stats.qmc; repeatable)",
    )
    variants.add_argument(
        "--spread",
        dest="tolerance",
        action="append",
        default=[],
        metavar="KEY=SIGMA|KEY=±X",
        help="with --sample: a normal spread of σ, or a uniform one within ±X (also +-X), around the machine's value (repeatable)",
    )
    variants.add_argument(
        "--seed",
        type=int,
        default=1,
        metavar="N",
        help="random seed of --sample (default 1: a rerun draws the same variants)",
    )
    variants.add_argument("--variants", metavar="CSV", help="a CSV of variants: a header of keys, one variant a line")
    check = parser.add_argument_group("model and rating")
    check.add_argument(
        "--engine",
        choices=engine_names(optional=False),
        default="analytic",
        help="analytic (default) or pinocchio (adds the peak joint forces; slower)",
    )
    check.add_argument(
        "--drive",
        metavar="FILE",
        help="drive file to check every variant against (see hipsim size); default: each variant's [motor] table",
    )
    engine = parser.add_argument_group("engine (dask.distributed; pip install 'hipsim[sweep]')")
    engine.add_argument(
        "--workers", type=int, metavar="N", help="local worker processes (default: the cores; 1 runs in this process)"
    )
    engine.add_argument(
        "--scheduler",
        metavar="ADDRESS",
        help="run on the dask cluster of this scheduler, e.g. tcp://10.0.0.5:8786 (README 'Design sweeps')",
    )
    engine.add_argument(
        "--batch-size",
        type=int,
        metavar="N",
        help="variants per task (default: about eight tasks a worker, at most 200 variants each)",
    )
    out = parser.add_argument_group("output")
    out.add_argument(
        "--out",
        default="hipsim_sweep.csv",
        metavar="FILE",
        help="results, .parquet or .csv (default hipsim_sweep.csv); an existing file of the same set-up is resumed: its variants are skipped",
    )
    out.add_argument(
        "--restart", action="store_true", help="replace an existing --out instead of resuming it (its rows are dropped)"
    )
    out.add_argument(
        "--pareto",
        metavar="X,Y",
        help="write the Pareto front of two columns as OUT_pareto.png and .svg; a leading - maximises, "
        "e.g. tau_peak_max_Nmm,-cond_inv_min",
    )
    out.add_argument("--summary-format", choices=["table", "json"], default="table", help="summary on standard output")
    add_provenance_options(parser)
    parser.set_defaults(run=run)
    return parser


def _variants(args, params):
    from ..design import variants as v

    kinds = [
        name
        for name, given in (("--grid", args.grid), ("--sample", args.sample is not None), ("--variants", args.variants))
        if given
    ]
    if len(kinds) > 1:
        raise HipsimError(f"{' and '.join(kinds)}: choose one kind of variants")
    if args.sample is None and (args.ranges or args.tolerance):
        raise HipsimError(f"{'--range' if args.ranges else '--spread'} needs --sample N (how many variants to draw)")
    if args.variants:
        return v.read_variants(args.variants)
    if args.sample is not None:
        if args.sample < 1:
            raise HipsimError(f"--sample: expected a positive number of variants, got {args.sample}")
        if args.ranges and args.tolerance:
            raise HipsimError(
                "--sample takes either --range KEY=LOW:HIGH (Latin hypercube) or --spread KEY=SIGMA (tolerance study), not both"
            )
        if not args.ranges and not args.tolerance:
            raise HipsimError(
                "--sample needs either --range KEY=LOW:HIGH (Latin hypercube) or --spread KEY=SIGMA (tolerance study): "
                "what to draw the variants over"
            )
        if args.ranges:
            ranges: dict[str | v.KeyRef, tuple[float, float]] = {}
            for text in args.ranges:
                key, (low, high) = v.parse_axis(text, "--range", 2)
                ranges[_unique(v.key_ref(key, "--range"), ranges, "--range")] = (low, high)
            return v.latin_hypercube(ranges, args.sample, args.seed)
        tolerances: dict[str | v.KeyRef, tuple[str, float]] = {}
        for text in args.tolerance:
            key, spread = v.parse_tolerance(text)
            tolerances[_unique(v.key_ref(key, "--spread"), tolerances, "--spread")] = spread
        return v.tolerance_study(params, tolerances, args.sample, args.seed)
    axes: dict[str | v.KeyRef, tuple[float, float, float]] = {}
    for text in args.grid or DEFAULT_GRID:
        key, (first, last, count) = v.parse_axis(text, "--grid", 3)
        axes[_unique(v.key_ref(key, "--grid"), axes, "--grid")] = (first, last, count)
    return v.grid(axes)


def _unique(key, seen, option):
    if key in seen:
        raise HipsimError(f"{option} {key.name} is given twice")
    return key


def _drive(args):
    from ..machine.drive import load_drive

    return load_drive(args.drive) if args.drive else None


def _check_out(path: str) -> Path:
    """The output must be a .parquet/.csv file in an existing folder: checked before any variant runs."""
    from ..design.sweep_table import SWEEP_TABLE

    return SWEEP_TABLE.check_out(path)


#: What each part of a sweep's fingerprint comes from, for the message refusing another set-up's file.
_PARTS = {
    "parameters": "the machine (--params, --set)",
    "trajectory": "the trajectory (--trajectory, --rate, --cycles, --frequency …)",
    "model": "--engine",
    "drive": "--drive",
    "cycles": "the test cycles (--cycles)",
    "keys": "the swept keys",
}


def _previous(out: Path, names: list[str], fingerprints: dict[str, str], restart: bool) -> dict[str, list]:
    """The rows already in ``out`` (empty columns when it does not exist yet, or with --restart); refused when they are another sweep's."""
    from ..design.sweep_table import SWEEP_TABLE

    return SWEEP_TABLE.resume(out, names, fingerprints, restart, _PARTS)


def run(args) -> int:
    """Run the variants, append their rows to ``--out`` and print the summary; exit status 1 when no variant passes."""
    from ..design.sweep import OBJECTIVES, SweepSetup, metric_columns, parse_objective, run_sweep, variant_id
    from ..design.sweep_summary import pareto_points, sweep_result
    from ..design.sweep_table import write_table
    from ..records import exit_status
    from .documents_more import SweepRun

    params = parameters(args)
    # Every input is read and checked before the first variant runs.
    out = _check_out(args.out)
    try:
        variants = _variants(args, params)
    except ArgumentError as error:  # the library names the key; the user typed an option
        option = (
            "--variants"
            if args.variants
            else ("--grid" if args.sample is None else ("--range" if args.ranges else "--spread"))
        )
        raise HipsimError(str(error) if error.name == option else f"{option} {error}") from None
    trajectory = load_trajectory(args)
    drive = _drive(args)
    provenance = page_provenance(
        args, trajectory=args.trajectory, load=getattr(args, "load", None), drive=args.drive, variants=args.variants
    )
    cycles = (
        args.cycles if args.cycles is not None and not args.trajectory else 1.0
    )  # test cycles the motion holds, for the ratings
    setup = SweepSetup(params, trajectory, variants.keys, model=args.engine, drive=drive, cycles=cycles)
    names = list(variants.names) + metric_columns(setup.joint_forces)
    pareto = None
    if args.pareto:
        parts = args.pareto.split(",")
        if len(parts) != 2:
            raise HipsimError(
                f"--pareto: expected two columns X,Y, e.g. tau_peak_max_Nmm,-cond_inv_min, got '{args.pareto}'"
            )
        try:
            pareto = [parse_objective(part, metric_columns(setup.joint_forces)) for part in parts]
        except ArgumentError as error:
            raise HipsimError(f"--pareto: expected {error.expected}, got {error.value!r}") from None
    if args.batch_size is not None and args.batch_size < 1:
        raise HipsimError(f"--batch-size: expected a positive number of variants, got {args.batch_size}")
    if args.workers is not None and args.workers < 1:
        raise HipsimError(f"--workers: expected a positive number of processes, got {args.workers}")
    fingerprints = setup.fingerprints()
    table = _previous(out, names, fingerprints, args.restart)
    done = {variant_id(row) for row in zip(*(table[k] for k in variants.names))}
    todo, queued = [], set()
    for index, values in enumerate(variants.values):
        key = variant_id(values)
        if key not in done and key not in queued:
            queued.add(key)
            todo.append(index)
    metadata = {
        "hipsim": _version(),
        "trajectory": trajectory.name,
        "samples": len(trajectory),
        "model": args.engine,
        "parameters": params.source,
        "drive": drive.source if drive is not None else None,
        "keys": list(variants.names),
        "fingerprints": fingerprints,
    }
    skipped = len(variants) - len(todo)
    new_rows: dict[int, dict] = {}

    def save():
        ordered = [new_rows[i] for i in sorted(new_rows)]
        columns = {name: list(table[name]) for name in names}
        for index in sorted(new_rows):
            for key, value in zip(variants.names, variants.values[index]):
                columns[key].append(float(value))
        for name in names[len(variants.names) :]:
            columns[name] += [row[name] for row in ordered]
        return write_table(out, columns, metadata), columns

    bar = _progress_bar(len(todo))
    started = last_save = time.monotonic()
    try:
        for rows in run_sweep(
            setup,
            variants,
            indices=todo,
            workers=args.workers,
            scheduler=args.scheduler,
            batch_size=args.batch_size,
            progress=lambda n, total: bar.update(n - bar.n),
        ):
            new_rows.update(rows)
            if time.monotonic() - last_save > CHECKPOINT_S:
                save()
                last_save = time.monotonic()
    except BaseException:
        if new_rows:  # Ctrl-C, SIGTERM, a lost cluster: keep what is done, so a rerun resumes
            save()
            print(
                f"hipsim: kept the {len(new_rows)} variants done in {out}; rerun the same command to resume",
                file=sys.stderr,
            )
        raise
    finally:
        bar.close()
    elapsed = time.monotonic() - started
    path, columns = save()
    result = sweep_result(columns, variants.names, OBJECTIVES, pareto or ())
    front = None
    if pareto:
        mask, points, edged = pareto_points(columns, variants.names, pareto)
        front = (points, edged)
    summary = SweepRun(
        result,
        variants=len(variants),
        new=len(todo),
        skipped=skipped,
        seconds=elapsed,
        out=str(path),
        hipsim=metadata["hipsim"],
        trajectory=trajectory.name,
        samples=len(trajectory),
        model=args.engine,
        parameters=params.source,
        drive=drive.source if drive is not None else None,
        keys=tuple(variants.names),
        fingerprints={"setup": fingerprints["setup"]},  # the whole set-up's; its parts are in the file
        provenance=provenance.as_dict(),
        pareto_front=None if front is None else front[0],
        pareto_edges=None if front is None else front[1],
    )
    if pareto:
        figure = tuple(str(p) for p in _figure(columns, pareto, mask, out, summary))
        summary = dataclasses.replace(summary, figure=figure)
    if args.summary_format == "json":
        print_json(summary.to_json())
    else:
        print(format_summary(summary))
    if summary.result.verdict.failed:
        print(
            "hipsim: no variant passes the rating" if result.rated else "hipsim: no variant could be computed",
            file=sys.stderr,
        )
    return exit_status([summary.result.verdict])


def _version() -> str:
    from ..version import __version__

    return __version__


def _progress_bar(total: int):
    from tqdm.auto import tqdm

    # On a terminal only, and only once the sweep has run a couple of seconds.
    return tqdm(total=total, disable=not sys.stderr.isatty(), unit="variant", delay=2.0, leave=False)


def _figure(columns: dict, pareto, front, out: Path, summary: SweepRun):
    import numpy as np

    from ..present.figures import save_figure
    from ..present.sweep_figures import design_label, plot_pareto

    (x_name, x_max), (y_name, y_max) = pareto
    keys = summary.keys
    values = np.column_stack([np.array(columns[x_name], dtype=float), np.array(columns[y_name], dtype=float)])
    title = f"{summary.result.rows} variants of {', '.join(keys)} along {summary.trajectory} ({summary.model} model)"
    labels = [design_label({key: float(columns[key][k]) for key in keys}) for k in range(values.shape[0])]
    fig = plot_pareto(
        values[:, 0], values[:, 1], front, (x_name, y_name), (x_max, y_max), columns["rating"], title, labels
    )
    return save_figure(fig, out.parent if str(out.parent) else Path("."), f"{out.stem}_pareto")


def _extend(edges) -> str:
    """The extended ranges of a point's edges, as --grid or --range would take them."""
    parts = []
    for e in edges:
        low, high = e.suggestion
        parts.append(f"{e.key}={low:.6g}:{high:.6g}" + (f":{e.step:.6g}" if e.step is not None else ""))
    return "sweep on, e.g. " + " ".join(parts)


def _onward_lines(result: SweepResult) -> list[str]:
    """Per objective: the best variant on an edge of the swept range (and the range to sweep next), and its nearest failing neighbour."""
    lines: dict[str, list[str]] = {}  # one message, the objectives it is about
    for name, best in result.best.items():
        for e in best.edges:
            text = (
                f"lies on the {e.side} edge of {e.key} ({e.value:.6g}, swept {e.low:.6g}…{e.high:.6g}): "
                f"the optimum may lie beyond; {_extend([e])}"
            )
            lines.setdefault(text, []).append(name)
        neighbour = best.nearest_failing
        if neighbour is not None:
            at = ", ".join(f"{key} {value:.6g}" for key, value in neighbour.variant.items())
            why = (
                f"FAIL, margin {format_margin(neighbour.margin)}"
                + (f", {neighbour.binding}" if neighbour.binding else "")
                if neighbour.status == "ok"
                else neighbour.status.replace("_", " ")
            )
            own = "" if best.margin is None else f"; its own margin {format_margin(best.margin)}"
            mine = ", ".join(f"{key} {value:.6g}" for key, value in best.variant.items())
            lines.setdefault(f"(at {mine}): nearest failing neighbour at {at} ({why}){own}", []).append(name)
    return [""] + [f"best {', '.join(names)} {text}" for text, names in lines.items()] if lines else []


def format_summary(summary: SweepRun) -> str:
    """The sweep's summary as plain text."""
    keys = summary.keys
    result = summary.result
    lines = [
        f"sweep of {summary.variants} variants over {', '.join(keys)}: {summary.new} run in {summary.seconds:.1f} s, "
        f"{summary.skipped} already in {summary.out}",
        f"trajectory: {summary.trajectory} ({summary.samples} samples); model: {summary.model}; parameters: {summary.parameters}",
        f"rows: {result.rows}: {result.ok} ok, {result.cannot_assemble} cannot assemble, {result.out_of_workspace} out of the workspace",
    ]
    if result.rated:
        lines.append(
            f"rating ({summary.drive or 'the [motor] table'}): {result.passed} pass, {result.fail} FAIL, {result.unchecked} unchecked"
        )
    else:
        lines.append(
            "rating: none checked (give --drive FILE or a [motor] table, e.g. --set motor.peak_torque_Nmm=500)"
        )
    rows = []
    for name, best in result.best.items():
        rows.append([name, best.goal, f"{best.value:.6g}", *(f"{best.variant[k]:.6g}" for k in keys), best.rating])
    lines += ["", format_table(["objective", "goal", "best", *keys, "rating"], rows, "Best variant per objective")]
    lines += _onward_lines(result)
    if summary.figure is not None and summary.pareto_front is not None and summary.pareto_edges is not None:
        lines += ["", f"Pareto front: {len(summary.pareto_front)} variants; figure {', '.join(summary.figure)}"]
        for point in summary.pareto_edges[:5]:
            where = "; ".join(f"{e.side} edge of {e.key}" for e in point.edges)
            values = ", ".join(f"{key} {point.variant[key]:.6g}" for key in keys)
            lines.append(f"  Pareto point ({values}) on the {where}: {_extend(point.edges)}")
        if len(summary.pareto_edges) > 5:
            lines.append(
                f"  and {len(summary.pareto_edges) - 5} more Pareto points on an edge (--summary-format json lists them)"
            )
    lines.append(f"\nwrote {summary.out} ({result.rows} rows)")
    lines.append(f"verdict: {result.verdict.level.value}: {result.verdict.judged}")
    return "\n".join(lines)
