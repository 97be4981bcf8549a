"""``hipsim simulate``: closed-loop tracking of a trajectory by the workspace PD and the augmented PD on a plant."""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

from ..analysis.registry import make_plant, plant_entry, plant_names
from ..exceptions import ArgumentError, HipsimError
from ..present.tables import format_table
from .common import (
    add_machine_options,
    add_summary_format,
    desired_motion,
    load_pinocchio_kernels,
    note,
    parameters,
    print_json,
)
from .feasible import add_strict_option
from .learn import add_learning_options
from .mjcf import add_simulate_options, format_gaps
from .motion_options import add_trajectory_options, load_trajectory
from .simulate_machine import (
    add_machine_loop_options,
    check_options,
    format_tracking,
    machine_loop_asked,
    run_machine_loop,
    station_verdicts,
)

__all__ = ["add_parser", "format_iso", "format_simulations", "run"]

#: Most cycles ``--learn`` runs.
MAX_LEARN_CYCLES = 100


def add_parser(subparsers) -> argparse.ArgumentParser:
    """Register ``simulate`` on the main parser's subcommands."""
    sim = subparsers.add_parser(
        "simulate",
        help="closed-loop trajectory tracking: workspace PD and augmented PD on a plant",
        description="Simulates the servo loop: the controller runs at the servo rate on the measured platform state, "
        "its torques are held over each period and drive the plant's forward dynamics (RK4). Prints the tracking errors "
        "of the three angles and the motor torques; writes desired and actual angles, errors and torques to CSV. "
        "The servo-loop kernels are compiled with numba on the first run on a machine and cached: about 5 s for the "
        "controller law, 10 s more for the reduced plant.",
    )
    add_machine_options(sim)
    add_trajectory_options(sim, rate=False)
    sim.add_argument(
        "--controller",
        choices=["pd", "augmented-pd", "both"],
        default="both",
        help="controller (default both, one after the other)",
    )
    sim.add_argument(
        "--plant",
        choices=plant_names(),
        default="pinocchio",
        help="pinocchio = closed-chain model (default), analytic = reduced 3-DOF model, compiled (about 4x faster); "
        "they agree to 1e-11 deg. mujoco = MuJoCo's forward dynamics of the MJCF (soft closures; needs the mujoco extra)",
    )
    add_simulate_options(sim)
    sim.add_argument(
        "--mismatch", metavar="SPEC", help="plant off from the controller's model, e.g. friction=+20%%,masses=-10%%"
    )
    sim.add_argument("--servo-rate", type=float, metavar="HZ", help="servo rate (default control.servo_rate_Hz)")
    sim.add_argument(
        "--step", type=float, metavar="MS", help="integration step in ms (default control.integration_step_ms)"
    )
    sim.add_argument(
        "--torque-limit",
        type=float,
        metavar="NMM",
        help="motor torque limit in N·mm (default control.torque_limit_Nmm)",
    )
    sim.add_argument(
        "--learn",
        type=int,
        metavar="N",
        help=f"run N cycles (1 to {MAX_LEARN_CYCLES}) of the augmented PD, its reference (carriage positions) and "
        "inverse-dynamics torque learned from one cycle to the next (docs/guide/learning.md); the last cycle to --out, "
        "the error per cycle to OUT_learning.csv",
    )
    add_learning_options(sim)
    sim.add_argument(
        "--out",
        default="hipsim_simulation.csv",
        metavar="FILE",
        help="CSV to write (with --plant-params or --feedback also .parquet); with both controllers, _pd and "
        "_augmented-pd are added to the name",
    )
    add_machine_loop_options(sim)
    add_summary_format(sim)
    add_strict_option(sim)
    sim.add_argument(
        "--iso-tolerance",
        dest="tolerance",
        metavar="SPEC",
        help="ISO 14242-1 tolerances for the verdict on the tracked motion, e.g. alpha=3,beta=3,gamma=3,load=3%%,frequency=0.1 "
        "(default: those values, assumed: confirm them against the standard; see hipsim iso-check)",
    )
    sim.set_defaults(run=run)
    return sim


