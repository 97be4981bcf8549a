"""The identified parameter file: the one writer and the one reader of what ``hipsim identify`` (and ``calibrate``) write.

An identified file is a parameter file every command accepts, with two more tables::

    # comment lines, for people only: never read back
    [slider] … [friction]                the machine (:func:`hipsim.machine.toml_writer.parameter_toml`)
    [identification]                     what the fit found (base parameters, prior, covariance, residual, validation)
    [identification.provenance]          hipsim's version, the time (UTC), the command line and the lab's fields
    [[identification.provenance.inputs]] each input file: role, path, SHA-256 and size in bytes

:func:`write_identified_file` writes it (atomically); :func:`read_identified_file`
reads it back, the machine aside (:func:`hipsim.load_parameters` reads that). A
file is identified when its ``[identification]`` table holds more than a
``prior`` (a starting file may carry ``[identification.prior]``), or, for a file
written before the table existed, when it starts with :data:`IDENTIFIED_MARK`.
What a file's tables say is never taken from its comments; only a file written
before the tables existed is read from its comment header (its values, its
``# Made by hipsim …`` line and its input hashes), so old files read as they did.
"""

from __future__ import annotations

import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

from ...exceptions import ParameterError
from ...files import write_atomic
from ...machine.parameter_set import Parameters
from ...machine.parameters import read_toml
from ...machine.toml_writer import parameter_toml, table_toml, toml_value
from .quantities import QUANTITIES

__all__ = [
    "IDENTIFIED_MARK",
    "FileEstimate",
    "FileProvenance",
    "IdentifiedFile",
    "InputRecord",
    "identification_table",
    "identified_toml",
    "read_identified_file",
    "write_identified_file",
]

#: The first comment line of a file ``hipsim identify`` writes; how a file written before the tables is recognised.
IDENTIFIED_MARK = "# Identified by hipsim identify"


@dataclass(frozen=True)
class InputRecord:
    """One input file of an identification: its role ("parameters", "log", "validate"…), path, SHA-256 (hex) and size in [bytes].

    ``size`` is None when an old file's comment header did not say it.
    """

    role: str
    path: str
    sha256: str
    size: int | None = None

    def table(self) -> dict[str, Any]:
        return {"role": self.role, "path": self.path, "sha256": self.sha256} | (
            {} if self.size is None else {"bytes": self.size}
        )


@dataclass(frozen=True)
class FileProvenance:
    """What made an identified file (its ``[identification.provenance]`` table).

    Attributes:
        version: hipsim's version.
        created: date and time, ISO 8601 UTC.
        command: the command line, shell-quoted.
        inputs: each input file with its SHA-256.
        title, author, rig: the lab's fields (``--title``, ``--author``, ``--rig``), or None.
        warnings: what the fit's self-check found implausible, for a file written with ``--force`` (issue 48).
    """

    version: str
    created: str
    command: str
    inputs: tuple[InputRecord, ...] = ()
    title: str | None = None
    author: str | None = None
    rig: str | None = None
    warnings: tuple[str, ...] = ()

    @classmethod
    def from_dict(cls, block: Mapping[str, Any]) -> FileProvenance:
        """From a page's provenance block as JSON has it (:meth:`hipsim.present.provenance.Provenance.as_dict`)."""
        return cls(
            str(block["hipsim"]),
            str(block["created_utc"]),
            str(block["command"]),
            tuple(InputRecord(f["role"], f["path"], f["sha256"], f.get("bytes")) for f in block.get("inputs", ())),
            block.get("title"),
            block.get("author"),
            block.get("rig"),
            tuple(str(w) for w in block.get("warnings", ())),
        )

    def made(self) -> str:
        """The sentence "Made by hipsim 0.9 on 2026-11-27T04:00:00Z (UTC): hipsim identify …"."""
        return f"Made by hipsim {self.version} on {self.created} (UTC): {self.command}"

    def comments(self) -> list[str]:
        """The comment lines that tell a reader the same (the file's tables are what programs read)."""
        lines = [f"# {self.made()}"]
        lines += [f"#   {f.role} {f.path}: SHA-256 {f.sha256}" for f in self.inputs]
        lines += [
            f"# {label}: {value}"
            for label, value in (("Title", self.title), ("Author", self.author), ("Rig", self.rig))
            if value
        ]
        lines += [f"# WARNING (written with --force): {warning}" for warning in self.warnings]
        return lines

    def toml(self) -> str:
        """The ``[identification.provenance]`` table and one ``[[identification.provenance.inputs]]`` table per input."""
        entries: dict[str, Any] = {"hipsim": self.version, "created_utc": self.created, "command": self.command}
        entries |= {k: v for k, v in (("title", self.title), ("author", self.author), ("rig", self.rig)) if v}
        if self.warnings:
            entries["warnings"] = list(self.warnings)
        text = table_toml("identification.provenance", entries)
        for record in self.inputs:
            text += "\n[[identification.provenance.inputs]]\n"
            text += "".join(f"{key} = {toml_value(value)}\n" for key, value in record.table().items())
        return text


