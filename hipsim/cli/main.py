"""The ``hipsim`` command line.

Every subcommand reads the machine from ``--params`` (default: the published
machine) with ``--set KEY=VALUE`` overrides, and the motion from
``--trajectory`` (default: the built-in ISO 14242-1 cycle). Errors print one
line starting with ``hipsim: error:`` and exit with status 2.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
from pathlib import Path

import numpy as np

from ..exceptions import ArgumentError, HipsimError
from ..files import exit_on_terminate, is_stdout
from .motion_options import add_trajectory_options as _add_trajectory_options
from .motion_options import builtin_frequency, cycle_period, locate, span
from .motion_options import load_source as _source
from .motion_options import load_trajectory as _trajectory

__all__ = ["main"]

EXAMPLES = """\
examples:
  hipsim torques                          ISO 14242-1 on the published machine -> hipsim_torques.csv
  hipsim torques --set lever.length_mm=340 --out longer.csv
  hipsim torques --trajectory gait.csv --summary-format json
  hipsim torques --trajectory walk.mot --side left --frequency 1 --out -   OpenSim hip angles, CSV to stdout
  hipsim torques --trajectory lab.csv --columns time=Time,flexion=FE,adduction=AA,rotation=IE,load=Fz:%BW --body-weight 75
  hipsim simulate --cycles 1 --mismatch friction=+20%   tracking errors of both controllers
  hipsim params                           the parameter set in use, with units
