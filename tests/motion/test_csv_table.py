"""Tests of hipsim.motion.csv_table: CSV trajectories in hipsim's own columns, and any lab's table through a mapping.

Files are written here from the ISO formulas (spec §7.2) or closed-form motions,
never by the code under test.
"""

from __future__ import annotations

import csv

import numpy as np
import pytest
from support import Rx, Ry, Rz
from trajectory_files import (
    DEG,
    assert_same_trajectory,
    assert_traj_error,
    canonical,
    csv_text,
    iso_rows,
    set_cell,
    small_csv,
    write_iso_csv,
    write_lines,
)

from hipsim import TrajectoryError
from hipsim.motion.csv_table import load_trajectory_csv
from hipsim.motion.trajectories import MIN_SAMPLES, iso14242_angles, iso14242_load

# --------------------------------------------------------------------------- CSV: reading


def test_csv_degrees_header(tmp_path):
    t, q, _, _, load = write_iso_csv(tmp_path / "deg.csv", rate=100, cycles=0.5, closing=False)
    traj = load_trajectory_csv(tmp_path / "deg.csv")
    assert traj.name == str(tmp_path / "deg.csv")  # the path as given, as every message names it
    assert traj.periodic is False
    np.testing.assert_array_equal(traj.t, t)
    np.testing.assert_allclose(traj.q, q, rtol=0, atol=1e-15)
    np.testing.assert_array_equal(traj.Fe, load)


def test_csv_radians_header(tmp_path):
    t, q, _, _, load = write_iso_csv(tmp_path / "rad.csv", rate=100, cycles=0.5, closing=False, unit="rad")
    traj = load_trajectory_csv(tmp_path / "rad.csv")
    np.testing.assert_allclose(traj.q, q, rtol=0, atol=1e-15)  # radians are taken as they are
    np.testing.assert_array_equal(traj.Fe, load)


def test_csv_degrees_are_converted(tmp_path):
    lines = ["t_s,alpha_deg,beta_deg,gamma_deg"] + [f"{k / 10},{90.0},{-45.0},{180.0 * k / 9}" for k in range(10)]
    traj = load_trajectory_csv(write_lines(tmp_path / "conv.csv", lines))
    np.testing.assert_allclose(traj.q[:, 0], np.pi / 2, rtol=1e-15)
    np.testing.assert_allclose(traj.q[:, 1], -np.pi / 4, rtol=1e-15)
    np.testing.assert_allclose(traj.q[:, 2], np.pi * np.arange(10) / 9, rtol=1e-14)
    # A linear ramp: π/9 rad per 0.1 s, no acceleration.
    np.testing.assert_allclose(traj.qd[:, 2], 10 * np.pi / 9, rtol=1e-9)
    np.testing.assert_allclose(traj.qdd[:, 2], 0.0, atol=1e-6)


def test_csv_without_load_gives_zero_load(tmp_path):
    t, q, _, _, _ = write_iso_csv(tmp_path / "noload.csv", rate=100, cycles=0.5, closing=False, with_load=False)
    traj = load_trajectory_csv(tmp_path / "noload.csv")
    np.testing.assert_array_equal(traj.Fe, np.zeros(len(t)))


def test_csv_columns_in_any_order_with_spaces_and_blank_lines(tmp_path):
    t = np.arange(8) / 50.0
    q, _, _ = iso14242_angles(t)
    load = iso14242_load(t)
    lines = ["Fe_N, gamma_rad, t_s , beta_rad,alpha_rad", ""]
    r = lambda x: repr(float(x))
    lines += [f"{r(load[k])}, {r(q[k, 2])},{r(t[k])}, {r(q[k, 1])},{r(q[k, 0])}" for k in range(8)]
    lines.insert(5, "")
    traj = load_trajectory_csv(write_lines(tmp_path / "order.csv", lines))
    np.testing.assert_array_equal(traj.t, t)
    np.testing.assert_allclose(traj.q, q, rtol=0, atol=1e-15)
    np.testing.assert_array_equal(traj.Fe, load)


