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
errors, and what made it), read back through
:mod:`hipsim.rig.identification.identified_file` (the one reader of those
files; a file written before the tables is read from its comment header); any
other file is the user's; ``--set`` overrides are listed key by key.
"""

from __future__ import annotations

import datetime as _datetime
import hashlib
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
    warnings: tuple[str, ...] = ()  # what the option table warned of on the command line (a run on a warned value)

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
            "warnings": list(self.warnings),
        }


def file_sha256(path: str | Path) -> str:
    """The SHA-256 of a file's bytes, hex; read in 1 MiB pieces, so a long log costs no memory."""
    digest = hashlib.sha256()
    with open(path, "rb") as stream:
        for block in iter(lambda: stream.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


def _input(role: str, path: str | Path | InputFile) -> InputFile:
    if isinstance(path, InputFile):  # hashed already, as it was read
        return InputFile(role, path.path, path.sha256, path.size)
    path = Path(path)
    return InputFile(role, str(path), file_sha256(path), path.stat().st_size)


def parameter_origin(path: str | Path | None, overrides: Iterable[str] = ()) -> ParameterOrigin:
    """Where the values of a parameter file (None: the published machine) and its ``--set`` overrides came from.

    An identified file is read through :func:`hipsim.rig.identification.identified_file.read_identified_file`
    (its tables; an old file's comment header), so its comments change nothing.

    Args:
        path: the ``--params`` file; None for the package's published machine.
        overrides: the ``--set`` texts, KEY=VALUE.
    """
    from ..machine.parameters import default_parameters_path
    from ..rig.identification.identified_file import read_identified_file

    published = default_parameters_path()
    file = _input("parameters", published if path is None else path)
    overrides = tuple(overrides)
    if path is None or Path(path).resolve() == published.resolve():
        return ParameterOrigin(file, "published", overrides=overrides)
    found = read_identified_file(path)
    if found is None:
        return ParameterOrigin(file, "file", overrides=overrides)
    made = found.provenance
    return ParameterOrigin(
        file,
        "identified",
        start=found.start,
        logs=found.logs,
        validation=found.validation,
        identified=tuple(
            IdentifiedValue(e.key, e.label, e.value, e.std, e.unit, e.definition if e.definition != e.label else "")
            for e in found.estimates
            if e.determined
        ),
        combined=found.combined,
        held=found.held,
        overrides=overrides,
        made="" if made is None else made.made(),
        log_hashes=() if made is None else tuple((f.role, f.path, f.sha256) for f in made.inputs),
    )


def _now() -> str:
    return _datetime.datetime.now(_datetime.UTC).replace(microsecond=0).isoformat().replace("+00:00", "Z")


def provenance(
    inputs: Mapping[str, str | Path | InputFile | Sequence[str | Path | InputFile] | None] | None = None,
    parameters: ParameterOrigin | None = None,
    command: Sequence[str] | str | None = None,
    title: str | None = None,
    author: str | None = None,
    rig: str | None = None,
    created: str | None = None,
    warnings: Sequence[str] = (),
) -> Provenance:
    """The provenance block of one page.

    Args:
        inputs: role → a file path, a list of paths, or None (left out); each file is hashed (SHA-256), but
            an :class:`InputFile` (a file hashed as it was read, e.g. a rig log's single read) is taken as it is.
        parameters: the parameter set's origin (:func:`parameter_origin`); its file is listed among the inputs.
        command: the command line (a list of words, shell-quoted here) or its text; None: "(called from Python)".
        title: the report's title (``--title``).
        author: who made it (``--author``).
        rig: the rig's name or serial number (``--rig``).
        created: date and time, ISO 8601 UTC; default now.
        warnings: the warnings the command line drew (a value outside its option's plausible range, a deprecated
            name), kept so that a page made on a warned value says so.
    """
    import shlex

    from ..version import __version__

    files = [] if parameters is None else [parameters.file]
    for role, value in dict(inputs or {}).items():
        if value is None:
            continue
        for path in [value] if isinstance(value, (str, Path, InputFile)) else value:
            files.append(_input(role, path))
    if command is None:
        text = "(called from Python, not the command line)"
    else:
        text = command if isinstance(command, str) else shlex.join(str(word) for word in command)
    clean = [None if value is None or not str(value).strip() else str(value).strip() for value in (title, author, rig)]
    return Provenance(
        __version__,
        created or _now(),
        text,
        tuple(files),
        parameters,
        title=clean[0],
        author=clean[1],
        rig=clean[2],
        warnings=tuple(str(w) for w in warnings),
    )
