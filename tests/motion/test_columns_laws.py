"""hipsim.motion.columns pinned case by case: units stated in names, the mapping text, what is refused and why."""

from __future__ import annotations

import pytest
from support import given

from hipsim.exceptions import TrajectoryError
from hipsim.motion.columns import (
    HIP_ANGLE_NAMES,
    STANDARD_GRAVITY,
    UNITS,
    ZERO,
    Column,
    ColumnMap,
    as_column_map,
    as_load_column,
    column_options,
    parse_columns,
    stated_unit,
)


def test_the_constants():
    assert ZERO == "zero" and STANDARD_GRAVITY == 9.80665
    assert HIP_ANGLE_NAMES == ("flexion", "adduction", "rotation")
    assert (
        UNITS["time"] == ("s", "ms", "%") and UNITS["alpha"] == ("deg", "rad") and UNITS["load"] == ("N", "kN", "%BW")
    )


@pytest.mark.parametrize(
    ("name", "key", "unit"),
    [
        ("Fz [kN]", "load", "kN"),
        ("Fz (%BW)", "load", "%BW"),
        ("Fz ( % BW )", "load", "%BW"),
        ("Fz_%BW", "load", "%BW"),
        ("Load %BW", "load", "%BW"),
        ("Fz_% BW", "load", "%BW"),
        ("Fz %_BW", "load", "%BW"),
        ("Fz_BW%", "load", "%BW"),
        ("Fz (% body weight)", "load", "%BW"),
        ("Fz_kN", "load", "kN"),
        ("Fz_KN", "load", "kN"),
        ("Fz_left_kN", "load", "kN"),
        ("Time_%", "time", None),
        ("Fz [N]", "load", "N"),
        ("Fz [N]", "alpha", None),
        ("FE (deg)", "alpha", "deg"),
        ("FE [°]", "alpha", "deg"),
        ("FE_rad", "flexion", "rad"),
        ("Time [ms]", "time", "ms"),
        ("Time [%]", "time", "%"),
        ("Fz", "load", None),
        ("Fz_total", "load", None),
        ("kN", "load", None),
        ("Fz [lbf]", "load", None),
    ],
)
def test_the_unit_a_name_states(name, key, unit):
    assert stated_unit(name, key) == unit


def test_a_column_from_its_text_and_back():
    c = Column.parse(" -AA : RAD ", "beta")
    assert (c.name, c.unit, c.sign) == ("AA", "rad", -1.0) and c.text() == "-AA:rad"
    assert Column.parse("Fz:%bw", "load").unit == "%BW"
    assert Column.parse("Time", "time") == Column("Time") and Column("Time").text() == "Time"
    # Only the last colon starts the unit: a name may hold colons.
    assert Column.parse("a:b:ms", "time").name == "a:b"
    assert Column.parse("Zero", "gamma").zero and not Column.parse("zeros", "gamma").zero
    with pytest.raises(TrajectoryError, match="'kN' is not a unit of alpha \\(expected deg, rad\\)"):
        Column.parse("FE:kN", "alpha")
    with pytest.raises(TrajectoryError, match="no column name given for load"):
        Column.parse("- :N", "load")
    for name in ("", "  ", None):
        with pytest.raises(TrajectoryError) as refused:
            Column(name)  # type: ignore[arg-type]  # None on purpose: refused like a blank
        assert str(refused.value) == f"column mapping: a column needs a name, got {name!r}"
    with pytest.raises(TrajectoryError) as refused:
        Column("FE", sign=2)
    assert str(refused.value) == "column mapping: column 'FE': sign must be +1 or -1, got 2"


def test_a_mapping_text_round_trips():
    text = "time=Time:ms,alpha=FE,beta=-AA:rad,gamma=zero,load=Fz:%BW"
    m = parse_columns(text)
    assert m.text() == text and not m.hip_chain
    assert [k for k, _ in m.items()] == ["time", "alpha", "beta", "gamma", "load"]
    assert m.angles[1] == Column("AA", "rad", -1.0) and m.load == Column("Fz", "%BW")
    hip = parse_columns("TIME=t, Flexion=F, adduction=A, rotation=R")
    assert hip.hip_chain and hip.angle_keys == HIP_ANGLE_NAMES and hip.load is None
    assert hip.text() == "time=t,flexion=F,adduction=A,rotation=R"


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("", "empty column mapping (expected e.g. time=Time,alpha=FE,beta=AA,gamma=IE)"),
        ("   ", "empty column mapping (expected e.g. time=Time,alpha=FE,beta=AA,gamma=IE)"),
        ("time=T,alpha", "'alpha' is not QUANTITY=COLUMN"),
        ("time=T,=FE", "'=FE' is not QUANTITY=COLUMN"),
        ("time=T,alpha=A,ALPHA=B,beta=C,gamma=D", "ALPHA is mapped twice"),
        (
            "time=T,alpha=A,beta=B,gamma=C,delta=D",
            "unknown quantity 'delta' (expected time; alpha, beta, gamma or flexion, adduction, rotation; optionally load)",
        ),
        (
            "time=T,alpha=A,beta=B,flexion=C",
            "map either the platform angles alpha, beta, gamma or the hip's flexion, adduction, rotation, not both",
        ),
        ("time=T,alpha=A,beta=B", "gamma not mapped (time and all three angles are needed)"),
        ("alpha=A,beta=B,gamma=C", "time not mapped (time and all three angles are needed)"),
        ("time=T,flexion=F", "adduction, rotation not mapped (time and all three angles are needed)"),
        ("time=-T,alpha=A,beta=B,gamma=C", "the time column cannot have its sign flipped"),
        (
            "time=zero,alpha=A,beta=B,gamma=C",
            "'zero' stands for an angle the file does not have, not for the time",
        ),
        (
            "time=T,alpha=A,beta=B,gamma=C,load=zero",
            "'zero' stands for an angle the file does not have, not for the load",
        ),
        ("time=T:deg,alpha=A,beta=B,gamma=C", "'deg' is not a unit of time (expected s, ms, %)"),
    ],
)
def test_mappings_refused(text, message):
    # Each message whole, named by where it comes from: "column mapping: ...".
    with pytest.raises(TrajectoryError) as refused:
        parse_columns(text)
    assert str(refused.value) == f"column mapping: {message}"