"""


def _add_machine_options(parser: argparse.ArgumentParser) -> None:
    group = parser.add_argument_group("machine")
    group.add_argument("--params", metavar="FILE", help="parameter TOML file (default: the published machine)")
    group.add_argument(
        "--set", dest="overrides", metavar="KEY=VALUE", action="append", default=[],
        help="override one parameter in the file's units, e.g. lever.length_mm=330 (repeatable)",
    )


def _add_summary_format(parser: argparse.ArgumentParser, help: str = "summary on standard output: tables (default) or JSON") -> None:
    parser.add_argument("--summary-format", choices=["table", "json"], default="table", help=help)


def _print_json(document, stream=None) -> None:
    """A summary as indented JSON (NaN and infinities as null)."""
    from ..files import json_ready

    print(json.dumps(json_ready(document), indent=2), file=stream if stream is not None else sys.stdout)


def _parameters(args):
    from ..machine.parameters import load_parameters, parse_override

    overrides = dict(parse_override(text, source="--set") for text in args.overrides)
    return load_parameters(args.params, overrides, overrides_source="--set")


def _format_table(header: list[str], rows: list[list], title: str = "") -> str:
    cells = [header] + [[c if isinstance(c, str) else f"{c:.2f}" for c in row] for row in rows]
    widths = [max(len(row[k]) for row in cells) for k in range(len(header))]
    lines = [title] if title else []
    for n, row in enumerate(cells):
        lines.append("  ".join(c.rjust(w) if k else c.ljust(w) for k, (c, w) in enumerate(zip(row, widths))))
        if n == 0:
            lines.append("  ".join("-" * w for w in widths))
    return "\n".join(lines)


def format_summary(summary: dict) -> str:
    """The torque run summary as plain-text tables."""
    out = [
        f"model: {summary['model']}   trajectory: {summary['trajectory']} ({summary['samples']} samples)",
        f"parameters: {summary['parameters']}",
        "",
    ]
    if summary["flagged_samples"]:
        out += [f"WARNING: {summary['flagged_samples']} samples out of reach or singular (flagged in the CSV, left out below)", ""]
    rows = [[f"S{name}", s["L_max_mm"], s["L_min_mm"], s["stroke_mm"], s["Ld_max_mm_s"], s["Ldd_max_mm_s2"]] for name, s in summary["sliders"].items()]
    out.append(_format_table(["slider", "L max [mm]", "L min [mm]", "stroke [mm]", "|Ld| max [mm/s]", "|Ldd| max [mm/s²]"], rows, "Sliders"))
    out.append("")
    header = ["motor", "platforms", "levers", "sliders", "screws", "friction", "peak", "RMS", "speed [rpm]"]
    rows = [
        [f"M{i}", *(m[f"{p}_max_Nmm"] for p in ("tau_m", "tau_l", "tau_s", "tau_L", "tau_f")), m["tau_peak_Nmm"], m["tau_rms_Nmm"], m["speed_peak_rpm"]]
        for i, m in summary["motors"].items()
    ]
    out.append(_format_table(header, rows, "Motor torques [N·mm] (max |part|; peak and RMS of the total)"))
    if "joints" in summary:
        out.append("")
        rows = [[name, j["peak_N"], j["rms_N"]] for name, j in summary["joints"].items()]
        out.append(_format_table(["joint", "peak [N]", "RMS [N]"], rows, "Joint forces (spherical joints a_ji, central joints o_j)"))
    where = f"t = {summary['cond_inv_min_t_s']:.6g} s"
    if "cond_inv_min_cycle" in summary:
        where += f" (cycle {summary['cond_inv_min_cycle']}, {summary['cond_inv_min_t_in_cycle_s']:.4g} s into it)"
    out += ["", f"smallest singularity measure (inverse condition number of J): {summary['cond_inv_min']:.4f} at {where}"]
    return "\n".join(out)


def _cycle_of(time: float, trajectory, period: float | None) -> dict:
    """Which cycle (from 1) a time in [s] falls in and how far into it, when the run spans more than one cycle (a trajectory or a source)."""
    start = float(trajectory.t[0]) if hasattr(trajectory, "t") else trajectory.time(0)
    if period is None or span(trajectory) <= period * (1 + 1e-9):
        return {}
    # A hair over whole cycles: a time printed as 395.0 s is the start of cycle 396, not the end of 395.
    cycle = math.floor((time - start) / period + 1e-9)
    return {"cond_inv_min_cycle": cycle + 1, "cond_inv_min_t_in_cycle_s": max(0.0, time - start - cycle * period)}


def _progress(what: str):
    """A progress callback (done, total) drawing a tqdm bar on a terminal once a run takes over 2 s; None elsewhere."""
    if not sys.stderr.isatty():
        return None
    from tqdm import tqdm

    bars = []

    def update(done: int, total: int) -> None:
        if not bars:
            bars.append(tqdm(total=total, desc=what, unit=" samples", unit_scale=True, delay=2.0, file=sys.stderr, leave=False))
        bars[0].update(done - bars[0].n)
        if done >= total:
            bars[0].close()

    return update


def _file_metadata(params) -> dict[str, str]:
    """A results file's key-value metadata: the hipsim version and the parameter set as a parameter file's text."""
    from .. import __version__
    from ..rig.identification import parameter_toml

    return {"hipsim.version": __version__, "hipsim.parameters_source": str(params.source), "hipsim.parameters": parameter_toml(params)}


def _cmd_torques(args) -> int:
    from ..analysis.streaming import stream_run
    from ..files import ColumnWriter, check_output

    check_output(args.out)  # an unusable output is refused before the computing
    params = _parameters(args)
    source = _source(args)
    if args.model == "pinocchio":
        _load_pinocchio_kernels()
    with ColumnWriter(args.out, _file_metadata(params)) as writer:
        summary = stream_run(
            params, source, model=args.model, on_error="flag" if args.flag_bad_poses else "raise", write=writer.write,
            progress=_progress(f"{args.model} model"),
        )
        path = writer.close()
    summary |= _cycle_of(summary["cond_inv_min_t_s"], source, cycle_period(args, source))
    report = sys.stderr if is_stdout(args.out) else sys.stdout  # the CSV has standard output
    kind = "Parquet" if writer.parquet else "CSV"
    if args.summary_format == "json":
        _print_json(summary | {("parquet" if writer.parquet else "csv"): str(path)}, report)
    else:
        print(format_summary(summary), file=report)
        where = "the CSV to standard output" if is_stdout(args.out) else path
        print(f"\nwrote {where} ({summary['samples']} rows, {len(writer.names)} columns{', Parquet' if kind == 'Parquet' else ''})", file=report)
    return 0


def _cmd_params(args) -> int:
    from ..machine.parameters import SCHEMA, file_values

    params = _parameters(args)
    values = file_values(params)
    print(f"# parameters: {params.source}")
    for section, keys in SCHEMA.items():
        present = [key for key in keys if f"{section}.{key}" in values]  # an optional table may be absent
        if present:
            print(f"\n[{section}]")
        for key in present:
            spec = keys[key]
            value = values[f"{section}.{key}"]
            note = spec.meaning + (f" [{spec.unit}]" if spec.unit else "")
            shown = json.dumps(value).replace("Infinity", "inf")  # TOML spells it inf
            print(f"{key} = {shown}".ljust(60) + f"# {note}")
    return 0


def _make_plant(kind: str, params, mujoco_integrator: str = "RK4"):
    if kind == "mujoco":
        from .mjcf import make_plant

        return make_plant(params, mujoco_integrator)
    if kind == "analytic":
        from ..control.simulation import ReducedPlant

        return ReducedPlant(params)
    from ..closed_chain.plant import PinocchioPlant

    return PinocchioPlant(params)


def format_simulations(simulations) -> str:
    """Tracking errors and torques of closed-loop runs as plain-text tables."""
    rows = []
    for sim in simulations:
        s = sim.summary()
        e = s["errors_deg"]
        rows.append([s["controller"], s["plant"], *(e[n][k] for n in ("alpha", "beta", "gamma") for k in ("peak", "rms")), str(s["saturated_samples"])])
    header = ["controller", "plant", "α peak", "α RMS", "β peak", "β RMS", "γ peak", "γ RMS", "saturated"]
    cells = [[c if isinstance(c, str) else f"{c:.3g}" for c in row] for row in rows]
    out = [_format_table(header, cells, "Tracking errors [deg] (flexion/extension α, abduction/adduction β, rotation γ)"), ""]
    rows = []
    for sim in simulations:
        s = sim.summary()
        for i in ("1", "2", "3"):
            rows.append([s["controller"], f"M{i}", s["torques_Nmm"][i]["peak"], s["torques_Nmm"][i]["rms"], s["speed_peak_rpm"][i]])
    out.append(_format_table(["controller", "motor", "peak [N·mm]", "RMS [N·mm]", "peak speed [rpm]"], rows, "Motor torques and speeds"))
    return "\n".join(out)


def _note(message: str) -> None:
    """A message of the library's for the user, on standard error (standard output may carry results)."""
    print(message, file=sys.stderr, flush=True)


