"""Where a page's numbers came from: the block every report page and JSON summary carries.

A lab signs a report only when it can say what made it: the hipsim version,
the date and time (UTC, ISO 8601), the command line, each input file with its
SHA-256, the parameter file and where its values came from, and the fields a
lab fills in (``--title``, ``--author``, ``--rig``). :func:`provenance` builds
that block as plain data (:class:`Provenance`; ``as_dict`` for JSON), and the
template partial ``templates/provenance.html.j2`` shows it on a page.

Where the parameter values came from (:func:`parameter_origin`): the
package's own file is the published machine; a file that ``hipsim identify``
wrote carries its ``[identification]`` table (the logs fitted, the starting
parameters, every base parameter with its definition, value, standard
deviation and whether the logs determined it, the held-out (validation)
errors), and those are read back from it (from its comment header for a file
written before the table existed); any other file is the user's; ``--set``
overrides are listed key by key.
"""

from __future__ import annotations

import datetime as _datetime
import hashlib
import re
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

__all__ = [
    "IdentifiedValue",
    "InputFile",
    "ParameterOrigin",
    "Provenance",
    "file_sha256",
    "parameter_origin",
    "provenance",
]

#: The first line of a parameter file ``hipsim identify`` wrote.
IDENTIFIED_MARK = "# Identified by hipsim identify"


@dataclass(frozen=True)
class InputFile:
    """One input file: its role ("trajectory", "log", "drive"...), path, size in [bytes] and SHA-256 (hex)."""

    role: str
    path: str
    sha256: str
    size: int

    def as_dict(self) -> dict[str, Any]:
        return {"role": self.role, "path": self.path, "sha256": self.sha256, "bytes": self.size}


@dataclass(frozen=True)
class IdentifiedValue:
    """A parameter an identification determined: its file key, the value and standard deviation in the file's unit.

    Attributes:
        key: the parameter file's key, with a component for inertias (``platform.inertia_kgmm2[xy]``).
        label: the identification's short name (``m_L``).
        value: the identified quantity in [unit].
        std: its standard deviation in [unit].
        unit: the file's unit.
        combination: the whole combination the data determine (``m_L + 0.5 kg·m_l``), when it is one.
    """

    key: str
    label: str
    value: float
    std: float
    unit: str
    combination: str = ""


