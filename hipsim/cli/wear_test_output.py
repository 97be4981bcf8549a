"""The outputs of ``hipsim wear --weighings``: per-station context read, the table of stops, the summary, the page."""

from __future__ import annotations

import math
from pathlib import Path

__all__ = ["context", "format_result", "print_result", "write_outputs"]


def _station_number(args, name: str) -> int | None:
    for text in args.station or ():
        station, _, spec = text.partition("=")
        if station == name and spec.rpartition(":")[2] in ("1", "2"):
            return int(spec.rpartition(":")[2])
    return int(name) if name in ("1", "2") else None


def _motion(args, name: str):
    from ..wear.test_context import motion_error

    for text in args.station or ():
        station, _, spec = text.partition("=")
        path, _, j = spec.rpartition(":")
        if station != name or j not in ("1", "2") or path == "snapshots" or not Path(path).is_file():
            continue
        errors = motion_errors(path, tuple(f"err_{angle}_{j}_deg" for angle in ("alpha", "beta", "gamma")))
        return None if errors is None else motion_error(errors, f"{path}, platform {j}")
    return None


def motion_errors(path: str, columns: tuple[str, ...]):
    """A stations output's error columns (N, len(columns)) in [deg], or None when it has none of them (a motion
    file without errors: the motion error is not known, not an error).

    Raises:
        FileRowError: a malformed file, naming it: some of the columns and not the others, a cell that is not a
            finite number (by line and column), no rows.
    """
    import numpy as np

    from ..exceptions import FileRowError
    from ..tables import open_parquet
    from ..wear.laws import read_numeric_columns
    from .wear_sources import header

    present = [column for column in columns if column in header(path)]
    if not present:
        return None
    if Path(path).suffix.lower() not in (".parquet", ".pq"):
        return read_numeric_columns(path, columns, "stations output")[0]
    if len(present) < len(columns):
        missing = ", ".join(column for column in columns if column not in present)
        raise FileRowError(f"no column {missing} beside {', '.join(present)}", source=path)
    table = open_parquet(path, "stations output").read(columns=list(columns))
    errors = np.empty((table.num_rows, len(columns)))
    for c, column in enumerate(columns):
        try:
            errors[:, c] = table.column(column).to_numpy(zero_copy_only=False).astype(float)
        except (TypeError, ValueError):
            raise FileRowError(
                f"expected numbers in [deg], got {table.column(column).type}", source=path, column=column
            ) from None
        bad = np.flatnonzero(~np.isfinite(errors[:, c]))
        if bad.size:
            raise FileRowError(
                f"expected a finite number, got {errors[bad[0], c]} at row {bad[0] + 1}", source=path, column=column
            )
    if not table.num_rows:
        raise FileRowError("the stations output has no rows", source=path)
    return errors


def context(args, result, errors: dict):
    """Per station: its motion error (a stations output's own columns, else ``errors``: the snapshots' or the
    motion's against ISO by gait phase) and its friction (from the monitor's table)."""
    from ..wear.test_context import StationContext, friction_state

    table = None
    if args.friction:
        from ..rig.monitoring.monitor_table import read_table

        table = read_table(args.friction)
    out = []
    for station in result.stations:
        name = station.rate.station
        friction = None if table is None else friction_state(table, _station_number(args, name), args.friction)
        out.append(StationContext(name, _motion(args, name) or errors.get(name), friction))
    return tuple(out)


def _rows(result) -> dict:
    import numpy as np

    columns: dict[str, list] = {"station": [], "cycle": [], "loss_mg": [], "volume_mm3": [], "predicted_mm3": []}
    for s in result.stations:
        rate = s.rate
        kind, k = (result.given.kind, result.given.k) if result.given else ("local", s.fitted.k("local"))
        predicted = s.exposure.predicted_mm3(k, kind, np.asarray(rate.cycles, dtype=float))
        for c, loss, volume, p in zip(rate.cycles, rate.loss_mg, rate.volume_mm3, predicted, strict=True):
            columns["station"].append(rate.station)
            columns["cycle"].append(c)
            columns["loss_mg"].append(loss)
            columns["volume_mm3"].append(volume)
            columns["predicted_mm3"].append(float(p))
    return columns


def _write_csv(path: str, columns: dict) -> None:
    from ..files import write_atomic

    names = list(columns)
    lines = [",".join(names)]
    for k in range(len(columns["station"])):
        lines.append(",".join(str(columns[name][k]) if name == "station" else repr(columns[name][k]) for name in names))
    write_atomic(path, "\n".join(lines) + "\n")


