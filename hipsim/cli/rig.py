"""``hipsim compare``, ``hipsim identify``: the rig in the loop (``hipsim excite`` designs their motion: :mod:`hipsim.cli.excite`).

- ``compare``: the model's torques along a rig log against the measured ones; figures, a page and JSON.
- ``identify``: the dynamic parameters fitted to rig logs; a parameter file every command accepts.
"""

from __future__ import annotations

import argparse
import contextlib
import dataclasses
import json
import math
import sys
from pathlib import Path
from typing import Any

from ..exceptions import ArgumentError, OutputError
from ..present.tables import format_table
from .common import (
    add_channel_columns,
    add_machine_options,
    add_provenance_options,
    add_summary_format,
    page_provenance,
    parameters,
    print_json,
    progress,
)

__all__ = ["add_parser", "run", "run_compare", "run_identify"]

#: The defaults of ``--cutoff`` in [Hz] and ``--angle-tolerance`` in [deg], written out so that the parser loads no signal processing;
#: they are the library's :data:`hipsim.rig.logs.DEFAULT_CUTOFF` and :data:`hipsim.rig.logs.DEFAULT_TOLERANCE_DEG` (a test checks).
DEFAULT_CUTOFF = 20.0
DEFAULT_TOLERANCE_DEG = 0.5
#: What an identification's self-check does not judge (its verdict says so).
NOT_JUDGED = (
    "the base parameters these logs do not determine (listed apart, near their priors) and the model beyond the "
    "logs' envelope"
)


def _add_log_options(parser: argparse.ArgumentParser) -> None:
    group = parser.add_argument_group("logs")
    group.add_argument(
        "--torque-constant",
        type=float,
        metavar="NM_PER_A",
        help="motor torque constant in N·m/A, for logs of motor currents (current_1_A …)",
    )
    group.add_argument(
        "--cutoff",
        type=float,
        default=DEFAULT_CUTOFF,
        metavar="HZ",
        help=f"zero-phase low-pass cutoff for measured motion, load and torques (default {DEFAULT_CUTOFF:g} Hz)",
    )
    group.add_argument("--no-filter", action="store_true", help="no low-pass filter (a log filtered already)")
    group.add_argument(
        "--angle-tolerance",
        dest="tolerance",
        type=float,
        default=DEFAULT_TOLERANCE_DEG,
        metavar="DEG",
        help=f"largest disagreement of attitude sensor and encoders when a log has both (default {DEFAULT_TOLERANCE_DEG:g}°)",
    )
    add_channel_columns(group)
    group.add_argument(
        "--spin-free-levers",
        action="store_true",
        help="the spec's levers without the universal joints' spin (default: with it, as real joints move)",
    )
    group.add_argument(
        "--no-plausibility-check",
        dest="plausibility_check",
        action="store_false",
        help="skip the check of each logged signal against what the machine produces (a factor of ~1000 "
        "or ~57, a unit slip, is otherwise an error); for the rare log that is right",
    )


