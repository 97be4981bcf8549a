"""``hipsim export``: per motor, a position–velocity–time table at the servo rate a drive loads, with the torque
feed-forward from the model, every machine limit checked before anything is written."""

from __future__ import annotations

import argparse
import math
from pathlib import Path

from ..exceptions import HipsimError
from .common import add_machine_options, add_summary_format, page_provenance, parameters, print_json

__all__ = ["add_parser", "run"]

RATE_RANGE_HZ = (1.0, 100_000.0)
COUNTS_RANGE = (1.0, 1e9)
DEFAULT_COUNTS_PER_REV = 10_000.0

UNITS = {
    "t_s": "s",
    "position_counts": "encoder counts",
    "velocity_counts_s": "encoder counts/s",
    "position_rev": "motor revolutions",
    "velocity_rev_s": "motor revolutions/s",
    "torque_ff_Nmm": "motor N·mm (model inverse dynamics)",
}


def add_parser(subparsers) -> argparse.ArgumentParser:
    """Register ``export`` on the main parser's subcommands."""
    p = subparsers.add_parser(
        "export",
        help="per-motor position-velocity-time tables at the servo rate, with torque feed-forward -> DIR",
        description="Reads a carriage command (hipsim learn's NEXT or a hipsim stations table: t_s, L_11_mm.., "
        "optional Fe_N; periodic) and writes, per motor, DIR/motor_I.csv: positions and velocities at the servo rate "
        "in encoder counts and motor revolutions (screw lead from the parameters; carriage mm = revolutions x lead), and the torque "
        "feed-forward from the model's inverse dynamics along the commanded motion; DIR/export.json: rate, units, "
        "limits checked and not, provenance with SHA-256 of the inputs. Every machine limit is checked first: a "
        "command over one is refused, nothing written.",
    )
    add_machine_options(p)
    p.add_argument("--commands", required=True, metavar="FILE", help="the carriage command, .csv or .parquet")
    p.add_argument(
        "--rate",
        type=float,
        metavar="HZ",
        help=f"servo rate in Hz, in [{RATE_RANGE_HZ[0]:g}, {RATE_RANGE_HZ[1]:g}] (default control.servo_rate_Hz)",
    )
    p.add_argument(
        "--counts-per-rev",
        type=float,
        default=DEFAULT_COUNTS_PER_REV,
        metavar="N",
        help=f"encoder counts per motor revolution, in [{COUNTS_RANGE[0]:g}, {COUNTS_RANGE[1]:g}] (default "
        f"{DEFAULT_COUNTS_PER_REV:g}: a 2500-line quadrature encoder)",
    )
    p.add_argument(
        "--drive",
        metavar="FILE",
        help="the drive's data (TOML, as hipsim size takes it): motor top speed and peak torque-speed curve, stroke; "
        "default the parameter file's [motor] table",
    )
    p.add_argument("--out", default="hipsim_export", metavar="DIR", help="folder to write (default hipsim_export)")
    add_summary_format(p, "what to print: a line per file (default) or the sidecar as JSON")
    p.set_defaults(run=run)
    return p


def _check(args, params) -> float:
    rate = params.control.servo_rate if args.rate is None else args.rate
    low, high = RATE_RANGE_HZ
    if not (math.isfinite(rate) and low <= rate <= high):
        raise HipsimError(f"--rate: expected a servo rate in [{low:g}, {high:g}] Hz, got {rate:g} Hz")
    low, high = COUNTS_RANGE
    if not (math.isfinite(args.counts_per_rev) and low <= args.counts_per_rev <= high):
        raise HipsimError(
            f"--counts-per-rev: expected counts per motor revolution in [{low:g}, {high:g}], got {args.counts_per_rev:g}"
        )
    return rate


#: Decimals written per column (by its name's start): far below a count or a µN·m, and short numbers to write and load.
DECIMALS = {
    "t_s": 9,
    "position_counts": 6,
    "velocity_counts_s": 6,
    "position_rev": 10,
    "velocity_rev_s": 10,
    "torque": 9,
}


def _decimals(name: str) -> int:
    return next(d for start, d in DECIMALS.items() if name.startswith(start))


