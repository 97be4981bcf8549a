"""``hipsim report``: the design report (plots, sizing table, an HTML page) in a folder."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from ..analysis.registry import engine_entry, engine_names
from ..exceptions import HipsimError
from ..records import Level, exit_status
from .common import (
    add_machine_options,
    add_provenance_options,
    add_summary_format,
    desired_motion,
    load_pinocchio_kernels,
    note,
    page_provenance,
    parameters,
    print_json,
)
from .feasible import add_strict_option
from .motion_options import add_trajectory_options, load_trajectory

__all__ = ["add_parser", "run"]


def add_parser(subparsers) -> argparse.ArgumentParser:
    """Register ``report`` on the main parser's subcommands."""
    report = subparsers.add_parser(
        "report",
        help="design report: plots, sizing table and an HTML page in a folder",
        description="Plots of slider motion, motor torque parts, load and friction, joint forces (PNG and SVG) and a "
        "self-contained index.html with the summary and the sizing table (per module peak and RMS torque, speed, power, "
        "axial screw force; per joint the peak force), checked against the [motor] ratings when given. Exits with status 1 "
        "(after writing the report) when the drive fails a rating check.",
    )
    add_machine_options(report)
    add_trajectory_options(report)
    report.add_argument("--out", required=True, metavar="DIR", help="folder to write (created if missing)")
    report.add_argument(
        "--engine",
        choices=["auto", *engine_names(optional=False)],
        default="auto",
        help="where joint forces come from (auto: Pinocchio)",
    )
    report.add_argument(
        "--motor",
        metavar="FILE",
        help="drive file (TOML: [motor], [amplifier], [gearbox], [lead_screw], [rules]) to check "
        "(default: the parameter file's [motor] table); see hipsim size",
    )
    report.add_argument(
        "--simulate", action="store_true", help="also simulate both controllers and plot their tracking errors"
    )
    report.add_argument(
        "--mismatch",
        metavar="SPEC",
        help="with --simulate: plant off from the controllers' model, e.g. friction=+20%%,masses=-10%%",
    )
    report.add_argument(
        "--pdf", action="store_true", help="also print the page to DIR/report.pdf (needs Chromium on PATH)"
    )
    add_provenance_options(report)
    add_summary_format(
        report,
        "what to print: the folder written and the rating check (default), or the run's summary and sizing as JSON",
    )
    add_strict_option(report)
    report.set_defaults(run=run)
    return report


def run(args) -> int:
    """Write the report; status 1 when the drive fails its rating check."""
    from ..analysis.runs import analyse
    from ..control.simulation import parse_mismatch
    from ..files import check_folder
    from ..machine.drive import drive_from_motor_table, load_drive
    from ..present.report import write_report
    from ..rig.identification.uncertainty import read_covariance

    params = parameters(args)
    covariance = read_covariance(args.params, params)  # a bad table refused before the work
    identified = params
    trajectory = load_trajectory(args)
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
    if args.pdf:
        from ..present.pages import require_pdf_renderer

        require_pdf_renderer()  # no Chromium: said before the computing
    provenance = page_provenance(args, trajectory=args.trajectory, load=getattr(args, "load", None), drive=args.motor)
    run = analyse(params, trajectory)
    from .feasible import check_run, report_crossings

    if report_crossings(check_run(run, params, drive), args.strict):
        return 1
    joint_run, notes = None, []
    # auto: the first engine whose runs carry the joint forces (Pinocchio's)
    joint_model = (
        args.engine
        if args.engine != "auto"
        else next(n for n in engine_names(optional=False) if engine_entry(n).joint_forces)
    )
    if not engine_entry(joint_model).joint_forces:
        notes.append("Joint reaction forces were not computed (analytic model only: it has no joint forces).")
    else:
        try:
            if engine_entry(joint_model).warm_up:
                load_pinocchio_kernels()
            joint_run = analyse(params, trajectory, model=joint_model)
        except (ImportError, AttributeError) as error:
            if args.engine != "auto":
                raise HipsimError(f"the Pinocchio model is not available ({error})") from None
            notes.append(
                f"Joint reaction forces are missing: the Pinocchio model is not available ({type(error).__name__}: {error}); torques are from the analytic model."
            )
    simulations = None
    if args.simulate:
        desired_at, duration = desired_motion(args, trajectory)
        simulations = _simulate_both(params, desired_at, duration, mismatch)
        if mismatch:
            notes.append(
                "Tracking: the simulated plant is off from the controllers' model: "
                + ", ".join(f"{k} {v:+.0%}" for k, v in mismatch.items())
                + "."
            )
    cycles = 1.0 if args.trajectory or args.cycles is None else args.cycles  # a trajectory file is one test cycle
    bands = _margin_bands(identified, params, covariance, run, trajectory, drive, cycles)
    if bands:
        notes.append(_bands_note(bands))
    files = write_report(
        Path(args.out),
        run,
        joint_run,
        simulations=simulations,
        drive=drive,
        notes=tuple(notes),
        cycles=cycles,
        provenance=provenance,
        pdf=args.pdf,
    )
    verdict = files.verdict  # the drive's verdict, made beside the sizing (NOT MADE without a drive)
    assert verdict is not None  # write_report always judges the drive
    pdf = files.folder / "report.pdf" if args.pdf else None
    if args.summary_format == "json":
        from ..design.sizing_summary import MarginBandSummary, sizing_summary
        from .documents import ReportRun

        document = ReportRun(
            (joint_run or run).summary(),
            sizing=sizing_summary(files.sizing) if files.sizing is not None else None,
            index=str(files.index),
            pdf=None if pdf is None else str(pdf),
            verdict=verdict,
            provenance=provenance.as_dict(),
            margin_bands=tuple(MarginBandSummary.of(b) for b in bands) if bands else None,
        )
        print_json(document.to_json())
    else:
        print(f"wrote {files.index}" + (f" and {pdf}" if pdf is not None else ""))
        if verdict.level is not Level.NOT_MADE:
            print(
                f"rating check: {verdict.level.value}: {verdict.judged}"
                + (" (see the sizing table in the report)" if verdict.failed else "")
            )
        if bands:
            print(_bands_note(bands))
    status = exit_status([verdict])
    if status:
        print("hipsim: the drive fails its rating check (exit status 1)", file=sys.stderr)
    return status