def write_outputs(args, result, contexts, notes, inputs) -> dict[str, str]:
    """The table of stops (--out, CSV), and the page, JSON and fitted law (--report)."""
    from ..files import write_atomic

    written: dict[str, str] = {}
    columns = _rows(result)
    if args.report:
        from ..present.wear_test_page import write_wear_test_page
        from .common import page_provenance

        provenance = page_provenance(args, **{key.replace(" ", "_"): value for key, value in inputs.items()})
        page = write_wear_test_page(args.report, result, contexts, provenance, tuple(notes), args.pdf)
        written["index"] = str(page.index)
        if page.pdf is not None:
            written["pdf"] = str(page.pdf)
        if result.fitted_law is not None:
            law = result.fitted_law
            text = "# k(CS) fitted from the weighings by hipsim wear: each station's local k at its work-weighted CS\n"
            text += "cross_shear,k_mm3_per_Nm\n" + "".join(
                f"{cs!r},{k!r}\n" for cs, k in zip(law.cross_shear.tolist(), law.k.tolist(), strict=True)
            )
            written["wear_law"] = str(write_atomic(Path(args.report) / "fitted_wear_law.csv", text))
    if args.out and args.out != "-":
        _write_csv(args.out, columns)
        written["table"] = str(args.out)
    return written


def _ci(pair) -> str:
    low, high = pair
    return "–" if not (math.isfinite(low) and math.isfinite(high)) else f"[{low:.4g}, {high:.4g}]"


def format_result(result, contexts, notes) -> str:
    """The result as tables: the verdict first."""
    from ..present.tables import format_table

    g = result.gravimetry
    out = [f"verdict: {result.word}", *(f"  {line}" for line in result.lines)]
    rows = []
    for s in result.stations:
        r = s.rate
        rows.append(
            [
                r.station,
                f"{r.rate_mg_per_Mc:.4g}",
                _ci(r.ci95_mg_per_Mc),
                f"{r.rate_mm3_per_Mc:.4g}",
                _ci(r.ci95_mm3_per_Mc),
                f"{r.from_cycle / 1e6:.3g} ({r.bedding_in})",
                f"{s.fitted.k('local'):.3g} {_ci(s.fitted.ci95('local'))}",
                f"{s.fitted.k('force-track'):.3g} {_ci(s.fitted.ci95('force-track'))}",
            ]
        )
    out.append(
        format_table(
            ["station", "mg/Mc", "95 %", "mm³/Mc", "95 %", "from Mc (bedding-in)", "k local", "k force-track"],
            rows,
            f"Wear rates ({g.density_stated}; k in mm³/(N·m) from each station's own motion)",
        )
    )
    if g.differences:
        out.append(
            format_table(
                ["stations", "mg/Mc", "95 %", "mm³/Mc", "95 %"],
                [
                    [
                        f"{d.b} − {d.a}",
                        f"{d.difference_mg_per_Mc:+.4g}",
                        _ci(d.ci95_mg_per_Mc),
                        f"{d.difference_mm3_per_Mc:+.4g}",
                        _ci(d.ci95_mm3_per_Mc),
                    ]
                    for d in g.differences
                ],
                "Differences between stations",
            )
        )
    if result.reference is not None:
        rows = []
        for s in result.stations:
            predicted = s.fitted.predict(result.reference)
            rows += [[s.rate.station, kind, f"{v:.4g}", _ci((lo, hi))] for kind, (v, lo, hi) in predicted.items()]
        out.append(
            format_table(["station", "k kind", "mm³/Mc", "95 %"], rows, "Each station's k on the built-in ISO cycle")
        )
    for c in contexts:
        if c.motion is not None:
            out.append(
                f"station {c.station} motion error RMS α, β, γ: "
                + ", ".join(f"{x:.3g}" for x in c.motion.rms_deg)
                + " deg"
            )
        if c.friction is not None:
            out.append(f"station {c.station} friction: {c.friction.describe()}")
    out += [f"note: {note}" for note in notes]
    return "\n".join(out)


def print_result(args, result, contexts, notes, written) -> None:
    """The summary on standard output: tables (verdict first) or JSON."""
    from .common import print_json

    if args.summary_format == "json":
        from ..wear.test_summary import wear_test_summary
        from .documents_more import WearTestRun

        print_json(WearTestRun(wear_test_summary(result, contexts), tuple(notes), **written).to_json())
    else:
        print(format_result(result, contexts, notes))
        if written:
            print(f"wrote {', '.join(written.values())}")