def test_csv_periodic_detection(tmp_path):
    write_iso_csv(tmp_path / "closed.csv", rate=100, cycles=1, closing=True)
    write_iso_csv(tmp_path / "open.csv", rate=100, cycles=1, closing=False)
    closed = load_trajectory_csv(tmp_path / "closed.csv")
    assert closed.periodic is True
    assert len(closed) == 100  # the closing row is dropped: t = 0 … 0.99 s
    assert closed.t[-1] == pytest.approx(0.99)
    opened = load_trajectory_csv(tmp_path / "open.csv")
    assert opened.periodic is False
    assert len(opened) == 100
    forced = load_trajectory_csv(tmp_path / "closed.csv", periodic=False)
    assert forced.periodic is False and len(forced) == 101


def test_csv_motion_returning_home_is_not_mistaken_for_periodic(tmp_path):
    t = np.arange(501) / 1000.0
    w = np.pi / 0.5
    q = np.zeros((501, 3))
    q[:, 0] = 10 * DEG * np.sin(w * t)
    q[-1] = q[0]
    path = tmp_path / "home.csv"
    path.write_text(csv_text(t, q, None, "deg"))
    traj = load_trajectory_csv(path)
    m = len(traj)
    qd = 10 * DEG * w * np.cos(w * t[:m])
    qdd = -10 * DEG * w**2 * np.sin(w * t[:m])
    assert np.abs(traj.qd[:, 0] - qd).max() <= 1e-6 * 10 * DEG * w
    assert np.abs(traj.qdd[:, 0] - qdd).max() <= 1e-4 * 10 * DEG * w**2


def test_csv_periodic_true_on_an_open_file_is_refused(tmp_path):
    path = tmp_path / "open.csv"
    write_iso_csv(path, rate=100, cycles=1, closing=False)
    with pytest.raises(TrajectoryError) as info:
        load_trajectory_csv(path, periodic=True)
    assert_traj_error(info, path)


# --------------------------------------------------------------------------- CSV: bad input


def test_csv_missing_time_column(tmp_path):
    path = write_lines(tmp_path / "x.csv", small_csv(header="time,alpha_deg,beta_deg,gamma_deg,Fe_N"))
    with pytest.raises(TrajectoryError) as info:
        load_trajectory_csv(path)
    assert_traj_error(info, path, line=1)
    assert "t_s" in str(info.value)


@pytest.mark.parametrize(
    ("header", "missing"),
    [
        ("t_s,alpha_deg,beta_deg,Fe_N,gamma", "gamma_deg"),
        ("t_s,beta_rad,gamma_rad,Fe_N,Alpha_rad", "alpha_rad"),
    ],
)
def test_csv_missing_angle_column(tmp_path, header, missing):
    path = write_lines(tmp_path / "x.csv", small_csv(header=header))
    with pytest.raises(TrajectoryError) as info:
        load_trajectory_csv(path)
    assert_traj_error(info, path, line=1)
    assert missing in str(info.value)


def test_csv_no_angle_columns(tmp_path):
    lines = ["t_s,Fe_N"] + [f"{k / 100},300" for k in range(10)]
    path = write_lines(tmp_path / "x.csv", lines)
    with pytest.raises(TrajectoryError) as info:
        load_trajectory_csv(path)
    assert_traj_error(info, path, line=1)
    assert "alpha_deg" in str(info.value)


@pytest.mark.parametrize("extra", ["Fe_kN", "delta_deg", "alpha_rad"])
def test_csv_unknown_column(tmp_path, extra):
    lines = small_csv()
    lines = [lines[0] + "," + extra] + [row + ",1.0" for row in lines[1:]]
    path = write_lines(tmp_path / "x.csv", lines)
    with pytest.raises(TrajectoryError) as info:
        load_trajectory_csv(path)
    assert_traj_error(info, path, line=1)
    if extra != "alpha_rad":  # alpha_rad beside alpha_deg is reported as a mix of units
        assert_traj_error(info, path, line=1, column=extra)


