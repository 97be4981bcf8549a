"""The schema a record makes, written out by hand for every kind of type hint (hipsim/records.py), and the JSON of
values at their edges."""

from __future__ import annotations

import enum
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np
import pytest

from hipsim.records import Level, Record, Verdict, exit_status, flattened, json_value, optional


class _Colour(enum.Enum):
    RED = "red"
    BLUE = "blue"


@dataclass(frozen=True)
class _Leaf(Record):
    """A leaf.

    More lines that the schema's description leaves out.
    """

    size: int


@dataclass(frozen=True)
class _Extra(Record):
    """Extra keys laid in."""

    note: str


@dataclass(frozen=True)
class _Every(Record):
    """Every hint."""

    anything: Any
    yes: bool
    ratio: float
    count: int
    text: str
    colour: _Colour
    leaf: _Leaf
    either: int | str
    kind: Literal["a", "b"]
    items: list[float]
    seq: Sequence[int]
    pair: tuple[int, str]
    many: tuple[float, ...]
    table: dict[str, int]
    mapping: Mapping[str, bool]
    loose: dict  # a bare dict: any values
    extra: _Extra = flattened()
    spare: _Extra | None = optional(flatten=True)
    nothing: None = None
    maybe: float | None = optional(description="a number when known")
    renamed: int = field(default=0, metadata={"key": "from"})


EXPECTED_PROPERTIES: dict[str, Any] = {
    "anything": {},
    "yes": {"type": "boolean"},
    "ratio": {"type": ["number", "null"]},
    "count": {"type": "integer"},
    "text": {"type": "string"},
    "colour": {"enum": ["red", "blue"]},
    "leaf": {"$ref": "#/$defs/_Leaf"},
    "either": {"anyOf": [{"type": "integer"}, {"type": "string"}]},
    "kind": {"enum": ["a", "b"]},
    "items": {"type": "array", "items": {"type": ["number", "null"]}},
    "seq": {"type": "array", "items": {"type": "integer"}},
    "pair": {
        "type": "array",
        "prefixItems": [{"type": "integer"}, {"type": "string"}],
        "minItems": 2,
        "maxItems": 2,
    },
    "many": {"type": "array", "items": {"type": ["number", "null"]}},
    "table": {"type": "object", "additionalProperties": {"type": "integer"}},
    "mapping": {"type": "object", "additionalProperties": {"type": "boolean"}},
    "loose": {"type": "object", "additionalProperties": {}},
    "note": {"type": "string"},
    "nothing": {"type": "null"},
    "maybe": {"description": "a number when known", "anyOf": [{"type": ["number", "null"]}, {"type": "null"}]},
    "from": {"type": "integer"},
}


def test_the_schema_of_every_hint_by_hand():
    schema = _Every.json_schema()
    assert schema == {
        "$schema": "https://json-schema.org/draft/2020-12/schema",
        "$id": "https://hipsim.invalid/schemas/_Every/v1.json",
        "title": "_Every",
        "version": "1",
        "type": "object",
        "properties": EXPECTED_PROPERTIES,
        "required": [k for k in EXPECTED_PROPERTIES if k != "maybe"],
        "additionalProperties": False,
        "description": "Every hint.",
        "$defs": {
            "_Leaf": {
                "type": "object",
                "properties": {"size": {"type": "integer"}},
                "required": ["size"],
                "additionalProperties": False,
                "description": "A leaf.",
            }
        },
    }
    assert list(schema["properties"]) == list(EXPECTED_PROPERTIES)  # the fields' order
    named = _Every.json_schema("check all")
    assert named["$id"] == "https://hipsim.invalid/schemas/check-all/v1.json"
    assert named["title"] == "hipsim check all --summary-format json"
    assert "$defs" not in _Leaf.json_schema()


def test_a_record_s_own_schema_title():
    @dataclass(frozen=True)
    class Titled(Record):
        schema_title = "titled thing"
        x: int

    assert Titled.json_schema()["title"] == "titled thing" and Titled.json_schema()["$id"].endswith(
        "/titled-thing/v1.json"
    )
    assert Titled.json_schema("cmd")["title"] == "hipsim cmd --summary-format json"


def test_a_type_with_no_schema_is_named():
    @dataclass(frozen=True)
    class Odd(Record):
        when: complex

    with pytest.raises(TypeError, match="^no JSON Schema for the type hint <class 'complex'>$"):
        Odd.json_schema()


def test_the_json_of_every_kind():
    values: dict[str, Any] = dict(
        anything=[1, "x"], yes=True, ratio=math.inf, count=np.int64(4), text="t", colour=_Colour.BLUE, leaf=_Leaf(2),
        either="s", kind="a", items=[1.0, math.nan], seq=(1, 2), pair=(1, "a"), many=np.array([0.5, -math.inf]),
        table={1: 2}, mapping={"k": True}, loose={}, extra=_Extra("n"), spare=None, maybe=None, renamed=7,
    )  # fmt: skip
    every = _Every(**values)
    doc = every.to_json()
    assert doc == {
        "anything": [1, "x"], "yes": True, "ratio": None, "count": 4, "text": "t", "colour": "blue", "leaf": {"size": 2},
        "either": "s", "kind": "a", "items": [1.0, None], "seq": [1, 2], "pair": [1, "a"],
        "many": [0.5, None], "table": {"1": 2}, "mapping": {"k": True}, "loose": {}, "note": "n", "nothing": None,
        "from": 7,
    }  # fmt: skip
    assert list(doc) == [k for k in EXPECTED_PROPERTIES if k != "maybe"]
    with_spare = _Every(**{**vars(every), "spare": _Extra("m"), "maybe": 1.5}).to_json()
    assert with_spare["maybe"] == 1.5 and with_spare["note"] == "m"  # the optional flattened record's keys laid in last