def add_parser(subparsers) -> None:
    """Register ``compare`` and ``identify``."""
    compare = subparsers.add_parser(
        "compare",
        help="the model's torques along a rig log against the measured ones -> figures, HTML, JSON",
        description="Runs the analytic model along a rig log's motion and load and compares its motor torques (total "
        "and parts) with the measured ones, per motor: RMS and peak error, absolute and relative, where the peak occurs, "
        "and the error per phase of the cycle when the log repeats. Model and measurement are low-passed alike. Writes "
        "figures (PNG, SVG), index.html and comparison.json to --out and prints the table. The log is read and compared "
        "in pieces: memory does not grow with its length.",
    )
    compare.add_argument(
        "--log",
        required=True,
        metavar="FILE",
        help="rig log (CSV, TDMS or HDF5): t_s, Fe_N, tau_i_Nmm (or current_i_A), angles and/or L_1i_mm",
    )
    add_machine_options(compare)
    _add_log_options(compare)
    compare.add_argument(
        "--log-period",
        dest="period",
        type=float,
        metavar="S",
        help="the log's period in s (default: detected; 0: not periodic)",
    )
    compare.add_argument(
        "--out", default="hipsim_compare", metavar="DIR", help="folder to write (default hipsim_compare)"
    )
    compare.add_argument(
        "--accept",
        type=float,
        metavar="PERCENT",
        help="largest RMS error accepted, in %% of each motor's measured RMS torque: the page's verdict (default: not judged)",
    )
    add_provenance_options(compare)
    add_summary_format(compare, "what to print")
    compare.set_defaults(run=run)

    identify = subparsers.add_parser(
        "identify",
        help="fit the dynamic parameters to rig logs -> a parameter TOML",
        description="Estimates the machine's base parameters (fixed combinations of the inertial parameters and friction "
        "coefficients that motor torques can determine, defined by the geometry: --base lists them) by Bayesian least "
        "squares: the starting file's values are the prior (uncertainties by default 30 %% of masses and inertias, 50 %% of "
        "friction; [identification.prior] in the file or --prior change them), so a weakly excited parameter stays near its "
        "prior with a large standard deviation instead of biasing the others. The machine written is physically consistent "
        "and carries the posterior covariance ([identification] table), from which torques, compare, size and report give "
        "95 %% bands. With --validate, the held-out error per motor and gait phase next to the starting parameters'. Logs are "
        "read in pieces: memory does not grow with their length.",
    )
    identify.add_argument(
        "--log", action="append", metavar="FILE", help="rig log to fit (repeatable; required unless --base)"
    )
    identify.add_argument(
        "--validate", action="append", default=[], metavar="FILE", help="held-out rig log to predict (repeatable)"
    )
    add_machine_options(identify)
    _add_log_options(identify)
    identify.add_argument(
        "--prior",
        metavar="NAME=STD,...",
        help="prior standard deviations: a parameter's label, key or key prefix "
        "and a number in its file unit or a percentage ('mu_h=0.02,lever=10 %%'); 0 holds it at its value",
    )
    identify.add_argument(
        "--fix",
        metavar="NAMES",
        help="parameters to hold at their starting values, comma-separated "
        "(labels such as m_l, keys, or prefixes such as lever, friction.ujoint): a prior of zero uncertainty",
    )
    identify.add_argument(
        "--base", action="store_true", help="print the machine's base parameters with their definitions and stop"
    )
    identify.add_argument("--json", metavar="FILE", help="also write the results as JSON")
    identify.add_argument(
        "--force",
        action="store_true",
        help="write an implausible fit anyway (residuals beyond 3x the noise, a parameter beyond 5 prior σ, a held-out "
        "log it does not predict), its warning kept in the file's provenance",
    )
    identify.add_argument("--out", metavar="FILE", help="parameter TOML to write (.toml; required unless --base)")
    add_provenance_options(identify)
    add_summary_format(identify, "what to print: tables (default) or the fit's summary as JSON")
    identify.set_defaults(run=run)


def _cutoff(args) -> float | None:
    if args.no_filter or args.cutoff is None:
        return None
    if not (math.isfinite(args.cutoff) and args.cutoff > 0):
        raise ArgumentError("--cutoff", args.cutoff, "a positive frequency in Hz (or 0 for none)")
    return args.cutoff


def _not_an_input(out: str, inputs: list[str], option: str) -> None:
    for name in inputs:
        if name and Path(out).exists() and Path(name).exists() and Path(out).resolve() == Path(name).resolve():
            raise OutputError(out, f"is the input {name} itself ({option}): choose another output")


def _pieces(path: str, params, args):
    from ..rig.logs import LogPieces

    return LogPieces(
        path,
        params,
        torque_constant=args.torque_constant,
        cutoff=_cutoff(args),
        tolerance_deg=args.tolerance,
        columns=args.columns,
    )


def _plausible(log, params, args) -> None:
    """The log's signals against the machine's (:func:`hipsim.rig.plausibility.check_log`): a unit slip raised, warnings printed."""
    if not args.plausibility_check:
        return
    from ..rig.plausibility import check_log

    for warning in check_log(params, log, lever_spin=not args.spin_free_levers, torque_constant=args.torque_constant):
        print(f"hipsim: warning: {warning}", file=sys.stderr)


