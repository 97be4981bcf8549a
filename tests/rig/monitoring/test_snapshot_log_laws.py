"""hipsim.rig.monitoring.snapshot_log on tiny files written here: the counter and the station loads kept beside the
samples, the load cell's gain over the commanded load worked out by hand, and each refusal named by file, line, column.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from support import given

import hipsim
from hipsim.exceptions import TrajectoryError
from hipsim.rig.monitoring.snapshot_log import SnapshotLog, read_snapshot
from hipsim.rig.monitoring.snapshots import find_snapshots

PARAMS = hipsim.load_parameters()
N = 40  # samples, 1 ms apart


def write(path, extra: dict[str, list[float]] | None = None, cycle: bool = True, load=None, jitter: float = 0.0, n=N):
    """A still machine (angles 1°, 2°, 3°), the load ``load`` (default 1000 + 10·k N), torques 10, 20, 30 N·mm;
    the time stamps ``jitter`` seconds late at every odd sample."""
    load = [1000.0 + 10 * k for k in range(n)] if load is None else load
    columns = {"t_s": [k / 1000 + jitter * (k % 2) for k in range(n)], "Fe_N": load}
    if cycle:
        columns["cycle"] = [5 + k // 10 for k in range(n)]
    columns |= {"alpha_deg": [1.0] * n, "beta_deg": [2.0] * n, "gamma_deg": [3.0] * n}
    columns |= {f"tau_{i}_Nmm": [10.0 * i] * n for i in (1, 2, 3)}
    columns |= extra or {}
    lines = [",".join(columns)] + [",".join(repr(columns[c][k]) for c in columns) for k in range(n)]
    path.write_text("\n".join(lines) + "\n")
    (found,), _ = find_snapshots(str(path))
    return found


def test_the_counter_and_the_log_as_the_models_take_it(tmp_path):
    read = read_snapshot(write(tmp_path / "a.csv"), PARAMS, cutoff=None)
    assert isinstance(read, SnapshotLog)
    assert read.cycles.tolist() == [5 + k // 10 for k in range(N)]
    assert read.loads is None and math.isnan(read.load_gain)
    log = read.log
    assert len(log) == N and log.cutoff is None and log.name == "a.csv"
    np.testing.assert_allclose(log.tau, np.tile([0.01, 0.02, 0.03], (N, 1)), rtol=1e-15)
    np.testing.assert_allclose(log.trajectory.Fe, [1000.0 + 10 * k for k in range(N)], rtol=1e-15)
    np.testing.assert_allclose(log.trajectory.q, np.tile(np.radians([1.0, 2.0, 3.0]), (N, 1)), rtol=1e-12)


def test_the_options_reach_the_log(tmp_path):
    # Stamps jittered by 0.2 ms: with the rate the times are the sample index over it.
    snap = write(tmp_path / "a.csv", jitter=2e-4)
    np.testing.assert_allclose(read_snapshot(snap, PARAMS, cutoff=None, rate=1000.0).log.t, np.arange(N) / 1000.0)
    # The cutoff: 40 samples are too few for 100 Hz (16 periods of it needed), enough for 450 Hz.
    with pytest.raises(TrajectoryError, match="40 samples .* too short to filter at 100 Hz"):
        read_snapshot(write(tmp_path / "b.csv"), PARAMS, cutoff=100.0)
    assert read_snapshot(write(tmp_path / "b.csv"), PARAMS, cutoff=450.0).log.cutoff == 450.0
    # By default through 20 Hz (800 samples needed at 1 kHz).
    assert read_snapshot(write(tmp_path / "e.csv", n=1000), PARAMS).log.cutoff == 20.0
    path = tmp_path / "c.csv"
    text = write(path).path
    lines = open(text).read().splitlines()
    # Torques as currents: τ = k·i with the constant given.
    header = lines[0].replace("tau_1_Nmm,tau_2_Nmm,tau_3_Nmm", "current_1_A,current_2_A,current_3_A")
    path.write_text(
        "\n".join([header] + [",".join(line.split(",")[:-3] + ["1.0", "2.0", "3.0"]) for line in lines[1:]]) + "\n"
    )
    (found,), _ = find_snapshots(str(path))
    log = read_snapshot(found, PARAMS, torque_constant=0.5, cutoff=None).log
    np.testing.assert_allclose(log.tau[0], [0.5, 1.0, 1.5], rtol=1e-15)


def test_the_station_loads_and_the_load_cell_s_gain(tmp_path):
    # The measured load (1000 + 10·k) against a commanded half of it: Σ F·F_cmd / Σ F_cmd² = 2 exactly.
    loads = {"Fe_1_N": [400.0 + k for k in range(N)], "Fe_2_N": [600.0] * N}
    commanded = {"Fe_cmd_N": [500.0 + 5 * k for k in range(N)]}
    read = read_snapshot(write(tmp_path / "a.csv", loads | commanded), PARAMS, cutoff=None)
    np.testing.assert_array_equal(read.loads, np.column_stack([loads["Fe_1_N"], loads["Fe_2_N"]]))
    assert read.load_gain == pytest.approx(2.0, rel=1e-15)
    # One station's load alone is no split; a commanded load of zero throughout gives no gain.
    read = read_snapshot(write(tmp_path / "b.csv", {"Fe_1_N": [1.0] * N, "Fe_cmd_N": [0.0] * N}), PARAMS, cutoff=None)
    assert read.loads is None and math.isnan(read.load_gain)
    only_two = read_snapshot(write(tmp_path / "c.csv", {"Fe_2_N": [1.0] * N}), PARAMS, cutoff=None)
    assert only_two.loads is None
    # A gain from a commanded load that is zero but once: (Σ F·F_cmd) over F_cmd² of the one sample.
    once = [0.0] * N
    once[3] = 0.5  # a square below one
    read = read_snapshot(write(tmp_path / "d.csv", {"Fe_cmd_N": once}), PARAMS, cutoff=None)
    assert read.load_gain == pytest.approx((1000.0 + 30.0) * 0.5 / 0.25, rel=1e-15)


def test_a_negative_station_load_is_named_by_line_and_column(tmp_path):
    second = [600.0] * N
    second[7] = -2.5
    first = [400.0] * N
    first[9] = -1.0  # later in the file than the other: the first by line is named
    first[2], second[4] = 0.0, 0.5  # loads of zero and below one newton before it are loads
    path = tmp_path / "a.csv"
    with pytest.raises(TrajectoryError) as error:
        read_snapshot(write(path, {"Fe_1_N": first, "Fe_2_N": second}), PARAMS, cutoff=None)
    e = error.value
    assert (e.source, e.line, e.column) == (str(path), 9, "Fe_2_N")  # sample 7 on line 9 (the header is line 1)
    assert "load -2.5 N is negative (a station's load is a magnitude)" in str(e)
    first[9], second[7] = 0.0, 0.0  # zero is a load
    assert (
        given(read_snapshot(write(path, {"Fe_1_N": first, "Fe_2_N": second}), PARAMS, cutoff=None).loads).min() == 0.0
    )


def test_no_counter_and_a_counter_that_goes_back(tmp_path):
    path = tmp_path / "a.csv"
    with pytest.raises(TrajectoryError) as error:
        read_snapshot(write(path, cycle=False), PARAMS, cutoff=None)
    assert str(error.value) == f"{path}: no 'cycle' column: a snapshot needs the machine's cycle counter"
    assert error.value.source == str(path)
    text = path.read_text().splitlines()
    write(path)
    lines = path.read_text().splitlines()
    k = lines[0].split(",").index("cycle")
    cells = lines[12].split(",")
    cells[k] = "3"
    lines[12] = ",".join(cells)
    path.write_text("\n".join(lines) + "\n")
    (found,), _ = find_snapshots(str(path))
    with pytest.raises(TrajectoryError) as error:
        read_snapshot(found, PARAMS, cutoff=None)
    assert (error.value.line, error.value.column, error.value.source) == (13, "cycle", str(path)) and text


def test_a_window_of_a_long_log_reads_its_lines_only(tmp_path):
    path = tmp_path / "long.csv"
    write(path)
    (first, *_), _ = find_snapshots(str(path), window=1)
    read = read_snapshot(first, PARAMS, cutoff=None)
    assert read.cycles.tolist() == [5] * 10 and len(read.log) == 10
