"""Design variants (hipsim.design.variants): grids, Latin hypercubes, tolerance studies, CSV files, the option texts;
each refusal naming its key, option, file line or column."""

from __future__ import annotations

import math

import numpy as np
import pytest

import hipsim
from hipsim.design import variants as v
from hipsim.exceptions import ArgumentError, FileRowError, ParameterError


@pytest.fixture(scope="module")
def base():
    return hipsim.load_parameters()


def test_grid_includes_its_stop_and_gives_the_values_as_typed():
    variants = v.grid({"platform.home_offset_deg": (0.1, 0.3, 0.1), "lever.length_mm": (300.0, 360.0, 5.0)})
    assert len(variants) == 3 * 13
    assert variants.names == ("platform.home_offset_deg", "lever.length_mm")
    assert sorted(set(variants.values[:, 0])) == [0.1, 0.2, 0.3]  # 0.1 + 2·0.1 is 0.30000000000000004 in floats
    assert sorted(set(variants.values[:, 1])) == [300.0 + 5.0 * k for k in range(13)]
    # Every combination once.
    assert len({tuple(row) for row in variants.values}) == len(variants)


@pytest.mark.parametrize(
    "axis", [(300.0, 360.0, 0.0), (300.0, 360.0, -5.0), (360.0, 300.0, 5.0), (300.0, math.inf, 5.0)]
)
def test_a_bad_grid_axis_is_refused_naming_its_key(axis):
    with pytest.raises(ArgumentError, match="lever.length_mm"):
        v.grid({"lever.length_mm": axis})


def test_latin_hypercube_puts_one_variant_in_each_stratum_of_each_range():
    n = 40
    variants = v.latin_hypercube({"lever.length_mm": (300.0, 360.0), "screw.lead_mm": (5.0, 20.0)}, n, seed=7)
    for column, (low, high) in zip(variants.values.T, ((300.0, 360.0), (5.0, 20.0))):
        strata = np.floor((column - low) / (high - low) * n).astype(int)
        assert sorted(strata) == list(range(n))
    again = v.latin_hypercube({"lever.length_mm": (300.0, 360.0), "screw.lead_mm": (5.0, 20.0)}, n, seed=7)
    assert np.array_equal(again.values, variants.values)
    with pytest.raises(ArgumentError, match="screw.lead_mm"):
        v.latin_hypercube({"screw.lead_mm": (20.0, 5.0)}, n)


def test_tolerance_study_spreads_around_the_machines_own_values(base):
    machine = hipsim.load_parameters(overrides={"lever.length_mm": 331.0})
    n = 4000
    variants = v.tolerance_study(
        machine, {"lever.length_mm": ("normal", 0.05), "platform.heights_mm[2]": ("uniform", 0.2)}, n, seed=3
    )
    length, height = variants.values.T
    # Normal: mean within 4 standard errors of the nominal, σ within 5 %.
    assert abs(length.mean() - 331.0) < 4 * 0.05 / math.sqrt(n)
    assert length.std() == pytest.approx(0.05, rel=0.05)
    # Uniform within ±0.2 around h_2 = 490 mm (the file's second height), spread σ = 0.2/√3.
    assert np.all(np.abs(height - 490.0) <= 0.2)
    assert height.std() == pytest.approx(0.2 / math.sqrt(3), rel=0.05)


@pytest.mark.parametrize(
    ("name", "message"),
    [
        ("lever.lenght_mm", "did you mean 'lever.length_mm'"),
        ("platform.heights_mm", "list of 2 numbers"),
        ("platform.heights_mm[3]", "index 3 is out of the list"),
        ("lever.length_mm[1]", "single number"),
        ("friction.thrust_bearing_axial_only", "cannot be swept"),
    ],
)
def test_a_bad_key_is_refused_before_anything_runs(name, message):
    with pytest.raises(ParameterError, match=message.replace("(", r"\(")) as caught:
        v.key_ref(name, "--grid")
    assert "--grid" in str(caught.value)


def test_variants_csv_is_read_and_its_bad_rows_named(tmp_path):
    good = tmp_path / "good.csv"
    good.write_text("# candidates\nlever.length_mm,platform.heights_mm[1]\n330,900\n\n340.5,905\n")
    variants = v.read_variants(good)
    assert variants.names == ("lever.length_mm", "platform.heights_mm[1]")
    assert variants.values.tolist() == [[330.0, 900.0], [340.5, 905.0]]
    bad = tmp_path / "bad.csv"
    bad.write_text("lever.length_mm,platform.home_offset_deg\n330,30\n340,thirty\n")
    with pytest.raises(FileRowError) as caught:
        v.read_variants(bad)
    assert (caught.value.source, caught.value.line, caught.value.column) == (str(bad), 3, "platform.home_offset_deg")
    bad.write_text("lever.length_mm,platform.home_offset_dg\n330,30\n")
    with pytest.raises(FileRowError, match="did you mean") as caught:
        v.read_variants(bad)
    assert (caught.value.line, caught.value.column) == (1, "platform.home_offset_dg")
    bad.write_text("lever.length_mm,platform.home_offset_deg\n330\n")
    with pytest.raises(FileRowError, match="1 cells, the header has 2") as caught:
        v.read_variants(bad)
    assert caught.value.line == 2


