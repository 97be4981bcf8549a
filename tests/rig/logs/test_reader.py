"""hipsim.rig.logs.reader: the rig-log reader's rules and errors."""

import numpy as np
import pytest
from support import given

from hipsim.exceptions import TrajectoryError
from hipsim.rig.logs.reader import read_rig_log


def write(path, header, rows):
    path.write_text(",".join(header) + "\n" + "\n".join(",".join(str(x) for x in row) for row in rows) + "\n")
    return path


def good_rows(n=400, rate=1000.0):
    t = np.arange(n) / rate
    return [[f"{x:.6f}", 1000 + 10 * k % 7, 100.0, -50.0, 25.5, 10.0, -2.0, 3.0] for k, x in enumerate(t)]


HEADER = ["t_s", "Fe_N", "tau_1_Nmm", "tau_2_Nmm", "tau_3_Nmm", "alpha_deg", "beta_deg", "gamma_deg"]


def test_a_good_log_in_si(tmp_path):
    log = read_rig_log(write(tmp_path / "log.csv", HEADER + ["temp_C"], [row + [21.0] for row in good_rows()]))
    assert len(log) == 400 and log.rate == pytest.approx(1000.0)
    np.testing.assert_allclose(log.tau[0], [0.1, -0.05, 0.0255])
    np.testing.assert_allclose(given(log.angles)[0], np.radians([10.0, -2.0, 3.0]))
    assert log.heights is None and log.torque_from == "torques" and log.ignored == ("temp_C",)
    assert log.lines[0] == 2 and log.angle_unit == "deg"


def test_currents_times_the_torque_constant(tmp_path):
    header = ["t_s", "Fe_N", "current_1_A", "current_2_A", "current_3_A", "L_11_mm", "L_12_mm", "L_13_mm"]
    rows = [[k / 500, 800, 1.0, -2.0, 0.5, 600.0, 610.0, 590.0] for k in range(50)]
    log = read_rig_log(write(tmp_path / "c.csv", header, rows), torque_constant=0.25)
    np.testing.assert_allclose(log.tau[0], [0.25, -0.5, 0.125])
    np.testing.assert_allclose(given(log.heights)[0], [0.6, 0.61, 0.59])
    assert log.angles is None and log.torque_from == "currents"


def one_line(error) -> str:
    text = str(error.value)
    assert "\n" not in text and text.strip() == text
    return text


@pytest.mark.parametrize(
    ("header", "change", "needle"),
    [
        (["t_s", "Fe_N", "alpha_deg", "beta_deg", "gamma_deg"], None, "missing torque columns: expected tau_1_Nmm"),
        (
            ["t_s", "Fe_N", "tau_1_Nmm", "tau_2_Nmm", "tau_3_Nm", "alpha_deg", "beta_deg", "gamma_deg"],
            None,
            "missing torque column 'tau_3_Nmm' (the file has 'tau_3_Nm'",
        ),
        (
            ["t_s", "Fe_N", "current_1_A", "current_2_A", "current_3_A", "alpha_deg", "beta_deg", "gamma_deg"],
            None,
            "motor currents (current_1_A …) but no torque constant",
        ),
        (
            ["t_s", "Fe_N", "tau_1_Nmm", "tau_2_Nmm", "tau_3_Nmm", "x", "y", "z"],
            None,
            "no motion: expected the platform angles",
        ),
        (
            ["t_s", "Fe_N", "tau_1_Nmm", "tau_2_Nmm", "tau_3_Nmm", "alpha_deg", "beta_rad", "gamma_deg"],
            None,
            "mix _deg and _rad",
        ),
        (
            ["t_s", "tau_1_Nmm", "tau_2_Nmm", "tau_3_Nmm", "alpha_deg", "beta_deg", "gamma_deg", "Fe"],
            None,
            "missing load column 'Fe_N'",
        ),
        (HEADER, (5, 1, "-20"), "line 7, column 'Fe_N': load -20 N is negative"),
        (HEADER, (3, 0, "0.0031"), "line 5, column 't_s': uneven time step"),
        (HEADER, (8, 3, "abc"), "line 10, column 'tau_2_Nmm': 'abc' is not a number"),
        (HEADER, (8, 3, "1_0"), "line 10, column 'tau_2_Nmm': '1_0' is not a number"),
        (HEADER, (2, 6, "nan"), "line 4, column 'beta_deg'"),
        (HEADER, (9, 5, "400"), "line 11, column 'alpha_deg': 400 deg is more than a full turn"),
    ],
)
def test_bad_logs_one_clear_line(tmp_path, header, change, needle):
    rows = [row[: len(header)] for row in good_rows(60)]
    if change:
        k, column, value = change
        rows[k][column] = value
    with pytest.raises(TrajectoryError) as error:
        read_rig_log(write(tmp_path / "bad.csv", header, rows))
    text = one_line(error)
    assert needle in text and "bad.csv" in text


