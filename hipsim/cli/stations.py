"""``hipsim stations``: carriage commands for one platform or both, each platform's resulting attitude and error, and
manufacturing tolerances before building.

Three modes:

- the desired motion (``--trajectory`` or the built-in cycle) commanded with ``--control 1|2|both``: the per-sample
  table (``--table``, CSV or Parquet by suffix), the figure, ``index.html`` and ``stations.json`` in ``--out``;
- ``--sliders LOG``: both platforms' attitudes from a log's carriages;
- ``--bands SPEC``: Monte Carlo of per-chain deviations on dask, the 95th percentiles and the sensitivity table.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from ..exceptions import HipsimError
from .common import (
    add_machine_options,
    add_provenance_options,
    add_summary_format,
    numbers,
    page_provenance,
    parameters,
    print_json,
    progress,
)
from .motion_options import add_trajectory_options, load_trajectory

__all__ = ["add_parser", "parse_weights", "run"]

#: Samples of the desired motion each drawn machine runs (the motion is decimated to at most this).
TOLERANCE_SAMPLES = 200


def add_parser(subparsers) -> argparse.ArgumentParser:
    """Register ``stations`` on the main parser's subcommands."""
    p = subparsers.add_parser(
        "stations",
        help="carriage commands for platform 1, 2 or both; each platform's attitude error; tolerances -> table, page",
        description="Both platforms hang on the same carriages; with per-chain geometry (the parameter file's [geometry], "
        "e.g. from hipsim calibrate) they turn differently. --control 1 or 2 commands the carriages by that platform's "
        "inverse kinematics (the other follows); --control both minimises the weighted sum of both platforms' squared "
        "angle errors. Writes the per-sample table (t_s, L_11_mm.., alpha_1_deg..gamma_2_deg, err_alpha_1_deg.., Fe_N), "
        "the figure of each platform's errors, index.html and stations.json to --out.",
    )
    add_machine_options(p)
    add_trajectory_options(p)
    p.add_argument(
        "--control",
        choices=["1", "2", "both", "all"],
        help="which platform the carriages serve: 1, 2, both (default: the parameter file's [geometry] control, else 2: "
        "the paper's, m_1 follows); 'all' with --bands evaluates the three",
    )
    p.add_argument(
        "--weights", metavar="W1,W2", help="weights of the two platforms' squared errors for both (default 1,1)"
    )
    p.add_argument(
        "--sliders",
        metavar="LOG",
        help="a log's carriages (L_11_mm.. or motor_1_deg..; CSV, Parquet, TDMS or HDF5, its channels by "
        "--columns NAME=GROUP/CHANNEL): both attitudes",
    )
    p.add_argument(
        "--bands",
        dest="tolerance",
        metavar="FILE|KEY=V,...",
        help="draw per-chain deviations within ±V mm: keys ujoint, slider, joint, lever, centre, spline (the stack-up seat, named only), all (e.g. all=0.1), "
        "or a TOML file of them",
    )
    p.add_argument("--draws", type=int, default=1000, metavar="N", help="machines drawn for --bands (default 1000)")
    p.add_argument("--seed", type=int, default=0, metavar="N", help="seed of the draws (default 0)")
    p.add_argument(
        "--workers", type=int, default=2, metavar="N", help="local worker processes (default 2; 1 runs in this process)"
    )
    p.add_argument("--scheduler", metavar="ADDRESS", help="a running dask scheduler instead of a local cluster")
    p.add_argument("--table", metavar="FILE", help="per-sample table, .csv or .parquet (default OUT/stations.csv)")
    p.add_argument("--out", default="hipsim_stations", metavar="DIR", help="folder to write (default hipsim_stations)")
    add_summary_format(p, "what to print: tables (default) or the summary as JSON")
    add_provenance_options(p)
    p.set_defaults(run=run)
    return p


def parse_weights(args) -> tuple[float, float]:
    """``--weights W1,W2`` (dimensionless, >= 0, not both zero; default 1,1), as ``stations`` and ``learn`` take it."""
    if args.weights is None:
        return 1.0, 1.0
    w = numbers(args.weights, ",", "--weights", "two weights W1,W2 >= 0", count=2)
    if min(w) < 0 or sum(w) == 0:
        raise HipsimError(f"--weights: expected two weights >= 0, not both zero, got '{args.weights}'")
    return w[0], w[1]


def _check(args) -> None:
    if args.sliders and args.tolerance:
        raise HipsimError("give --sliders or --bands, not both")
    if args.control == "all" and not args.tolerance:
        raise HipsimError("--control all applies to --bands; give 1, 2 or both")
    if args.tolerance and args.draws < 1:
        raise HipsimError(f"--draws: expected at least 1, got {args.draws}")
    if args.table and Path(args.table).suffix.lower() not in (".csv", ".parquet"):
        raise HipsimError(f"--table {args.table}: expected a .csv or .parquet file")


