"""Tests of hipsim.motion.columns: column mappings as text, their mistakes named."""

from __future__ import annotations

import pytest

from hipsim import TrajectoryError
from hipsim.motion.columns import parse_columns


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("", "empty column mapping"),
        ("time=t,alpha=a,beta=b", "gamma not mapped"),
        ("time=t,alpha=a,beta=b,gamma=c,flexion=f", "not both"),
        ("time=t,alpha=a,beta=b,gamma=c,rho=r", "unknown quantity 'rho'"),
        ("time=t,alpha=a,alpha=b,beta=b,gamma=c", "alpha is mapped twice"),
        ("time=-t,alpha=a,beta=b,gamma=c", "time column cannot have its sign flipped"),
        ("time=t:min,alpha=a,beta=b,gamma=c", "'min' is not a unit of time (expected s, ms, %)"),
        ("time=t,alpha=a:N,beta=b,gamma=c", "'N' is not a unit of alpha (expected deg, rad)"),
        ("time=t,alpha,beta=b,gamma=c", "'alpha' is not QUANTITY=COLUMN"),
        ("time=t,alpha=:deg,beta=b,gamma=c", "no column name given for alpha"),
    ],
)
def test_column_mapping_mistakes_are_named(text, message):
    with pytest.raises(TrajectoryError) as info:
        parse_columns(text)
    assert str(info.value).startswith("column mapping: ") and message in str(info.value), str(info.value)


def test_column_mapping_round_trips_through_text():
    mapping = parse_columns("Time = Zeit:ms , alpha=FE, beta=-AA:RAD,gamma=IE,load=F res:%bw")
    assert mapping.text() == "time=Zeit:ms,alpha=FE,beta=-AA:rad,gamma=IE,load=F res:%BW"
    assert parse_columns(mapping.text()) == mapping
