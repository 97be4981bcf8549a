"""The typed records' foundation: JSON, the schema made from the type hints, and the exit rule (hipsim/records.py)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import jsonschema
import numpy as np
import pytest

from hipsim.records import EXIT_RULE, REFUSED, Level, Record, Verdict, exit_status, flattened, optional


@dataclass(frozen=True)
class _Inner(Record):
    """An inner record."""

    x_deg: float
    tags: tuple[str, ...]


@dataclass(frozen=True)
class _Outer(Record):
    """An outer record."""

    name: str
    count: int
    flag: bool
    inner: _Inner
    by_angle: dict[str, _Inner]
    pair: tuple[float, float]
    level: Level
    maybe: float | None = optional()
    renamed: int = 0


def _outer(**changes) -> _Outer:
    base: dict[str, Any] = dict(
        name="a",
        count=3,
        flag=True,
        inner=_Inner(1.5, ("p",)),
        by_angle={"alpha": _Inner(math.nan, ())},
        pair=(np.float64(1.0), 2.0),
        level=Level.ALIKE,
    )
    return _Outer(**(base | changes))


def test_to_json_walks_records_enums_arrays_and_nan():
    document = _outer().to_json()
    assert document == {
        "name": "a",
        "count": 3,
        "flag": True,
        "inner": {"x_deg": 1.5, "tags": ["p"]},
        "by_angle": {"alpha": {"x_deg": None, "tags": []}},
        "pair": [1.0, 2.0],
        "level": "ALIKE",
        "renamed": 0,
    }
    assert "maybe" not in document  # omitted when None
    assert _outer(maybe=2.0).to_json()["maybe"] == 2.0


def test_schema_accepts_the_records_json_and_refuses_drift():
    schema = _Outer.json_schema("demo")
    assert schema["version"] == "1" and schema["title"] == "hipsim demo --summary-format json"
    jsonschema.Draft202012Validator.check_schema(schema)
    validator = jsonschema.Draft202012Validator(schema)
    good = _outer(maybe=2.0).to_json()
    validator.validate(good)
    validator.validate(_outer().to_json())
    for bad in (
        good | {"extra": 1},  # a key the record does not have
        {k: v for k, v in good.items() if k != "count"},  # a key missing
        good | {"count": 1.5},  # an int that is not
        good | {"level": "MAYBE"},  # a level that does not exist
        good | {"pair": [1.0]},  # a pair of one
        good | {"inner": {"x_deg": "1", "tags": []}},  # a number as text
        good | {"flag": 1},
    ):
        with pytest.raises(jsonschema.ValidationError):
            validator.validate(bad)


def test_levels_and_exit_rule():
    failing = {Level.FAIL, Level.ALARM, Level.DIFFERENT, Level.NOT_FEASIBLE}
    for level in Level:
        assert level.failed == (level in failing)
        assert exit_status([level]) == (1 if level in failing else 0)
    assert exit_status([]) == 0 and exit_status([None, Level.PASS]) == 0
    assert exit_status([Level.PASS, Verdict(Level.DIFFERENT, "x")]) == 1  # one failing verdict is enough
    assert exit_status([Verdict(Level.OK, "x"), Level.NOTICE, Level.NOT_MADE]) == 0
    assert REFUSED == 2 and EXIT_RULE[1] == ("FAIL", "ALARM", "DIFFERENT", "NOT FEASIBLE")
    assert {"PASS", "OK", "ALIKE"} <= set(EXIT_RULE[0])
    assert Level.NOTICE.state == "open" and Level.OK.state == "pass" and Level.ALARM.state == "fail"


def test_verdict_json():
    verdict = Verdict(Level.FAIL, "m_2 against ISO", "the load", {"worst_deg": 3.5})
    assert verdict.to_json() == {
        "level": "FAIL",
        "judged": "m_2 against ISO",
        "not_judged": "the load",
        "numbers": {"worst_deg": 3.5},
    }
    jsonschema.validate(verdict.to_json(), Verdict.json_schema())
    assert verdict.failed and not Verdict(Level.PASS, "x").failed


@dataclass(frozen=True)
class _Document(Record):
    """A summary with what was written beside it."""

    summary: _Inner = flattened()
    table: str = ""
    index: str | None = optional()


def test_a_flattened_record_lays_its_keys_into_the_document():
    document = _Document(_Inner(2.0, ("a",)), "t.csv").to_json()
    assert document == {"x_deg": 2.0, "tags": ["a"], "table": "t.csv"}
    schema = _Document.json_schema("demo")
    assert schema["required"] == ["x_deg", "tags", "table"] and set(schema["properties"]) == {
        "x_deg",
        "tags",
        "table",
        "index",
    }
    jsonschema.validate(document, schema)
    with pytest.raises(jsonschema.ValidationError):
        jsonschema.validate({"tags": [], "table": "t"}, schema)