def test_a_mapping_of_columns_checks_their_units():
    with pytest.raises(TrajectoryError) as refused:
        ColumnMap.from_mapping({"time": "t", "alpha": Column("A", "N"), "beta": "B", "gamma": "C"})
    assert str(refused.value) == "column mapping: 'N' is not a unit of alpha (expected deg, rad)"
    with pytest.raises(TrajectoryError) as refused:
        ColumnMap.from_mapping({"time": "t", " alpha": "A", "ALPHA": "B", "beta": "B", "gamma": "C"})
    assert str(refused.value) == "column mapping: alpha is mapped twice"
    m = ColumnMap.from_mapping({" Time ": "t", "alpha": Column("A", "rad"), "beta": "B", "gamma": "C"})
    assert m.time == Column("t") and m.angles[0].unit == "rad"


def test_the_readers_options():
    assert as_column_map(None) is None
    m = parse_columns("time=T,alpha=A,beta=B,gamma=C")
    assert as_column_map(m) is m
    assert as_column_map("time=T,alpha=A,beta=B,gamma=C") == m
    assert as_column_map({"time": "T", "alpha": "A", "beta": "B", "gamma": "C"}) == m
    with pytest.raises(TypeError, match="columns must be a ColumnMap, a mapping or text, got int"):
        as_column_map(3)
    assert as_load_column(None) is None
    assert as_load_column("-Fz:kN") == Column("Fz", "kN", -1.0)
    column = Column("Fz")
    assert as_load_column(column) is column
    # The load named on its own joins a mapping without one; named in both, refused.
    merged_map, load = column_options("time=T,alpha=A,beta=B,gamma=C", "Fz:kN", "walk.csv")
    merged = given(merged_map)
    assert merged.load == Column("Fz", "kN") and load == Column("Fz", "kN") and merged.time == Column("T")
    assert column_options(None, "Fz", "walk.csv") == (None, Column("Fz"))
    assert column_options(m, None, "walk.csv") == (m, None)
    with pytest.raises(TrajectoryError) as refused:
        column_options("time=T,alpha=A,beta=B,gamma=C,load=F", "Fz", "walk.csv")
    assert str(refused.value) == "walk.csv: the load column is named twice (in the column mapping and on its own)"
    # Merged into a hip-chain mapping: its angles and chain kept.
    hip_map, _ = column_options("time=T,flexion=F,adduction=A,rotation=R", "Fz", "walk.csv")
    hip = given(hip_map)
    assert hip.hip_chain and hip.angles == (Column("F"), Column("A"), Column("R")) and hip.load == Column("Fz")


def test_a_columns_refusals_are_named_by_the_column_mapping():
    for text, key, message in [
        ("FE:kN", "alpha", "'kN' is not a unit of alpha (expected deg, rad)"),
        ("Fz: lbf ", "load", "'lbf' is not a unit of load (expected N, kN, %BW)"),
        ("T:rad", "time", "'rad' is not a unit of time (expected s, ms, %)"),
        ("- :N", "load", "no column name given for load"),
        (":s", "time", "no column name given for time"),
        ("-", "gamma", "no column name given for gamma"),
    ]:
        with pytest.raises(TrajectoryError) as refused:
            Column.parse(text, key)
        assert str(refused.value) == f"column mapping: {message}"
    # A leading minus flips the sign; a minus elsewhere is part of the name.
    assert Column.parse("F-E", "alpha") == Column("F-E") and Column.parse(" - FE", "alpha").sign == -1.0


def test_only_the_first_equals_sign_ends_the_quantity():
    m = parse_columns("time=T,alpha=F=E,beta=B,gamma=C")
    assert m.angles[0] == Column("F=E")