def _load_pinocchio_kernels() -> None:
    """Load the Pinocchio model's compiled kernels before a run, saying so when numba compiles them (a machine's first run)."""
    import threading

    from ..closed_chain.dynamics import warm_up

    note = threading.Timer(1.0, _note, args=("Pinocchio model: compiling (first run only) ...",))
    note.daemon = True
    note.start()
    try:
        warm_up()
    finally:
        note.cancel()


def _cmd_simulate(args) -> int:
    from ..control.controllers import AugmentedPD, WorkspacePD
    from ..control.simulation import apply_mismatch, parse_mismatch, simulate

    if args.rate is not None:
        raise HipsimError("--rate does not apply to simulate: the run is sampled at the servo rate (--servo-rate)")
    # The shortcuts are parameter overrides, so they get the parameter file's checks.
    for option, key in (("servo_rate", "servo_rate_Hz"), ("step", "integration_step_ms"), ("torque_limit", "torque_limit_Nmm")):
        if getattr(args, option) is not None:
            args.overrides.append(f"control.{key}={getattr(args, option)!r}")
    params = _parameters(args)
    if Path(args.out).is_dir():  # before the run, not after it
        raise HipsimError(f"--out {args.out} is a folder; give a CSV file name")
    if is_stdout(args.out) and args.controller == "both":
        raise HipsimError(f"--out {args.out} takes one CSV: choose one controller (--controller pd or --controller augmented-pd)")
    report = sys.stderr if is_stdout(args.out) else sys.stdout  # the CSV has standard output
    desired_at, duration = _desired(args, _trajectory(args) if args.trajectory else None)
    try:
        mismatch = parse_mismatch(args.mismatch) if args.mismatch else {}
    except ArgumentError as error:  # the library names its argument; the user typed an option
        raise HipsimError(f"--mismatch: expected {error.expected}, got {error.value!r}") from None
    if args.plant == "pinocchio":
        _load_pinocchio_kernels()  # its initial state is closed before the first servo period
    plant = _make_plant(args.plant, apply_mismatch(params, **mismatch), args.mujoco_integrator)
    chosen = ["pd", "augmented-pd"] if args.controller == "both" else [args.controller]
    simulations, gaps = [], []
    for name in chosen:
        if name == "pd":
            controller = WorkspacePD(params)
        else:
            controller = AugmentedPD(params, desired_at, params.control.servo_rate, duration)
        simulations.append(simulate(plant, controller, desired_at, duration, progress=True, controller_name=name, notify=_note))
        if args.plant == "mujoco":
            from .mjcf import format_gaps

            gaps.append(format_gaps(name, plant))
    out = Path(args.out)
    json_out = args.summary_format == "json"
    written = []
    for sim in simulations:
        if not math.isclose(sim.step, params.control.integration_step, rel_tol=1e-9) and not json_out:
            print(f"{sim.controller}: RK4 step {sim.step * 1e3:g} ms, the {params.control.integration_step * 1e3:g} ms asked "
                  f"for rounded down so that whole steps fill the {1e3 / params.control.servo_rate:g} ms servo period", file=report)  # fmt: skip
        path = args.out if len(simulations) == 1 else out.with_name(f"{out.stem}_{sim.controller}{out.suffix}")
        written.append(str(sim.write_csv(path)))
        if not json_out:
            print(f"wrote {written[-1]}", file=report)
    if json_out:
        _print_json({"simulations": [sim.summary() | {"step_s": sim.step} for sim in simulations], "mismatch": mismatch, "csv": written}, report)
        return 0
    if mismatch:
        print("plant off from the controller's model: " + ", ".join(f"{k} {v:+.0%}" for k, v in mismatch.items()), file=report)
    print(format_simulations(simulations), file=report)
    for line in gaps:
        print(line, file=report)
    return 0


