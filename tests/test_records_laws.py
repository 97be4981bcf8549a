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