def _hashed(log):
    """A log's file as the page's provenance lists it, hashed as it was read (the file is not opened again)."""
    from ..present.provenance import InputFile

    return InputFile("log", str(Path(log.source)), log.sha256, log.size)


def run_compare(args) -> int:
    """Compare the model with ``--log``: write the figures, page and JSON to ``--out`` and print the errors; exit status 1 when --accept is given and a motor exceeds it."""
    from ..files import check_folder
    from ..present.rig_figures import write_comparison
    from ..records import exit_status
    from ..rig.compare import compare_log
    from ..rig.identification.uncertainty import read_covariance

    params = parameters(args)
    covariance = read_covariance(args.params, params)  # a bad table refused before the work
    if args.accept is not None and not (math.isfinite(args.accept) and args.accept > 0):
        raise ArgumentError("--accept", args.accept, "a positive percentage")
    _check_log_options(args)
    check_folder(Path(args.out))  # a bad folder is refused before the work
    with _pieces(args.log, params, args) as log:  # in pieces: memory does not grow with the log
        provenance = page_provenance(args, log=_hashed(log))  # the log as it was read, hashed by its one read
        _plausible(log, params, args)  # a unit slip refused before the comparison
        comparison = compare_log(
            params, log, lever_spin=not args.spin_free_levers, period=args.period, progress=progress("compare")
        )
        band = None
        if covariance is not None:  # an identified file: the model's 95 % band at the samples kept
            from ..rig.identification.uncertainty import Z95, log_torque_std

            band = Z95 * log_torque_std(params, log, comparison.t, covariance)
    files = write_comparison(
        args.out,
        comparison,
        provenance=provenance,
        accept=None if args.accept is None else args.accept / 100,
        band=band,
        residual=None if covariance is None else covariance.residual,
    )
    summary, accepted = comparison.summary(), files.verdict  # the verdict made beside the comparison, once
    if args.summary_format == "json":
        print(json.dumps(json.loads(files.summary.read_text(encoding="utf-8")), indent=2))
        return exit_status([accepted])
    print(f"{accepted.level.value}: {accepted.judged}" + (f"\n  {accepted.not_judged}" if accepted.not_judged else ""))
    print(
        f"log: {log.name} ({summary.samples} samples compared, motion from the {log.motion_from}); parameters: {params.source}"
    )
    for note in log.notes:
        print(f"  {note}")
    if band is not None:
        bands = json.loads(files.summary.read_text(encoding="utf-8"))["model_band95"]
        print(
            "model's 95 % band (the parameter file's covariance): "
            + ", ".join(f"M{i} ±{b['rms_half_width_Nmm']:.3g} N·mm RMS" for i, b in bands.items())
        )
        if "measured_within_prediction_band" in bands["1"]:
            print(
                "  with the fit's residual (a measurement's noise and model error), the prediction band: "
                + ", ".join(
                    f"M{i} ±{b['prediction_rms_half_width_Nmm']:.3g} N·mm RMS, {100 * b['measured_within_prediction_band']:.0f} % of measured samples within"
                    for i, b in bands.items()
                )
            )
    rows = [
        [
            f"M{i}",
            m.measured_rms_Nmm,
            m.measured_peak_Nmm,
            m.rms_error_Nmm,
            f"{100 * m.relative_rms_error:.2f} %",
            m.peak_error_Nmm,
            f"{100 * m.relative_peak_error:.2f} %",
            f"{m.peak_error_t_s:.3f}",
            m.rms_error_away_from_reversals_Nmm,
        ]
        for i, m in summary.motors.items()
    ]
    print(
        format_table(
            [
                "motor",
                "RMS [N·mm]",
                "peak [N·mm]",
                "RMS error",
                "/ RMS",
                "peak error",
                "/ peak",
                "at [s]",
                "RMS error away from reversals",
            ],
            rows,
            "Model vs measured motor torque [N·mm]",
        )
    )
    if comparison.phase_rms is not None:
        anchor = "heel strike" if comparison.stance is not None else "the first sample"
        print(
            f"\nthe log repeats every {comparison.period:.4g} s; RMS error per tenth of the gait cycle from {anchor} "
            f"(t = {comparison.heel_strike:.4g} s) [N·mm]:"
        )
        if comparison.stance is not None:
            print("      " + " ".join(f"{'stance' if s else 'swing':>6}" for s in comparison.stance))
        for i in range(3):
            print(f"  M{i + 1}: " + " ".join(f"{x * 1e3:6.2f}" for x in comparison.phase_rms[:, i]))
    print(f"\nwrote {files.index} (figures, comparison.json)")
    return exit_status([accepted])


