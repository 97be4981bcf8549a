"""hipsim/stations/logs.py on the files themselves: a TDMS/HDF5 log through its column map and its refusals by sample,
Parquet logs (text columns, a fixture's rows, no lines to name), the CSV's separator read from its header and first row,
a line the csv module cannot split, and the files that are not there. Each refusal whole (file, line, column)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq
import pytest

from hipsim.exceptions import TrajectoryError
from hipsim.stations import logs as logs_module
from hipsim.stations.logs import read_calibration_log, read_carriage_log, read_desired, read_run_log, read_slider_log

h5py = pytest.importorskip("h5py")

SENSORS = [f"{a}_{j}_deg" for j in (1, 2) for a in ("alpha", "beta", "gamma")]
CARRIAGES = ["L_11_mm", "L_12_mm", "L_13_mm"]
DESIRED = ["alpha_des_deg", "beta_des_deg", "gamma_des_deg"]


def _refusal(read, *args, **kwargs) -> str:
    with pytest.raises(TrajectoryError) as error:
        read(*args, **kwargs)
    assert type(error.value) is TrajectoryError
    return str(error.value)


def _hdf5(path: Path, channels: dict[str, np.ndarray], group: str = "acq") -> Path:
    with h5py.File(path, "w") as file:
        where = file.create_group(group)
        for name, values in channels.items():
            where.create_dataset(name, data=np.asarray(values, dtype=float))
    return path


def test_a_channel_log_read_through_its_column_map(tmp_path):
    """Channels named by the acquisition (time, enc1 …), each reader given the map to the log's columns."""
    n = 3
    t = np.array([0.0, 0.1, 0.2])
    carriages = np.array([[500.0, 510.0, 520.0], [501.0, 511.0, 521.0], [502.0, 512.0, 522.0]])
    sensors = np.arange(18.0).reshape(n, 6) - 4.0
    desired = np.array([[1.0, 2.0, 3.0], [4.0, 5.0, 6.0], [7.0, 8.0, 9.0]])
    channels = {"time": t}
    channels |= {f"enc{i + 1}": carriages[:, i] for i in range(3)}
    channels |= {f"imu{k}": sensors[:, k] for k in range(6)}
    channels |= {f"ref{k}": desired[:, k] for k in range(3)}
    path = _hdf5(tmp_path / "log.h5", channels)
    named = ["t_s", *CARRIAGES, *SENSORS, *DESIRED]
    columns = ",".join(f"{name}=acq/{channel}" for name, channel in zip(named, channels, strict=True))
    log = read_calibration_log(path, 0.01, columns=columns)
    np.testing.assert_array_equal(log.t, t)
    np.testing.assert_allclose(log.carriages, carriages * 1e-3, rtol=1e-15)
    np.testing.assert_allclose(np.degrees(log.sensors), sensors.reshape(n, 2, 3), rtol=1e-15, atol=1e-14)
    slider = read_slider_log(path, 0.01, columns=columns)
    assert slider[2] is not None and np.degrees(slider[2][2, 1, 2]) == pytest.approx(sensors[2, 5])
    assert read_carriage_log(path, 0.01, columns=columns)[1][1] == pytest.approx([0.501, 0.511, 0.521])
    read = read_desired(path, columns)
    assert read is not None
    np.testing.assert_allclose(np.degrees(read), desired, rtol=1e-15)


def test_a_channel_log_is_refused_by_its_sample_number(tmp_path):
    """Six samples of four channels: the sample a refusal names counts from 1 (past the channels' count)."""
    t = np.array([0.0, 0.1, 0.2, 0.3, 0.4, 0.5])
    ones = np.ones(6)
    bad = ones.copy()
    bad[5] = math.nan
    path = _hdf5(tmp_path / "nan.h5", {"t_s": t, "L_11_mm": ones, "L_12_mm": bad, "L_13_mm": ones})
    assert _refusal(read_carriage_log, path, 0.01) == f"{path}, line 6, column 'L_12_mm': not a finite number"
    back = t.copy()
    back[1] = 0.0
    path = _hdf5(tmp_path / "back.h5", {"t_s": back, "L_11_mm": ones, "L_12_mm": ones, "L_13_mm": ones})
    assert _refusal(read_carriage_log, path, 0.01) == (
        f"{path}, line 2, column 't_s': time does not increase (t = 0 s after 0 s)"
    )