def _write_table(path: Path, columns) -> Path:
    from ..files import ColumnWriter

    with ColumnWriter(path) as writer:
        writer.write(columns)
        return writer.close()


def _print_summary(summary) -> None:
    from ..present.tables import format_table

    rows = []
    for p in summary.platforms:
        role = "controlled" if p.controlled else "following"
        for name, a in p.angles.items():
            rows.append(
                [f"m_{p.platform} ({role})", name, f"{a.rms_deg:.4g}", f"{a.peak_deg:.4g}", f"{a.peak_at_s:.4g}"]
            )
    print(format_table(["platform", "angle", "RMS [°]", "peak [°]", "at t [s]"], rows, f"--control {summary.control}"))
    for p in summary.platforms:
        if p.iso is not None:
            reason = f" ({p.iso.reason})" if p.iso.reason else ""
            print(f"station {p.platform}: ISO 14242-1: {p.iso.verdict.value}: {p.iso.judged}{reason}")
            if p.iso.desired_line:
                print(f"station {p.platform}: {p.iso.desired_line}")


def run(args) -> int:
    """Run the mode the options ask for; write the folder; exit status 1 when a station's ISO verdict fails."""
    from ..files import check_folder, check_output

    _check(args)
    weights = parse_weights(args)
    params = parameters(args)
    if args.control is None:
        args.control = str(params.geometry.control) if params.geometry is not None else "2"
    if args.weights is not None and args.control not in ("both", "all"):
        raise HipsimError(f"--weights {args.weights} applies to --control both, not to --control {args.control}")
    out = Path(args.out)
    check_folder(out)
    table = Path(args.table) if args.table else out / "stations.csv"
    if args.table and not args.tolerance:
        check_output(table)
    if args.tolerance:
        return _tolerance(args, params, weights, out)
    if args.sliders:
        return _sliders(args, params, out, table)
    return _commands(args, params, weights, out, table)


def _commands(args, params, weights, out: Path, table: Path) -> int:
    from ..files import output_folder
    from ..present.stations_page import write_stations
    from ..records import exit_status
    from ..stations.commands import station_commands
    from ..stations.summary import station_columns, station_summary, stations_verdict
    from .documents import StationsRun

    trajectory = load_trajectory(args)
    motion = station_commands(params, trajectory.t, trajectory.q, args.control, weights, source=trajectory.name)
    has_load = bool(trajectory.Fe.any())
    load = trajectory.Fe if has_load else None
    summary = station_summary(motion, load, trajectory.name, trajectory.periodic)
    provenance = page_provenance(args, trajectory=args.trajectory)
    import numpy as np

    with output_folder(out):
        _write_table(table, station_columns(motion, load))
        files = write_stations(out, {"table": str(table)}, summary, motion.t, np.degrees(motion.errors), provenance)
    verdict = stations_verdict(summary)  # FAIL when a station's ISO 14242-1 verdict fails, as on the page
    if args.summary_format == "json":
        print_json(StationsRun(verdict, summary, str(table), str(files.index), provenance.as_dict()).to_json())
    else:
        _print_summary(summary)
        print(f"wrote {table} and {files.index}")
    return exit_status([verdict])


def _sliders(args, params, out: Path, table: Path) -> int:
    import numpy as np

    from ..channels import channel_kind
    from ..files import output_folder
    from ..present.stations_page import write_stations
    from ..stations.commands import attitudes
    from ..stations.logs import read_slider_log
    from ..stations.summary import attitude_columns, sliders_summary
    from .documents import StationsSliders

    # A TDMS or HDF5 log's channels by --columns (NAME=GROUP/CHANNEL); a CSV's are its header's.
    channel_map = args.columns if channel_kind(args.sliders) else None
    t, carriages, sensors = read_slider_log(args.sliders, params.lead, channel_map)
    q = attitudes(params, carriages, None, t, args.sliders)
    flat = np.degrees(q).reshape(len(t), 6)
    columns = {"t_s": t} | {f"L_1{i + 1}_mm": carriages[:, i] * 1e3 for i in range(3)}
    columns |= {name: flat[:, k] for k, name in enumerate(attitude_columns())}
    sliders = sliders_summary(args.sliders, q)
    comparison = None if sensors is None else _sensor_comparison(args, params, t, q, sensors)
    extra = {} if comparison is None else {"sensors": comparison.to_json()}
    provenance = page_provenance(args, log=args.sliders)
    fig7 = None if sensors is None else _fig7(t, q, sensors, args.sliders, channel_map)
    with output_folder(out):
        _write_table(table, columns)
        files = write_stations(out, {"table": str(table)} | extra, sliders=sliders, provenance=provenance, fig7=fig7)
    if args.summary_format == "json":
        print_json(StationsSliders(sliders, str(table), str(files.index), provenance.as_dict(), comparison).to_json())
    else:
        rms = sliders.platform_difference_rms_deg
        print(f"{len(t)} samples; m_1 − m_2 attitude RMS α {rms[0]:.4g}°, β {rms[1]:.4g}°, γ {rms[2]:.4g}°")
        if comparison is not None:
            _print_comparison(comparison)
        print(f"wrote {table} and {files.index}")
    return 0