def _simulate_both(params, desired_at, duration, mismatch=None):
    """Both controllers on the Pinocchio plant (the whole closed chain, the CLI's default), optionally off from their model: the report's tracking plots."""
    from ..control.controllers import AugmentedPD, WorkspacePD
    from ..closed_chain.plant import PinocchioPlant
    from ..control.simulation import apply_mismatch, simulate

    plant = PinocchioPlant(apply_mismatch(params, **(mismatch or {})))
    return {
        "pd": simulate(plant, WorkspacePD(params), desired_at, duration, progress=True, controller_name="pd", notify=_note),
        "augmented-pd": simulate(
            plant, AugmentedPD(params, desired_at, params.control.servo_rate, duration), desired_at, duration,
            progress=True, controller_name="augmented-pd", notify=_note,
        ),
    }


def _desired(args, trajectory):
    """The desired motion as a function of time, and the duration of the run in [s]."""
    from ..motion.trajectories import interpolator, iso14242, iso14242_at

    if args.trajectory:
        span = trajectory.t[-1] - trajectory.t[0]
        if trajectory.periodic:  # one whole period: the last sample's step closes it
            span += trajectory.t[1] - trajectory.t[0]
        return interpolator(trajectory), span
    frequency = builtin_frequency(args)
    iso = iso14242(rate=1000.0, cycles=1 if args.cycles is None else args.cycles, frequency=frequency)  # checks them as torques does
    return (lambda t: iso14242_at(t, frequency)), len(iso) / 1000.0