def _margin_bands(identified, params, covariance, run, trajectory, drive, cycles):
    """The sizing margins with the identified parameters' uncertainty (:func:`hipsim.design.sizing.margin_bands`); None without a covariance or a drive."""
    if covariance is None or drive is None:
        return None
    from ..analysis.runs import analyse
    from ..design.sizing import margin_bands, sizing
    from ..rig.identification.uncertainty import sigma_machines

    changes = {"lead": params.lead, "screw_inertia": params.screw_inertia} if params is not identified else {}
    variants = [v.replace(**changes) if changes else v for v in sigma_machines(identified, covariance)]
    return margin_bands(
        sizing(run, drive, None, cycles), [sizing(analyse(v, trajectory), drive, None, cycles) for v in variants]
    )


def _bands_note(bands) -> str:
    """One sentence for the page's notes: how many margins pass with 95 % confidence, and which do not, with their intervals."""
    made = [b for b in bands if b.confident is not None]
    weak = [b for b in made if not b.confident]
    text = (
        f"Sizing margins with the uncertainty of the identified parameters (the parameter file's covariance): "
        f"{len(made) - len(weak)} of {len(made)} checks pass with 95 % confidence (margin at least 1.645 of its standard deviations)"
    )
    if not weak:
        return text + "."
    parts = []
    for b in weak:
        lo, hi = b.interval
        parts.append(
            f"{b.check.kind.label}, LN{b.check.module}: margin {100 * b.check.margin:+.1f} % (95 %: {100 * lo:+.1f} % to {100 * hi:+.1f} %)"
        )
    return text + "; not: " + "; ".join(parts) + "."


def _simulate_both(params, desired_at, duration, mismatch=None):
    """Both controllers on the Pinocchio plant (the whole closed chain, the CLI's default), optionally off from their model: the report's tracking plots."""
    from ..closed_chain.plant import PinocchioPlant
    from ..control.controllers import AugmentedPD, WorkspacePD
    from ..control.simulation import apply_mismatch, simulate

    plant = PinocchioPlant(apply_mismatch(params, **(mismatch or {})))
    return {
        "pd": simulate(
            plant, WorkspacePD(params), desired_at, duration, progress=True, controller_name="pd", notify=note
        ),
        "augmented-pd": simulate(
            plant,
            AugmentedPD(params, desired_at, params.control.servo_rate, duration),
            desired_at,
            duration,
            progress=True,
            controller_name="augmented-pd",
            notify=note,
        ),
    }