def test_json_values_at_their_edges():
    assert json_value(np.float32(0.5)) == 0.5 and json_value(np.array([[1, 2]])) == [[1, 2]]
    assert json_value(-math.inf) is None and json_value(1e308) == 1e308 and json_value(0.0) == 0.0
    assert json_value(Level.NOT_MADE) == "NOT MADE" and json_value(None) is None
    assert json_value({"a": (1, Level.OK)}) == {"a": [1, "OK"]}


def test_exit_status_of_records_levels_and_none():
    assert exit_status([None, Verdict(Level.NOT_MADE, "x"), Level.FEASIBLE]) == 0
    assert exit_status([Verdict(Level.ALARM, "x")]) == 1 and exit_status(iter([None, Level.NOT_FEASIBLE])) == 1
    assert exit_status([Level.PASS, Level.FAIL, Level.PASS]) == 1
    assert Level.FEASIBLE.state == "pass" and Level.ALIKE.state == "pass" and Level.NOT_MADE.state == "open"
    assert Level.DIFFERENT.state == "fail" and Level.PASS.state == "pass"
    assert Verdict(Level.OK, "j").to_json() == {"level": "OK", "judged": "j", "not_judged": "", "numbers": {}}


@dataclass(frozen=True)
class _Deep(Record):
    """A second record named Verdict, in a module of a dotted name."""

    word: str


@dataclass(frozen=True)
class _Top(Record):
    """A third record named Verdict, in a module of one name."""

    word: str


_Deep.__name__, _Deep.__module__ = "Verdict", "hipsim.pages.deep"
_Top.__name__, _Top.__module__ = "Verdict", "toplevel"


@dataclass(frozen=True)
class _Pair(Record):
    """Two verdicts, the second nested a level down."""

    first: Verdict
    deep: _Deep


@dataclass(frozen=True)
class _Laid(Record):
    """A record laid into another."""

    a: int
    pair: _Pair


@dataclass(frozen=True)
class _Outer(Record):
    """Every kind of field: a record and a mapping laid in, an optional key, records of one class name."""

    x: int
    laid: _Laid = flattened()
    extra: Mapping[str, float] = flattened()
    top: _Top = flattened()
    again: Verdict = field(default_factory=lambda: Verdict(Level.PASS, "again"))
    note: str | None = optional()


def _outer(note: str | None = None) -> _Outer:
    pair = _Pair(Verdict(Level.FAIL, "f"), _Deep("d"))
    return (
        _Outer(1, _Laid(2, pair), {"k": 1.5}, _Top("t"), note=note)
        if note
        else _Outer(1, _Laid(2, pair), {"k": 1.5}, _Top("t"))
    )


def test_laid_in_and_optional_fields_in_the_json():
    verdict = {"level": "FAIL", "judged": "f", "not_judged": "", "numbers": {}}
    assert _outer().to_json() == {
        "x": 1,
        "a": 2,
        "pair": {"first": verdict, "deep": {"word": "d"}},
        "k": 1.5,
        "word": "t",
        "again": {"level": "PASS", "judged": "again", "not_judged": "", "numbers": {}},
    }
    assert _outer().note is None
    assert _outer("n").to_json()["note"] == "n" and list(_outer("n").to_json())[-1] == "note"


def test_laid_in_fields_and_records_of_one_name_in_the_schema():
    schema = _Outer.json_schema()
    assert list(schema["properties"]) == ["x", "a", "pair", "word", "again", "note"]
    assert schema["required"] == ["x", "a", "pair", "word", "again"]  # the optional key not
    assert schema["additionalProperties"] == {"type": ["number", "null"]}  # the mapping's values, any key
    assert schema["properties"]["pair"] == {"$ref": "#/$defs/_Pair"}
    assert schema["properties"]["word"] == {"type": "string"}
    assert schema["properties"]["again"] == {"$ref": "#/$defs/Verdict"}  # the same class: the same name
    assert sorted(schema["$defs"]) == ["Verdict", "_Pair", "deep_Verdict"]
    assert schema["$defs"]["_Pair"]["properties"] == {
        "first": {"$ref": "#/$defs/Verdict"},
        "deep": {"$ref": "#/$defs/deep_Verdict"},
    }
    assert schema["$defs"]["deep_Verdict"]["properties"] == {"word": {"type": "string"}}
    assert schema["$defs"]["Verdict"]["properties"]["level"] == {"enum": [level.value for level in Level]}


@dataclass(frozen=True)
class _Three(Record):
    """Three records named Verdict, from three modules."""

    one: Verdict
    two: _Deep
    three: _Top


def test_records_of_one_class_name_are_named_by_their_module():
    schema = _Three.json_schema()
    assert [schema["properties"][k]["$ref"] for k in ("one", "two", "three")] == [
        "#/$defs/Verdict",
        "#/$defs/deep_Verdict",
        "#/$defs/toplevel_Verdict",
    ]