def test_a_bad_torque_constant(tmp_path):
    header = ["t_s", "Fe_N", "current_1_A", "current_2_A", "current_3_A", "alpha_deg", "beta_deg", "gamma_deg"]
    path = write(tmp_path / "c.csv", header, good_rows(20))
    with pytest.raises(TrajectoryError, match="torque constant must be a positive number"):
        read_rig_log(path, torque_constant=-1.0)


def test_empty_and_missing_files(tmp_path):
    with pytest.raises(TrajectoryError, match="no such log file"):
        read_rig_log(tmp_path / "none.csv")
    (tmp_path / "empty.csv").write_text("\n\n")
    with pytest.raises(TrajectoryError, match="the file is empty"):
        read_rig_log(tmp_path / "empty.csv")


def test_blank_lines_keep_the_file_line_numbers(tmp_path):
    rows = good_rows(60)
    text = "\n" + ",".join(HEADER) + "\n" + "\n".join(",".join(str(x) for x in row) for row in rows[:10]) + "\n\n"
    text += "\n".join(",".join(str(x) for x in row) for row in rows[10:]) + "\n"
    path = tmp_path / "blank.csv"
    path.write_text(text)
    log = read_rig_log(path)
    assert len(log) == 60 and log.lines[0] == 3 and log.lines[10] == 14
    path.write_text(text.replace(f"{rows[20][0]},", f"{rows[20][0]}x,", 1))
    with pytest.raises(TrajectoryError, match="line 24, column 't_s'"):
        read_rig_log(path)


def test_a_log_scanned_in_small_blocks(tmp_path):
    """Blocks of 7 lines (blank lines among them) give the samples, lines and errors of the file read in one block."""
    from hipsim.rig.logs.reader import RigLogFile

    rows = good_rows(60)
    text = ",".join(HEADER) + "\n" + "\n".join(",".join(str(x) for x in row) for row in rows[:10]) + "\n\n\n"
    text += "\n".join(",".join(str(x) for x in row) for row in rows[10:]) + "\n"
    path = tmp_path / "blocks.csv"
    path.write_text(text)
    whole = RigLogFile(path, block=10_000)
    small = RigLogFile(path, block=7)
    for a, b in ((0, 60), (5, 23), (40, 60)):
        x, y = whole.piece(a, b), small.piece(a, b)
        for name in ("t", "Fe", "tau", "angles", "lines"):
            np.testing.assert_array_equal(getattr(x, name), getattr(y, name))
    assert small.lines[10] == 14 and len(small) == 60
    # The largest torque beyond any motor is named where it is, in whichever block (the first of two equal ones).
    rows[30][2] = rows[50][2] = "2e12"
    write(path, HEADER, rows)
    with pytest.raises(TrajectoryError, match="line 32, column 'tau_1_Nmm'"):
        RigLogFile(path, block=7)
    rows[30][2] = rows[50][2] = "100.0"
    rows[45][1] = "-1"  # the least load, in a later block than any other
    write(path, HEADER, rows)
    with pytest.raises(TrajectoryError, match="line 47, column 'Fe_N': load -1 N is negative"):
        RigLogFile(path, block=7)