@pytest.mark.parametrize("dup", ["beta_deg", "t_s", "Fe_N"])
def test_csv_duplicate_column(tmp_path, dup):
    lines = small_csv()
    lines = [lines[0] + "," + dup] + [row + ",1.0" for row in lines[1:]]
    path = write_lines(tmp_path / "x.csv", lines)
    with pytest.raises(TrajectoryError) as info:
        load_trajectory_csv(path)
    assert_traj_error(info, path, line=1, column=dup)


def test_csv_duplicate_column_after_blank_lines(tmp_path):
    lines = ["", "", "t_s,alpha_deg,alpha_deg,beta_deg,gamma_deg"] + [f"{k / 100},1,1,1,1" for k in range(10)]
    path = write_lines(tmp_path / "x.csv", lines)
    with pytest.raises(TrajectoryError) as info:
        load_trajectory_csv(path)
    assert_traj_error(info, path, line=3, column="alpha_deg")


@pytest.mark.parametrize("header", ["t_s,alpha_deg,beta_rad,gamma_deg", "t_s,alpha_rad,beta_rad,gamma_deg,Fe_N"])
def test_csv_mixed_degrees_and_radians(tmp_path, header):
    ncols = len(header.split(","))
    lines = [header] + [",".join([f"{k / 100}"] + ["0.1"] * (ncols - 1)) for k in range(10)]
    path = write_lines(tmp_path / "x.csv", lines)
    with pytest.raises(TrajectoryError) as info:
        load_trajectory_csv(path)
    assert_traj_error(info, path, line=1)
    assert "_deg" in str(info.value) and "_rad" in str(info.value)


@pytest.mark.parametrize("cell", ["abc", "", "1.0.0", "12 deg", "0x10"])
def test_csv_non_numeric_cell(tmp_path, cell):
    path = write_lines(tmp_path / "x.csv", set_cell(small_csv(), line=5, column=2, value=cell))
    with pytest.raises(TrajectoryError) as info:
        load_trajectory_csv(path)
    assert_traj_error(info, path, line=5, column="beta_deg")


def test_csv_non_numeric_cell_line_counts_blank_lines(tmp_path):
    lines = small_csv()
    lines.insert(1, "")
    lines.insert(3, "  ,  ")  # a row of blank cells is skipped too
    lines = set_cell(lines, line=7, column=0, value="t?")
    path = write_lines(tmp_path / "x.csv", lines)
    with pytest.raises(TrajectoryError) as info:
        load_trajectory_csv(path)
    assert_traj_error(info, path, line=7, column="t_s")


@pytest.mark.parametrize(
    ("cell", "column", "name"),
    [
        ("nan", 1, "alpha_deg"),
        ("NaN", 4, "Fe_N"),
        ("inf", 3, "gamma_deg"),
        ("-inf", 2, "beta_deg"),
        ("inf", 0, "t_s"),
    ],
)
def test_csv_non_finite_cell(tmp_path, cell, column, name):
    path = write_lines(tmp_path / "x.csv", set_cell(small_csv(), line=8, column=column, value=cell))
    with pytest.raises(TrajectoryError) as info:
        load_trajectory_csv(path)
    assert_traj_error(info, path, line=8, column=name)


@pytest.mark.parametrize("samples", [0, 1, MIN_SAMPLES - 1])
def test_csv_too_few_samples(tmp_path, samples):
    assert MIN_SAMPLES == 6
    path = write_lines(tmp_path / "x.csv", small_csv(n=samples) if samples else ["t_s,alpha_deg,beta_deg,gamma_deg"])
    with pytest.raises(TrajectoryError) as info:
        load_trajectory_csv(path)
    assert_traj_error(info, path)
    assert str(samples) in str(info.value)


def test_csv_six_samples_are_enough(tmp_path):
    path = write_lines(tmp_path / "x.csv", small_csv(n=MIN_SAMPLES))
    assert len(load_trajectory_csv(path, periodic=False)) == MIN_SAMPLES


