"""``hipsim check``: the analytic and Pinocchio (or MuJoCo) models along a trajectory, every output column compared."""

from __future__ import annotations

import argparse
import sys

from ..analysis.registry import check_names, engine_entry
from ..present.tables import format_table
from .common import add_machine_options, add_summary_format, load_pinocchio_kernels, parameters, print_json, progress
from .feasible import add_strict_option
from .motion_options import add_trajectory_options, load_source, load_trajectory

__all__ = ["add_parser", "run"]


def add_parser(subparsers) -> argparse.ArgumentParser:
    """Register ``check`` on the main parser's subcommands."""
    check = subparsers.add_parser(
        "check",
        help="run the analytic and Pinocchio models and compare every output column",
        description="Runs both models along the trajectory and prints, per CSV column, the largest absolute and "
        "relative difference: in spec §7.4's exact configuration (slender-rod levers), with the published lever "
        "inertia (the paper model's error: the universal joints' lever spin), and with that spin added to the "
        "analytic model. Exits with status 1 when a configuration that must agree does not.",
    )
    add_machine_options(check)
    add_trajectory_options(check)
    check.add_argument(
        "--engine",
        choices=check_names(),
        default="pinocchio",
        help="mujoco: compare MuJoCo's inverse dynamics with the analytic (lever spin) and Pinocchio models instead",
    )
    add_summary_format(check, "the differences as tables (default) or JSON")
    add_strict_option(check)
    check.set_defaults(run=run)
    return check


def run(args) -> int:
    """Compare the models; status 1 when they disagree where they must agree."""
    from ..analysis.crosscheck import compare_models
    from ..analysis.crosscheck_summary import crosscheck_summary
    from ..analysis.streaming import stream_run
    from ..records import exit_status
    from .feasible import FeasibilityWatch, limits, report_crossings

    params = parameters(args)
    whole = engine_entry(args.engine).checked_whole
    trajectory = load_trajectory(args) if whole else load_source(args)
    watch = FeasibilityWatch(limits(params))
    stream_run(params, trajectory, write=watch.add)  # the analytic model, for the machine's limits
    if report_crossings(watch.crossings(), args.strict):
        return 1
    if whole:
        from ..analysis.crosscheck import compare_mujoco

        comparisons = compare_mujoco(params, trajectory)
    else:
        load_pinocchio_kernels()
        comparisons = compare_models(params, trajectory, progress=progress("check"))
    summary = crosscheck_summary(trajectory.name, len(trajectory), params.source, comparisons)
    if args.summary_format == "json":
        print_json(summary.to_json())
    else:
        _print_comparisons(comparisons)
        print(f"trajectory: {trajectory.name} ({len(trajectory)} samples); parameters: {params.source}")
    if summary.level.failed:
        print("hipsim: error: the models disagree where they must agree", file=sys.stderr)
    return exit_status([summary])


def _print_comparisons(comparisons) -> None:
    from ..analysis.crosscheck import TOLERANCE

    for comparison in comparisons:
        header = ["column", "max |diff| [column unit]", "max |diff| / peak"]
        if comparison.required:  # a check: each row passes or fails
            rows = [
                [name, f"{a:.3e}", f"{r:.3e}", "ok" if r <= TOLERANCE else "FAILS"] for name, a, r in comparison.rows
            ]
            print(
                format_table(
                    [*header, f"≤ {TOLERANCE:g}"], rows, f"{comparison.name}: {comparison.description} (must agree)"
                )
            )
            status = "within" if comparison.ok else "OUT OF"
            print(
                f"-> {comparison.name}: largest relative difference {comparison.worst:.3e}, {status} tolerance {TOLERANCE:g}\n"
            )
        else:  # a measurement of a known modelling difference: nothing to pass or fail
            rows = [[name, f"{a:.3e}", f"{r:.3e}"] for name, a, r in comparison.rows]
            print(
                format_table(
                    header, rows, f"{comparison.name}: {comparison.description} (for information: not a check)"
                )
            )
            print(
                f"-> {comparison.name}: largest relative difference {comparison.worst:.3e} "
                "(for information: a known modelling difference, no tolerance applies)\n"
            )
