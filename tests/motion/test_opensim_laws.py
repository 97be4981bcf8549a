"""Laws of the OpenSim .mot/.sto reader (hipsim.motion.opensim), on tiny files written here.

Eight rows at 100 Hz; the hip's flexion alone (a rotation about Z, so α = flexion) in whole degrees or
tenths of a radian, so the angles read, the header's declarations and each message are known by hand.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from motion_support import error_of, quiet
from support import given

from hipsim.motion.build import SampledMotion, TrajectoryWarning
from hipsim.motion.columns import Column
from hipsim.motion.opensim import HIP_COORDINATES, _find, _header, _read, load_opensim

N = 8
T = np.arange(N) / 100.0
FLEXION = 10.0 + np.arange(N)  # [deg]
LABELS = ["time", "hip_flexion_r", "hip_adduction_r", "hip_rotation_r", "knee_angle_r", "F"]


def mot(path, header=("inDegrees=yes",), labels=LABELS, rows=None, separator="\t") -> str:
    if rows is None:
        rows = [[T[k], FLEXION[k], 0, 0, 5, 1000 + 100 * k] for k in range(N)]
    lines = ["ik", *header, "endheader", separator.join(labels)]
    lines += [separator.join(v if isinstance(v, str) else f"{v:g}" for v in row) for row in rows]
    path.write_text("\n".join(lines) + "\n")
    return str(path)


def test_the_right_hip_in_degrees_with_its_load(tmp_path):
    path = mot(tmp_path / "a.mot")
    trajectory = load_opensim(path, load_column="F")
    np.testing.assert_allclose(trajectory.q[:, 0], np.radians(FLEXION), rtol=0, atol=1e-12)
    np.testing.assert_allclose(trajectory.q[:, 1:], 0.0, atol=1e-12)
    np.testing.assert_array_equal(trajectory.Fe, 1000.0 + 100.0 * np.arange(N))
    np.testing.assert_array_equal(trajectory.lines, np.arange(5, 5 + N))
    assert trajectory.name == path
    assert HIP_COORDINATES == ("hip_flexion", "hip_adduction", "hip_rotation")


def test_the_table_as_read(tmp_path):
    path = mot(tmp_path / "a.mot", header=("version=1", "inDegrees=yes"))
    table = _read(path, path, "r", None)
    np.testing.assert_array_equal(table.time, T)
    np.testing.assert_array_equal(table.angles, np.column_stack([FLEXION, np.zeros(N), np.zeros(N)]))
    assert table.load is None
    assert table.columns.hip_chain
    assert [c.name for c in table.columns.angles] == ["hip_flexion_r", "hip_adduction_r", "hip_rotation_r"]
    assert [c.unit for c in table.columns.angles] == ["deg"] * 3
    assert (table.columns.time.name, table.columns.time.unit) == ("time", "s")
    assert table.time_quantum == pytest.approx(0.01, rel=1e-15)
    np.testing.assert_array_equal(table.lines, np.arange(6, 6 + N))


def test_the_time_resolution_is_the_finest_printed_or_unknown(tmp_path):
    rows = [[T[k], FLEXION[k], 0, 0, 5, 1000] for k in range(N)]
    rows[3][0] = "0.030"
    path = tmp_path / "a.mot"
    lines = ["endheader", "\t".join(LABELS)] + ["\t".join(str(v) for v in row) for row in rows]
    path.write_text("\n".join(lines) + "\n")
    assert _read(str(path), path, "r", None).time_quantum == pytest.approx(0.001, rel=1e-15)
    rows[3][0] = "3e-2"
    lines = ["endheader", "\t".join(LABELS)] + ["\t".join(str(v) for v in row) for row in rows]
    path.write_text("\n".join(lines) + "\n")
    assert _read(str(path), path, "r", None).time_quantum == 0.0


def test_in_degrees_absent_or_no_is_radians(tmp_path):
    rows = [[T[k], 0.1 * k, 0, 0, 5, 1000] for k in range(N)]
    for header in ((), ("inDegrees=no",), ("InDegrees = NO",), ("indegrees no",)):
        trajectory = quiet(lambda: load_opensim(mot(tmp_path / "a.mot", header=header, rows=rows)))
        np.testing.assert_allclose(trajectory.q[:, 0], 0.1 * np.arange(N), rtol=0, atol=1e-12)
    trajectory = quiet(lambda: load_opensim(mot(tmp_path / "b.mot", header=("inDegrees = YES",))))
    np.testing.assert_allclose(trajectory.q[:, 0], np.radians(FLEXION), rtol=0, atol=1e-12)


def test_the_header_by_hand():
    assert _header([], "f") == (False, None, None)
    lines = ["Coordinates", "version=1", "nRows=8", "nColumns=6", "inDegrees=yes"]
    assert _header(lines, "f") == (True, (3, 8), (4, 6))
    assert _header(["datarows 5", "datacolumns\t3", "inDegrees=no"], "f") == (False, (1, 5), (2, 3))
    assert _header(["name with several words", " NROWS = 4 "], "f") == (False, (2, 4), None)
    error = error_of(lambda: _header(["x", "inDegrees=maybe"], "f.mot"))
    assert str(error) == "f.mot, line 2: inDegrees must be yes or no, got 'maybe'"
    error = error_of(lambda: _header(["x", "y", "nColumns=six"], "f.mot"))
    assert str(error) == "f.mot, line 3: nColumns must be a whole number, got 'six'"


def test_declared_counts_that_disagree_are_warned_of_with_their_lines(tmp_path):
    path = mot(tmp_path / "a.mot", header=("nRows=9", "nColumns=6", "inDegrees=yes"))
    with pytest.warns(TrajectoryWarning) as record:
        load_opensim(path, load_column="F")
    assert [str(w.message) for w in record] == [
        f"{path}, line 2: the header says 9 rows, the file has 8: the rows are read"
    ]
    path = mot(tmp_path / "b.mot", header=("nRows=8", "nColumns=5", "inDegrees=yes"))
    with pytest.warns(TrajectoryWarning) as record:
        load_opensim(path, load_column="F")
    assert [str(w.message) for w in record] == [
        f"{path}, line 3: the header says 5 columns, the labels are 6: the labels are read"
    ]
    path = mot(tmp_path / "c.mot", header=("nRows=8", "nColumns=6", "inDegrees=yes"))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        load_opensim(path, load_column="F")


def test_labels_by_tabs_spaces_or_a_trailing_tab(tmp_path):
    spaced = mot(tmp_path / "a.mot", separator="   ")
    np.testing.assert_allclose(load_opensim(spaced, load_column="F").q[:, 0], np.radians(FLEXION), atol=1e-12)
    path = tmp_path / "b.mot"
    text = mot(path)
    lines = path.read_text().split("\n")
    lines[3] += "\t"
    path.write_text("\n".join(lines))
    np.testing.assert_allclose(load_opensim(text, load_column="F").q[:, 0], np.radians(FLEXION), atol=1e-12)
    # Tab-separated labels may hold spaces.
    labels = ["time", "hip_flexion_r", "hip_adduction_r", "hip_rotation_r", "knee angle", "F"]
    path = mot(tmp_path / "c.mot", labels=labels)
    assert len(quiet(lambda: load_opensim(path))) == N


def test_comma_separated_labels_are_named(tmp_path):
    path = mot(tmp_path / "a.mot", separator=",")
    error = error_of(lambda: load_opensim(path))
    assert str(error) == (
        f"{path}, line 4: the labels are separated by commas (6 of them): a .mot/.sto file is tab- or space-separated, "
        "as OpenSim writes it; save it with tabs, or as a .csv read with --columns"
    )
    # One label with a comma in it, or an empty cell between commas, is not a comma-separated file.
    path = mot(tmp_path / "b.mot", labels=["time", "hip_flexion_r", "hip_adduction_r", "hip_rotation_r", "a,b", "F"])
    assert len(quiet(lambda: load_opensim(path))) == N
    path = mot(tmp_path / "c.mot", labels=["time", "hip_flexion_r", "hip_adduction_r", "hip_rotation_r", "k,,l", "F"])
    assert len(quiet(lambda: load_opensim(path))) == N


def test_problems_are_named_at_their_lines(tmp_path):
    path = tmp_path / "a.mot"
    path.write_text("ik\ntime\t1\n")
    assert str(error_of(lambda: load_opensim(path))) == f"{path}: no 'endheader' line: not an OpenSim .mot/.sto file"
    path.write_text("ik\nEndHeader\n\n  \n")
    assert str(error_of(lambda: load_opensim(path))) == f"{path}, line 2: no column labels after 'endheader'"
    rows = [[T[k], FLEXION[k], 0, 0, 5, 1000] for k in range(5)]
    short = mot(tmp_path / "b.mot", rows=rows)
    assert str(error_of(lambda: load_opensim(short))) == f"{short}: 5 samples; at least 6 are needed"
    rows = [[T[k], FLEXION[k], 0, 0, 5, 1000] for k in range(N)]
    rows[2] = rows[2][:5]
    ragged = mot(tmp_path / "c.mot", rows=rows)
    assert str(error_of(lambda: load_opensim(ragged))) == f"{ragged}, line 7: 5 values, the labels are 6"
    rows = [[T[k], FLEXION[k], 0, 0, 5, 1000] for k in range(N)]
    rows[4][3] = "x"
    bad = mot(tmp_path / "d.mot", rows=rows)
    assert str(error_of(lambda: load_opensim(bad))) == f"{bad}, line 9, column 'hip_rotation_r': 'x' is not a number"
    rows[4][3] = "inf"
    bad = mot(tmp_path / "e.mot", rows=rows)
    assert str(error_of(lambda: load_opensim(bad))) == f"{bad}, line 9, column 'hip_rotation_r': 'inf' is not finite"
    rows[4][3] = 0
    rows[4][4] = "x"  # the knee is not read
    assert len(quiet(lambda: load_opensim(mot(tmp_path / "f.mot", rows=rows)))) == N


def test_the_side_and_its_spellings(tmp_path):
    labels = ["time", "hip_flexion_l", "hip_adduction_l", "hip_rotation_l", "knee_angle_l", "F"]
    path = mot(tmp_path / "a.mot", labels=labels)
    for side in ("left", "l", " LEFT "):
        trajectory = quiet(lambda: load_opensim(path, side))
        np.testing.assert_allclose(trajectory.q[:, 0], np.radians(FLEXION), rtol=0, atol=1e-12)
    error = error_of(lambda: load_opensim(path))
    assert str(error) == (
        f"{path}, line 4: no column 'hip_flexion_r' (the right hip's coordinate); its hip columns are "
        "hip_flexion_l, hip_adduction_l, hip_rotation_l (the other hip's are there: read them with --side left, "
        'side="left" in Python)'
    )
    for bad in ("both", None, 1):
        assert (
            str(error_of(lambda: load_opensim(path, bad)))  # type: ignore[arg-type]  # wrong sides on purpose == f"{path}: side must be 'right' or 'left', got {bad!r}"
        )
    path = mot(tmp_path / "b.mot")
    error = error_of(lambda: load_opensim(path, "l"))
    assert "no column 'hip_flexion_l' (the left hip's coordinate)" in str(error)
    assert "read them with --side right" in str(error)


def test_find_by_name_state_path_or_case(tmp_path):
    labels = ["/jointset/hip_r/hip_flexion_r/value", "HIP_ADDUCTION_R", "hip_rotation_r", "hip_rotation_rr"]
    assert _find(labels, ("hip_flexion_r",), "x", "f", 1) == 0
    assert _find(labels, ("hip_adduction_r",), "x", "f", 1) == 1
    assert _find(labels, ("hip_rotation_r",), "x", "f", 1) == 2
    assert _find(["a", "b"], ("c", "B"), "x", "f", 1) == 1
    assert _find(["Time", "time"], ("time",), "x", "f", 1) == 1  # exact wins over case
    error = error_of(lambda: _find(["time", "TIME", "x"], ("Time",), "the time", "f", 3))
    assert str(error) == "f, line 3, column 'Time': column 'Time' appears 2 times"


def test_a_missing_column_lists_what_is_there(tmp_path):
    labels = [f"c{k}" for k in range(9)]
    error = error_of(lambda: _find(labels, ("time",), "the time", "f", 2))
    assert str(error) == "f, line 2: no column 'time' (the time); its columns are c0, c1, c2, c3, c4, c5, c6, c7 …"
    error = error_of(lambda: _find(labels[:8], ("time",), "the time", "f", 2))
    assert str(error) == "f, line 2: no column 'time' (the time); its columns are c0, c1, c2, c3, c4, c5, c6, c7"
    hips = ["time"] + [f"Hip_{k}" for k in range(7)]
    error = error_of(lambda: _find(hips, ("hip_flexion_r",), "the right hip's coordinate", "f", 2))
    assert str(error).endswith("its hip columns are Hip_0, Hip_1, Hip_2, Hip_3, Hip_4, Hip_5")
    planar = ["time", "hip_flexion_r", "knee_angle_r"]
    error = error_of(lambda: _find(planar, ("hip_adduction_r",), "the right hip's coordinate", "f", 2))
    assert str(error) == (
        "f, line 2: no column 'hip_adduction_r' (the right hip's coordinate); its hip columns are hip_flexion_r "
        "(a planar model? read it with --columns time=time,flexion=hip_flexion_r,adduction=zero,rotation=zero)"
    )
    error = error_of(lambda: _find(planar, ("hip_rotation_r",), "x", "f", 2))
    assert "flexion=hip_flexion_r,adduction=zero" in str(error)
    error = error_of(lambda: _find(["time", "/a/hip_flexion_l/value"], ("hip_flexion_r",), "x", "f", 2))
    assert "read them with --side left" in str(error)
    error = error_of(lambda: _find(["time", "hip_flexion_l"], ("knee_r",), "x", "f", 2))
    assert "--side" not in str(error) and "planar" not in str(error)


def test_a_mapping_reads_any_columns_with_the_files_unit(tmp_path):
    rows = [[T[k], 0.1 * k, 0, 0, 0.5, 1000] for k in range(N)]
    path = mot(tmp_path / "a.mot", header=("inDegrees=no",), rows=rows)
    trajectory = quiet(
        lambda: load_opensim(path, columns="time=time,alpha=hip_flexion_r,beta=zero,gamma=-knee_angle_r")
    )
    np.testing.assert_allclose(trajectory.q[:, 0], 0.1 * np.arange(N), rtol=0, atol=1e-15)
    np.testing.assert_array_equal(trajectory.q[:, 1], 0.0)
    np.testing.assert_allclose(trajectory.q[:, 2], np.full(N, -0.5), rtol=0, atol=1e-15)
    trajectory = quiet(lambda: load_opensim(path, columns="time=time,alpha=hip_flexion_r:deg,beta=zero,gamma=zero"))
    np.testing.assert_allclose(trajectory.q[:, 0], np.radians(0.1 * np.arange(N)), rtol=0, atol=1e-15)
    trajectory = load_opensim(
        path, columns="time=time,alpha=hip_flexion_r,beta=zero,gamma=zero,load=F:%BW", body_weight=50.0
    )
    np.testing.assert_array_equal(trajectory.Fe, np.full(N, 500.0))
    trajectory = load_opensim(path, columns="time=time,alpha=hip_flexion_r,beta=zero,gamma=zero", load_column="F")
    np.testing.assert_array_equal(trajectory.Fe, np.full(N, 1000.0))
    mapped = "time=time,flexion=hip_flexion_r,adduction=zero,rotation=zero"
    trajectory = quiet(lambda: load_opensim(path, columns=mapped))
    np.testing.assert_allclose(trajectory.q[:, 0], 0.1 * np.arange(N), rtol=0, atol=1e-12)
    error = error_of(lambda: load_opensim(path, columns="time=time,alpha=a,beta=zero,gamma=zero"))
    assert str(error).startswith(f"{path}, line 4: no column 'a' (mapped to alpha)")
    error = error_of(lambda: load_opensim(path, columns="time=t,alpha=a,beta=zero,gamma=zero"))
    assert "no column 't' (the time)" in str(error)
    error = error_of(lambda: load_opensim(path, columns="time=time,alpha=hip_flexion_r,beta=zero,gamma=zero,load=G"))
    assert "no column 'G' (the load)" in str(error)
    error = error_of(lambda: load_opensim(path, columns="time=time,alpha=a,beta=b,gamma=c,load=F", load_column="F"))
    assert str(error) == f"{path}: the load column is named twice (in the column mapping and on its own)"


def test_the_load_column_keeps_its_sign_and_unit_and_is_found_loosely(tmp_path):
    rows = [[T[k], FLEXION[k], 0, 0, 5, -1.5] for k in range(N)]
    path = mot(tmp_path / "a.mot", rows=rows)
    trajectory = load_opensim(path, load_column="-f:kN")
    np.testing.assert_array_equal(trajectory.Fe, np.full(N, 1500.0))
    table = _read(path, path, "r", Column("f", "kN", -1.0))
    load = given(table.columns.load)
    assert (load.name, load.unit, load.sign) == ("F", "kN", -1.0)
    error = error_of(lambda: load_opensim(path, load_column="G"))
    assert "no column 'G' (the load)" in str(error)


def test_every_option_reaches_the_builder(tmp_path):
    path = mot(tmp_path / "a.mot")
    base = load_opensim(path, load_column="F")
    np.testing.assert_allclose(quiet(lambda: load_opensim(path, frequency=2.0)).t, np.arange(N) / 16.0, atol=1e-15)
    np.testing.assert_allclose(quiet(lambda: load_opensim(path, period=4.0)).t, np.arange(N) * 0.5, atol=1e-15)
    np.testing.assert_allclose(quiet(lambda: load_opensim(path, resample=200.0)).t, np.arange(15) / 200.0, atol=1e-15)
    assert isinstance(quiet(lambda: load_opensim(path, lazy=True)), SampledMotion)
    assert np.abs(load_opensim(path, load_column="F", cutoff=10.0).q - base.q).max() > 1e-4
    assert "periodic was asked for" in str(error_of(lambda: load_opensim(path, periodic=True)))
    np.testing.assert_allclose(load_opensim(path, load_column="F", body_weight=50.0).Fe, base.Fe / 2.0, rtol=1e-15)
    from hipsim.motion.load_file import LoadCurve

    curve = LoadCurve(np.array([-1.0, 1.0]), np.array([0.0, 2000.0]), np.array([2, 3]), "l.csv", "F")
    np.testing.assert_allclose(load_opensim(path, load_curve=curve).Fe, 1000.0 * (T + 1.0), rtol=1e-15)


def test_the_right_sides_spellings_extra_values_and_two_comma_labels(tmp_path):
    path = mot(tmp_path / "a.mot")
    for side in ("r", "RIGHT", "right"):
        np.testing.assert_allclose(load_opensim(path, side, load_column="F").q[:, 0], np.radians(FLEXION), atol=1e-12)
    rows = [[T[k], FLEXION[k], 0, 0, 5, 1000] for k in range(N)]
    rows[1] = rows[1] + [7]
    extra = mot(tmp_path / "b.mot", rows=rows)
    assert str(error_of(lambda: load_opensim(extra))) == f"{extra}, line 6: 7 values, the labels are 6"
    two = tmp_path / "c.mot"
    two.write_text("endheader\ntime,hip_flexion_r\n0,1\n")
    assert "the labels are separated by commas (2 of them)" in str(error_of(lambda: load_opensim(two)))


def test_a_mapping_with_a_separate_load_column_keeps_its_columns_and_chain(tmp_path):
    rows = [[T[k], 0.1 * k, 0, 0, 0.5, -1.5] for k in range(N)]
    path = mot(tmp_path / "a.mot", header=("inDegrees=no",), rows=rows)
    trajectory = load_opensim(
        path, columns="time=time,alpha=hip_flexion_r,beta=zero,gamma=-knee_angle_r", load_column="-F:kN"
    )
    np.testing.assert_allclose(trajectory.q[:, 2], np.full(N, -0.5), rtol=0, atol=1e-15)
    np.testing.assert_array_equal(trajectory.Fe, np.full(N, 1500.0))
    trajectory = load_opensim(path, columns="time=time,alpha=hip_flexion_r,beta=zero,gamma=zero,load=-F:kN")
    np.testing.assert_array_equal(trajectory.Fe, np.full(N, 1500.0))
    chain = "time=time,flexion=hip_flexion_r,adduction=knee_angle_r,rotation=zero"
    plain = "time=time,alpha=hip_flexion_r,beta=knee_angle_r,gamma=zero"
    with_load = load_opensim(path, columns=chain, load_column="-F:kN")
    np.testing.assert_array_equal(with_load.q, quiet(lambda: load_opensim(path, columns=chain)).q)
    assert np.abs(with_load.q - load_opensim(path, columns=plain, load_column="-F:kN").q).max() > 1e-3


def test_a_mappings_problems_name_the_file_line_and_the_files_label(tmp_path):
    rows = [[T[k], 0.1 * k, 0, 0, 0.5, 1000] for k in range(N)]
    path = mot(tmp_path / "a.mot", header=("inDegrees=no",), rows=rows)
    error = error_of(lambda: load_opensim(path, columns="time=t,alpha=a,beta=zero,gamma=zero"))
    assert str(error).startswith(f"{path}, line 4: no column 't' (the time)")
    error = error_of(lambda: load_opensim(path, columns="time=time,alpha=hip_flexion_r,beta=zero,gamma=zero,load=G"))
    assert str(error).startswith(f"{path}, line 4: no column 'G' (the load)")
    short = mot(tmp_path / "b.mot", header=("inDegrees=no",), rows=rows[:5])
    error = error_of(lambda: load_opensim(short, columns="time=time,alpha=hip_flexion_r,beta=zero,gamma=zero"))
    assert str(error) == f"{short}: 5 samples; at least 6 are needed"
    six = mot(tmp_path / "c.mot", header=("inDegrees=no",), rows=rows[:6])
    assert len(quiet(lambda: load_opensim(six))) == 6
    # A column found by its name in another case is named as the file has it.
    rows[3][4] = 4.0
    bad = mot(tmp_path / "d.mot", header=("inDegrees=no",), rows=rows)
    error = error_of(lambda: load_opensim(bad, columns="time=time,alpha=hip_flexion_r,beta=zero,gamma=KNEE_ANGLE_R"))
    assert (
        str(error) == f"{bad}, line 8, column 'knee_angle_r': 4 rad is more than half a turn: these look like degrees"
    )


def test_the_hip_paths_messages_name_the_file_and_line(tmp_path):
    missing = str(tmp_path / "none.mot")
    assert str(error_of(lambda: load_opensim(missing))) == f"{missing}: no such OpenSim file"
    path = mot(tmp_path / "a.mot", labels=["t", *LABELS[1:]])
    assert str(error_of(lambda: load_opensim(path))).startswith(f"{path}, line 4: no column 'time' (the time); its hip")
    path = mot(tmp_path / "b.mot")
    assert str(error_of(lambda: load_opensim(path, load_column="G"))).startswith(
        f"{path}, line 4: no column 'G' (the load); its hip columns are"
    )
    # Labels with a comma in one of two: not a comma-separated file, but one without the hip's columns.
    two = tmp_path / "c.mot"
    two.write_text("endheader\ntime x,y\n" + "".join(f"{k / 100} 1\n" for k in range(8)))
    assert str(error_of(lambda: load_opensim(two))).startswith(f"{two}, line 2: no column 'hip_flexion_r'")
    # "time" exactly, beside "Time".
    labels = ["Time", "time", *LABELS[1:]]
    rows = [[9.0, T[k], FLEXION[k], 0, 0, 5, 1000] for k in range(N)]
    np.testing.assert_array_equal(quiet(lambda: load_opensim(mot(tmp_path / "d.mot", labels=labels, rows=rows))).t, T)


def test_the_other_hips_hint_comes_before_the_planar_one():
    labels = ["time", "hip_flexion_r", "hip_adduction_l"]
    error = error_of(lambda: _find(labels, ("hip_adduction_r",), "x", "f", 2))
    assert "read them with --side left" in str(error) and "planar" not in str(error)