def format_simulations(summaries) -> str:
    """Tracking errors and torques of closed-loop runs (:class:`hipsim.control.simulation_summary.SimulationSummary`)
    as plain-text tables."""
    rows = []
    for s in summaries:
        e = s.errors_deg
        rows.append(
            [
                s.controller,
                s.plant,
                *(getattr(e[n], k) for n in ("alpha", "beta", "gamma") for k in ("peak", "rms")),
                str(s.saturated_samples),
            ]
        )
    header = ["controller", "plant", "α peak", "α RMS", "β peak", "β RMS", "γ peak", "γ RMS", "saturated"]
    cells = [[c if isinstance(c, str) else f"{c:.3g}" for c in row] for row in rows]
    out = [
        format_table(header, cells, "Tracking errors [deg] (flexion/extension α, abduction/adduction β, rotation γ)"),
        "",
    ]
    rows = []
    for s in summaries:
        for i in ("1", "2", "3"):
            rows.append([s.controller, f"M{i}", s.torques_Nmm[i].peak, s.torques_Nmm[i].rms, s.speed_peak_rpm[i]])
    out.append(
        format_table(
            ["controller", "motor", "peak [N·mm]", "RMS [N·mm]", "peak speed [rpm]"], rows, "Motor torques and speeds"
        )
    )
    return "\n".join(out)


def format_iso(summary) -> list[str]:
    """The ISO 14242-1 verdict on a run's tracked motion, and in a line of its own a desired motion that is not ISO."""
    iso = summary.iso
    if iso is None:
        return []
    if iso.reason:
        return [f"ISO 14242-1 check of {summary.controller}'s tracked motion: not made ({iso.reason})"]
    lines = [
        f"ISO 14242-1 check of {summary.controller}'s tracked motion ({iso.cycles} cycle(s)): {iso.verdict.value}: "
        f"{iso.judged} (tolerances assumed, see hipsim iso-check)"
    ]
    if iso.desired_line:
        lines.append(f"{summary.controller}: {iso.desired_line}")
    return lines


def run(args) -> int:
    """Simulate the controllers asked for, write their CSV and print their tracking errors."""
    from ..control.controllers import AugmentedPD, WorkspacePD
    from ..control.simulation import apply_mismatch, parse_mismatch, simulate
    from ..control.simulation_summary import simulation_summary
    from ..files import is_stdout
    from ..records import exit_status
    from .documents import SimulateRun

    if args.rate is not None:
        raise HipsimError("--rate does not apply to simulate: the run is sampled at the servo rate (--servo-rate)")
    # The shortcuts are parameter overrides, so they get the parameter file's checks.
    for option, key in (
        ("servo_rate", "servo_rate_Hz"),
        ("step", "integration_step_ms"),
        ("torque_limit", "torque_limit_Nmm"),
    ):
        if getattr(args, option) is not None:
            args.overrides.append(f"control.{key}={getattr(args, option)!r}")
    params = parameters(args)
    apart = _plant_and_model_apart(args, params)
    if args.fig7 and not apart:
        raise HipsimError("--fig7 draws both platforms of a run with --plant-params or --feedback; give one of them")
    if apart:
        check_options(args)  # each option in its range before any work
    if Path(args.out).is_dir():  # before the run, not after it
        raise HipsimError(f"--out {args.out} is a folder; give a CSV file name")
    if is_stdout(args.out) and args.controller == "both":
        raise HipsimError(
            f"--out {args.out} takes one CSV: choose one controller (--controller pd or --controller augmented-pd)"
        )
    if args.learn is not None:
        if not 1 <= args.learn <= MAX_LEARN_CYCLES:
            raise HipsimError(f"--learn: expected a number of cycles in [1, {MAX_LEARN_CYCLES}], got {args.learn}")
        if args.controller == "pd":
            raise HipsimError(
                "--learn runs the augmented PD (its feed-forward is what is learned): leave out --controller pd"
            )
        if is_stdout(args.out):
            raise HipsimError(f"--out {args.out}: --learn writes two CSV files; give a file name")
    report = sys.stderr if is_stdout(args.out) else sys.stdout  # the CSV has standard output
    trajectory = load_trajectory(args) if args.trajectory else None
    desired_at, duration = desired_motion(args, trajectory)
    from .feasible import report_crossings
    from .iso_check import parse_tolerance_option

    tolerances = parse_tolerance_option(args.tolerance)
    if report_crossings(_feasibility(params, args, trajectory), args.strict):
        return 1
    try:
        mismatch = parse_mismatch(args.mismatch) if args.mismatch else {}
    except ArgumentError as error:  # the library names its argument; the user typed an option
        raise HipsimError(f"--mismatch: expected {error.expected}, got {error.value!r}") from None
    if apart and args.learn is not None:
        from .simulate_learn import run_learning

        return run_learning(args, params, None, trajectory, mismatch, report)
    if apart:
        runs, written = run_machine_loop(args, params, desired_at, duration, mismatch)
        periodic = _repeats(args, trajectory)
        machine = tuple(run.summary(tolerances, periodic, iso=True) for run in runs)
        status = exit_status(iso for m in machine for iso in m.stations or ())
        if args.summary_format == "json":
            from .documents_more import SimulatePlantRun

            document = SimulatePlantRun(
                params.source, args.plant_params or params.source, machine, mismatch, tuple(written)
            )
            print_json(document.to_json(), report)
            return status
        for name in written:
            print(f"wrote {name}", file=report)
        print(format_tracking(machine), file=report)
        for line in station_verdicts(machine):
            print(line, file=report)
        return status
    if plant_entry(args.plant).warm_up:
        load_pinocchio_kernels()  # its initial state is closed before the first servo period
    if args.integrator is not None and args.plant != "mujoco":
        raise HipsimError(f"--integrator {args.integrator} applies to --plant mujoco, not to --plant {args.plant}")
    integrator = args.integrator or "RK4"
    plant = make_plant(args.plant, apply_mismatch(params, **mismatch), integrator=integrator)
    if args.learn is not None:
        from .simulate_learn import run_learning

        return run_learning(args, params, plant, trajectory, mismatch, report)
    chosen = ["pd", "augmented-pd"] if args.controller == "both" else [args.controller]
    simulations, gaps = [], []
    for name in chosen:
        if name == "pd":
            controller = WorkspacePD(params)
        else:
            controller = AugmentedPD(params, desired_at, params.control.servo_rate, duration)
        simulations.append(
            simulate(plant, controller, desired_at, duration, progress=True, controller_name=name, notify=note)
        )
        if hasattr(plant, "gap_history"):  # a plant with soft closures (MuJoCo's) says how far they opened
            gaps.append(format_gaps(name, plant))
    out = Path(args.out)
    json_out = args.summary_format == "json"
    written = []
    for sim in simulations:
        if not math.isclose(sim.step, params.control.integration_step, rel_tol=1e-9) and not json_out:
            print(
                f"{sim.controller}: RK4 step {sim.step * 1e3:g} ms, the {params.control.integration_step * 1e3:g} ms asked "
                f"for rounded down so that whole steps fill the {1e3 / params.control.servo_rate:g} ms servo period",
                file=report,
            )
        path = args.out if len(simulations) == 1 else out.with_name(f"{out.stem}_{sim.controller}{out.suffix}")
        written.append(str(sim.write_csv(path)))
        if not json_out:
            print(f"wrote {written[-1]}", file=report)
    periodic = _repeats(args, trajectory)
    summaries = tuple(simulation_summary(sim, tolerances, periodic, iso=True) for sim in simulations)
    if json_out:
        print_json(SimulateRun(summaries, mismatch, tuple(written)).to_json(), report)
        return exit_status(s.iso for s in summaries)
    if mismatch:
        print(
            "plant off from the controller's model: " + ", ".join(f"{k} {v:+.0%}" for k, v in mismatch.items()),
            file=report,
        )
    print(format_simulations(summaries), file=report)
    for line in gaps:
        print(line, file=report)
    for summary in summaries:
        for line in format_iso(summary):
            print(line, file=report)
    return exit_status(s.iso for s in summaries)


