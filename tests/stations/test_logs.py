"""hipsim/stations/logs.py on logs of a few lines written here: each column's unit, the motor angles, a fixture's rows,
the run logs of ``learn``, the desired motion of ``simulate``, Parquet, and every refusal whole (file, line, column)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq
import pytest

from hipsim.exceptions import TrajectoryError
from hipsim.stations.logs import (
    read_calibration_log,
    read_carriage_log,
    read_desired,
    read_run_log,
    read_slider_log,
)

SENSORS = "alpha_1_deg,beta_1_deg,gamma_1_deg,alpha_2_deg,beta_2_deg,gamma_2_deg"
HEADER = f"t_s,L_11_mm,L_12_mm,L_13_mm,{SENSORS}"
ROWS = ["0,500,510,520,1,2,3,4,5,6", "0.01,501,511,521,-1,-2,-3,-4,-5,-6.5"]


def _write(tmp_path: Path, text: str, name: str = "log.csv") -> Path:
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


def _error(path: Path, *args) -> str:
    with pytest.raises(TrajectoryError) as error:
        read_calibration_log(path, *(args or (0.01,)))
    return str(error.value)


def test_a_calibration_log_in_si(tmp_path):
    path = _write(tmp_path, "# a comment\n" + "\n".join([HEADER, "", *ROWS]) + "\n")
    log = read_calibration_log(path, 0.01)
    assert log.name == str(path) and log.known is None
    assert log.t == pytest.approx([0.0, 0.01])
    assert log.carriages == pytest.approx(np.array([[0.5, 0.51, 0.52], [0.501, 0.511, 0.521]]))
    assert np.degrees(log.sensors[1]) == pytest.approx(np.array([[-1, -2, -3], [-4, -5, -6.5]]))
    assert np.degrees(log.sensors[0, 1]) == pytest.approx([4, 5, 6])


def test_semicolons_and_decimal_commas_and_motor_angles(tmp_path):
    """Motor angles of 36° and 720° on a 10 mm lead: 1 mm and 20 mm of carriage."""
    header = f"t_s;motor_1_deg;motor_2_deg;motor_3_deg;{SENSORS.replace(',', ';')}"
    path = _write(tmp_path, f"{header}\n0;36;720;0;1;2;3;4;5;6\n0,5;-36;0;3600;0,5;0;0;0;0;0\n")
    log = read_calibration_log(path, 0.01)
    assert log.t == pytest.approx([0.0, 0.5])
    assert log.carriages == pytest.approx(np.array([[0.001, 0.02, 0.0], [-0.001, 0.0, 0.1]]))
    assert math.degrees(log.sensors[1, 0, 0]) == pytest.approx(0.5)
    # The encoders win when both are logged.
    both = _write(
        tmp_path, "t_s,L_11_mm,L_12_mm,L_13_mm,motor_1_deg,motor_2_deg,motor_3_deg\n0,1,2,3,4,5,6\n1,1,2,3,4,5,6\n"
    )
    assert read_carriage_log(both, 0.01)[1][0] == pytest.approx([0.001, 0.002, 0.003])


def test_missing_columns_are_named_with_the_header(tmp_path):
    path = _write(tmp_path, "time,L_11_mm\n0,1\n1,2\n")
    assert _error(path) == f"{path}: no time: missing column(s) t_s (the header has time, L_11_mm)"
    path = _write(tmp_path, "t_s,L_11_mm,motor_2_deg\n0,1,2\n1,2,3\n")
    assert _error(path) == (
        f"{path}: no carriage encoders (or motor angles motor_1_deg, motor_2_deg, motor_3_deg): missing column(s) "
        "L_12_mm, L_13_mm (the header has t_s, L_11_mm, motor_2_deg)"
    )
    path = _write(
        tmp_path, "t_s,L_11_mm,L_12_mm,L_13_mm,alpha_1_deg,beta_1_deg,gamma_1_deg,beta_2_deg\n0,1,2,3,4,5,6,7\n"
    )
    assert _error(path) == (
        f"{path}: no attitude sensor of platform 2: missing column(s) alpha_2_deg, gamma_2_deg (the header has t_s, "
        "L_11_mm, L_12_mm, L_13_mm, alpha_1_deg, beta_1_deg, gamma_1_deg, beta_2_deg)"
    )


@pytest.mark.parametrize("lead", [0.0, -0.01, math.nan, math.inf])
def test_the_lead_must_be_positive(tmp_path, lead):
    path = _write(tmp_path, "\n".join([HEADER, *ROWS]))
    assert _error(path, lead) == f"{path}: the screw lead must be positive, got {lead!r}"


def test_bad_cells_and_times_are_named_by_line_and_column(tmp_path):
    path = _write(tmp_path, "\n".join([HEADER, ROWS[0], "# note", "0.01,501,x,521,1,2,3,4,5,6"]))
    assert _error(path) == f"{path}, line 4, column 'L_12_mm': 'x' is not a number"
    path = _write(tmp_path, "\n".join([HEADER, ROWS[0], "0.01,501,511,521,1,2,3,4,nan,6"]))
    assert _error(path) == f"{path}, line 3, column 'beta_2_deg': not a finite number"
    path = _write(tmp_path, "\n".join([HEADER, ROWS[0], "0.01,501,511"]))
    assert _error(path) == f"{path}, line 3, column 'L_13_mm': '' is not a number"
    path = _write(tmp_path, "\n".join([HEADER, ROWS[0]]))
    assert _error(path) == f"{path}: 1 row(s): a log needs at least 2"
    path = _write(tmp_path, "\n".join([HEADER, ROWS[0], ROWS[1], ROWS[1].replace("0.01", "0.02", 1), ROWS[1]]))
    assert _error(path) == f"{path}, line 5, column 't_s': time does not increase (t = 0.01 s after 0.02 s)"
    path = _write(tmp_path, "\n".join([HEADER, ROWS[0], ROWS[0]]))
    assert _error(path) == f"{path}, line 3, column 't_s': time does not increase (t = 0 s after 0 s)"
    path = _write(tmp_path, "# only a comment\n\n")
    assert _error(path) == f"{path}: empty: no header and no rows"
    path = _write(tmp_path, "\n".join([HEADER, *ROWS]))
    with pytest.raises(TrajectoryError) as error:
        read_calibration_log(path, 0.01, columns="t_s=g/t")
    assert (
        str(error.value) == f"{path}: a column map of channels (--columns GROUP/CHANNEL) applies to TDMS and HDF5 logs"
    )


KNOWN = "known_alpha_2_deg,known_beta_2_deg,known_gamma_2_deg"


def test_a_fixtures_rows_with_empty_cells_where_the_platform_is_free(tmp_path):
    rows = [
        "0,500,510,520,1,2,3,4,5,6,10,20,30",
        "0.01,501,511,521,1,2,3,4,5,6,,NaN, ",
        "0.02,501,511,521,1,2,3,4,5,6,nan,,",
    ]
    log = read_calibration_log(_write(tmp_path, "\n".join([f"{HEADER},{KNOWN}", *rows])), 0.01)
    assert log.known is not None and log.known.shape == (3, 2, 3)
    assert np.degrees(log.known[0, 1]) == pytest.approx([10, 20, 30])
    assert np.all(np.isnan(log.known[1:, 1])) and np.all(np.isnan(log.known[:, 0]))
    partial = _write(tmp_path, "\n".join([f"{HEADER},{KNOWN}", rows[0], "0.01,501,511,521,1,2,3,4,5,6,1,,3"]))
    assert _error(partial) == (
        f"{partial}, line 3, column 'known_beta_2_deg': a fixture's known attitude needs all three angles of platform 2 "
        "on a row, or none"
    )
    two = _write(
        tmp_path,
        "\n".join(
            [f"{HEADER},known_alpha_1_deg,known_gamma_1_deg", "0,500,510,520,1,2,3,4,5,6,1,2", "1,5,5,5,1,2,3,4,5,6,,"]
        ),
    )
    assert _error(two) == (
        f"{two}: no fixture's known attitude of platform 1: missing column(s) known_beta_1_deg (the header has "
        f"{HEADER.replace(',', ', ')}, known_alpha_1_deg, known_gamma_1_deg)"
    )
    bad = _write(tmp_path, "\n".join([f"{HEADER},{KNOWN}", rows[0], "0.01,501,511,521,1,2,3,4,5,6,1,x,3"]))
    assert _error(bad) == f"{bad}, line 3, column 'known_beta_2_deg': 'x' is not a number"


def test_slider_and_carriage_logs_need_no_sensors(tmp_path):
    bare = _write(tmp_path, "t_s,L_11_mm,L_12_mm,L_13_mm,alpha_1_deg\n0,1,2,3,4\n1,1,2,3,5\n")
    t, carriages = read_carriage_log(bare, 0.01)
    assert t == pytest.approx([0.0, 1.0]) and carriages[1] == pytest.approx([0.001, 0.002, 0.003])
    with pytest.raises(TrajectoryError, match="no attitude sensor of platform 1: missing column"):
        read_slider_log(bare, 0.01)  # a sensor column: all six are wanted
    none = _write(tmp_path, "t_s,L_11_mm,L_12_mm,L_13_mm\n0,1,2,3\n1,1,2,3\n", "none.csv")
    assert read_slider_log(none, 0.01)[2] is None
    full = _write(tmp_path, "\n".join([HEADER, *ROWS]), "full.csv")
    sensors = read_slider_log(full, 0.01)[2]
    assert sensors is not None and np.degrees(sensors[0, 1, 2]) == pytest.approx(6.0)


def test_the_desired_motion_only_when_whole_and_finite(tmp_path):
    desired = "t_s,alpha_des_deg,beta_des_deg,gamma_des_deg"
    assert read_desired(_write(tmp_path, f"{desired}\n0,1,2,3\n1,4,5,6\n")) == pytest.approx(
        np.radians([[1, 2, 3], [4, 5, 6]])
    )
    assert read_desired(_write(tmp_path, f"{desired}\n0,1,2,3\n1,4,nan,6\n")) is None
    assert read_desired(_write(tmp_path, "t_s,alpha_des_deg,beta_des_deg\n0,1,2\n1,4,5\n")) is None


RUN = "t_s,L_11_mm,L_12_mm,L_13_mm,L_11_cmd_mm,L_12_cmd_mm,L_13_cmd_mm,alpha_2_deg,beta_2_deg,gamma_2_deg"


def test_a_run_log_with_its_commands_and_the_sensors_it_has(tmp_path):
    path = _write(tmp_path, f"{RUN}\n0,1,2,3,1.5,2.5,3.5,10,20,30\n1,1,2,3,4,5,6,-1,-2,-3\n")
    t, carriages, commands, sensors = read_run_log(path, 0.01, (2,))
    assert t == pytest.approx([0.0, 1.0]) and carriages[0] == pytest.approx([0.001, 0.002, 0.003])
    assert commands is not None and commands == pytest.approx(np.array([[1.5e-3, 2.5e-3, 3.5e-3], [4e-3, 5e-3, 6e-3]]))
    assert np.all(np.isnan(sensors[:, 0])) and np.degrees(sensors[1, 1]) == pytest.approx([-1, -2, -3])
    with pytest.raises(TrajectoryError) as error:
        read_run_log(path, 0.01, (1, 2))
    assert str(error.value) == (
        f"{path}: no attitude sensor of platform 1: missing column(s) alpha_1_deg, beta_1_deg, gamma_1_deg (the header "
        f"has {RUN.replace(',', ', ')})"
    )
    partial = _write(
        tmp_path, f"{RUN.replace(',L_13_cmd_mm', '')}\n0,1,2,3,1.5,2.5,10,20,30\n1,1,2,3,4,5,1,2,3\n", "p.csv"
    )
    assert read_run_log(partial, 0.01, ())[2] is None  # not all three commands: none
    bad = _write(tmp_path, f"{RUN}\n0,1,2,3,1.5,2.5,nan,10,20,30\n1,1,2,3,4,5,6,1,2,3\n", "bad.csv")
    with pytest.raises(TrajectoryError) as error:
        read_run_log(bad, 0.01, ())
    assert str(error.value) == f"{bad}, line 2, column 'L_13_cmd_mm': not a finite number"
    sensor = _write(tmp_path, f"{RUN}\n0,1,2,3,1.5,2.5,3,10,20,30\n1,1,2,3,4,5,6,1,inf,3\n", "sensor.csv")
    with pytest.raises(TrajectoryError, match=r"line 3, column 'beta_2_deg': not a finite number"):
        read_run_log(sensor, 0.01, ())


def test_a_parquet_log_ignores_text_and_names_no_line(tmp_path):
    names = HEADER.split(",")
    columns = {name: [float(row.split(",")[k]) for row in ROWS] for k, name in enumerate(names)}
    table = pa.table({**{n: pa.array(v) for n, v in columns.items()}, "note": pa.array(["a", "b"])})
    path = tmp_path / "log.parquet"
    pq.write_table(table, path)
    log = read_calibration_log(path, 0.01)
    assert log.carriages[1] == pytest.approx([0.501, 0.511, 0.521])
    columns["beta_1_deg"][1] = math.nan
    pq.write_table(pa.table(columns), tmp_path / "nan.PQ")
    assert _error(tmp_path / "nan.PQ") == f"{tmp_path / 'nan.PQ'}, column 'beta_1_deg': not a finite number"
    columns["beta_1_deg"][1] = 1.0
    columns["t_s"] = [0.0, 0.0]
    pq.write_table(pa.table(columns), tmp_path / "still.parquet")
    assert _error(tmp_path / "still.parquet") == (
        f"{tmp_path / 'still.parquet'}, column 't_s': time does not increase (t = 0 s after 0 s)"
    )


def test_a_text_cell_only_where_the_reader_needs_a_number_is_refused(tmp_path):
    """An unplugged sensor logged as "n/a": the carriages alone are read; the sensors, asked for, are refused."""
    path = _write(
        tmp_path,
        f"{HEADER},alpha_des_deg,beta_des_deg,gamma_des_deg\n0,1,2,3,n/a,0,0,0,0,0,1,2,3\n1,1,2,3,0,0,0,0,0,0,4,5,6\n",
    )
    t, carriages = read_carriage_log(path, 0.01)
    assert t == pytest.approx([0.0, 1.0]) and carriages[0] == pytest.approx([0.001, 0.002, 0.003])
    with pytest.raises(TrajectoryError) as error:
        read_slider_log(path, 0.01)
    assert str(error.value) == f"{path}, line 2, column 'alpha_1_deg': 'n/a' is not a number"
    assert read_desired(path) == pytest.approx(np.radians([[1, 2, 3], [4, 5, 6]]))
    run = _write(tmp_path, f"{RUN},known_alpha_1_deg\n0,1,2,3,1,2,3,4,5,6,free\n1,1,2,3,1,2,3,4,5,6,free\n", "run.csv")
    assert np.degrees(read_run_log(run, 0.01, (2,))[3][1, 1]) == pytest.approx([4, 5, 6])
    with pytest.raises(TrajectoryError, match=r"line 3, column 'L_12_cmd_mm': 'x' is not a number"):
        read_run_log(_write(tmp_path, f"{RUN}\n0,1,2,3,1,2,3,4,5,6\n1,1,2,3,1,x,3,4,5,6\n", "x.csv"), 0.01, ())