@dataclass(frozen=True)
class ParameterOrigin:
    """Where a parameter set's values came from.

    Attributes:
        file: the parameter file, as an :class:`InputFile`.
        kind: "published" (the package's file), "identified" (written by ``hipsim identify``) or "file".
        start: for an identified file, the starting parameters it names.
        logs: for an identified file, the logs fitted.
        validation: for an identified file, per held-out log the RMS torque error per motor in [N·mm],
            identified and starting parameters: (log, ((M1 identified, M1 starting), ...)).
        identified: the identified values, by their key.
        combined: keys that keep their starting value inside an identified combination.
        held: keys not identified (starting value kept), with the reason.
        overrides: the ``--set`` overrides, KEY=VALUE as typed.
        made: for an identified file, the line saying which hipsim made it, when and with what command.
        log_hashes: for an identified file, the SHA-256 of each input it names: (role, path, SHA-256).
    """

    file: InputFile
    kind: str
    start: str = ""
    logs: tuple[str, ...] = ()
    validation: tuple[tuple[str, tuple[tuple[float, float], ...]], ...] = ()
    identified: tuple[IdentifiedValue, ...] = ()
    combined: tuple[str, ...] = ()
    held: tuple[tuple[str, str], ...] = ()
    overrides: tuple[str, ...] = ()
    made: str = ""
    log_hashes: tuple[tuple[str, str, str], ...] = ()

    def origin_of(self, dotted: str) -> tuple[str, list[IdentifiedValue]]:
        """How ``dotted`` (``lever.mass_kg``) got its value, in words, and its identified components (empty: none)."""
        if any(text.split("=", 1)[0].strip() == dotted for text in self.overrides):
            return "--set", []
        found = [v for v in self.identified if v.key.split("[")[0] == dotted]
        if found:
            return "identified", found
        if self.kind == "identified":
            if any(key.split("[")[0] == dotted for key in self.combined):
                return "start value, in an identified combination", []
            if any(key.split("[")[0] == dotted for key, _ in self.held):
                return "start value, not identified", []
            return "start value", []
        return self.kind, []

    def summary(self) -> str:
        """One sentence: "published (…/hip_simulator.toml)", "identified from fit.csv (held-out error …)"."""
        text = {"published": "published values", "file": "values as written in the file"}.get(self.kind, "identified")
        if self.kind == "identified":
            text += f" from {', '.join(self.logs) or 'logs not named'}; starting parameters {self.start or 'not named'}"
            for log, errors in self.validation:
                text += (
                    f"; held-out error on {log}: "
                    + ", ".join(f"M{i + 1} {a:.3g}" for i, (a, _) in enumerate(errors))
                    + " N·mm RMS (starting parameters: "
                    + ", ".join(f"{b:.3g}" for _, b in errors)
                    + ")"
                )
            if not self.validation:
                text += "; no held-out log (the file names no validation)"
            if self.made:
                text += f"; {self.made[0].lower()}{self.made[1:]}"
        if self.overrides:
            text += "; overridden with --set " + ", ".join(self.overrides)
        return text

    def as_dict(self) -> dict[str, Any]:
        return {
            "file": self.file.as_dict(),
            "kind": self.kind,
            "summary": self.summary(),
            "start": self.start or None,
            "logs": list(self.logs),
            "validation": [
                {"log": log, "rms_error_Nmm": [{"identified": a, "starting": b} for a, b in errors]}
                for log, errors in self.validation
            ],
            "identified": [
                {
                    "key": v.key,
                    "label": v.label,
                    "value": v.value,
                    "std": v.std,
                    "unit": v.unit,
                    "combination": v.combination or None,
                }
                for v in self.identified
            ],
            "overrides": list(self.overrides),
            "made": self.made or None,
            "inputs_of_the_identification": [{"role": r, "path": p, "sha256": h} for r, p, h in self.log_hashes],
        }


@dataclass(frozen=True)
class Provenance:
    """What made a page: version, time, command, inputs, parameter origin and the lab's own fields."""

    version: str
    created: str
    command: str
    inputs: tuple[InputFile, ...]
    parameters: ParameterOrigin | None
    title: str | None = None
    author: str | None = None
    rig: str | None = None
    extra: tuple[tuple[str, str], ...] = field(default_factory=tuple)

    def as_dict(self) -> dict[str, Any]:
        """Plain data for a JSON summary."""
        return {
            "hipsim": self.version,
            "created_utc": self.created,
            "command": self.command,
            "title": self.title,
            "author": self.author,
            "rig": self.rig,
            "inputs": [f.as_dict() for f in self.inputs],
            "parameters": None if self.parameters is None else self.parameters.as_dict(),
        }


