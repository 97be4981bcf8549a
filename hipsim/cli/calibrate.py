"""``hipsim calibrate``: kinematic calibration of the two stations from the carriage encoders and both attitude sensors.

Reads the logs (:mod:`hipsim.stations.logs`), fits the per-chain values the
sensors can see (:func:`hipsim.stations.calibration.calibrate`), checks the
result on held-out logs (``--validate``) and writes a parameter file every
command takes (:mod:`hipsim.stations.calibration_file`).
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import sys
from pathlib import Path

from ..exceptions import HipsimError
from .common import (
    add_channel_columns,
    add_machine_options,
    add_provenance_options,
    add_summary_format,
    page_provenance,
    parameters,
    print_json,
)

__all__ = ["add_parser", "run", "run_excite_calibration"]


def add_parser(subparsers) -> argparse.ArgumentParser:
    """Register ``calibrate`` on the main parser's subcommands."""
    p = subparsers.add_parser(
        "calibrate",
        help="kinematic calibration of both stations from encoder and attitude-sensor logs -> parameter TOML",
        description="Fits each chain's deviations from the drawing (U-joint offsets, slider offsets, platform joints, "
        "lever lengths, rotation centres: the combinations the two attitude sensors can see, the others kept at the "
        "start and named) to logs of the carriages (L_11_mm, L_12_mm, L_13_mm or motor_1_deg..) and both sensors "
        "(alpha_1_deg, beta_1_deg, gamma_1_deg, alpha_2_deg, beta_2_deg, gamma_2_deg), with a prior on every value. "
        "Writes a parameter file with the calibrated [geometry] table and the calibration's record.",
    )
    add_machine_options(p)
    p.add_argument(
        "--log",
        action="append",
        required=True,
        metavar="FILE",
        help="calibration log, CSV, Parquet, TDMS or HDF5 (repeatable)",
    )
    add_channel_columns(p)
    p.add_argument(
        "--validate", action="append", default=[], metavar="FILE", help="held-out log to check on (repeatable)"
    )
    p.add_argument(
        "--chain-prior",
        dest="prior",
        type=float,
        default=0.5,
        metavar="MM",
        help="prior standard deviation of every per-chain value (default 0.5)",
    )
    p.add_argument(
        "--sensor-offset",
        choices=["none", "per-log"],
        default="none",
        help="per-log: estimate a constant offset per sensor angle and log (a sensor that drifts at its zero); the "
        "offsets trade with each platform's joint-pattern tilt and turn (named in the output) unless a log has a "
        "fixture's rows (known_alpha_j_deg, known_beta_j_deg, known_gamma_j_deg)",
    )
    p.add_argument("--out", required=True, metavar="FILE", help="parameter TOML to write (.toml)")
    p.add_argument("--json", metavar="FILE", help="also write the summary as JSON")
    p.add_argument(
        "--force",
        action="store_true",
        help="write an implausible calibration anyway (residuals beyond 3x the sensors' noise, a chain beyond 5 prior σ, "
        "a held-out log it does not predict), its warning kept in the file's provenance",
    )
    add_summary_format(p, "what to print: tables (default) or the summary as JSON")
    add_provenance_options(p)
    p.set_defaults(run=run)
    return p


def _check(args) -> None:
    from ..files import check_output

    if Path(args.out).suffix.lower() != ".toml":
        raise HipsimError(f"--out {args.out}: expected a .toml parameter file")
    if Path(args.out).is_dir():
        raise HipsimError(f"--out {args.out} is a folder; give a .toml file name")
    if not (math.isfinite(args.prior) and args.prior > 0):
        raise HipsimError(f"--prior: expected a positive standard deviation in mm, got {args.prior!r}")
    check_output(args.out)
    if args.json:
        check_output(args.json)
    from ..fit_checks import duplicate_inputs

    twice = duplicate_inputs([*args.log, *args.validate])
    if twice:
        raise HipsimError(f"--log/--validate: {twice}")
    inputs = {str(Path(f).resolve()) for f in args.log + args.validate}
    for path in (args.out, args.json):
        if path and str(Path(path).resolve()) in inputs:
            raise HipsimError(f"{path} is one of the logs read; give another output file")


def _print(summary) -> None:
    """The calibration's tables, from its record (:class:`hipsim.stations.calibration_summary.CalibrationSummary`)."""
    from ..present.tables import format_table

    def sensors(values):
        return [f"{v:.4g}" for row in values for v in row]

    header = ["log", "m_1 α", "m_1 β", "m_1 γ", "m_2 α", "m_2 β", "m_2 γ"]
    rows = []
    for name, before, after in zip(summary.logs, summary.start_residual_rms_deg, summary.residual_rms_deg):
        rows += [[f"{Path(name).name} (start)", *sensors(before)], [f"{Path(name).name} (calibrated)", *sensors(after)]]
    for v in summary.validation:
        rows += [
            [f"{Path(v.log).name} held out (start)", *sensors(v.start_rms_deg)],
            [f"{Path(v.log).name} held out (calibrated)", *sensors(v.rms_deg)],
        ]
    print(format_table(header, rows, "RMS residual of each sensor angle [°]"))
    print("noise [°]: " + ", ".join(f"{v:.4g}" for v in sum(summary.noise_deg, [])))
    largest = sorted(summary.values, key=lambda v: -abs(v.deviation_mm))[:8]
    rows = [[v.value, f"{v.deviation_mm:.4f}", f"{v.std_mm:.4f}", "yes" if v.determined else "no"] for v in largest]
    print()
    print(format_table(["value", "deviation [mm]", "std [mm]", "determined"], rows, "Largest calibrated deviations"))
    print("not seen by any log of this kind (kept at the start): " + (", ".join(summary.unseen) or "none"))
    if summary.weak:
        print("barely seen by these logs (posterior std above half the prior's): " + ", ".join(summary.weak))
    if summary.confounded:
        print()
        rows = [[c.sensor, f"{c.explained:.4f}", ", ".join(c.values)] for c in summary.confounded]
        title = (
            "Sensor offsets these logs cannot tell apart from the per-chain values (the posterior carries the trade)"
        )
        print(format_table(["offset", "explained (R²)", "trades with"], rows, title))
        print(f"what separates them: {summary.confounded[0].separated_by}")


