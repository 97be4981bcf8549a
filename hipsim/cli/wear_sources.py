"""The motion sources ``hipsim wear`` names: a file's kind told from its columns, ``FILE[:TAG]`` split."""

from __future__ import annotations

from pathlib import Path

from ..exceptions import HipsimError

__all__ = ["header", "kind_of", "split_source"]

#: Columns that tell a file's kind, checked in this order (a simulate output has torque columns too).
_KINDS = (("simulate", ("alpha_des_deg",)), ("stations", ("alpha_1_deg",)), ("rig log", ("tau_1_Nmm", "current_1_A")))


def kind_of(names: set[str]) -> str:
    """A file's kind from its column names: simulate, stations, rig log, else trajectory."""
    return next((kind for kind, marks in _KINDS if any(mark in names for mark in marks)), "trajectory")


def header(path: str) -> set[str]:
    """A table's column names (CSV or Parquet); empty for an OpenSim file or an unreadable one (its reader says why)."""
    from ..exceptions import TrajectoryError
    from ..tables import cells, data_lines, detect_separator, open_parquet, read_text_lines

    suffix = Path(path).suffix.lower()
    if suffix in (".mot", ".sto") or not Path(path).is_file():
        return set()
    if suffix == ".parquet":
        return set(open_parquet(path, "trajectory file", TrajectoryError).schema_arrow.names)
    numbered = data_lines(read_text_lines(path, "trajectory file", TrajectoryError))
    if not numbered:
        return set()
    first = numbered[0][1]
    separator = detect_separator(first, numbered[1][1] if len(numbered) > 1 else None)
    return {cell.strip() for cell in cells(first, separator)}


def split_source(spec: str) -> tuple[str, str | None]:
    """``FILE[:TAG]`` → (FILE, TAG); a file whose name holds a colon is taken whole."""
    if Path(spec).exists() or ":" not in spec:
        return spec, None
    path, tag = spec.rsplit(":", 1)
    if tag not in ("1", "2", "desired"):
        raise HipsimError(
            f"{spec}: expected FILE, FILE:1, FILE:2 (a stations output) or FILE:desired (a simulate output)"
        )
    return path, tag