@pytest.mark.parametrize("name", ["absent.h5", "absent.parquet", "absent.csv"])
def test_a_log_that_is_not_there(tmp_path, name):
    path = tmp_path / name
    assert _refusal(read_calibration_log, path, 0.01) == f"{path}: no such calibration log"


def _parquet(path: Path, columns: dict[str, list]) -> Path:
    pq.write_table(pa.table(columns), path)
    return path


def test_parquet_columns_of_text_are_left_out_unless_needed(tmp_path):
    numbers = {"t_s": [0.0, 1.0], "L_11_mm": [1.0, 1.0], "L_12_mm": [2.0, 2.0], "L_13_mm": [3.0, 3.0]}
    # A note before the columns read, and a sensor logged as text that the carriages alone do not need.
    path = _parquet(tmp_path / "notes.parquet", {"note": ["a", "b"], **numbers, "alpha_1_deg": ["n/a", "n/a"]})
    t, carriages = read_carriage_log(path, 0.01)
    assert t == pytest.approx([0.0, 1.0]) and carriages[1] == pytest.approx([0.001, 0.002, 0.003])
    assert _refusal(read_slider_log, path, 0.01) == f"{path}, column 'alpha_1_deg': holds string, not numbers"
    text = _parquet(tmp_path / "text.parquet", numbers | {"L_12_mm": ["2", "two"]})
    assert _refusal(read_carriage_log, text, 0.01) == f"{text}, column 'L_12_mm': holds string, not numbers"
    empty = _parquet(tmp_path / "empty.parquet", {})
    assert _refusal(read_carriage_log, empty, 0.01) == (
        f"{empty}: no time: missing column(s) t_s (the header has nothing)"
    )
    not_parquet = tmp_path / "not.parquet"
    not_parquet.write_text("t_s,L_11_mm\n", encoding="utf-8")
    assert _refusal(read_carriage_log, not_parquet, 0.01).startswith(f"{not_parquet}: not a Parquet file (")


def test_a_parquet_log_names_the_column_of_a_refusal_and_no_line(tmp_path):
    columns: dict[str, list] = {"t_s": [0.0, 1.0], **{name: [1.0, 2.0] for name in CARRIAGES + SENSORS}}
    partial = {f"known_{a}_2_deg": [10.0, None] for a in ("alpha", "beta", "gamma")}
    partial["known_beta_2_deg"] = [None, None]
    path = _parquet(tmp_path / "fixture.parquet", columns | partial)
    assert _refusal(read_calibration_log, path, 0.01) == (
        f"{path}, column 'known_beta_2_deg': a fixture's known attitude needs all three angles of platform 2 on a row, "
        "or none"
    )
    commands = {"L_11_cmd_mm": [1.0, 1.0], "L_12_cmd_mm": [1.0, math.nan], "L_13_cmd_mm": [1.0, 1.0]}
    run = _parquet(tmp_path / "run.parquet", columns | commands)
    assert _refusal(read_run_log, run, 0.01, (1, 2)) == f"{run}, column 'L_12_cmd_mm': not a finite number"


def _write(tmp_path: Path, text: str, name: str = "log.csv") -> Path:
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


def test_the_separator_is_the_one_that_splits_the_header_and_the_first_row_alike(tmp_path):
    """A comma log whose header has a ';' in a name: the semicolon splits the header in two but not the first row."""
    header = "t_s,L_11_mm,L_12_mm,L_13_mm,note; free text"
    path = _write(tmp_path, f"{header}\n0,1,2,3,a\n1,4,5,6,b\n")
    t, carriages = read_carriage_log(path, 0.01)
    assert t == pytest.approx([0.0, 1.0]) and carriages[1] == pytest.approx([0.004, 0.005, 0.006])
    one = _write(tmp_path, f"{header}\n0,1,2,3,a\n", "one.csv")
    assert _refusal(read_carriage_log, one, 0.01) == f"{one}: 1 row(s): a log needs at least 2"
    none = _write(tmp_path, "t_s,L_11_mm,L_12_mm,L_13_mm\n", "none.csv")  # the header alone decides
    assert _refusal(read_carriage_log, none, 0.01) == f"{none}: 0 row(s): a log needs at least 2"


