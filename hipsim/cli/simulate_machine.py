"""``hipsim simulate --plant-params FILE``: the plant is one machine (as built), the controller knows another (its model).

The options of the plant, of what the controller sees and of the controlled
platform, and the run of :func:`hipsim.control.machine_loop.run_machine` for
each controller asked for. Without these options ``simulate`` is today's run
(:mod:`hipsim.cli.simulate`).
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path
from typing import cast

from ..exceptions import HipsimError

__all__ = [
    "MACHINE_OPTIONS",
    "add_machine_loop_options",
    "check_options",
    "format_tracking",
    "machine_loop_asked",
    "machine_setup",
    "run_machine_loop",
    "sensor_noise",
    "station_verdicts",
]

#: The options that make ``simulate`` run the plant and the model apart (their ``args`` names).
MACHINE_OPTIONS = ("plant_params", "feedback", "encoder_step", "sensor_noise", "sensor_drift", "sensor_seed", "control")

#: Hard ranges of the feedback options (a value outside is refused in one line).
ENCODER_STEP_MM = (0.0, 1.0)
SENSOR_NOISE_DEG = (0.0, 5.0)
SENSOR_DRIFT_DEG_PER_MIN = (-10.0, 10.0)


def add_machine_loop_options(parser: argparse.ArgumentParser) -> None:
    """``--plant-params``, ``--feedback``, ``--encoder-step``, ``--sensor-noise``, ``--sensor-drift``, ``--sensor-seed``, ``--control``."""
    group = parser.add_argument_group(
        "plant and model apart (the machine as built under a controller that knows its model)"
    )
    group.add_argument(
        "--plant-params",
        metavar="FILE",
        help="the plant's machine: per-chain [geometry], its own masses, friction and drive (e.g. a hidden true "
        "machine); --params (and --set) stay the controller's model. Default: the plant is the model, as before",
    )
    group.add_argument(
        "--feedback",
        choices=["encoders", "sensors"],
        help="what closes the loop: encoders = the controlled platform's attitude from the carriage encoders through "
        "the model's forward kinematics (default); sensors = that platform's attitude sensor",
    )
    group.add_argument(
        "--encoder-step",
        type=float,
        metavar="MM",
        help=f"the encoders' resolution in carriage travel [mm], {ENCODER_STEP_MM[0]:g} to {ENCODER_STEP_MM[1]:g} "
        "(default 0.001; 0: exact)",
    )
    group.add_argument(
        "--sensor-noise",
        type=float,
        metavar="DEG",
        help=f"with --feedback sensors: white noise on each angle, standard deviation [deg], "
        f"{SENSOR_NOISE_DEG[0]:g} to {SENSOR_NOISE_DEG[1]:g} (default 0.05)",
    )
    group.add_argument(
        "--sensor-drift",
        type=float,
        metavar="DEG_PER_MIN",
        help=f"with --feedback sensors: the sensor zero's drift [deg/min], {SENSOR_DRIFT_DEG_PER_MIN[0]:g} to "
        f"{SENSOR_DRIFT_DEG_PER_MIN[1]:g} (default 0)",
    )
    group.add_argument(
        "--sensor-seed", type=int, metavar="N", help="with --feedback sensors: the noise's seed (default 0)"
    )
    group.add_argument(
        "--fig7",
        action="store_true",
        help="also draw the paper's Fig. 7 of each run (AA, IER, FE panels; desired and both platforms' true "
        "attitudes) as OUT_fig7.png and .svg beside the table",
    )
    group.add_argument(
        "--control",
        choices=["1", "2"],
        help="the controlled platform (default: the model's [geometry] control, else the plant's, else 2: the paper's)",
    )


def machine_loop_asked(args) -> bool:
    """True when an option of the plant-and-model run is given."""
    return any(getattr(args, name) is not None for name in MACHINE_OPTIONS)


def check_options(args) -> None:
    """The sensor's options only with the sensors, the output's kind (one line each; the ranges are the option
    table's, hipsim.cli.option_table, checked as the options are read)."""
    if args.feedback != "sensors":
        for option in ("sensor_noise", "sensor_drift", "sensor_seed"):
            if getattr(args, option) is not None:
                raise HipsimError(
                    f"--{option.replace('_', '-')} describes the attitude sensor: it needs --feedback sensors "
                    f"(the loop closes on the {args.feedback or 'encoders'})"
                )
    if args.out != "-" and Path(args.out).suffix.lower() not in (".csv", ".parquet"):
        raise HipsimError(f"--out {args.out}: expected a .csv or .parquet file")
    from ..files import check_output

    check_output(args.out)  # before the run: a missing folder is said now, not after minutes


def _plant_machine(args, model):
    """The plant's parameters: the --plant-params file as written (None: the model's machine)."""
    from ..machine.parameters import load_parameters

    return model if args.plant_params is None else load_parameters(args.plant_params)


def _control(args, model, plant) -> int:
    if args.control is not None:
        return int(args.control)
    for machine in (model, plant):
        if machine.geometry is not None:
            return machine.geometry.control
    return 2


def machine_setup(args, model, desired_at, duration, mismatch: dict):
    """The plant as built (a MachinePlant), the controlled platform, and a maker of the feedback (seed offset → Feedback).

    Raises:
        HipsimError: a plant the chosen engine cannot be, a plant that is not the model's machine as built,
            or an option out of its range (one line, before anything is written).
    """
    from ..analysis.registry import make_plant, plant_entry
    from ..control.feedback import DEFAULT_ENCODER_STEP, DEFAULT_SENSOR_NOISE, EncoderFeedback, SensorFeedback
    from ..control.machine_loop import MachinePlant, check_plant, controlled_machine
    from ..control.simulation import apply_mismatch
    from .common import load_pinocchio_kernels

    check_options(args)
    plant_params = _plant_machine(args, model)
    control = _control(args, model, plant_params)
    if plant_params.geometry is not None and args.plant == "analytic":
        raise HipsimError(
            f"--plant analytic: the reduced plant has one state for both platforms, so it cannot be the per-chain "
            f"machine of {plant_params.source} ([geometry]); use --plant pinocchio or --plant mujoco"
        )
    servo_rate = model.control.servo_rate
    check_plant(model, plant_params, desired_at(_instants(duration, servo_rate)), control)
    plant_params = controlled_machine(apply_mismatch(plant_params, **mismatch), control)
    plant_params = plant_params.replace(control=model.control)  # the servo settings are the controller's
    if plant_entry(args.plant).warm_up:
        load_pinocchio_kernels()
    plant = cast(MachinePlant, make_plant(args.plant, plant_params, integrator=args.integrator or "RK4"))
    step = DEFAULT_ENCODER_STEP if args.encoder_step is None else args.encoder_step * 1e-3

    def feedback(offset: int = 0):
        if args.feedback == "sensors":
            noise = DEFAULT_SENSOR_NOISE if args.sensor_noise is None else math.radians(args.sensor_noise)
            drift = math.radians(args.sensor_drift or 0.0) / 60.0
            return SensorFeedback(control, noise, drift, (args.sensor_seed or 0) + offset, step)
        return EncoderFeedback(model, control, step)

    return plant, control, feedback


def sensor_noise(args) -> float:
    """The attitude sensor's white noise in [rad]: --sensor-noise's (default 0.05°) with --feedback sensors, else 0."""
    from ..control.feedback import DEFAULT_SENSOR_NOISE

    if args.feedback != "sensors":
        return 0.0
    return DEFAULT_SENSOR_NOISE if args.sensor_noise is None else math.radians(args.sensor_noise)


def run_machine_loop(args, model, desired_at, duration, mismatch: dict) -> tuple[list, list[str]]:
    """The runs of the controllers asked for, each written to its file; (their runs, the files written).

    Raises:
        HipsimError: as :func:`machine_setup`.
    """
    from ..control.machine_loop import ModelPD, model_feedforward, run_machine
    from .common import note

    plant, control, feedback = machine_setup(args, model, desired_at, duration, mismatch)
    servo_rate = model.control.servo_rate
    chosen = ["pd", "augmented-pd"] if args.controller == "both" else [args.controller]
    runs = []
    for name in chosen:
        feedforward = (
            model_feedforward(model, control, desired_at, servo_rate, duration) if name == "augmented-pd" else None
        )
        runs.append(
            run_machine(
                plant,
                ModelPD(model, control),
                feedback(),
                desired_at,
                duration,
                feedforward=feedforward,
                progress=True,
                notify=note,
                controller_name=name,
            )
        )
    out = Path(args.out)
    written = []
    for run in runs:
        path = args.out if len(runs) == 1 else out.with_name(f"{out.stem}_{run.controller}{out.suffix}")
        written.append(str(run.write(path)))
        if args.fig7 and args.out != "-":
            written += [str(p) for p in _write_fig7(run, Path(path))]
    return runs, written


def _write_fig7(run, table: Path):
    import numpy as np

    from ..present.fig7 import Curve, plot_fig7
    from ..present.figures import save_figure

    curves = [
        Curve("desired", np.degrees(run.desired.q), "k", ":"),
        Curve("m_1 true", np.degrees(run.attitudes[:, 0]), "tab:blue"),
        Curve("m_2 true", np.degrees(run.attitudes[:, 1]), "tab:red"),
    ]
    title = f"Fig. 7: {run.controller}, {run.feedback} close the loop on m_{run.control} ({run.plant} plant)"
    return save_figure(plot_fig7(run.t, curves, title), table.parent, f"{table.stem}_fig7")


def _instants(duration: float, servo_rate: float):
    import numpy as np

    return np.arange(int(round(duration * servo_rate))) / servo_rate


def format_tracking(summaries) -> str:
    """Per platform and angle the RMS and peak error and when, per run's summary; then the motors."""
    from ..present.tables import format_table

    rows = []
    for s in summaries:
        for e in s.errors:
            role = "controlled" if e.controlled else "following"
            rows.append(
                [
                    s.controller,
                    s.feedback,
                    f"m_{e.platform} ({role})",
                    e.angle,
                    f"{e.rms_deg:.4g}",
                    f"{e.peak_deg:+.4g}",
                    f"{e.peak_at_s:.3f}",
                ]
            )
    out = [
        format_table(
            ["controller", "feedback", "platform", "angle", "RMS [deg]", "peak [deg]", "at [s]"],
            rows,
            "Tracking errors of the true attitudes (desired - true)",
        ),
        "",
    ]
    rows = []
    for s in summaries:
        for m in s.motors:
            rows.append(
                [
                    s.controller,
                    f"M{m.motor}",
                    f"{m.torque_peak_Nmm:.4g}",
                    f"{m.torque_rms_Nmm:.4g}",
                    f"{m.speed_peak_rpm:.4g}",
                ]
            )
    out.append(
        format_table(
            ["controller", "motor", "peak [N·mm]", "RMS [N·mm]", "peak speed [rpm]"], rows, "Motor torques and speeds"
        )
    )
    return "\n".join(out)


def station_verdicts(summaries) -> list[str]:
    """One ISO 14242-1 verdict line per run and station (:meth:`hipsim.control.tracking.MachineRun.summary` with
    ``iso=True``): the motion that platform truly went through, and its load."""
    lines = []
    for s in summaries:
        for j, iso in enumerate(s.stations or (), start=1):
            role = "controlled" if j == s.control else "following"
            what = f"station {j}'s motion under {s.controller} (m_{j}, {role})"
            if iso.reason:
                lines.append(f"ISO 14242-1 check of {what}: not made ({iso.reason})")
                continue
            failing = f" ({', '.join(iso.failing)})" if iso.failing else ""
            lines.append(
                f"ISO 14242-1 check of {what} ({iso.cycles} cycle(s)): {iso.verdict.value}{failing}: {iso.judged} "
                "(tolerances assumed, see hipsim iso-check)"
            )
            if iso.desired_line:
                lines.append(f"station {j} under {s.controller}: {iso.desired_line}")
    return lines