#: What a calibration's self-check does not judge (its verdict says so).
NOT_JUDGED = "the values no log of this kind can see (kept at the start, listed as unseen)"


def run(args) -> int:
    """Calibrate, check on held-out logs, write the parameter file; exit status 1 when the self-check FAILs (a
    calibration written with ``--force``), else 0."""
    import json

    import numpy as np

    from ..exceptions import CalibrationError
    from ..files import write_atomic
    from ..records import exit_status
    from ..stations.calibration import calibrate
    from ..stations.calibration_check import check_calibration
    from ..stations.calibration_file import write_calibrated
    from ..stations.calibration_summary import calibration_summary, held_out_residual
    from ..stations.logs import read_calibration_log
    from .documents import CalibrateRun

    _check(args)
    params = parameters(args)
    offsets = args.sensor_offset == "per-log"
    logs = [read_calibration_log(path, params.lead, args.columns) for path in args.log]
    held = [read_calibration_log(path, params.lead, args.columns) for path in args.validate]
    calibration = calibrate(logs, params, prior=args.prior * 1e-3, offsets=offsets)
    validation = [held_out_residual(calibration, params, log, offsets) for log in held]
    check = check_calibration(calibration, logs, held, [np.radians(v.rms_deg) for v in validation])
    if not check.plausible:
        if not args.force:
            raise CalibrationError(
                f"{check.message()}; nothing written (--force writes it, the warning kept in its provenance)"
            )
        print(f"hipsim: warning: {check.message()} (written with --force)", file=sys.stderr)
    provenance = page_provenance(args, log=args.log, validation=args.validate or None)
    from ..rig.identification.identified_file import FileProvenance

    record = dataclasses.replace(FileProvenance.from_dict(provenance.as_dict()), warnings=check.findings)
    summary = calibration_summary(calibration, validation)
    path = write_calibrated(args.out, calibration, validation, record, start=args.params or "the published machine")
    self_check = check.summary(len(held), NOT_JUDGED)
    document = CalibrateRun(summary, self_check, str(path), provenance.as_dict())
    if args.json:
        write_atomic(args.json, json.dumps(document.to_json(), indent=2) + "\n")
    if args.summary_format == "json":
        print_json(document.to_json())
    else:
        _print(summary)
        print(check.verdict(len(held)))
        print(f"wrote {path}")
    return exit_status([self_check])


def run_excite_calibration(args, params, limits) -> int:
    """``hipsim excite --for calibration``: design the motion, write it as a trajectory CSV, print its condition number;
    exit status by its limits' verdict (as ``excite``'s)."""
    from ..records import exit_status
    from ..stations.excitation import calibration_excitation
    from .documents import ExciteCalibrationRun

    if args.max_angle is None:
        limits = dataclasses.replace(limits, max_angle=math.radians(20.0))
    json_out = args.summary_format == "json"
    print(
        f"designing a calibration motion: {args.harmonics} harmonics of {args.frequency:g} Hz, {8 * args.seeds} candidates …",
        flush=True,
        file=sys.stderr if json_out else sys.stdout,
    )
    design = calibration_excitation(
        params, frequency=args.frequency, harmonics=args.harmonics, limits=limits, seeds=8 * args.seeds
    )
    path = design.write_csv(args.out, rate=args.rate, duration=args.duration)
    summary = design.summary()
    if json_out:
        print_json(ExciteCalibrationRun(summary, str(path)).to_json())
        return exit_status([summary])
    peaks = summary.peaks
    print(
        f"condition number of the calibration Jacobian: {summary.condition_number:.4g} "
        f"(ISO 14242-1 cycle: {summary.iso_condition_number:.4g})"
    )
    print(
        f"largest |angle| {peaks.angle_deg:.3g}°, slider speed {peaks.speed_mm_s:.4g} mm/s, acceleration "
        f"{peaks.acceleration_mm_s2:.4g} mm/s², singularity measure ≥ {peaks.cond_inv_min:.3g}"
    )
    print(f"limits: {summary.verdict.level.value}: {summary.verdict.judged}")
    print(f"wrote {path}: drive platform m_2 along it with both attitude sensors logging, then hipsim calibrate --log")
    return exit_status([summary])