def test_a_decimal_comma_only_where_the_comma_does_not_separate(tmp_path):
    path = _write(tmp_path, 't_s,L_11_mm,L_12_mm,L_13_mm\n0,1,2,3\n1,"1,5",2,3\n')
    assert _refusal(read_carriage_log, path, 0.01) == f"{path}, line 3, column 'L_11_mm': '1,5' is not a number"
    semicolons = _write(tmp_path, "t_s;L_11_mm;L_12_mm;L_13_mm\n0;1;2;3\n1;1,5;2;3\n", "semi.csv")
    assert read_carriage_log(semicolons, 0.01)[1][1] == pytest.approx([0.0015, 0.002, 0.003])


def test_a_line_the_csv_module_cannot_split_is_named(tmp_path, monkeypatch):
    """The csv module's refusal (stood in: a file read as text has no line it refuses today) named by its line."""
    split = logs_module.cells

    def cells(text: str, separator: str = ",") -> list[str]:
        if text.startswith("bad"):
            raise ValueError("cannot split the line into cells (?)")
        return split(text, separator)

    monkeypatch.setattr(logs_module, "cells", cells)
    path = _write(tmp_path, "# a comment\nbad,t_s,L_11_mm,L_12_mm,L_13_mm\n0,0,1,2,3\n")
    assert _refusal(read_carriage_log, path, 0.01) == f"{path}, line 2: cannot split the line into cells (?)"
    path = _write(tmp_path, "t_s,L_11_mm,L_12_mm,L_13_mm\n0,1,2,3\n\nbad,1,2,3\n", "row.csv")
    assert _refusal(read_carriage_log, path, 0.01) == f"{path}, line 4: cannot split the line into cells (?)"


def test_time_is_a_number_a_carriage_log_needs(tmp_path):
    path = _write(tmp_path, "t_s,L_11_mm,L_12_mm,L_13_mm\n0,1,2,3\nlater,1,2,3\n")
    assert _refusal(read_carriage_log, path, 0.01) == f"{path}, line 3, column 't_s': 'later' is not a number"


def test_time_that_stands_still_is_named_where_it_first_does(tmp_path):
    """0, 1, 1, 0.5 s: the first step that does not increase is the still one (line 4), not the one back (line 5)."""
    path = _write(tmp_path, "t_s,L_11_mm,L_12_mm,L_13_mm\n0,1,2,3\n1,1,2,3\n1,1,2,3\n0.5,1,2,3\n")
    assert _refusal(read_carriage_log, path, 0.01) == (
        f"{path}, line 4, column 't_s': time does not increase (t = 1 s after 1 s)"
    )


def test_a_calibration_log_needs_the_sensors(tmp_path):
    path = _write(tmp_path, "t_s,L_11_mm,L_12_mm,L_13_mm\n0,1,2,3\n1,1,2,3\n")
    assert _refusal(read_calibration_log, path, 0.01) == (
        f"{path}: no attitude sensor of platform 1: missing column(s) alpha_1_deg, beta_1_deg, gamma_1_deg (the header "
        "has t_s, L_11_mm, L_12_mm, L_13_mm)"
    )


def test_a_run_log_with_platform_1s_sensor_alone(tmp_path):
    header = ",".join(["t_s", *CARRIAGES, *SENSORS[:3]])
    path = _write(tmp_path, f"{header}\n0,1,2,3,10,20,30\n1,1,2,3,-1,-2,-3\n")
    t, _, commands, sensors = read_run_log(path, 0.01, (1,))
    assert commands is None and sensors.shape == (2, 2, 3)
    assert np.degrees(sensors[:, 0]) == pytest.approx(np.array([[10, 20, 30], [-1, -2, -3]]))
    assert np.all(np.isnan(sensors[:, 1]))