def file_sha256(path: str | Path) -> str:
    """The SHA-256 of a file's bytes, hex; read in 1 MiB pieces, so a long log costs no memory."""
    digest = hashlib.sha256()
    with open(path, "rb") as stream:
        for block in iter(lambda: stream.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


def _input(role: str, path: str | Path) -> InputFile:
    path = Path(path)
    return InputFile(role, str(path), file_sha256(path), path.stat().st_size)


_QUANTITY_LINE = re.compile(
    r"^# +(?P<expr>.+?) = (?P<value>\S+) ± (?P<std>\S+) ?(?P<unit>[^(]*?) ?\((?P<relative>[^)]*)\)$"
)
_VALIDATION_LINE = re.compile(r"^# +(?P<log>.+?): (?P<errors>M1 .*) N·mm$")
_MADE_LINE = re.compile(r"^# (?P<made>Made by hipsim .*)$")
_HASH_LINE = re.compile(r"^#   (?P<role>\S+) (?P<path>.+): SHA-256 (?P<sha>[0-9a-f]{64})$")
_HELD_LINE = re.compile(r"^# +(?P<label>\S+) = \S+ .*?: (?P<reason>.+)$")


def _labels() -> dict[str, str]:
    """The identification's short names → parameter keys (``m_L`` → ``slider.mass_kg``)."""
    from ..rig.identification.quantities import QUANTITIES

    return {q.label: q.key for q in QUANTITIES}


def _read_identified_header(lines: Sequence[str]) -> dict[str, Any]:
    """What ``hipsim identify`` wrote in a parameter file's comment header (:meth:`hipsim.rig.identification.fit.Identification.toml`)."""
    labels = _labels()
    found: dict[str, Any] = {
        "logs": (),
        "start": "",
        "validation": [],
        "identified": [],
        "combined": [],
        "held": [],
        "made": "",
        "hashes": [],
    }
    section = ""
    for line in lines:
        if not line.startswith("#"):
            break
        if _MADE_LINE.match(line):
            found["made"] = _MADE_LINE.match(line)["made"]
        elif not section and _HASH_LINE.match(line):
            match = _HASH_LINE.match(line)
            found["hashes"].append((match["role"], match["path"], match["sha"]))
        elif line.startswith("# From the logs: "):
            names = line[len("# From the logs: ") :].rsplit(" (", 1)[0]
            found["logs"] = tuple(name.strip() for name in names.split(", ") if name.strip())
        elif line.startswith("# Starting parameters: "):
            found["start"] = line[len("# Starting parameters: ") :].rstrip(".")
        elif line.startswith("# Identified ("):
            section = "identified"
        elif line.startswith("# Not identified"):
            section = "held"
        elif line.startswith("# Validation"):
            section = "validation"
        elif line.startswith("#  ") and section == "identified":  # identify writes these with two spaces
            match = _QUANTITY_LINE.match(line)
            if match is None:
                continue
            expression = match["expr"]
            label = re.split(r" [+−] ", expression, maxsplit=1)[0]
            if label not in labels:
                continue
            for term in re.findall(r"·([^\s·+−]+)", expression):
                if term in labels:
                    found["combined"].append(labels[term])
            try:
                value, std = float(match["value"]), float(match["std"])
            except ValueError:
                continue
            found["identified"].append(
                IdentifiedValue(
                    labels[label], label, value, std, match["unit"].strip(), expression if expression != label else ""
                )
            )
        elif line.startswith("#  ") and section == "held":
            match = _HELD_LINE.match(line)
            if match is not None and match["label"] in labels:
                found["held"].append((labels[match["label"]], match["reason"]))
        elif line.startswith("#  ") and section == "validation":
            match = _VALIDATION_LINE.match(line)
            if match is None:
                continue
            pairs = re.findall(r"M\d (\S+) vs (\S+)", match["errors"])
            try:
                found["validation"].append((match["log"], tuple((float(a), float(b)) for a, b in pairs)))
            except ValueError:
                continue
    return found


def _read_identification_table(path: str | Path) -> dict[str, Any]:
    """What the file's ``[identification]`` table says (:meth:`hipsim.rig.identification.fit.Identification.table`), in the
    shape of :func:`_read_identified_header`; empty when the file has no such table (the header's reading then stands)."""
    import tomllib

    try:
        table = tomllib.loads(Path(path).read_text(encoding="utf-8")).get("identification")
    except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError):
        return {}
    columns = ("base", "keys", "units", "value", "std", "determined", "definitions")
    if not isinstance(table, dict) or not all(isinstance(table.get(c), list) for c in columns):
        return {}
    if len({len(table[c]) for c in columns}) != 1:
        return {}
    labels = _labels()
    identified, combined, held = [], [], []
    for label, key, unit, value, std, determined, definition in zip(*(table[c] for c in columns)):
        terms = [term for term in re.findall(r"·([^\s·+−]+)", str(definition)) if term in labels]
        if determined:
            identified.append(
                IdentifiedValue(
                    str(key),
                    str(label),
                    float(value),
                    float(std),
                    str(unit),
                    str(definition) if definition != label else "",
                )
            )
            combined += [labels[term] for term in terms]
        else:
            held.append(
                (
                    str(key),
                    f"not determined by these logs: near its prior ({float(value):.6g} ± {float(std):.2g} {unit})".replace(
                        " )", ")"
                    ),
                )
            )
            held += [(labels[term], f"folded into {label}, not determined by these logs") for term in terms]
    found: dict[str, Any] = {"identified": identified, "combined": combined, "held": held}
    if isinstance(table.get("logs"), list):
        found["logs"] = tuple(str(name) for name in table["logs"])
    if isinstance(table.get("start"), str):
        found["start"] = table["start"]
    names, errors, starting = (
        table.get(c) for c in ("validation_logs", "validation_rms_error_Nmm", "validation_start_rms_error_Nmm")
    )
    if (
        isinstance(names, list)
        and isinstance(errors, list)
        and isinstance(starting, list)
        and len(names) == len(errors) == len(starting)
    ):
        try:
            found["validation"] = [
                (str(name), tuple((float(a), float(b)) for a, b in zip(e, s0)))
                for name, e, s0 in zip(names, errors, starting)
            ]
        except (TypeError, ValueError):
            pass
    return found