def _cmd_report(args) -> int:
    from ..analysis.runs import analyse
    from ..files import check_folder
    from ..control.simulation import parse_mismatch
    from ..machine.drive import drive_from_motor_table, load_drive
    from ..present.report import write_report

    params = _parameters(args)
    trajectory = _trajectory(args)
    if args.mismatch and not args.simulate:
        raise HipsimError("--mismatch applies to the simulations: give --simulate too")
    mismatch = parse_mismatch(args.mismatch) if args.mismatch else {}
    if args.motor:
        drive = load_drive(args.motor)
    elif params.motor:
        drive = drive_from_motor_table(params.motor, params.source)
    else:
        drive = None
    if drive is not None and drive.screw is not None:  # the drive's screw, when it names one, is the machine's
        screw = {"lead": drive.screw.lead, "screw_inertia": drive.screw.inertia}
        params = params.replace(**{k: v for k, v in screw.items() if v is not None})
    check_folder(Path(args.out))  # an unusable folder is refused before the computing
    run = analyse(params, trajectory)
    joint_run, notes = None, []
    if args.model == "analytic":
        notes.append("Joint reaction forces were not computed (analytic model only: it has no joint forces).")
    else:
        try:
            _load_pinocchio_kernels()
            joint_run = analyse(params, trajectory, model="pinocchio")
        except (ImportError, AttributeError) as error:
            if args.model == "pinocchio":
                raise HipsimError(f"the Pinocchio model is not available ({error})") from None
            notes.append(f"Joint reaction forces are missing: the Pinocchio model is not available ({type(error).__name__}: {error}); torques are from the analytic model.")
    simulations = None
    if args.simulate:
        desired_at, duration = _desired(args, trajectory)
        simulations = _simulate_both(params, desired_at, duration, mismatch)
        if mismatch:
            notes.append("Tracking: the simulated plant is off from the controllers' model: " + ", ".join(f"{k} {v:+.0%}" for k, v in mismatch.items()) + ".")
    cycles = 1.0 if args.trajectory or args.cycles is None else args.cycles  # a trajectory file is one test cycle
    files = write_report(Path(args.out), run, joint_run, simulations=simulations, drive=drive, notes=tuple(notes), cycles=cycles)
    passed = files.sizing.passed if files.sizing is not None else None
    if args.summary_format == "json":
        _print_json((joint_run or run).summary() | {"sizing": files.sizing.as_dict() if files.sizing is not None else None,
                                                    "rating_check": _verdict(passed), "index": str(files.index)})
    else:
        print(f"wrote {files.index}")
        if passed is not None:
            print(f"rating check of {files.sizing.drive.name}: {_verdict(passed)}" + ("" if passed else " (see the sizing table in the report)"))
    if passed is False:
        print("hipsim: the drive fails its rating check (exit status 1)", file=sys.stderr)
        return 1
    return 0


def _verdict(passed: bool | None) -> str:
    return "not checked" if passed is None else ("pass" if passed else "FAIL")


def _numbers(text: str, separator: str, option: str, expected: str, count: int | None = None) -> list[float]:
    """Finite numbers from an option's text, or a one-line error naming the option."""
    try:
        if "_" in text:  # Python's float() reads "1_0" as 10; a user would not mean that
            raise ValueError(text)
        values = [float(part) for part in text.split(separator)]
    except ValueError:
        raise HipsimError(f"{option}: expected {expected}, got '{text}'") from None
    if (count is not None and len(values) != count) or not all(np.isfinite(values)):
        raise HipsimError(f"{option}: expected {expected}, got '{text}'")
    return values


def _cmd_workspace(args) -> int:
    from .workspace import run_workspace

    params = _parameters(args)
    trajectory = _trajectory(args)
    gamma = _numbers(args.gamma, ",", "--gamma", "comma-separated angles in degrees") if args.gamma is not None else None
    if gamma is not None and np.any(np.abs(gamma) > 180):
        raise HipsimError(f"--gamma: angles must lie within ±180°, got '{args.gamma}'")
    deltas = None
    if args.deltas is not None:
        start, stop, step = _numbers(args.deltas, ":", "--deltas", "START:STOP:STEP in degrees", count=3)
        if step <= 0 or stop < start:
            raise HipsimError(f"--deltas: expected START <= STOP and STEP > 0, got '{args.deltas}'")
        if max(abs(start), abs(stop)) > 180:
            raise HipsimError(f"--deltas: offsets must lie within ±180°, got '{args.deltas}'")
        if (stop - start) / step > 100_000:
            raise HipsimError(f"--deltas: {args.deltas} asks for more than 100,000 offsets")
        deltas = np.arange(start, stop + step / 2, step)
    run_workspace(params, trajectory, Path(args.out), gamma_deg=gamma, deltas_deg=deltas, summary_format=args.summary_format)
    return 0


def _cmd_check(args) -> int:
    from ..analysis.crosscheck import TOLERANCE, compare_models

    params = _parameters(args)
    if args.engine == "mujoco":
        from ..analysis.engines import compare_mujoco

        trajectory = _trajectory(args)
        comparisons = compare_mujoco(params, trajectory)
    else:
        trajectory = _source(args)
        _load_pinocchio_kernels()
        comparisons = compare_models(params, trajectory, progress=_progress("check"))
    failed = any(c.required and not c.ok for c in comparisons)
    if args.summary_format == "json":
        _print_json({
            "trajectory": trajectory.name, "samples": len(trajectory), "parameters": params.source, "tolerance": TOLERANCE,
            "agree": not failed,
            "comparisons": [
                {"name": c.name, "description": c.description, "required": c.required, "ok": c.ok, "worst": c.worst,
                 "columns": [{"column": name, "max_abs_diff": a, "max_rel_diff": r} for name, a, r in c.rows]}
                for c in comparisons
            ],
        })
    else:
        _print_comparisons(comparisons)
        print(f"trajectory: {trajectory.name} ({len(trajectory)} samples); parameters: {params.source}")
    if failed:
        print("hipsim: error: the models disagree where they must agree", file=sys.stderr)
        return 1
    return 0


