"""hipsim.machine.drive_fields by hand: each entry converted to SI by its unit, and refused at each bound's edge."""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

from hipsim.machine.drive_fields import FIELDS, checked_value, field_lookup, file_fields


class Refused(Exception):
    pass


def fail(message, name):
    raise Refused(f"{name}: {message}")


def value(table, base, raw, unit=None):
    spec = FIELDS[table][base]
    unit = next(iter(spec.units)) if unit is None else unit
    name = spec.names(base)[list(spec.units).index(unit)]
    return checked_value(spec, spec.units[unit], raw, name, fail)


def test_units_convert_to_si():
    assert value("lead_screw", "lead", 5, "mm") == pytest.approx(0.005)
    assert value("motor", "rotor_inertia", 2.5, "kgcm2") == pytest.approx(2.5e-4)
    assert value("motor", "rotor_inertia", 250, "kgmm2") == pytest.approx(2.5e-4)
    assert value("motor", "thermal_time_constant", 2, "min") == 120.0
    assert_allclose(value("motor", "s1_speed", [0, 3000], "rpm"), [0.0, 100 * math.pi])
    assert_allclose(value("motor", "s1_torque", [1500, 1200], "Nmm"), [1.5, 1.2])
    assert isinstance(value("motor", "rated_power", 1, "kW"), float)


def test_a_fraction_is_in_zero_to_one_with_one_included():
    assert value("gearbox", "efficiency", 1.0) == 1.0
    assert value("gearbox", "efficiency", 0.9) == 0.9
    for bad in (0.0, 1.0000001):
        with pytest.raises(Refused, match=r"efficiency: must lie in \(0, 1\]"):
            value("gearbox", "efficiency", bad)
    with pytest.raises(Refused, match="must not be negative"):
        value("gearbox", "efficiency", -0.5)


def test_positive_and_nonnegative_bounds_at_zero():
    with pytest.raises(Refused, match="ratio: must be positive, got 0"):
        value("gearbox", "ratio", 0)
    assert value("gearbox", "inertia", 0, "kgcm2") == 0.0  # a part left out
    with pytest.raises(Refused, match="must not be negative"):
        value("gearbox", "inertia", -1, "kgcm2")


def test_more_than_a_billion_is_a_unit_slip():
    assert value("lead_screw", "dynamic_load_rating", 1e9) == 1e9
    with pytest.raises(Refused, match="out of range"):
        value("lead_screw", "dynamic_load_rating", 1.000001e9)


def test_a_drive_figure_in_another_unit_is_named():
    with pytest.raises(Refused, match="lead_mm: "):
        value("lead_screw", "lead", 5000, "mm")  # 5 m a turn: metres written as millimetres


@pytest.mark.parametrize(
    ("table", "base", "raw", "words"),
    [
        ("gearbox", "ratio", [3, 4], "expected one number, got a list"),
        ("gearbox", "ratio", True, "expected a number, got True"),
        ("gearbox", "ratio", "3", "expected a number"),
        ("gearbox", "ratio", math.inf, "expected finite numbers"),
        ("motor", "s1_speed", [], "expected numbers, got \\[\\]"),
        ("motor", "name", "  ", "expected a name"),
        ("motor", "name", False, "expected a name"),
        ("lead_screw", "end_fixing", "glued", "expected one of"),
    ],
)
def test_wrong_kinds_are_refused(table, base, raw, words):
    with pytest.raises(Refused, match=words):
        value(table, base, raw)


def test_names_text_and_choices():
    assert value("motor", "name", " M-100 ") == "M-100"
    assert value("motor", "name", 42) == "42"
    assert value("lead_screw", "end_fixing", " Fixed-Free ") == "fixed-free"  # stripped, any case


def test_every_file_name_is_its_base_and_unit():
    fields = file_fields("gearbox")
    assert fields["inertia_kgcm2"].endswith("[kgcm2]") and fields["inertia_kgmm2"].endswith("[kgmm2]")
    assert "ratio" in fields and "ratio_" not in "".join(fields)
    lookup = field_lookup(("lead_screw",), exclude=("name",))
    assert "name" not in lookup
    table, base, spec, factor = lookup["lead_mm"]
    assert (table, base, spec.attribute, factor) == ("lead_screw", "lead", "lead", 1e-3)
    assert np.isclose(lookup["inertia_kgcm2"][3], 1e-4)