def parameter_origin(path: str | Path | None, overrides: Iterable[str] = ()) -> ParameterOrigin:
    """Where the values of a parameter file (None: the published machine) and its ``--set`` overrides came from.

    Args:
        path: the ``--params`` file; None for the package's published machine.
        overrides: the ``--set`` texts, KEY=VALUE.
    """
    from ..machine.parameters import default_parameters_path

    published = default_parameters_path()
    file = _input("parameters", published if path is None else path)
    overrides = tuple(overrides)
    if path is None or Path(path).resolve() == published.resolve():
        return ParameterOrigin(file, "published", overrides=overrides)
    try:
        lines = Path(path).read_text(encoding="utf-8").splitlines()
    except (OSError, UnicodeDecodeError):
        lines = []
    if not lines or not lines[0].startswith(IDENTIFIED_MARK):
        return ParameterOrigin(file, "file", overrides=overrides)
    header = _read_identified_header(lines)
    header |= _read_identification_table(path)
    return ParameterOrigin(
        file,
        "identified",
        start=header["start"],
        logs=header["logs"],
        validation=tuple(header["validation"]),
        identified=tuple(header["identified"]),
        combined=tuple(dict.fromkeys(header["combined"])),
        held=tuple(header["held"]),
        overrides=overrides,
        made=header["made"],
        log_hashes=tuple(header["hashes"]),
    )


def _now() -> str:
    return _datetime.datetime.now(_datetime.UTC).replace(microsecond=0).isoformat().replace("+00:00", "Z")


def provenance(
    inputs: Mapping[str, str | Path | Sequence[str | Path] | None] = (),
    parameters: ParameterOrigin | None = None,
    command: Sequence[str] | str | None = None,
    title: str | None = None,
    author: str | None = None,
    rig: str | None = None,
    created: str | None = None,
) -> Provenance:
    """The provenance block of one page.

    Args:
        inputs: role → a file path, a list of paths, or None (left out); each file is hashed (SHA-256).
        parameters: the parameter set's origin (:func:`parameter_origin`); its file is listed among the inputs.
        command: the command line (a list of words, shell-quoted here) or its text; None: "(called from Python)".
        title: the report's title (``--title``).
        author: who made it (``--author``).
        rig: the rig's name or serial number (``--rig``).
        created: date and time, ISO 8601 UTC; default now.
    """
    import shlex

    from ..version import __version__

    files = [] if parameters is None else [parameters.file]
    for role, value in dict(inputs).items():
        if value is None:
            continue
        for path in [value] if isinstance(value, (str, Path)) else value:
            files.append(_input(role, path))
    if command is None:
        text = "(called from Python, not the command line)"
    else:
        text = command if isinstance(command, str) else shlex.join(str(word) for word in command)
    clean = [None if value is None or not str(value).strip() else str(value).strip() for value in (title, author, rig)]
    return Provenance(__version__, created or _now(), text, tuple(files), parameters, *clean)