def _print_comparisons(comparisons) -> None:
    from ..analysis.crosscheck import TOLERANCE

    for comparison in comparisons:
        header = ["column", "max |diff| [column unit]", "max |diff| / peak"]
        if comparison.required:  # a check: each row passes or fails
            rows = [[name, f"{a:.3e}", f"{r:.3e}", "ok" if r <= TOLERANCE else "FAILS"] for name, a, r in comparison.rows]
            print(_format_table([*header, f"≤ {TOLERANCE:g}"], rows, f"{comparison.name}: {comparison.description} (must agree)"))
            status = "within" if comparison.ok else "OUT OF"
            print(f"-> {comparison.name}: largest relative difference {comparison.worst:.3e}, {status} tolerance {TOLERANCE:g}\n")
        else:  # a measurement of a known modelling difference: nothing to pass or fail
            rows = [[name, f"{a:.3e}", f"{r:.3e}"] for name, a, r in comparison.rows]
            print(_format_table(header, rows, f"{comparison.name}: {comparison.description} (for information: not a check)"))
            print(f"-> {comparison.name}: largest relative difference {comparison.worst:.3e} "
                  "(for information: a known modelling difference, no tolerance applies)\n")  # fmt: skip


def _cmd_urdf(args) -> int:
    from ..machine.model_files import write_closures, write_urdf

    params = _parameters(args)
    if args.closures and not is_stdout(args.out) and Path(args.closures).resolve() == Path(args.out).resolve():
        raise HipsimError(f"--closures {args.closures} is the --out file itself: choose another name (e.g. hip_simulator.yaml)")
    messages = sys.stderr if is_stdout(args.out) or (args.closures and is_stdout(args.closures)) else sys.stdout
    path = write_urdf(params, args.out if is_stdout(args.out) else Path(args.out))
    print(f"wrote {path}", file=messages)
    if args.closures:
        print(f"wrote {write_closures(params, args.closures if is_stdout(args.closures) else Path(args.closures))}", file=messages)
    return 0