def csv_bytes(columns, period_rows: int | None = None, times: list[str] | None = None) -> bytes:
    """Named float columns as CSV text, each rounded to its :data:`DECIMALS` and written as the shortest number that
    reads back to it (pyarrow's writer, where Python's formatting takes seconds).

    With ``period_rows``, every column but the first (time) repeats with that period: one period of them is
    formatted and repeated beside each row's time (a 10-minute table of a 1 s cycle formats 1,000 rows, not
    600,000); ``times``, the first column already formatted (one line a row), is shared by tables of one clock.
    """
    names = list(columns)
    header = ",".join(names) + "\n"
    n = len(columns[names[0]])
    if not period_rows or period_rows >= n or n % period_rows:
        return header.encode() + _formatted(columns)
    if times is None:
        times = formatted_lines(columns[names[0]], names[0])
    tails = _formatted({name: columns[name][:period_rows] for name in names[1:]}).decode().splitlines()
    rows = "\n".join([f"{a},{b}" for a, b in zip(times, tails * (n // period_rows))])
    return (header + rows + "\n").encode()


def formatted_lines(values, name: str) -> list[str]:
    """One column formatted as :func:`csv_bytes` writes it, a string a row."""
    return _formatted({name: values}).decode().splitlines()


def _formatted(columns) -> bytes:
    import io

    import numpy as np
    import pyarrow as pa
    import pyarrow.csv as pacsv

    buffer = io.BytesIO()
    pacsv.write_csv(
        pa.table(
            {name: pa.array(np.round(values, _decimals(name)), type=pa.float64()) for name, values in columns.items()}
        ),
        buffer,
        pacsv.WriteOptions(include_header=False, quoting_style="none"),
    )
    return buffer.getvalue()


def run(args) -> int:
    """Check the command against every limit, then write the tables and the sidecar; exit status 0."""
    from ..design.feasibility import Limits
    from ..files import check_folder, output_folder, write_atomic
    from ..learning.command_file import read_command_file
    from ..learning.export import drive_tables
    from ..machine.drive import load_drive

    params = parameters(args)
    rate = _check(args, params)
    out = check_folder(Path(args.out))
    drive = load_drive(args.drive) if args.drive else None
    limits = Limits.from_machine(params, drive)
    command = read_command_file(args.commands)
    platform = params.geometry.control if params.geometry is not None else 2
    tables = drive_tables(
        params,
        command.t,
        command.L,
        command.load,
        rate,
        args.counts_per_rev,
        limits,
        guess=command.attitude[platform - 1],
        source=args.commands,
    )
    provenance = page_provenance(args, commands=args.commands, drive=args.drive)
    sidecar = {
        "rate_Hz": rate,
        "samples": len(tables.t),
        "duration_s": len(tables.t) / rate,
        "counts_per_rev": args.counts_per_rev,
        "lead_mm": params.lead * 1e3,
        "units": UNITS,
        "interpolation": "positions and velocities of the command's periodic trigonometric interpolant; a drive's "
        "cubic Hermite between points meets them",
        "torque_from": f"the model's inverse dynamics along platform {tables.platform}'s commanded motion",
        "limits": {"checked": list(tables.checked), "not_checked": list(tables.not_checked), "crossed": []},
        "files": [f"motor_{i}.csv" for i in (1, 2, 3)],
        "provenance": provenance.as_dict(),
    }
    import json

    from ..files import json_ready

    with output_folder(out):
        from concurrent.futures import ThreadPoolExecutor

        times = formatted_lines(tables.t, "t_s") if len(tables.t) > tables.period_samples else None
        with ThreadPoolExecutor(3) as pool:  # pyarrow formats without the GIL: the three tables side by side
            texts = list(
                pool.map(lambda i: csv_bytes(tables.motor_columns(i), tables.period_samples, times), (1, 2, 3))
            )
        for i, text in zip((1, 2, 3), texts):
            write_atomic(out / f"motor_{i}.csv", text)
        write_atomic(out / "export.json", json.dumps(json_ready(sidecar), indent=2) + "\n")
    if args.summary_format == "json":
        print_json(sidecar)
        return 0
    print(
        f"{len(tables.t)} samples at {rate:g} Hz per motor ({len(tables.t) / rate:g} s), {args.counts_per_rev:g} counts/rev"
    )
    print("limits checked: " + (", ".join(tables.checked) or "none"))
    if tables.not_checked:
        print(
            "not checked (no figure; give --drive FILE or the parameter file's [motor] table): "
            + ", ".join(tables.not_checked)
        )
    print(f"wrote {out / 'motor_1.csv'}, motor_2.csv, motor_3.csv and export.json")
    return 0