def _check_log_options(args) -> None:
    if not (math.isfinite(args.tolerance) and args.tolerance > 0):
        raise ArgumentError("--angle-tolerance", args.tolerance, "a positive angle in degrees")
    if args.torque_constant is not None and not (math.isfinite(args.torque_constant) and args.torque_constant > 0):
        raise ArgumentError("--torque-constant", args.torque_constant, "a positive number in N·m/A")


def run_base(args) -> int:
    """Print the machine's base parameters with their definitions; exit status 0."""
    from ..rig.identification.base import base_parameters
    from ..rig.identification.prior import prior

    params = parameters(args)
    base = base_parameters(params, not args.spin_free_levers)
    belief = prior(base, params)
    if args.summary_format == "json":
        from ..rig.identification.summary import base_listing

        print_json(base_listing(base, belief.mean, belief.std).to_json())
        return 0
    rows = [
        [p.label, p.definition, p.unit or "—", f"{m / s:.6g}", f"{d / s:.2g}"]
        for p, m, d, s in zip(base.parameters, belief.mean, belief.std, base.scale)
    ]
    print(
        format_table(
            ["base parameter", "definition", "unit", "start value", "prior std"],
            rows,
            f"Base parameters of {params.source} ({len(rows)}; lever spin {'off' if args.spin_free_levers else 'on'})",
        )
    )
    return 0