def _cmd_view(args) -> int:
    from .view import run_view

    return run_view(
        _parameters(args), _trajectory(args), html=args.html, speed=args.speed, step=args.step, forces=args.forces,
        singularity=args.singularity, human=args.human, fps=args.fps,
        stream=sys.stderr if args.html and is_stdout(args.html) else sys.stdout,
    )


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="hipsim",
        description="Kinematics, closed-chain dynamics and control of the 2(3PUS+S) parallel hip joint simulator.",
        epilog=EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    from .. import __version__

    parser.add_argument("--version", action="version", version=f"hipsim {__version__}")
    commands = parser.add_subparsers(dest="command", metavar="COMMAND")
    from . import mjcf as mjcf_command

    torques = commands.add_parser(
        "torques", help="slider motion and motor torques along a trajectory -> CSV + summary",
        description="Slider positions, velocities and accelerations, motor torques split into platforms, levers, "
        "sliders, screws and friction, motor speeds and the singularity measure along a trajectory. "
        "Writes the CSV of spec §7.5 and prints a summary.",
    )
    _add_machine_options(torques)
    _add_trajectory_options(torques)
    torques.add_argument("--model", choices=["analytic", "pinocchio", "mujoco"], default="analytic", help="which model computes the torques (default analytic; mujoco needs the mujoco extra)")
    torques.add_argument(
        "--out", default="hipsim_torques.csv", metavar="FILE",
        help="CSV to write (default hipsim_torques.csv); a .parquet name writes Apache Parquet (the same columns, the parameter set "
        "and hipsim version in its metadata); - for CSV on standard output",
    )
    _add_summary_format(torques)
    torques.add_argument(
        "--flag-bad-poses", action="store_true",
        help="carry on through poses out of reach or singular and mark them in a 'flagged' column instead of stopping",
    )
    torques.set_defaults(run=_cmd_torques)

    sim = commands.add_parser(
        "simulate", help="closed-loop trajectory tracking: workspace PD and augmented PD on a plant",
        description="Simulates the servo loop: the controller runs at the servo rate on the measured platform state, "
        "its torques are held over each period and drive the plant's forward dynamics (RK4). Prints the tracking errors "
        "of the three angles and the motor torques; writes desired and actual angles, errors and torques to CSV. "
        "The servo-loop kernels are compiled with numba on the first run on a machine and cached: about 5 s for the "
        "controller law, 10 s more for the reduced plant.",
    )
    _add_machine_options(sim)
    _add_trajectory_options(sim, rate=False)
    sim.add_argument("--controller", choices=["pd", "augmented-pd", "both"], default="both", help="controller (default both, one after the other)")
    sim.add_argument(
        "--plant", choices=["analytic", "pinocchio", "mujoco"], default="pinocchio",
        help="pinocchio = closed-chain model (default), analytic = reduced 3-DOF model, compiled (about 4x faster); "
        "they agree to 1e-11 deg. mujoco = MuJoCo's forward dynamics of the MJCF (soft closures; needs the mujoco extra)",
    )
    mjcf_command.add_simulate_options(sim)
    sim.add_argument("--mismatch", metavar="SPEC", help="plant off from the controller's model, e.g. friction=+20%%,masses=-10%%")
    sim.add_argument("--servo-rate", type=float, metavar="HZ", help="servo rate (default control.servo_rate_Hz)")
    sim.add_argument("--step", type=float, metavar="MS", help="integration step in ms (default control.integration_step_ms)")
    sim.add_argument("--torque-limit", type=float, metavar="NMM", help="motor torque limit in N·mm (default control.torque_limit_Nmm)")
    sim.add_argument("--out", default="hipsim_simulation.csv", metavar="FILE", help="CSV to write; with both controllers, _pd and _augmented-pd are added to the name")
    _add_summary_format(sim)
    sim.set_defaults(run=_cmd_simulate)

    report = commands.add_parser(
        "report", help="design report: plots, sizing table and an HTML page in a folder",
        description="Plots of slider motion, motor torque parts, load and friction, joint forces (PNG and SVG) and a "
        "self-contained index.html with the summary and the sizing table (per module peak and RMS torque, speed, power, "
        "axial screw force; per joint the peak force), checked against the [motor] ratings when given. Exits with status 1 "
        "(after writing the report) when the drive fails a rating check.",
    )
    _add_machine_options(report)
    _add_trajectory_options(report)
    report.add_argument("--out", required=True, metavar="DIR", help="folder to write (created if missing)")
    report.add_argument("--model", choices=["auto", "analytic", "pinocchio"], default="auto", help="where joint forces come from (auto: Pinocchio)")
    report.add_argument("--motor", metavar="FILE", help="drive file (TOML: [motor], [amplifier], [gearbox], [lead_screw], [rules]) to check "
                        "(default: the parameter file's [motor] table); see hipsim size")
    report.add_argument("--simulate", action="store_true", help="also simulate both controllers and plot their tracking errors")
    report.add_argument("--mismatch", metavar="SPEC", help="with --simulate: plant off from the controllers' model, e.g. friction=+20%%,masses=-10%%")
    _add_summary_format(report, "what to print: the folder written and the rating check (default), or the run's summary and sizing as JSON")
    report.set_defaults(run=_cmd_report)

    workspace = commands.add_parser(
        "workspace", help="singularity map over orientations, and the platform-offset sweep",
        description="Maps the singularity measure (inverse condition number of J) over flexion/extension x "
        "abduction/adduction at a few rotations with the trajectory drawn on it, and sweeps the platform offset δ "
        "showing the trajectory's singularity margin, peak torque and slider stroke.",
    )
    _add_machine_options(workspace)
    _add_trajectory_options(workspace)
    workspace.add_argument("--out", default="hipsim_workspace", metavar="DIR", help="folder to write (default hipsim_workspace)")
    workspace.add_argument("--gamma", metavar="LIST", help="rotations γ in degrees, comma-separated (default -12,-8,-4,0,4)")
    workspace.add_argument("--deltas", metavar="A:B:STEP", help="offsets δ to sweep in degrees (default -90:90:1)")
    _add_summary_format(workspace)
    workspace.set_defaults(run=_cmd_workspace)

    check = commands.add_parser(
        "check", help="run the analytic and Pinocchio models and compare every output column",
        description="Runs both models along the trajectory and prints, per CSV column, the largest absolute and "
        "relative difference: in spec §7.4's exact configuration (slender-rod levers), with the published lever "
        "inertia (the paper model's error: the universal joints' lever spin), and with that spin added to the "
        "analytic model. Exits with status 1 when a configuration that must agree does not.",
    )
    _add_machine_options(check)
    _add_trajectory_options(check)
    check.add_argument(
        "--engine", choices=["pinocchio", "mujoco"], default="pinocchio",
        help="mujoco: compare MuJoCo's inverse dynamics with the analytic (lever spin) and Pinocchio models instead",
    )
    _add_summary_format(check, "the differences as tables (default) or JSON")
    check.set_defaults(run=_cmd_check)

    view = commands.add_parser(
        "view", help="the machine moving through a trajectory in meshcat (live on loopback, or an offline page)",
        description="Starts a meshcat server on 127.0.0.1, prints its URL and plays the Pinocchio model's closed "
        "configurations through the trajectory in real time, looping, until Ctrl-C. With --html, writes the same "
        "animation as one self-contained offline page instead.",
    )
    _add_machine_options(view)
    _add_trajectory_options(view)
    view.add_argument("--html", metavar="FILE", help="write a self-contained offline page instead of serving")
    view.add_argument("--speed", type=float, default=1.0, metavar="X", help="playback speed (0.25: four times slower)")
    view.add_argument("--step", action="store_true", help="one frame per Enter (b: back, q: quit)")
    view.add_argument("--fps", type=int, default=30, metavar="N", help="frames per second of playback (default 30); the trajectory is sampled at fps/speed")
    view.add_argument("--forces", action="store_true", help="arrows for the motor force on each screw and the force at each spherical joint")
    view.add_argument("--singularity", action="store_true", help="colour the levers by the singularity measure (red singular, green clear)")
    view.add_argument("--human", action="store_true", help="the example-robot-data human model's hip moving beside the machine")
    view.set_defaults(run=_cmd_view)

    urdf = commands.add_parser("urdf", help="expand the xacro model with the parameter set and write the URDF")
    _add_machine_options(urdf)
    urdf.add_argument("--out", default="hip_simulator.urdf", metavar="FILE", help="URDF to write (default hip_simulator.urdf)")
    urdf.add_argument(
        "--closures", metavar="FILE",
        help="also write the closure file (loop closures, actuated joints, lead and rotor inertia of this parameter set)",
    )
    urdf.set_defaults(run=_cmd_urdf)

    mjcf_command.add_parser(commands)
    from . import size

    size.add_parser(commands)
    from . import sweep

    sweep.add_parser(commands)

    params = commands.add_parser("params", help="print the parameter set in use, with units")
    _add_machine_options(params)
    params.set_defaults(run=_cmd_params)

    from . import rig  # compare, identify, excite: the rig in the loop

    rig.add_parser(commands)
    return parser


#: Options whose values may start with "-" (negative angles), which argparse would read as options.
_SIGNED_VALUE_OPTIONS = ("--deltas", "--gamma", "--load-column")


def _join_signed_values(argv: list[str]) -> list[str]:
    """``--deltas -90:90:1`` → ``--deltas=-90:90:1``, so that argparse takes the value as a value."""
    out: list[str] = []
    for arg in argv:
        if out and out[-1] in _SIGNED_VALUE_OPTIONS and arg.startswith("-"):
            out[-1] = f"{out[-1]}={arg}"
        else:
            out.append(arg)
    return out


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(_join_signed_values(sys.argv[1:] if argv is None else list(argv)))
    if not getattr(args, "run", None):
        parser.print_help()
        return 2
    try:
        with exit_on_terminate():  # SIGTERM (timeout, kill, a scheduler) cleans up as Ctrl-C does
            return args.run(args)
    except HipsimError as error:
        print(f"hipsim: error: {locate(error, args)}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("hipsim: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:
        # The reader went away (``hipsim params | head``): not an error; silence the flush at exit.
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