def _plant_and_model_apart(args, params) -> bool:
    """Run the plant and the model apart: an option of that run given, unless it only names the model's own machine.

    ``--plant-params`` naming the very machine of ``--params`` (equal values) with no feedback option is today's run,
    bit for bit: the controller then sees the platform it drives, as it always did. A per-chain ``--params`` (a
    calibrated file) runs apart too, the plant that very machine: its platforms do not turn alike, so the loop must
    say which one it closes on and how it sees it.
    """
    if params.per_chain:
        return True
    if not machine_loop_asked(args):
        return False
    others = [name for name in ("feedback", "encoder_step", "sensor_noise", "sensor_drift", "sensor_seed", "control")]
    if args.plant_params is not None and not any(getattr(args, name) is not None for name in others):
        from ..fingerprint import fingerprint
        from ..machine.parameters import load_parameters

        return fingerprint(load_parameters(args.plant_params)) != fingerprint(params)
    return True


def _feasibility(params, args, trajectory) -> list:
    """The machine limits the desired motion crosses (the analytic model along it)."""
    from ..analysis.runs import analyse
    from ..motion.trajectories import iso14242
    from .feasible import check_run
    from .motion_options import builtin_frequency

    if trajectory is None:
        trajectory = iso14242(
            rate=1000.0, cycles=1 if args.cycles is None else args.cycles, frequency=builtin_frequency(args)
        )
    return check_run(analyse(params, trajectory, on_error="flag"), params)


def _repeats(args, trajectory) -> bool:
    """The desired motion covers whole periods and repeats: the tracked run is checked as one period of an endless run."""
    if trajectory is not None:
        return trajectory.periodic
    cycles = 1 if args.cycles is None else args.cycles
    return abs(cycles - round(cycles)) < 1e-12