def run_identify(args) -> int:
    """Identify the machine from the ``--log`` files, write the parameter file ``--out`` and print the fit; exit status 1
    when the self-check FAILs (a fit written with ``--force``), else 0."""
    from ..exceptions import IdentificationError
    from ..fit_checks import duplicate_digests
    from ..rig.identification.fit import identify
    from ..rig.identification.prior import parse_prior_option, prior_table
    from ..rig.identification.self_check import check_identification
    from ..rig.plausibility import far_from_priors

    if args.base:
        return run_base(args)
    if not args.log or not args.out:
        raise ArgumentError(
            "--log, --out",
            [args.log, args.out],
            "--log FILE and --out FILE.toml (or --base to list the base parameters)",
        )
    if Path(args.out).suffix.lower() != ".toml":
        raise ArgumentError("--out", args.out, "a .toml parameter file name")
    _check_log_options(args)
    params = parameters(args)
    _not_an_input(args.out, [*args.log, *args.validate, args.params or ""], "--out")
    if args.json:
        _not_an_input(args.json, [*args.log, *args.validate, args.params or "", args.out], "--json")
        if Path(args.json).resolve() == Path(args.out).resolve():
            raise OutputError(args.json, "--json and --out name the same file")
    entries = dict(prior_table(args.params))
    source = f"{args.params} [identification.prior]" if entries else "prior"
    if args.prior:
        entries |= parse_prior_option(args.prior)
        source = "--prior"
    fixed = [name.strip() for name in (args.fix or "").split(",") if name.strip()]
    with contextlib.ExitStack() as stack:  # the logs in pieces: memory does not grow with their length
        logs: list[Any] = []
        validate: list[Any] = []
        for paths, opened in ((args.log, logs), (args.validate, validate)):
            for path in paths:  # each file read once: scanned, checked, hashed; its pieces then come from that read
                opened.append(stack.enter_context(_pieces(path, params, args)))
                _plausible(opened[-1], params, args)  # a unit slip refused before the fit (hipsim.rig.plausibility)
        provenance = page_provenance(
            args, log=[_hashed(log) for log in logs], validate=[_hashed(log) for log in validate]
        )
        twice = duplicate_digests(  # the hashes made on the way through the one read of each file
            [(f["path"], f["sha256"]) for f in provenance.as_dict()["inputs"] if f["role"] in ("log", "validate")]
        )
        if twice:
            raise IdentificationError(f"--log/--validate: {twice}")
        result = identify(
            logs,
            params,
            validate=validate,
            lever_spin=not args.spin_free_levers,
            fixed=fixed,
            prior=entries,
            prior_source=source,
        )
        check = check_identification(result, logs, validate)  # the pattern of a failed gate reads the logs: here
    if not check.plausible:
        if not args.force:
            raise IdentificationError(
                f"{check.message()}; nothing written (--force writes it, the warning kept in its provenance)"
            )
        print(f"hipsim: warning: {check.message()} (written with --force)", file=sys.stderr)
    for line in far_from_priors(result.estimates):  # issue 38: a common cause named (hipsim/rig/plausibility.py)
        print(f"hipsim: warning: {line}", file=sys.stderr)

    from ..files import write_atomic
    from ..records import exit_status
    from ..rig.identification.identified_file import FileProvenance
    from .documents import IdentifyRun

    self_check = check.summary(len(validate), NOT_JUDGED)
    summary = result.summary()
    record = dataclasses.replace(FileProvenance.from_dict(provenance.as_dict()), warnings=check.findings)
    path = result.write_toml(args.out, record)
    document = IdentifyRun(provenance.as_dict(), self_check, summary, str(path), args.json)
    if args.json:
        write_atomic(args.json, json.dumps(document.to_json(), indent=2) + "\n")
    if args.summary_format == "json":
        print_json(document.to_json())
        return exit_status([self_check])
    print(
        f"logs: {', '.join(result.logs)}; {result.rows} samples (after filtering, decimation and the windows around reversals)"
    )
    print(f"starting parameters: {params.source}")
    rows: list[list[Any]] = [
        [
            e.definition if len(e.definition) < 60 else e.definition[:57] + "…",
            f"{e.value:.6g}",
            f"{e.std:.2g}",
            e.unit or "—",
            f"{e.prior:.6g} ± {e.prior_std:.2g}",
            f"{e.shift:+.2g}",
        ]
        for e in result.estimates
        if e.determined
    ]
    print(
        format_table(
            ["base parameter", "value", "std", "unit", "prior", "moved [prior std]"],
            rows,
            "\nIdentified (the base parameters these logs determine: posterior std at most half the prior's)",
        )
    )
    rest_ = [e for e in result.estimates if not e.determined]
    if rest_:
        print("\nNot determined by these logs (near the prior, posterior std ≥ half the prior's):")
        for e in rest_:
            print(f"  {e.name} = {e.value:.6g} ± {e.std:.2g} {e.unit} (prior {e.prior:.6g} ± {e.prior_std:.2g})")
    print(f"\nregressor condition number (determined base parameters): {result.condition_number:.4g}")
    print(
        "residual RMS per motor: "
        + ", ".join(f"M{i + 1} {r * 1e3:.3g} N·mm" for i, r in enumerate(result.residual_rms))
    )
    if result.active_constraints:
        print("physical consistency: " + "; ".join(result.active_constraints))
    for held_out, note in zip(summary.validation or (), result.notes or [None] * len(result.validation)):
        a, b = held_out.identified, held_out.starting
        rows = [
            [
                f"M{i}",
                a[i].rms_error_Nmm,
                f"{100 * a[i].relative_rms_error:.2f} %",
                b[i].rms_error_Nmm,
                f"{100 * b[i].relative_rms_error:.2f} %",
                f"{100 * a[i].relative_rms_error_away_from_reversals:.2f} %",
            ]
            for i in ("1", "2", "3")
        ]
        print(
            format_table(
                ["motor", "identified [N·mm]", "/ RMS", "starting [N·mm]", "/ RMS", "identified, away from reversals"],
                rows,
                f"\nPrediction error on {held_out.log} (held out): RMS of model − measured",
            )
        )
        if note is not None:
            print(note.text())
    print(f"\n{check.verdict(len(args.validate))}")
    print(f"wrote {path}" + (f" and {args.json}" if args.json else ""))
    return exit_status([self_check])


def run(args) -> int:
    """Run the subcommand ``args.command`` (compare or identify)."""
    return {"compare": run_compare, "identify": run_identify}[args.command](args)
