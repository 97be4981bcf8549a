"""A carriage command file read fast (hipsim.learning.command_file): columns, units, and the refusals naming the place."""

from __future__ import annotations

import numpy as np
import pytest

from hipsim.exceptions import TrajectoryError
from hipsim.learning.command_file import read_command_file

HEADER = "t_s,L_11_mm,L_12_mm,L_13_mm"


def write(tmp_path, text, name="command.csv"):
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


def test_millimetres_to_metres_and_the_optional_columns(tmp_path):
    path = write(
        tmp_path,
        HEADER + ",Fe_N,alpha_2_deg,beta_2_deg,gamma_2_deg,alpha_1_deg,other\n"
        "0.0,100,200,300,50,90,0,-45,1,x\n0.5,101,202,303,60,0,180,0,1,y\n",
    )
    command = read_command_file(path)
    assert command.source == str(path)
    assert command.t.tolist() == [0.0, 0.5]
    assert command.L == pytest.approx(np.array([[0.1, 0.2, 0.3], [0.101, 0.202, 0.303]]), rel=1e-15)
    assert command.load.tolist() == [50.0, 60.0]
    assert command.attitude[0] is None  # platform 1 has only α: no attitude at all
    assert command.attitude[1] == pytest.approx(np.radians([[90.0, 0.0, -45.0], [0.0, 180.0, 0.0]]), rel=1e-15)


def test_without_a_load_the_load_is_zero_and_parquet_reads_alike(tmp_path):
    import pyarrow as pa
    import pyarrow.parquet as pq

    path = tmp_path / "command.parquet"
    pq.write_table(
        pa.table({"t_s": [0.0, 1.0, 2.0], "L_11_mm": [1.0] * 3, "L_12_mm": [2.0] * 3, "L_13_mm": [3.0] * 3}), path
    )
    command = read_command_file(path)
    assert command.load.tolist() == [0.0, 0.0, 0.0]
    assert command.L[2] == pytest.approx([1e-3, 2e-3, 3e-3], rel=1e-15)
    assert command.attitude == (None, None)


def test_a_missing_file_and_a_missing_column_are_named(tmp_path):
    with pytest.raises(TrajectoryError, match="no such file"):
        read_command_file(tmp_path / "absent.csv")
    with pytest.raises(TrajectoryError, match=r"missing column\(s\) L_13_mm \(the header has t_s, L_11_mm, L_12_mm\)"):
        read_command_file(write(tmp_path, "t_s,L_11_mm,L_12_mm\n0,1,2\n"))


def test_a_cell_that_is_not_a_number_is_refused(tmp_path):
    with pytest.raises(TrajectoryError) as error:
        read_command_file(write(tmp_path, HEADER + "\n0,1,2,3\n1,1,abc,3\n"))
    assert "L_12_mm" in str(error.value)  # the cell's column (or its row, by pyarrow's own parse)


@pytest.mark.parametrize(("second", "word"), [("0.0", "t = 0 s after 0 s"), ("-1.0", "t = -1 s after 0 s")])
def test_time_must_increase_strictly(tmp_path, second, word):
    with pytest.raises(TrajectoryError, match=f"time does not increase \\({word}\\)"):
        read_command_file(write(tmp_path, f"{HEADER}\n0.0,1,2,3\n{second},1,2,3\n"))
    # the edge: the smallest increase is accepted
    assert len(read_command_file(write(tmp_path, f"{HEADER}\n0.0,1,2,3\n1e-12,1,2,3\n", "ok.csv")).t) == 2