def test_a_fault_far_into_a_long_log_names_its_line(tmp_path):
    """The scan reads megabytes at a time; a byte that is not UTF-8, a comment, a blank line deep in the file keep their lines."""
    rows = good_rows(200_000)
    text = ",".join(HEADER) + "\n" + "\n".join(",".join(str(x) for x in row) for row in rows) + "\n"
    lines = text.split("\n")
    lines.insert(150_000, "# a comment deep in the file")  # file line 150001: sample 149999 is on line 150002
    lines.insert(150_011, " ,, ")  # file line 150012, a spreadsheet's empty row: sample 150009 on line 150013
    path = tmp_path / "long.csv"
    path.write_text("\n".join(lines))
    log = read_rig_log(path)
    assert len(log) == 200_000 and log.lines[149_998] == 150_000 and log.lines[149_999] == 150_002
    assert log.lines[150_008] == 150_011 and log.lines[150_009] == 150_013
    data = path.read_bytes().split(b"\n")
    data[180_000] = data[180_000].replace(b"100.0", b"100\xff0")  # file line 180001
    path.write_bytes(b"\n".join(data))
    with pytest.raises(TrajectoryError, match="line 180001: not a text"):
        read_rig_log(path)


def test_a_window_of_lines_reads_nothing_after_it(tmp_path):
    """lines=(first, stop): the samples on those file lines only; what follows (a cell that is no number, a byte that is
    not UTF-8) is neither parsed nor read beyond the block that holds the window's end; kept columns and --rate's times
    cover the window alone."""
    from hipsim.rig.logs.reader import RigLogFile

    rows = [row + [k // 100] for k, row in enumerate(good_rows(200_000))]  # a cycle counter, 100 samples a cycle
    text = ",".join(HEADER + ["cycle"]) + "\n" + "\n".join(",".join(str(x) for x in row) for row in rows) + "\n"
    path = tmp_path / "long.csv"
    bad = b"9.9,x\xff\xfe,oops\n"  # 3 cells, not UTF-8, not numbers: any read of it fails
    path.write_bytes(text.encode() + bad)
    with pytest.raises(TrajectoryError):
        RigLogFile(path)
    window = RigLogFile(path, block=500, keep=("cycle", "absent"), lines=(1002, 1302))  # samples 1000-1299
    assert len(window) == 300 and window.lines[0] == 1002 and window.lines[-1] == 1301
    np.testing.assert_array_equal(window.t, np.arange(1000, 1300) / 1000.0)
    np.testing.assert_array_equal(window.kept["cycle"], np.arange(1000, 1300) // 100)
    assert set(window.kept) == {"cycle"}
    assert window.size < path.stat().st_size // 10  # read (and hashed): a block or two of 50,000 bytes, not 13 MB
    coarse = RigLogFile(path, block=500, rate=1000.0, lines=(1002, 1302))
    np.testing.assert_allclose(coarse.t, 1.0 + np.arange(300) / 1000.0, rtol=0, atol=1e-12)
    # The window's first line may be the header's block; its end after the last line of the file reads it whole.
    head = RigLogFile(path, lines=(1, 12))
    assert len(head) == 10 and head.lines[0] == 2
    with pytest.raises(TrajectoryError, match=f"line {len(rows) + 2}"):
        RigLogFile(path, lines=(150_000, 10**9))


def test_epoch_time_stamps_are_read_from_the_first_with_every_digit(tmp_path):
    from hipsim.motion.build import TrajectoryWarning

    # 1 kHz stamps from 1,733,000,000 s (Nov 2024) with their 13 digits; relative, the same log as from 0.
    rows = good_rows()
    epoch = [[f"{1_733_000_000 + k / 1000:.3f}"] + row[1:] for k, row in enumerate(rows)]
    with pytest.warns(TrajectoryWarning, match="Unix"):
        stamped = read_rig_log(write(tmp_path / "epoch.csv", HEADER, epoch))
    plain = read_rig_log(write(tmp_path / "plain.csv", HEADER, rows))
    assert stamped.t[0] == 0.0 and np.unique(stamped.t).size == 400
    # A stamp of 1.7e9 s holds its digits to half a double's step there, 2^-23 s (1.2e-7 s): that is the precision.
    np.testing.assert_allclose(stamped.t, np.arange(400) / 1000.0, rtol=0, atol=2.0**-23)
    np.testing.assert_allclose(stamped.tau, plain.tau) and np.testing.assert_allclose(stamped.Fe, plain.Fe)
    assert stamped.rate == pytest.approx(1000.0, rel=1e-6)  # the last stamp to 1.2e-7 s of 0.399 s
