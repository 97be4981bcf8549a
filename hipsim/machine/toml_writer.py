"""The one writer of parameter files: a machine back as the text of a TOML file every command reads.

:func:`parameter_toml` writes every section of :data:`~hipsim.machine.schema.SCHEMA`
in the file's units (:func:`~hipsim.machine.parameters.file_values`, 15
significant digits), each key with its meaning as a comment; what it writes,
:func:`~hipsim.machine.parameters.load_parameters` reads back to the same machine.
Identified machines (:meth:`hipsim.rig.Identification.toml`), the parameter
set stored in results files and ``hipsim params`` all go through it.
"""

from __future__ import annotations

import math

from .chains import CONTROL_MEANING, GEOMETRY_KEYS, geometry_table
from .parameter_set import Parameters
from .parameters import file_values
from .schema import SCHEMA

__all__ = ["parameter_toml", "table_toml", "toml_value"]


def toml_value(value) -> str:
    """One value as TOML spells it: a bool, a string, a number (``inf`` for infinity) or a list of these."""
    if isinstance(value, bool):  # before numbers: a bool is an int to Python
        return "true" if value else "false"
    if isinstance(value, str):
        return '"' + value.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(value, list):
        return "[" + ", ".join(toml_value(v) for v in value) + "]"
    if isinstance(value, float):
        if math.isinf(value):
            return "inf" if value > 0 else "-inf"
        return repr(float(f"{value:.15g}"))
    return repr(value)


def parameter_toml(params: Parameters, title: str | None = None, units: bool = False, comment_column: int = 0) -> str:
    """A machine as the text of a parameter file (every section, file units, 15 significant digits).

    Args:
        params: the machine.
        title: a first comment line (``"parameters: <source>"``) and a blank line before the tables; None for none.
        units: add each key's unit to its comment (``# l, lever length [mm]``).
        comment_column: pad each entry to this many characters before its comment; 0 for two spaces.

    Returns:
        The text, one ``[section]`` table after another, each followed by a blank line.
    """
    values = file_values(params)
    lines = [f"# {title}", ""] if title is not None else []
    for section, keys in SCHEMA.items():
        present = [key for key in keys if f"{section}.{key}" in values]  # an optional table may be absent
        if not present:
            continue
        lines.append(f"[{section}]")
        for key in present:
            value = values[f"{section}.{key}"]
            spec = SCHEMA[section][key]
            note = spec.meaning + (f" [{spec.unit}]" if units and spec.unit else "")
            entry = f"{key} = {toml_value(value)}"
            if comment_column:
                lines.append(entry.ljust(comment_column) + f"# {note}")
            else:
                lines.append(entry + (f"  # {note}" if note else ""))
        lines.append("")
    if params.geometry is not None:
        lines += _geometry_lines(params)
    return "\n".join(lines)


def _geometry_lines(params: Parameters) -> list[str]:
    """The ``[geometry]`` table: each chain's deviation from the drawing, in mm (:mod:`hipsim.machine.chains`)."""
    assert params.geometry is not None
    lines = [
        "# Per-chain deviations from the drawing in mm; rows: chains 11, 12, 13, 21, 22, 23 (platform j, module i).",
        "[geometry]",
    ]
    for key, value in geometry_table(params.geometry).items():
        lines.append(f"# {GEOMETRY_KEYS[key][3] if key in GEOMETRY_KEYS else CONTROL_MEANING}")
        lines.append(f"{key} = {toml_value(value)}")
    lines.append("")
    return lines


def table_toml(name: str, entries: dict) -> str:
    """One ``[name]`` table: each entry ``key = value`` (:func:`toml_value`; lists of lists for matrices), then a blank line.

    Keys that are not bare TOML keys are quoted.
    """
    lines = [f"[{name}]"]
    for key, value in entries.items():
        bare = key.replace("_", "").replace("-", "").isalnum() and key.isascii()
        lines.append(f"{key if bare else toml_value(key)} = {toml_value(value)}")
    return "\n".join(lines) + "\n"
