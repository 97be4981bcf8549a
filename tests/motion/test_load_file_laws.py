"""Laws of the load read from its own file (hipsim.motion.load_file), on tiny files written here.

Loads are whole numbers (a 3-4-12 triangle's resultant is 13) and times steps of 0.01 s, so each value
read, interpolated or scaled, and each message with its place, is known by hand.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from hipsim import TrajectoryError
from hipsim.motion.build import TrajectoryWarning
from hipsim.motion.columns import Column
from hipsim.motion.load_file import GAP_STEPS, LoadCurve, LoadScale, parse_load_scale, read_load_curve


def write(path, lines) -> str:
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return str(path)


def error_of(call) -> TrajectoryError:
    with pytest.raises(TrajectoryError) as info:
        call()
    return info.value


# --------------------------------------------------------------------------- scaling


def test_a_factor_multiplies_and_a_range_maps_the_ends_exactly():
    load = np.array([10.0, 35.0, 60.0])
    np.testing.assert_array_equal(LoadScale(2.5).apply(load), [25.0, 87.5, 150.0])
    np.testing.assert_array_equal(LoadScale().apply(load), load)
    np.testing.assert_allclose(LoadScale(1.0, 300.0, 3000.0).apply(load), [300.0, 1650.0, 3000.0], rtol=1e-15)
    assert LoadScale(7.0, 300.0, 3000.0).apply(load)[-1] == 3000.0  # the factor is not used with a range
    np.testing.assert_array_equal(LoadScale(1.0, 300.0, 3000.0).apply(np.array([5.0, 5.0])), [300.0, 300.0])
    # A range of half a newton is a range still.
    np.testing.assert_array_equal(LoadScale(1.0, 300.0, 3000.0).apply(np.array([5.0, 5.5])), [300.0, 3000.0])


@pytest.mark.parametrize(
    ("text", "scale"),
    [
        ("2.5", LoadScale(2.5)),
        ("300:3000", LoadScale(1.0, 300.0, 3000.0)),
        ("0:1", LoadScale(1.0, 0.0, 1.0)),
        (4, LoadScale(4.0)),
    ],
)
def test_a_scale_is_read_as_a_factor_or_a_range(text, scale):
    assert parse_load_scale(text) == scale


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("abc", "expected a factor (2.5) or a range MIN:MAX in N (300:3000), got 'abc'"),
        ("1:2:3", "expected a factor (2.5) or a range MIN:MAX in N (300:3000), got '1:2:3'"),
        ("1_000", "expected a factor (2.5) or a range MIN:MAX in N (300:3000), got '1_000'"),
        ("inf", "expected a factor (2.5) or a range MIN:MAX in N (300:3000), got 'inf'"),
        ("1:nan", "expected a factor (2.5) or a range MIN:MAX in N (300:3000), got '1:nan'"),
        ("0", "the factor must be positive, got '0'"),
        ("-2", "the factor must be positive, got '-2'"),
        ("3000:300", "the range must be 0 ≤ MIN < MAX in N, got '3000:300'"),
        ("5:5", "the range must be 0 ≤ MIN < MAX in N, got '5:5'"),
        ("-1:5", "the range must be 0 ≤ MIN < MAX in N, got '-1:5'"),
    ],
)
def test_a_scale_that_is_neither_is_named(text, message):
    assert str(error_of(lambda: parse_load_scale(text))) == f"--load-scale: {message}"


# --------------------------------------------------------------------------- onto the motion's times


def curve(t, load=None, lines=None):
    t = np.asarray(t, dtype=float)
    load = 100.0 * t if load is None else np.asarray(load, dtype=float)
    lines = np.arange(2, t.size + 2) if lines is None else np.asarray(lines)
    return LoadCurve(t, load, lines, "load.csv", "F")


def test_the_load_is_interpolated_at_the_motions_times():
    motion = np.arange(11) * 0.01
    keep, load = curve(np.arange(6) * 0.02, [0, 10, 30, 30, 0, 50]).onto(motion, "m.csv")
    assert keep.all()
    np.testing.assert_allclose(load, [0, 5, 10, 20, 30, 30, 30, 15, 0, 25, 50], rtol=1e-14, atol=1e-12)


def test_motion_samples_outside_the_load_are_left_out_with_a_warning():
    motion = np.arange(11) * 0.01
    with pytest.warns(TrajectoryWarning) as record:
        keep, load = curve(np.arange(7) * 0.01 + 0.02).onto(motion, "m.csv")
    np.testing.assert_array_equal(keep, [False, False] + [True] * 7 + [False, False])
    np.testing.assert_allclose(load, 100.0 * motion[2:9], rtol=1e-14)
    assert str(record[0].message) == (
        "load.csv: the load covers 0.02 to 0.08 s, the motion 0 to 0.1 s: 4 motion samples outside the overlap left out"
    )


def test_no_overlap_or_too_little_is_an_error_naming_both_spans():
    motion = np.arange(11) * 0.01
    error = error_of(lambda: curve([0.5, 0.6, 0.7]).onto(motion, "m.csv"))
    assert str(error) == (
        "load.csv, column 'F': no overlapping time: the motion m.csv covers 0 to 0.1 s, the load 0.5 to 0.7 s"
    )
    # Five motion samples in the overlap: fewer than a trajectory needs.
    error = error_of(lambda: curve(np.arange(5) * 0.01 + 0.06).onto(motion, "m.csv"))
    assert "no overlapping time" in str(error)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", TrajectoryWarning)
        keep, _ = curve(np.arange(6) * 0.01 + 0.05).onto(motion, "m.csv")
    assert keep.sum() == 6


def test_ends_within_a_billionth_count_as_covered():
    motion = np.arange(11) * 0.01
    keep, _ = curve(np.arange(11) * 0.01 * (1 - 5e-10)).onto(motion, "m.csv")
    assert keep.all()
    keep, _ = curve(np.arange(11) * 0.01 * (1 + 5e-10)).onto(motion, "m.csv")
    assert keep.all()
    with pytest.warns(TrajectoryWarning):
        keep, _ = curve(np.arange(11) * 0.01 * (1 - 5e-9)).onto(motion, "m.csv")
    assert keep.sum() == 10


def test_a_gap_in_the_load_inside_the_overlap_is_named_at_its_line():
    t = [0.0, 0.01, 0.02, 0.03, 0.09, 0.1, 0.11]  # a step of 6 median steps
    motion = np.arange(11) * 0.01
    error = error_of(lambda: curve(t, lines=[5, 6, 7, 8, 9, 10, 11]).onto(motion, "m.csv"))
    assert str(error) == "load.csv, line 9, column 'F': a gap in the load from 0.03 to 0.09 s (6 steps of 0.01 s)"
    assert error.line == 9
    # GAP_STEPS steps exactly are not a gap.
    assert GAP_STEPS == 5.0
    t = [0.0, 0.01, 0.02, 0.03, 0.08, 0.09, 0.1]
    keep, _ = curve(t).onto(motion, "m.csv")
    assert keep.all()


def test_a_gap_just_outside_the_overlap_counts_a_gap_far_outside_does_not():
    motion = np.arange(11) * 0.01 + 0.1
    # The load's step into the overlap (0.03 → 0.105) is a gap: the motion's first samples have no load near.
    t = [0.0, 0.01, 0.02, 0.03, 0.105, 0.115, 0.125, 0.135, 0.145, 0.155, 0.165, 0.175, 0.185, 0.195, 0.205]
    error = error_of(lambda: curve(t).onto(motion, "m.csv"))
    assert "a gap in the load from 0.03 to 0.105 s" in str(error)
    # A gap two steps before the overlap does not matter.
    t = [0.0, 0.01, 0.02, 0.09, 0.1, 0.11, 0.12, 0.13, 0.14, 0.15, 0.16, 0.17, 0.18, 0.19, 0.2, 0.21]
    keep, _ = curve(t).onto(motion, "m.csv")
    assert keep.all()
    # Nor after it.
    motion = np.arange(11) * 0.01
    t = [0.0, 0.01, 0.02, 0.03, 0.04, 0.05, 0.06, 0.07, 0.08, 0.09, 0.1, 0.11, 0.5]
    keep, _ = curve(t).onto(motion, "m.csv")
    assert keep.all()
    t = [0.0, 0.01, 0.02, 0.03, 0.04, 0.05, 0.06, 0.07, 0.08, 0.09, 0.095, 0.5]
    assert "a gap in the load from 0.095 to 0.5 s" in str(error_of(lambda: curve(t).onto(motion, "m.csv")))


def test_a_motion_between_two_load_samples_is_interpolated():
    motion = np.arange(8) * 0.01
    keep, load = curve([-1.0, 1.0], [0.0, 2000.0]).onto(motion, "m.csv")
    assert keep.all()
    np.testing.assert_allclose(load, 1000.0 * (motion + 1.0), rtol=1e-15)


# --------------------------------------------------------------------------- read from a file


def test_a_csv_load_by_name_with_its_time_column_anywhere(tmp_path):
    path = write(tmp_path / "f.csv", ["# forces", "F,Time,x"] + [f"{100 * k},{k / 100},a" for k in range(8)])
    read = read_load_curve(path, "F")
    np.testing.assert_array_equal(read.t, np.arange(8) / 100)
    np.testing.assert_array_equal(read.load, 100.0 * np.arange(8))
    np.testing.assert_array_equal(read.lines, np.arange(3, 11))
    assert (read.source, read.column) == (path, "F")


@pytest.mark.parametrize("label", ["time", "T_S", "t", " Time "])
def test_the_time_column_by_its_names_else_the_first(tmp_path, label):
    path = write(tmp_path / "f.csv", [f"F,{label}"] + [f"{100 * k},{k / 100}" for k in range(8)])
    np.testing.assert_array_equal(read_load_curve(path, "F").t, np.arange(8) / 100)
    path = write(tmp_path / "g.csv", ["clock,F"] + [f"{k / 100},{100 * k}" for k in range(8)])
    np.testing.assert_array_equal(read_load_curve(path, "F").t, np.arange(8) / 100)


def test_the_resultant_of_three_components_and_signs_and_units(tmp_path):
    lines = ["time\thip_r_fx\thip_r_fy\thip_r_fz\tFz"] + [
        f"{k / 100}\t{3 * k}\t{-4 * k}\t{12 * k}\t{-k}" for k in range(8)
    ]
    path = write(tmp_path / "f.csv", lines)
    read = read_load_curve(path, "hip_r")
    np.testing.assert_allclose(read.load, 13.0 * np.arange(8), rtol=1e-15)
    assert read.column == "hip_r_fx/_fy/_fz resultant"
    read = read_load_curve(path, "HIP_R:kN")  # case-blind, in kN
    np.testing.assert_allclose(read.load, 13e3 * np.arange(8), rtol=1e-15)
    read = read_load_curve(path, "-Fz")
    np.testing.assert_array_equal(read.load, np.arange(8.0))
    read = read_load_curve(path, Column("Fz", "kN", -1.0))
    np.testing.assert_array_equal(read.load, 1e3 * np.arange(8.0))
    read = read_load_curve(path, "-Fz", body_weight=50.0)  # % body weight by default with a body weight
    np.testing.assert_array_equal(read.load, 0.5 * np.arange(8.0))
    read = read_load_curve(path, "-Fz:N", body_weight=50.0)
    np.testing.assert_array_equal(read.load, np.arange(8.0))
    read = read_load_curve(path, "-Fz", scale=LoadScale(1.0, 300.0, 1000.0))
    np.testing.assert_allclose(read.load, 300.0 + 100.0 * np.arange(8), rtol=1e-15)
    read = read_load_curve(path, "-fz")  # case-blind when no exact match
    assert read.column == "Fz"
    error = error_of(lambda: read_load_curve(path, "-Fz:%BW"))
    assert str(error) == f"{path}, column 'Fz': the load is in % body weight: give the body weight"


def test_an_exact_name_wins_over_a_case_blind_one_and_over_a_resultant(tmp_path):
    lines = ["t,F,f,F_fx,F_fy,F_fz"] + [f"{k / 100},{k},{2 * k},{3 * k},{4 * k},{12 * k}" for k in range(8)]
    path = write(tmp_path / "f.csv", lines)
    np.testing.assert_array_equal(read_load_curve(path, "F").load, np.arange(8.0))
    np.testing.assert_array_equal(read_load_curve(path, "f").load, 2.0 * np.arange(8))


def test_decimal_commas_in_a_semicolon_table(tmp_path):
    path = write(tmp_path / "f.csv", ["t;F"] + [f"0,0{k};{k},5" for k in range(8)])
    read = read_load_curve(path, "F")
    np.testing.assert_allclose(read.t, np.arange(8) / 100, rtol=1e-15)
    np.testing.assert_array_equal(read.load, np.arange(8) + 0.5)


def test_an_opensim_storage_file(tmp_path):
    lines = ["JointReaction", "version=1", "inDegrees=no", "EndHeader", "", "time\thip_r_fx\thip_r_fy\thip_r_fz\t"]
    lines += [f"{k / 100}\t{3 * k}\t{4 * k}\t{12 * k}" for k in range(8)]
    path = write(tmp_path / "f.sto", lines)
    read = read_load_curve(path, "hip_r")
    np.testing.assert_allclose(read.load, 13.0 * np.arange(8), rtol=1e-15)
    np.testing.assert_array_equal(read.lines, np.arange(7, 15))
    lines = ["header", "endheader", "time   F"] + [f"{k / 100}   {k}" for k in range(8)]
    path = write(tmp_path / "g.MOT", lines)
    np.testing.assert_array_equal(read_load_curve(path, "F").load, np.arange(8.0))
    error = error_of(lambda: read_load_curve(write(tmp_path / "h.sto", ["time F", "0 1"]), "F"))
    assert str(error) == f"{tmp_path / 'h.sto'}: no 'endheader' line: not an OpenSim .mot/.sto file"
    error = error_of(lambda: read_load_curve(write(tmp_path / "i.sto", ["a", "endheader", "", " "]), "F"))
    assert str(error) == f"{tmp_path / 'i.sto'}, line 2: no column labels after 'endheader'"


def test_problems_in_the_file_are_named_where_they_are(tmp_path):
    good = ["t,F,G"] + [f"{k / 100},{k},{k}" for k in range(8)]
    assert str(error_of(lambda: read_load_curve(write(tmp_path / "a.csv", ["# x"]), "F"))) == (
        f"{tmp_path / 'a.csv'}: the file is empty"
    )
    path = write(tmp_path / "b.csv", good[:6])
    assert str(error_of(lambda: read_load_curve(path, "F"))) == f"{path}: 5 samples; at least 6 are needed"
    bad = list(good)
    bad[3] = "0.02,2"
    path = write(tmp_path / "c.csv", bad)
    assert str(error_of(lambda: read_load_curve(path, "F"))) == f"{path}, line 4: 2 values, the labels are 3"
    bad = list(good)
    bad[4] = "0.03, x ,3"
    path = write(tmp_path / "d.csv", bad)
    assert str(error_of(lambda: read_load_curve(path, "F"))) == f"{path}, line 5, column 'F': 'x' is not a number"
    bad[4] = "0.03,nan,3"
    path = write(tmp_path / "e.csv", bad)
    assert str(error_of(lambda: read_load_curve(path, "F"))) == f"{path}, line 5, column 'F': 'nan' is not finite"
    bad = list(good)
    bad[5] = "0.03,4,4"
    path = write(tmp_path / "f.csv", bad)
    assert str(error_of(lambda: read_load_curve(path, "F"))) == (
        f"{path}, line 6, column 't': time 0.03 s does not increase (previous 0.03 s)"
    )
    bad = list(good)
    bad[6] = "0.05,-5,5"
    path = write(tmp_path / "g.csv", bad)
    assert str(error_of(lambda: read_load_curve(path, "F"))) == (
        f"{path}, line 7, column 'F': load -5 N is negative (F_e is a magnitude: flip the column's sign with a leading "
        "'-' if it is a compressive component)"
    )
    # The unread column G may hold anything.
    bad = list(good)
    bad[2] = "0.01,1,x"
    np.testing.assert_array_equal(read_load_curve(write(tmp_path / "h.csv", bad), "F").load, np.arange(8.0))


def test_a_load_logged_in_milliseconds_is_refused(tmp_path):
    path = write(tmp_path / "a.csv", ["t,F"] + [f"{10 * k},{k}" for k in range(8)])
    error = error_of(lambda: read_load_curve(path, "F"))
    assert error.column == "t" and "the times look like milliseconds" in str(error)


def test_a_missing_column_is_answered_with_the_nearest_label(tmp_path):
    lines = ["time,hip_r_fx,hip_r_fy,hip_r_fz,knee"] + [f"{k / 100},1,2,3,4" for k in range(8)]
    path = write(tmp_path / "a.csv", lines)
    error = error_of(lambda: read_load_curve(path, "hip_l"))
    assert str(error) == (
        f"{path}, line 1: no load column 'hip_l' (nor 'hip_l_fx', '_fy', '_fz' for a resultant); did you mean 'hip_r'?"
    )
    error = error_of(lambda: read_load_curve(path, "kne"))
    assert str(error).endswith("did you mean 'knee'?")
    # Two labels of one component are not a resultant.
    lines = ["time,F_fx,F_fx,F_fy,F_fz"] + [f"{k / 100},1,2,3,4" for k in range(8)]
    path = write(tmp_path / "b.csv", lines)
    assert "no load column 'F'" in str(error_of(lambda: read_load_curve(path, "F")))


# --------------------------------------------------------------------------- survivors of the first run


def test_a_constant_load_maps_to_low_at_every_sample_and_factors_below_one():
    scaled = LoadScale(1.0, 300.0, 3000.0).apply(np.array([5.0, 5.0, 5.0]))
    assert scaled.shape == (3,)
    np.testing.assert_array_equal(scaled, [300.0, 300.0, 300.0])
    assert parse_load_scale("0.5") == LoadScale(0.5)


def test_a_motion_sample_a_little_outside_the_load_is_left_out():
    # The load starts at 0.02 s; a motion sample 3e-9 relative before it is outside (more than 1e-9 of 0.02 s).
    motion = 0.02 * (1 - 3e-9) + np.arange(8) * 0.01
    with pytest.warns(TrajectoryWarning):
        keep, _ = curve(np.arange(10) * 0.01 + 0.02).onto(motion, "m.csv")
    np.testing.assert_array_equal(keep, [False] + [True] * 7)
    # Times before 0: a motion ending at 0 s where the load ends keeps its last sample.
    motion = np.arange(-7, 1) * 0.01
    keep, _ = curve(np.arange(-9, 1) * 0.01).onto(motion, "m.csv")
    assert keep.all()


def test_only_steps_that_reach_into_the_overlap_can_be_gaps():
    motion = np.arange(8) * 0.01 + 0.09
    # A load sample exactly at the motion's first time: the step before it lies outside.
    t = [0.0, 0.09, 0.1, 0.11, 0.12, 0.13, 0.14, 0.15, 0.16]
    keep, _ = curve(t).onto(motion, "m.csv")
    assert keep.all()
    # And exactly at its last: the step after it lies outside.
    t = [0.09, 0.1, 0.11, 0.12, 0.13, 0.14, 0.15, 0.16, 0.9]
    keep, _ = curve(t).onto(motion, "m.csv")
    assert keep.all()
    # A step that straddles the last time is a gap.
    t = [0.09, 0.1, 0.11, 0.12, 0.13, 0.14, 0.15, 0.155, 0.9]
    assert "a gap in the load from 0.155 to 0.9 s" in str(error_of(lambda: curve(t).onto(motion, "m.csv")))
    # Between two load samples far apart: the one step across the motion is no gap of its own median.
    keep, _ = curve([0.0, 0.5, 1.0, 1.01, 1.02]).onto(motion, "m.csv")
    assert keep.all()
    assert "a gap in the load from 0 to 0.5 s" in str(
        error_of(lambda: curve([0.0, 0.5, 0.51, 0.52, 0.53]).onto(motion, "m.csv"))
    )


def test_six_rows_are_enough_and_a_label_line_alone_is_not(tmp_path):
    path = write(tmp_path / "a.csv", ["t,F"] + [f"{k / 100},{k}" for k in range(6)])
    assert len(read_load_curve(path, "F").t) == 6
    path = write(tmp_path / "b.csv", ["t,F"])
    assert str(error_of(lambda: read_load_curve(path, "F"))) == f"{path}: 0 samples; at least 6 are needed"


def test_decimal_commas_are_read_only_between_semicolons_or_tabs(tmp_path):
    rows = [f"{k / 100},{k}" for k in range(8)]
    rows[2] = '0.02,"2,5"'
    path = write(tmp_path / "a.csv", ["t,F", *rows])
    assert str(error_of(lambda: read_load_curve(path, "F"))) == f"{path}, line 4, column 'F': '2,5' is not a number"
    lines = ["endheader", "time F"] + [f"{k / 100} {k}" for k in range(8)]
    lines[4] = "0.02 2,5"
    path = write(tmp_path / "b.sto", lines)
    assert str(error_of(lambda: read_load_curve(path, "F"))) == f"{path}, line 5, column 'F': '2,5' is not a number"


def test_the_file_is_named_in_its_time_unit_and_when_missing(tmp_path):
    path = write(tmp_path / "a.csv", ["t,F"] + [f"{10 * k},{k}" for k in range(8)])
    assert str(error_of(lambda: read_load_curve(path, "F"))).startswith(
        f"{path}, column 't': the times look like milliseconds"
    )
    missing = str(tmp_path / "none.csv")
    assert str(error_of(lambda: read_load_curve(missing, "F"))) == f"{missing}: no such load file"


def test_tab_separated_labels_may_hold_spaces(tmp_path):
    lines = ["endheader", "time\thip r_fx\thip r_fy\thip r_fz"] + [
        f"{k / 100}\t{3 * k}\t{4 * k}\t{12 * k}" for k in range(8)
    ]
    path = write(tmp_path / "a.mot", lines)
    np.testing.assert_allclose(read_load_curve(path, "hip r").load, 13.0 * np.arange(8), rtol=1e-15)


def test_the_load_files_separator_is_judged_on_the_labels_and_the_first_row(tmp_path):
    # By ';' the labels have two cells and the rows one: the comma, which splits both into three, wins.
    path = write(tmp_path / "a.csv", ["t,F,note; remark"] + [f"{k / 100},{k},x" for k in range(8)])
    np.testing.assert_array_equal(read_load_curve(path, "F").load, np.arange(8.0))
    # So with one row too: the labels are read by commas, and the row count is what is wrong.
    path = write(tmp_path / "b.csv", ["t,F,note; remark", "0,1,x"])
    assert str(error_of(lambda: read_load_curve(path, "F"))) == f"{path}: 1 samples; at least 6 are needed"


def test_the_nearest_label_is_found_in_any_case_and_for_any_name(tmp_path):
    lines = ["time,HIP_R_FX,HIP_R_FY,HIP_R_FZ"] + [f"{k / 100},1,2,3" for k in range(8)]
    path = write(tmp_path / "a.csv", lines)
    assert str(error_of(lambda: read_load_curve(path, "HIP_L"))).endswith("did you mean 'HIP_R'?")
    assert "; did you mean '" in str(error_of(lambda: read_load_curve(path, "zzz")))