@dataclass(frozen=True)
class FileEstimate:
    """One base parameter as an identified file gives it (file units).

    Attributes:
        label: its name (``m_L``); key: its parameter's file key; unit: the file's unit.
        value, std: posterior mean and standard deviation.
        determined: whether the logs determined it.
        definition: the combination it stands for (``m_L + 0.5 kg·m_l``); the label alone for none.
    """

    label: str
    key: str
    unit: str
    value: float
    std: float
    determined: bool
    definition: str

    @property
    def terms(self) -> list[str]:
        """The labels of the other parameters its definition combines."""
        return [term for term in re.findall(r"·([^\s·+−]+)", self.definition) if term in _labels()]


@dataclass(frozen=True)
class IdentifiedFile:
    """An identified parameter file, read back (the machine aside).

    Attributes:
        source: the file.
        lever_spin: the model the fit used (True: levers with the universal joints' spin).
        logs: the logs fitted, by name.
        start: the starting parameters it names.
        estimates: every base parameter (determined or not); an old file's header gives the determined ones only.
        held: parameter keys not identified, with the reason (an old file's header, or from ``estimates``).
        combined: keys that keep their starting value inside an identified combination.
        validation: per held-out log, the RMS torque error per motor in [N·mm], (identified, starting).
        provenance: what made it, or None when the file does not say.
        table: the ``[identification]`` table as read (empty for an old file), its sub-tables included.
        from_comments: True for a file written before the tables, read from its comment header.
    """

    source: str
    lever_spin: bool
    logs: tuple[str, ...]
    start: str
    estimates: tuple[FileEstimate, ...]
    held: tuple[tuple[str, str], ...]
    combined: tuple[str, ...]
    validation: tuple[tuple[str, tuple[tuple[float, float], ...]], ...]
    provenance: FileProvenance | None
    table: Mapping[str, Any]
    from_comments: bool = False


# --- Writing ----------------------------------------------------------------------------------


def identified_toml(
    params: Parameters,
    table: Mapping[str, Any],
    provenance: FileProvenance | None = None,
    comments: Sequence[str] = (),
    tables: Mapping[str, Mapping[str, Any]] | None = None,
) -> str:
    """The text of an identified file.

    Args:
        params: the identified machine.
        table: the ``[identification]`` table (plain values, lists and lists of lists; no ``provenance`` key).
        provenance: what made it; None for a file made from Python without one.
        comments: lines for people, written first (a ``#`` is added to a line without one); :data:`IDENTIFIED_MARK`
            first when they do not start with it, and the provenance's own lines after them.
        tables: more sub-tables of ``[identification]`` by name (``calibration`` → ``[identification.calibration]``).

    Raises:
        ParameterError: a table or sub-table named ``provenance``: the writer's own.
    """
    reserved = {"provenance"} & (set(table) | set(tables or {}))
    if reserved:
        raise ParameterError(
            "is written by the identified file's writer itself", key=f"identification.{reserved.pop()}"
        )
    lines = [line if line.startswith("#") else f"# {line}" for line in comments]
    if not lines or not lines[0].startswith(IDENTIFIED_MARK):
        lines.insert(0, IDENTIFIED_MARK + ": a parameter file every hipsim command accepts (--params).")
    if provenance is not None:
        lines[1:1] = provenance.comments()  # the mark stays first
    text = "\n".join(lines) + "\n\n" + parameter_toml(params) + "\n" + table_toml("identification", dict(table))
    for name, entries in (tables or {}).items():
        text += "\n" + table_toml(f"identification.{name}", dict(entries))
    if provenance is not None:
        text += "\n" + provenance.toml()
    return text


def write_identified_file(
    path: str | Path,
    params: Parameters,
    table: Mapping[str, Any],
    provenance: FileProvenance | None = None,
    comments: Sequence[str] = (),
    tables: Mapping[str, Mapping[str, Any]] | None = None,
) -> Path:
    """Write :func:`identified_toml` atomically (nothing half-written). Returns the path."""
    return write_atomic(path, identified_toml(params, table, provenance, comments, tables))