@pytest.mark.parametrize("change", ["extra", "missing"])
def test_csv_ragged_row(tmp_path, change):
    lines = small_csv()
    lines[4] = lines[4] + ",1.0" if change == "extra" else lines[4].rsplit(",", 1)[0]
    path = write_lines(tmp_path / "x.csv", lines)
    with pytest.raises(TrajectoryError) as info:
        load_trajectory_csv(path)
    assert_traj_error(info, path, line=5)
    assert ("6" if change == "extra" else "4") in str(info.value)


@pytest.mark.parametrize("text", ["", "\n\n\n", " , ,\n\n"])
def test_csv_empty_file(tmp_path, text):
    path = tmp_path / "empty.csv"
    path.write_text(text)
    with pytest.raises(TrajectoryError) as info:
        load_trajectory_csv(path)
    assert_traj_error(info, path)
    assert "empty" in str(info.value)


def test_csv_missing_file(tmp_path):
    path = tmp_path / "nowhere.csv"
    with pytest.raises(TrajectoryError) as info:
        load_trajectory_csv(path)
    assert_traj_error(info, path)


def test_csv_not_utf8(tmp_path):
    path = tmp_path / "binary.csv"
    path.write_bytes(b"t_s,alpha_deg,beta_deg,gamma_deg\n\xff\xfe\x00\x81\n")
    with pytest.raises(TrajectoryError) as info:
        load_trajectory_csv(path)
    assert_traj_error(info, path)


def test_csv_directory_instead_of_file(tmp_path):
    with pytest.raises(TrajectoryError) as info:
        load_trajectory_csv(tmp_path)
    assert_traj_error(info, tmp_path)


def test_csv_with_utf8_byte_order_mark(tmp_path):
    path = tmp_path / "excel.csv"
    path.write_text("\n".join(small_csv()) + "\n", encoding="utf-8-sig")
    assert len(load_trajectory_csv(path)) == 10


def test_digit_separators_are_not_numbers_in_a_csv(tmp_path):
    lines = small_csv()
    lines[3] = "0.02,1_0,1,-2,500"  # line 4; float() would read 10
    with pytest.raises(TrajectoryError, match="'1_0' is not a number") as info:
        load_trajectory_csv(write_lines(tmp_path / "sep.csv", lines))
    assert "line 4" in str(info.value)


@pytest.mark.parametrize("line", [1, 2, 5])
def test_a_cell_beyond_the_field_size_limit_is_read_or_named_at_its_line(tmp_path, line):
    """Issue 30: a cell is as long as its line allows; a long number is a number, a long column name is named on its line, shortened."""
    lines = small_csv()
    lines[line - 1] += "9" * (csv.field_size_limit() + 1)
    path = write_lines(tmp_path / "huge.csv", lines)
    if line == 1:  # the load's column name, Fe_N999…
        with pytest.raises(TrajectoryError) as info:
            load_trajectory_csv(path)
        assert_traj_error(info, path, line=line)
        assert len(str(info.value)) < 1500
        return
    cell = lines[line - 1].rsplit(",", 1)[1]  # the load's number, with 128 Ki more digits
    assert load_trajectory_csv(path).Fe[line - 2] == float(cell)


# --------------------------------------------------------------------------- any lab's table (issue 15)
#
# The same ISO cycle written as hipsim's CSV and as a lab would export it: a spreadsheet's
# semicolons and decimal commas, tabs, its own column names, units and signs.


@pytest.mark.parametrize("separator", [";", "\t"])
def test_a_spreadsheet_export_with_decimal_commas_reads_as_the_canonical_file(tmp_path, separator):
    t, deg, load = iso_rows()
    reference = load_trajectory_csv(canonical(tmp_path / "canonical.csv", t, deg, load))
    rows = [separator.join(repr(float(v)).replace(".", ",") for v in (t[k], *deg[k], load[k])) for k in range(len(t))]
    export = write_lines(
        tmp_path / "export.csv", [separator.join(["t_s", "alpha_deg", "beta_deg", "gamma_deg", "Fe_N"]), *rows]
    )
    traj = load_trajectory_csv(export)
    assert_same_trajectory(traj, reference)
    assert traj.periodic and len(traj) == 100


