"""A carriage command file read fast: ``hipsim learn``'s or ``hipsim stations``' table (CSV or Parquet).

Columns: ``t_s``, ``L_11_mm, L_12_mm, L_13_mm``; optional ``Fe_N`` (the load)
and ``alpha_j_deg, beta_j_deg, gamma_j_deg`` (the model's predicted attitude,
used as a starting guess). Other columns are ignored. Read by pyarrow's CSV
reader (a 10-minute command at 1 kHz in a fraction of a second).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..exceptions import TrajectoryError

__all__ = ["CommandFile", "read_command_file"]

CARRIAGES = tuple(f"L_1{i}_mm" for i in (1, 2, 3))


@dataclass(frozen=True, eq=False)
class CommandFile:
    """A command as read, SI: t [s] (N,), L [m] (N, 3), load [N] (N,) (zeros without ``Fe_N``), attitude [rad]
    (N, 2, 3) or None per platform (the file's prediction)."""

    source: str
    t: np.ndarray
    L: np.ndarray
    load: np.ndarray
    attitude: tuple[np.ndarray | None, np.ndarray | None]


def read_command_file(path: str | Path) -> CommandFile:
    """The command in ``path``.

    Raises:
        TrajectoryError: no such file, a missing column, a cell that is not a number (naming its row), time that
            does not increase.
    """
    import pyarrow as pa
    import pyarrow.csv as pacsv

    source = str(path)
    if not Path(path).is_file():
        raise TrajectoryError("no such file", source=source)
    try:
        if Path(path).suffix.lower() in (".parquet", ".pq"):
            import pyarrow.parquet as pq

            table = pq.read_table(path)
        else:
            with open(path, encoding="utf-8", errors="replace") as stream:
                header = [name.strip().strip('"') for name in stream.readline().split(",")]
            wanted = ["t_s", *CARRIAGES, "Fe_N"] + [f"{a}_{j}_deg" for j in (1, 2) for a in ("alpha", "beta", "gamma")]
            table = pacsv.read_csv(  # only the columns used: a long command reads in half the time
                path,
                parse_options=pacsv.ParseOptions(delimiter=","),
                convert_options=pacsv.ConvertOptions(include_columns=[n for n in wanted if n in header]),
            )
    except (pa.ArrowInvalid, OSError) as error:
        raise TrajectoryError(str(error).splitlines()[0], source=source) from None
    names = table.column_names
    missing = [name for name in ("t_s",) + CARRIAGES if name not in names]
    if missing:
        raise TrajectoryError(
            f"missing column(s) {', '.join(missing)} (the header has {', '.join(names)})", source=source
        )

    def column(name: str) -> np.ndarray:
        try:
            return np.asarray(table.column(name).to_numpy(zero_copy_only=False), dtype=float)
        except (TypeError, ValueError, pa.ArrowInvalid):
            raise TrajectoryError("a cell is not a number", source=source, column=name) from None

    t = column("t_s")
    L = np.stack([column(name) for name in CARRIAGES], axis=1) * 1e-3
    if len(t) > 1 and np.any(np.diff(t) <= 0):
        k = int(np.argmax(np.diff(t) <= 0)) + 1
        raise TrajectoryError(
            f"time does not increase (t = {t[k]:.6g} s after {t[k - 1]:.6g} s)", source=source, column="t_s"
        )
    load = column("Fe_N") if "Fe_N" in names else np.zeros(len(t))
    attitude = []
    for j in (1, 2):
        wanted = [f"{a}_{j}_deg" for a in ("alpha", "beta", "gamma")]
        attitude.append(
            np.radians(np.stack([column(n) for n in wanted], axis=1)) if all(n in names for n in wanted) else None
        )
    return CommandFile(source, t, L, load, (attitude[0], attitude[1]))
