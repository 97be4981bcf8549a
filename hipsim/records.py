"""Typed records: the summaries and verdicts the commands print, their JSON, its JSON Schema, and the exit-status rule.

A command's summary is a frozen dataclass that mixes in :class:`Record`, made by
the layer that computes it; its :meth:`Record.to_json` is the document
``--summary-format json`` prints, and :meth:`Record.json_schema` the JSON
Schema (draft 2020-12) of that document, generated from the type hints, so the
published contract cannot drift from the code. A verdict is a :class:`Verdict`
made by a pure function beside its analysis: its :class:`Level`, what it
judged, what it did not judge, and the numbers it used.

The exit rule (:func:`exit_status`), one for every command that states a
verdict: 0 when every verdict is PASS, OK, ALIKE or FEASIBLE (or states none),
1 when one is FAIL, ALARM, DIFFERENT or NOT FEASIBLE, 2 when the input was
refused (:data:`REFUSED`, the status of every one-line error).

Mapping type hints to JSON (and to the schema): ``float`` is a number or null
(NaN and infinities print as null), ``int``, ``str`` and ``bool`` as such, a
tuple or list an array, ``dict[str, X]`` an object of X, an :class:`enum.Enum`
its values, a nested record an object of its own fields (every field required,
no other key), ``X | None`` X or null. A field whose metadata says
``{"omit_none": True}`` is left out of the JSON when it is None (a key a
document has only sometimes); ``{"key": "name"}`` prints the field under
another key; ``{"flatten": True}`` (:func:`flattened`) lays a nested record's
keys into this one's (a summary with the paths a command wrote beside it), or a
``dict[str, X]``'s keys (a document keyed by name: any other key, each an X).
"""

from __future__ import annotations

import dataclasses
import enum
import math
import sys
import types
import typing
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any, ClassVar

__all__ = [
    "EXIT_RULE",
    "REFUSED",
    "SCHEMA_VERSION",
    "Judged",
    "Level",
    "Record",
    "Verdict",
    "exit_status",
    "flattened",
    "json_value",
    "optional",
]

#: The first version of every schema :meth:`Record.json_schema` makes; a document whose published keys change or go
#: raises its own :attr:`Record.schema_version` (the other documents keep theirs).
SCHEMA_VERSION = "1"

#: The exit status of refused input (a one-line ``hipsim: error:``), nothing written.
REFUSED = 2


class Level(enum.StrEnum):
    """What a verdict says, in the word a user reads; each level is passing, failing or open (nothing decided)."""

    PASS = "PASS"
    OK = "OK"
    ALIKE = "ALIKE"
    FEASIBLE = "FEASIBLE"
    NOTICE = "NOTICE"
    NOT_MADE = "NOT MADE"
    FAIL = "FAIL"
    ALARM = "ALARM"
    DIFFERENT = "DIFFERENT"
    NOT_FEASIBLE = "NOT FEASIBLE"

    @property
    def failed(self) -> bool:
        """True for FAIL, ALARM, DIFFERENT and NOT FEASIBLE: the levels that exit 1."""
        return self in _FAILING

    @property
    def state(self) -> str:
        """ "pass", "fail" or "open": the page's colour of the level."""
        if self.failed:
            return "fail"
        return "pass" if self in (Level.PASS, Level.OK, Level.ALIKE, Level.FEASIBLE) else "open"


_FAILING = frozenset({Level.FAIL, Level.ALARM, Level.DIFFERENT, Level.NOT_FEASIBLE})

#: The exit rule as the docs' table gives it: status → the levels (or the case) that give it.
EXIT_RULE: dict[int, tuple[str, ...]] = {
    0: tuple(level.value for level in Level if not level.failed),
    1: tuple(level.value for level in Level if level.failed),
    REFUSED: ("refused input (one line `hipsim: error: ...`, nothing written)",),
}


class Judged(typing.Protocol):
    """Anything that carries a verdict's level (a :class:`Verdict`, a command's own verdict record)."""

    @property
    def level(self) -> Level: ...