def test_a_mapped_lab_export_reads_as_the_canonical_file(tmp_path):
    """Own names, extra columns, another order, ms, radians, a flipped sign, kN and a trailing separator."""
    t, deg, load = iso_rows()
    reference = load_trajectory_csv(canonical(tmp_path / "canonical.csv", t, deg, load))
    header = "Frame;Event;Zeit [ms];Fz [kN];Hip IE [rad];Hip AA (abd+) [deg];Hip FE [deg];"
    rows = [
        f"{k};{'HS' if k % 50 == 0 else ''};"
        + ";".join(
            repr(float(v)) for v in (t[k] * 1000, load[k] / 1000, np.radians(deg[k, 2]), -deg[k, 1], deg[k, 0])
        ).replace(".", ",")
        + ";"
        for k in range(len(t))
    ]
    export = write_lines(tmp_path / "lab.csv", ["# exported by the gait lab", header, *rows])
    mapping = "time=Zeit [ms]:ms,alpha=Hip FE [deg],beta=-Hip AA (abd+) [deg],gamma=Hip IE [rad]:rad,load=Fz [kN]:kN"
    traj = load_trajectory_csv(export, columns=mapping)
    assert_same_trajectory(traj, reference, exact=False)
    np.testing.assert_array_equal(traj.lines, np.arange(3, 103)[:100])  # the comment and the header are lines 1 and 2


def test_hip_chain_columns_are_turned_into_platform_angles(tmp_path):
    """A lab's ISB hip angles (flexion, adduction, internal rotation) give the α, β, γ that turn the femur alike."""
    t, deg, load = iso_rows()
    C = np.array([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])  # pelvis x, y, z → machine Y, Z, X
    hip = []
    for a, b, g in np.radians(deg):
        Rh = C.T @ Rz(g) @ Ry(b) @ Rx(a) @ C  # the femur in pelvis axes
        hip.append(np.degrees([np.arctan2(-Rh[0, 1], Rh[1, 1]), np.arcsin(Rh[2, 1]), np.arctan2(-Rh[2, 0], Rh[2, 2])]))
    hip_deg = np.array(hip)
    rows = [",".join(repr(float(v)) for v in (t[k], *hip_deg[k])) for k in range(len(t))]
    path = write_lines(tmp_path / "hip.csv", ["time,hip flexion,hip adduction,hip rotation", *rows])
    traj = load_trajectory_csv(
        path, columns="time=time,flexion=hip flexion,adduction=hip adduction,rotation=hip rotation"
    )
    np.testing.assert_allclose(traj.q, np.radians(deg[:100]), rtol=0, atol=1e-12)
    assert traj.periodic


@pytest.mark.parametrize(
    ("cell", "column", "name"), [("abc", 3, "Hip AA"), ("1.234,5", 2, "Hip FE"), ("nan", 1, "Time")]
)
def test_bad_cells_of_a_mapped_export_name_file_line_and_column(tmp_path, cell, column, name):
    t, deg, load = iso_rows(20)
    rows = [";".join(repr(float(v)).replace(".", ",") for v in (t[k], *deg[k])) for k in range(20)]
    lines = ["Time;Hip FE;Hip AA;Hip IE", *rows]
    cells = lines[7].split(";")
    cells[column - 1] = cell
    lines[7] = ";".join(cells)
    path = write_lines(tmp_path / "lab.csv", lines)
    with pytest.raises(TrajectoryError) as info:
        load_trajectory_csv(path, columns="time=Time,alpha=Hip FE,beta=Hip AA,gamma=Hip IE")
    assert_traj_error(info, path, line=8, column=name)
    assert "\n" not in str(info.value)


def test_decimal_commas_in_a_comma_separated_file_are_named(tmp_path):
    lines = small_csv()
    lines[4] = lines[4].replace(".", ",", 1)  # one decimal comma: a cell too many
    path = write_lines(tmp_path / "x.csv", lines)
    with pytest.raises(
        TrajectoryError,
        match="6 cells, the header has 5 \\(decimal commas\\? a comma-separated file needs decimal points\\)",
    ):
        load_trajectory_csv(path)