# --- Reading ----------------------------------------------------------------------------------


def identification_table(path: str | Path) -> Mapping[str, Any]:
    """A parameter file's ``[identification]`` table as it is (empty without one).

    Raises:
        ParameterError: naming the file: missing, unreadable, not TOML, or ``identification`` not a table.
    """
    table = read_toml(path).get("identification", {})
    if not isinstance(table, dict):
        raise ParameterError("expected a table", key="identification", source=str(path))
    return table


def read_identified_file(path: str | Path) -> IdentifiedFile | None:
    """An identified file read back; None for a parameter file that is not one.

    Raises:
        ParameterError: naming the file and key: unreadable, not TOML, or a table of the wrong shape.
    """
    source = str(path)
    table = identification_table(path)
    if set(table) - {"prior"}:
        found = _from_table(source, table)
        if found.provenance is None:  # written before [identification.provenance]: its comment header says it
            header = _header(path, source)
            if header is not None:
                found = replace(found, provenance=header.provenance)
        return found
    return _header(path, source)


def _header(path: str | Path, source: str) -> IdentifiedFile | None:
    """An old file's comment header read (:func:`_from_comments`); None when the file does not start with the mark."""
    try:
        lines = Path(path).read_text(encoding="utf-8-sig").splitlines()
    except (OSError, UnicodeDecodeError):
        return None
    if not lines or not lines[0].startswith(IDENTIFIED_MARK):
        return None
    return _from_comments(source, lines)


def _labels() -> dict[str, str]:
    """The identification's short names → parameter keys (``m_L`` → ``slider.mass_kg``)."""
    return {q.label: q.key for q in QUANTITIES}


def _list(table: Mapping[str, Any], key: str, source: str, size: int | None = None) -> list:
    value = table.get(key, [])
    if not isinstance(value, list) or (size is not None and len(value) != size):
        expected = "a list" if size is None else f"a list of {size} (one per base parameter)"
        raise ParameterError(f"expected {expected}, got {value!r}"[:200], key=f"identification.{key}", source=source)
    return value


def _provenance_table(table: Mapping[str, Any], source: str) -> FileProvenance | None:
    block = table.get("provenance")
    if block is None:
        return None
    key = "identification.provenance"
    if not isinstance(block, dict) or not all(
        isinstance(block.get(k), str) for k in ("hipsim", "created_utc", "command")
    ):
        raise ParameterError("expected a table with hipsim, created_utc and command (text)", key=key, source=source)
    inputs = block.get("inputs", [])
    if not isinstance(inputs, list) or not all(
        isinstance(f, dict) and all(isinstance(f.get(k), str) for k in ("role", "path", "sha256")) for f in inputs
    ):
        raise ParameterError(
            "expected [[inputs]] tables with role, path and sha256", key=key + ".inputs", source=source
        )
    return FileProvenance.from_dict(block)


def _from_table(source: str, table: Mapping[str, Any]) -> IdentifiedFile:
    labels = _labels()
    names = _list(table, "base", source)
    columns = [_list(table, key, source, len(names)) for key in ("keys", "units", "value", "std")]
    determined = table.get("determined", [True] * len(names))
    definitions = table.get("definitions", list(names))
    for key, value in (("determined", determined), ("definitions", definitions)):
        _list({key: value}, key, source, len(names))
    try:
        estimates = tuple(
            FileEstimate(str(label), str(key), str(unit), float(value), float(std), bool(d), str(definition))
            for label, key, unit, value, std, d, definition in zip(names, *columns, determined, definitions)
        )
    except (TypeError, ValueError):
        raise ParameterError("value and std: expected numbers", key="identification", source=source) from None
    combined, held = [], []
    for estimate in estimates:
        terms = [labels[term] for term in estimate.terms]
        if estimate.determined:
            combined += terms
        else:
            reason = f"not determined by these logs: near its prior ({estimate.value:.6g} ± {estimate.std:.2g} {estimate.unit})"
            held.append((estimate.key, reason.replace(" )", ")")))
            held += [(key, f"folded into {estimate.label}, not determined by these logs") for key in terms]
    validation: list = []
    names_, errors, starting = (
        table.get(c) for c in ("validation_logs", "validation_rms_error_Nmm", "validation_start_rms_error_Nmm")
    )
    if isinstance(names_, list) and isinstance(errors, list) and isinstance(starting, list):
        if not len(names_) == len(errors) == len(starting):
            raise ParameterError(
                "validation_logs, validation_rms_error_Nmm and validation_start_rms_error_Nmm differ in length",
                key="identification",
                source=source,
            )
        try:
            validation = [
                (str(name), tuple((float(a), float(b)) for a, b in zip(e, s0)))
                for name, e, s0 in zip(names_, errors, starting)
            ]
        except (TypeError, ValueError):
            raise ParameterError(
                "expected three numbers per log", key="identification.validation_rms_error_Nmm", source=source
            ) from None
    logs = table.get("logs", [])
    return IdentifiedFile(
        source,
        bool(table.get("lever_spin", True)),
        tuple(str(name) for name in logs) if isinstance(logs, list) else (),
        str(table.get("start", "")),
        estimates,
        tuple(held),
        tuple(dict.fromkeys(combined)),
        tuple(validation),
        _provenance_table(table, source),
        table,
    )