def exit_status(verdicts: Iterable[Judged | Level | None]) -> int:
    """The exit status of a command that states ``verdicts``: 1 when any is failing, else 0 (None: no verdict)."""
    for verdict in verdicts:
        level = verdict if verdict is None or isinstance(verdict, Level) else verdict.level
        if level is not None and level.failed:
            return 1
    return 0


def flattened() -> Any:
    """A record field whose record's keys are laid into the enclosing record's JSON (and schema)."""
    return field(metadata={"flatten": True})


def optional(**metadata: Any) -> Any:
    """A record field that defaults to None and is left out of the JSON when None (a key a document has sometimes)."""
    return field(default=None, metadata={"omit_none": True, **metadata})


def json_value(value: Any) -> Any:
    """``value`` as JSON data: records through :meth:`Record.to_json`, enums as their values, arrays as lists,
    NaN and infinities as None, mappings with string keys."""
    if isinstance(value, Record):
        return value.to_json()
    if isinstance(value, enum.Enum):
        return value.value
    np = sys.modules.get("numpy")  # not imported here: ``hipsim --help`` loads no NumPy; none loaded, no arrays
    if np is not None and isinstance(value, (np.ndarray, np.generic)):
        return json_value(value.tolist())
    if isinstance(value, Mapping):
        return {str(k): json_value(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [json_value(v) for v in value]
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


class Record:
    """Mixed into a frozen dataclass: its JSON (:meth:`to_json`) and that JSON's schema (:meth:`json_schema`).

    Class attributes:
        schema_title: the schema's title (default: the class name).
        schema_version: the version of this record's document (:data:`SCHEMA_VERSION` until a published key of it
            changes or goes).
    """

    schema_title: ClassVar[str | None] = None
    schema_version: ClassVar[str] = SCHEMA_VERSION

    def to_json(self) -> dict[str, Any]:
        """The record as JSON data, its fields in declaration order (see the module's mapping)."""
        out: dict[str, Any] = {}
        for f in dataclasses.fields(self):  # type: ignore[arg-type]
            value = getattr(self, f.name)
            if value is None and f.metadata.get("omit_none"):
                continue
            if f.metadata.get("flatten"):  # a record's keys laid into this one's
                out |= json_value(value)
                continue
            out[f.metadata.get("key", f.name)] = json_value(value)
        return out

    @classmethod
    def json_schema(cls, command: str | None = None, command_line: str | None = None) -> dict[str, Any]:
        """The JSON Schema (draft 2020-12) of :meth:`to_json`'s document, with ``$defs`` for nested records.

        Args:
            command: the document's name (``hipsim schema NAME``), for the ``$id`` and, without ``command_line``,
                the title (default: the class name).
            command_line: the words after ``hipsim`` that print the document (``"stations --sliders LOG"``), for
                the title ``hipsim ... --summary-format json`` (default: ``command``).
        """
        defs = _Defs()
        body = _record_schema(cls, defs)
        name = command or cls.schema_title or cls.__name__
        schema: dict[str, Any] = {
            "$schema": "https://json-schema.org/draft/2020-12/schema",
            "$id": f"https://hipsim.invalid/schemas/{name.replace(' ', '-')}/v{cls.schema_version}.json",
            "title": f"hipsim {command_line or name} --summary-format json" if command else name,
            "version": cls.schema_version,
            **body,
        }
        if defs:
            schema["$defs"] = dict(sorted(defs.items()))
        return schema


class _Defs(dict[str, Any]):
    """A schema's ``$defs`` as they are built, and the record each name stands for: two records of one class name
    (a page's ``Verdict`` and :class:`Verdict`) get names apart, the second prefixed with its module's name."""

    def __init__(self) -> None:
        super().__init__()
        self.owners: dict[str, type] = {}

    def name_of(self, record: type) -> str:
        """The name ``record`` goes by in ``$defs``."""
        name = record.__name__
        if self.owners.get(name, record) is not record:
            name = f"{record.__module__.rsplit('.', 1)[-1]}_{name}"
        self.owners.setdefault(name, record)
        return name


def _record_schema(cls: type, defs: _Defs) -> dict[str, Any]:
    hints = typing.get_type_hints(cls)
    properties: dict[str, Any] = {}
    required: list[str] = []
    others: dict[str, Any] | bool = False  # the keys no field names: none, but a flattened mapping's
    for f in dataclasses.fields(cls):
        if f.metadata.get("flatten") and typing.get_origin(hints[f.name]) in (dict, Mapping):
            others = _schema(typing.get_args(hints[f.name])[1], defs)  # a mapping's keys laid in: any key, its values
            continue
        if f.metadata.get("flatten"):
            record = next((h for h in typing.get_args(hints[f.name]) if h is not type(None)), hints[f.name])
            inner = _record_schema(record, defs)
            properties |= inner["properties"]
            if not f.metadata.get("omit_none"):  # an optional record's keys come all together or not at all
                required += inner["required"]
            continue
        key = f.metadata.get("key", f.name)
        properties[key] = _schema(hints[f.name], defs)
        if "description" in f.metadata:
            properties[key] = {"description": f.metadata["description"], **properties[key]}
        if not f.metadata.get("omit_none"):
            required.append(key)
    out: dict[str, Any] = {"type": "object", "properties": properties, "required": required}
    out["additionalProperties"] = others
    if cls.__doc__:
        out["description"] = cls.__doc__.strip().splitlines()[0]
    return out


_SIMPLE: dict[type, dict[str, Any]] = {
    float: {"type": ["number", "null"]},
    int: {"type": "integer"},
    str: {"type": "string"},
}


def _schema(hint: Any, defs: _Defs) -> dict[str, Any]:
    origin, args = typing.get_origin(hint), typing.get_args(hint)
    if hint is Any:
        return {}
    if hint is bool:
        return {"type": "boolean"}
    if hint in _SIMPLE:
        return dict(_SIMPLE[hint])
    if hint is type(None):
        return {"type": "null"}
    if isinstance(hint, type) and issubclass(hint, enum.Enum):
        return {"enum": [member.value for member in hint]}
    if isinstance(hint, type) and issubclass(hint, Record):
        name = defs.name_of(hint)
        if name not in defs:
            defs[name] = {}  # a placeholder first: a record that nests itself refers to itself
            defs[name] = _record_schema(hint, defs)
        return {"$ref": f"#/$defs/{name}"}
    if origin in (typing.Union, types.UnionType):
        options = [_schema(a, defs) for a in args]
        return {"anyOf": options}
    if origin is typing.Literal:
        return {"enum": list(args)}
    if origin in (list, tuple, Sequence):
        if origin is tuple and args and (len(args) != 2 or args[1] is not Ellipsis):
            items = [_schema(a, defs) for a in args]
            return {"type": "array", "prefixItems": items, "minItems": len(items), "maxItems": len(items)}
        return {"type": "array", "items": _schema(args[0], defs) if args else {}}
    if origin in (dict, Mapping) or hint is dict:
        return {"type": "object", "additionalProperties": _schema(args[1], defs) if args else {}}
    raise TypeError(f"no JSON Schema for the type hint {hint!r}")


@dataclass(frozen=True)
class Verdict(Record):
    """A verdict: its level, what it judged, what it did not, and the numbers it used.

    Attributes:
        level: the word.
        judged: what was judged, in a sentence with its numbers ("m_2's motion against ISO 14242-1: worst 1.2°").
        not_judged: what the verdict does not cover ("" when nothing needs saying).
        numbers: the numbers it used, by name with the unit in the name (``worst_alpha_deg``).
    """

    level: Level
    judged: str
    not_judged: str = ""
    numbers: Mapping[str, float] = field(default_factory=dict)

    @property
    def failed(self) -> bool:
        """True when the level exits 1."""
        return self.level.failed