def test_option_texts_are_parsed_or_refused_naming_the_option():
    assert v.parse_axis("lever.length_mm = 300:360:5", "--grid", 3) == ("lever.length_mm", [300.0, 360.0, 5.0])
    assert v.parse_tolerance("platform.home_offset_deg=±0.2") == ("platform.home_offset_deg", ("uniform", 0.2))
    assert v.parse_tolerance("platform.home_offset_deg=+-0.2") == ("platform.home_offset_deg", ("uniform", 0.2))
    assert v.parse_tolerance("lever.length_mm=0.05") == ("lever.length_mm", ("normal", 0.05))
    for text in ("lever.length_mm=300:360", "=300:360:5", "lever.length_mm=a:b:c"):
        with pytest.raises(ArgumentError, match="--grid"):
            v.parse_axis(text, "--grid", 3)
    for text in ("lever.length_mm=0", "lever.length_mm=±-1", "lever.length_mm"):
        with pytest.raises(ArgumentError, match="--spread"):
            v.parse_tolerance(text)


def test_a_stop_within_a_billionth_of_a_step_is_on_the_grid():
    assert v.grid({"lever.length_mm": (300.0, 310.0 - 1e-10, 5.0)}).values.ravel().tolist() == [300.0, 305.0, 310.0]
    assert v.grid({"lever.length_mm": (300.0, 310.0 - 1e-7, 5.0)}).values.ravel().tolist() == [300.0, 305.0]
    assert v.grid({"lever.length_mm": (300.0, 300.0, 5.0)}).values.tolist() == [[300.0]]  # stop = start: one value


def test_too_many_variants_are_refused_before_they_are_made():
    with pytest.raises(ArgumentError, match="at most 10,000,000"):
        v.grid({"lever.length_mm": (0.0, 5000.0, 1.0), "screw.lead_mm": (0.0, 2000.0, 1.0)})  # 5001·2001
    with pytest.raises(ArgumentError, match="variants"):
        v.latin_hypercube({"lever.length_mm": (300.0, 360.0)}, v.MAX_VARIANTS + 1)


@pytest.mark.parametrize("count", [0, -1, 1.5, 2.0])
def test_a_count_must_be_a_whole_number_of_at_least_one(base, count):
    with pytest.raises(ArgumentError, match="count"):
        v.latin_hypercube({"lever.length_mm": (300.0, 360.0)}, count)
    with pytest.raises(ArgumentError, match="count"):
        v.tolerance_study(base, {"lever.length_mm": ("normal", 0.1)}, count)


def test_one_variant_and_a_range_of_equal_ends():
    one = v.latin_hypercube({"lever.length_mm": (300.0, 360.0)}, 1)
    assert len(one) == 1 and 300.0 <= one.values[0, 0] <= 360.0
    with pytest.raises(ArgumentError, match="LOW:HIGH with HIGH > LOW"):
        v.latin_hypercube({"lever.length_mm": (300.0, 300.0)}, 3)
    with pytest.raises(ArgumentError, match="at least one key"):
        v.latin_hypercube({}, 3)


@pytest.mark.parametrize("spread", [("normal", 0.0), ("uniform", -1.0), ("box", 1.0), ("normal", math.nan)])
def test_a_bad_spread_is_refused_naming_its_key(base, spread):
    with pytest.raises(ArgumentError, match="lever.length_mm"):
        v.tolerance_study(base, {"lever.length_mm": spread}, 3)


def test_the_nominal_values_are_the_files_own_with_lists_counted_from_one(base):
    keys = [v.key_ref("lever.length_mm"), v.key_ref("platform.heights_mm[1]"), v.key_ref(" platform.heights_mm [ 2 ] ")]
    assert keys[2] == v.KeyRef("platform.heights_mm[2]", "platform.heights_mm", 1)
    assert v.nominal(base, keys).tolist() == [328.0, 899.0, 490.0]  # models/hip_simulator.toml


def test_variants_refuse_a_key_twice_and_values_that_are_not_finite():
    key = v.key_ref("lever.length_mm")
    with pytest.raises(ArgumentError, match="each key once"):
        v.Variants((key, key), np.zeros((1, 2)))
    with pytest.raises(ArgumentError, match="finite numbers"):
        v.Variants((key,), np.array([[1.0], [math.inf]]))
    assert len(v.Variants((), np.zeros((0, 0)))) == 0


def test_a_variants_file_with_semicolons_and_decimal_commas(tmp_path):
    path = tmp_path / "v.csv"
    path.write_text("lever.length_mm;platform.home_offset_deg\n330,5;29,75\n")
    assert v.read_variants(path).values.tolist() == [[330.5, 29.75]]


@pytest.mark.parametrize(
    ("text", "message", "line"),
    [("# nothing\n\n", "no header", None), ("lever.length_mm\n# none\n", "no variants below the header", 1)],
)
def test_a_variants_file_without_rows_says_so(tmp_path, text, message, line):
    path = tmp_path / "v.csv"
    path.write_text(text)
    with pytest.raises(FileRowError, match=message) as caught:
        v.read_variants(path)
    assert caught.value.line == line


def test_a_missing_variants_file_is_a_parameter_error_naming_it(tmp_path):
    with pytest.raises(ParameterError) as caught:
        v.read_variants(tmp_path / "absent.csv")
    assert caught.value.source == str(tmp_path / "absent.csv")


def test_an_axis_needs_its_number_of_parts():
    assert v.parse_axis("screw.lead_mm=5:20", "--range", 2) == ("screw.lead_mm", [5.0, 20.0])
    with pytest.raises(ArgumentError, match="--range: expected KEY=LOW:HIGH"):
        v.parse_axis("screw.lead_mm=5:20:1", "--range", 2)
    with pytest.raises(ArgumentError, match="--grid"):
        v.parse_axis("screw.lead_mm=5:inf:1", "--grid", 3)
    assert v.parse_tolerance("lever.length_mm=+/-0.5") == ("lever.length_mm", ("uniform", 0.5))