# An old file's comment header (written before the [identification] table held everything), line by line.
_QUANTITY_LINE = re.compile(
    r"^# +(?P<expr>.+?) = (?P<value>\S+) ± (?P<std>\S+) ?(?P<unit>[^(]*?) ?\((?P<relative>[^)]*)\)$"
)
_VALIDATION_LINE = re.compile(r"^# +(?P<log>.+?): (?P<errors>M1 .*) N·mm$")
_MADE_LINE = re.compile(r"^# Made by hipsim (?P<version>\S+) on (?P<created>\S+) \(UTC\): (?P<command>.*)$")
_HASH_LINE = re.compile(r"^#   (?P<role>\S+) (?P<path>.+): SHA-256 (?P<sha>[0-9a-f]{64})$")
_HELD_LINE = re.compile(r"^# +(?P<label>\S+) = \S+ .*?: (?P<reason>.+)$")
_MODEL_LINE = re.compile(r"^# Model: .*lever spin (?P<spin>on|off)")


def _from_comments(source: str, lines: Sequence[str]) -> IdentifiedFile:
    """What an old file's comment header says (the lines are matched one by one; a line not understood is skipped)."""
    labels = _labels()
    logs: tuple[str, ...] = ()
    start, spin, section, made = "", True, "", None
    hashes: list[InputRecord] = []
    estimates, combined, held, validation = [], [], [], []
    for line in lines:
        if not line.startswith("#"):
            break
        if match := _MADE_LINE.match(line):
            made = match
        elif match := _MODEL_LINE.match(line):
            spin = match["spin"] == "on"
        elif not section and (match := _HASH_LINE.match(line)):
            hashes.append(InputRecord(match["role"], match["path"], match["sha"]))
        elif line.startswith("# From the logs: "):
            names = line[len("# From the logs: ") :].rsplit(" (", 1)[0]
            logs = tuple(name.strip() for name in names.split(", ") if name.strip())
        elif line.startswith("# Starting parameters: "):
            start = line[len("# Starting parameters: ") :].rstrip(".")
        elif line.startswith("# Identified ("):
            section = "identified"
        elif line.startswith("# Not identified"):
            section = "held"
        elif line.startswith("# Validation"):
            section = "validation"
        elif line.startswith("#  ") and section == "identified":  # identify wrote these with two spaces
            match = _QUANTITY_LINE.match(line)
            if match is None:
                continue
            expression = match["expr"]
            label = re.split(r" [+−] ", expression, maxsplit=1)[0]
            if label not in labels:
                continue
            try:
                value, std = float(match["value"]), float(match["std"])
            except ValueError:
                continue
            estimate = FileEstimate(label, labels[label], match["unit"].strip(), value, std, True, expression)
            combined += [labels[term] for term in estimate.terms]
            estimates.append(estimate)
        elif line.startswith("#  ") and section == "held":
            match = _HELD_LINE.match(line)
            if match is not None and match["label"] in labels:
                held.append((labels[match["label"]], match["reason"]))
        elif line.startswith("#  ") and section == "validation":
            match = _VALIDATION_LINE.match(line)
            if match is None:
                continue
            pairs = re.findall(r"M\d (\S+) vs (\S+)", match["errors"])
            try:
                validation.append((match["log"], tuple((float(a), float(b)) for a, b in pairs)))
            except ValueError:
                continue
    provenance = None
    if made is not None:
        provenance = FileProvenance(made["version"], made["created"], made["command"], tuple(hashes))
    return IdentifiedFile(
        source,
        spin,
        logs,
        start,
        tuple(estimates),
        tuple(held),
        tuple(dict.fromkeys(combined)),
        tuple(validation),
        provenance,
        {},
        from_comments=True,
    )
