"""``hipsim simulate --learn N``: N cycles on a plant, the augmented PD's feed-forward learned from cycle to cycle."""

from __future__ import annotations

from pathlib import Path

from ..exceptions import HipsimError
from .common import note, print_json

__all__ = ["run_learning"]


def _one_period(args, trajectory):
    """The desired motion, one period at the servo rate."""
    from ..motion.trajectories import iso14242
    from .motion_options import builtin_frequency

    if trajectory is None:
        if args.cycles not in (None, 1, 1.0):
            raise HipsimError(f"--cycles {args.cycles:g}: --learn runs one period per cycle; leave --cycles out")
        return iso14242(rate=1000.0, frequency=builtin_frequency(args))
    if not trajectory.periodic:
        raise HipsimError(
            f"--trajectory {args.trajectory}: --learn repeats one period; the file is not one whole period"
        )
    return trajectory


def _change_mm(summary) -> float:
    """The largest RMS change of a carriage's command the step made, in [mm] (a step from a cycle always has one)."""
    assert summary.update is not None
    return max(summary.update.change_rms_mm)


def _apart(args, machine) -> str:
    """The table title's words for the machine as built: what the plant is and what closes the loop."""
    if machine is None:
        return ""
    return f" ({args.plant_params or 'the --params machine'} under the model, {args.feedback or 'encoders'} feedback)"


def run_learning(args, params, plant, trajectory, mismatch, report) -> int:
    """Run the cycles, write the last one and the error per cycle, print the table; exit status 0."""
    import numpy as np

    from ..files import check_output, write_columns
    from ..learning.servo import servo_runner
    from ..learning.step import learn_cycles
    from ..present.tables import format_table
    from .learn import learning_law

    desired = _one_period(args, trajectory)
    rate = params.control.servo_rate
    n = len(desired)
    period = float(desired.t[-1] - desired.t[0]) * n / (n - 1)
    if abs(period * rate - round(period * rate)) > 1e-6 or abs(n / period - rate) > 1e-6 * rate:
        raise HipsimError(
            f"--learn: the desired motion must be sampled at the servo rate ({rate:g} Hz) over a whole number of servo "
            f"periods; it has {n} samples over {period:g} s"
        )
    runs: list = []
    machine = None
    if plant is None:  # the machine as built: plant and model apart (per-chain plant, encoders or a sensor)
        from ..learning.servo import machine_runner
        from ..motion.trajectories import interpolator
        from .simulate_machine import machine_setup, sensor_noise

        plant, control, feedback = machine_setup(args, params, interpolator(desired), period, mismatch)
        args.control = str(control)  # the platform the loop closes on is the one learned
        machine = machine_runner(
            plant,
            params,
            control,
            lambda k: feedback(k - 1),  # a sensor's noise drawn anew each cycle
            desired.Fe,
            period,
            rate,
            sensor_noise(args),
            (args.sensor_seed or 0) + 1,
            runs,
        )
    else:
        args.control = getattr(args, "control", None)
    args.weights = getattr(args, "weights", None)
    law = learning_law(args, params, n / period)
    out = Path(args.out)
    table = out.with_name(f"{out.stem}_learning.csv")
    check_output(out)
    check_output(table)
    runner = machine if machine is not None else servo_runner(plant, params, desired.Fe, period, rate, runs)
    steps, _ = learn_cycles(
        runner, params, desired, law, args.learn, notify=note if args.summary_format != "json" else None
    )
    summaries = [step.summary for step in steps]
    columns: dict[str, np.ndarray] = {"cycle": np.array([s.cycle for s in summaries], dtype=float)}
    for name_j in (1, 2):
        for k, angle in enumerate(("alpha", "beta", "gamma")):
            columns[f"rms_{angle}_{name_j}_deg"] = np.array(
                [next(e.rms_deg[k] for e in s.errors if e.platform == name_j) for s in summaries]
            )
            columns[f"peak_{angle}_{name_j}_deg"] = np.array(
                [next(e.peak_deg[k] for e in s.errors if e.platform == name_j) for s in summaries]
            )
    columns["convergence_data"] = np.array(
        [np.nan if s.convergence.data is None else s.convergence.data for s in summaries]
    )
    columns["change_rms_mm"] = np.array([_change_mm(s) for s in summaries])
    if machine is not None:  # the true desired motion in the file, not the last cycle's learned reference
        import dataclasses

        from .simulate_machine import _write_fig7

        last = runs[-1]
        last = dataclasses.replace(last, desired=dataclasses.replace(desired, t=last.t))
        last.write(out)
        figures = [str(p) for p in _write_fig7(last, out)] if args.fig7 else []
    else:
        figures = []
        runs[-1].write_csv(out)
    write_columns(table, columns)
    if args.summary_format == "json":
        print_json(
            {
                "learning": [s.to_json() for s in summaries],
                "mismatch": mismatch,
                "csv": [str(out), str(table)],
                **({"figures": figures} if figures else {}),
                **({} if machine is None else {"model": params.source, "plant": args.plant_params or params.source}),
            },
            report,
        )
        return 0
    rows = [
        [
            str(s.cycle),
            f"m_{e.platform}" + (" (learned)" if e.controlled and machine is not None else ""),
            *(f"{e.rms_deg[k]:.4g}" for k in range(3)),
            *(f"{abs(e.peak_deg[k]):.4g}" for k in range(3)),
            f"{_change_mm(s):.3g}",
            "—" if s.convergence.data is None else f"{s.convergence.data:.3g}",
        ]
        for s in summaries
        for e in s.errors
        if e.controlled or machine is not None  # the machine as built: the following platform's error too
    ]
    header = [
        "cycle",
        "platform",
        "α RMS",
        "β RMS",
        "γ RMS",
        "α peak",
        "β peak",
        "γ peak",
        "update RMS [mm]",
        "‖Q(I−LP)‖ data",
    ]
    if mismatch:
        print(
            "plant off from the controller's model: " + ", ".join(f"{k} {v:+.0%}" for k, v in mismatch.items()),
            file=report,
        )
    print(
        format_table(
            header,
            rows,
            f"Tracking error per cycle [deg], {plant.name} plant{_apart(args, machine)}, augmented PD learning",
        ),
        file=report,
    )
    print(f"wrote {out} (the last cycle) and {table}", file=report)
    for name in figures:
        print(f"wrote {name} (Fig. 7 of the last cycle)", file=report)
    return 0