def _sensor_comparison(args, params, t, q, sensors):
    """The log's sensors against the prediction, with the calibrated file's uncertainty when it records one."""
    from ..rig.identification.identified_file import identification_table
    from ..stations.sensor_check import calibration_covariance, compare_sensors

    covariance = calibration_covariance(identification_table(args.params)) if args.params else None
    origin = f"{args.params}: the calibration's posterior covariance of the per-chain values"
    return compare_sensors(params, t, q, sensors, covariance, origin)


def _print_comparison(comparison) -> None:
    from ..present.tables import format_table

    rows = [
        [
            f"m_{e.platform}",
            e.angle,
            f"{e.rms_deg:.4g}",
            f"{e.mean_deg:+.4g}",
            f"{e.peak_deg:+.4g}",
            f"{e.peak_at_s:.3f}",
            "-" if e.prediction_std_deg is None else f"{e.prediction_std_deg:.3g}",
        ]
        for e in comparison.entries
    ]
    header = ["platform", "angle", "RMS [deg]", "mean [deg]", "peak [deg]", "at [s]", "prediction std [deg]"]
    print(
        format_table(header, rows, "The log's sensors against the prediction from its carriages (measured - predicted)")
    )


def _fig7(t, q, sensors, log: str, channel_map: str | None = None):
    """Fig. 7 of the log: each platform measured (sensors) and predicted (carriages) on the three panels."""
    import numpy as np

    from ..present.fig7 import Curve, plot_fig7
    from ..stations.logs import read_desired

    desired = read_desired(log, channel_map)
    curves = [] if desired is None else [Curve("desired", np.degrees(desired), "k", ":")]
    curves += [
        Curve("m_1 measured", np.degrees(sensors[:, 0]), "tab:blue", "-"),
        Curve("m_1 predicted", np.degrees(q[:, 0]), "tab:blue", "--"),
        Curve("m_2 measured", np.degrees(sensors[:, 1]), "tab:red", "-"),
        Curve("m_2 predicted", np.degrees(q[:, 1]), "tab:red", "--"),
    ]
    return plot_fig7(t, curves, f"Fig. 7 from {Path(log).name}")


def _tolerance(args, params, weights, out: Path) -> int:

    from ..files import output_folder
    from ..present.stations_page import write_stations
    from ..stations.tolerance import parse_tolerances, tolerance_draws
    from ..stations.tolerance_summary import tolerance_summary
    from .documents import StationsTolerance

    bands = parse_tolerances(args.tolerance)
    trajectory = load_trajectory(args)
    step = max(1, -(-len(trajectory.t) // TOLERANCE_SAMPLES))
    t, q = trajectory.t[::step], trajectory.q[::step]
    controls = ("1", "2", "both") if args.control == "all" else (args.control,)
    result = tolerance_draws(
        params,
        t,
        q,
        bands,
        controls,
        draws=args.draws,
        seed=args.seed,
        weights=weights,
        workers=0 if args.workers == 1 else args.workers,  # the library's 0: in this process
        scheduler=args.scheduler,
        progress=progress("hipsim stations --bands"),
    )
    tolerance = tolerance_summary(result, len(t))
    provenance = page_provenance(args, trajectory=args.trajectory, tolerance=_file(args.tolerance))
    with output_folder(out):
        files = write_stations(out, {}, tolerance=tolerance, provenance=provenance)
    if args.summary_format == "json":
        print_json(StationsTolerance(tolerance, str(files.index), provenance.as_dict()).to_json())
        return 0
    from ..present.tables import format_table

    rows = [
        [
            c.control,
            f"m_{p.platform}",
            *(f"{v:.3g}" for v in p.rms_p95_deg),
            *(f"{v:.3g}" for v in p.peak_p95_deg),
        ]
        for c in tolerance.controls
        for p in c.platforms
    ]
    header = ["control", "platform", "α RMS p95", "β RMS p95", "γ RMS p95", "α peak p95", "β peak p95", "γ peak p95"]
    print(format_table(header, rows, f"{args.draws} machines drawn, errors in degrees"))
    for c in tolerance.controls:
        families = ", ".join(f"{name} {100 * share:.0f} %" for name, share in c.family_share.items())
        print(f"--control {c.control}: share of the follower's mean square by tolerance: {families}")
        top = c.sensitivity[:5]
        print(f"--control {c.control}: largest shares: " + ", ".join(f"{r.value} {100 * r.share:.1f} %" for r in top))
    print(f"wrote {files.index}")
    return 0


def _file(text: str) -> str | None:
    return text if "=" not in text and Path(text).is_file() else None
