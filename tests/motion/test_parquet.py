"""Trajectories from Parquet tables (hipsim.motion.parquet), pinned on tiny tables written here (motion_support)."""

from __future__ import annotations

import numpy as np
import pytest
from motion_support import ALPHA, BETA, GAMMA, LOAD, N, Q, T, error_of, own_columns, parquet_file, quiet

from hipsim.motion.build import TrajectoryWarning
from hipsim.motion.parquet import load_trajectory_parquet
from hipsim.motion.readers import read_trajectory


def test_a_parquet_table_reads_as_its_numbers(tmp_path):
    path = parquet_file(tmp_path / "a.parquet", {**own_columns()})
    trajectory = load_trajectory_parquet(path)
    np.testing.assert_array_equal(trajectory.t, T)
    np.testing.assert_allclose(trajectory.q, Q, rtol=0, atol=1e-15)
    np.testing.assert_array_equal(trajectory.Fe, LOAD)
    assert trajectory.name == path
    # Integer columns are numbers too.
    ints = {"t_s": T, "alpha_deg": np.arange(N) + 10, "beta_deg": 2 * np.arange(N), "gamma_deg": -np.arange(N)}
    trajectory = quiet(lambda: load_trajectory_parquet(parquet_file(tmp_path / "b.parquet", ints)))
    np.testing.assert_allclose(trajectory.q, Q, rtol=0, atol=1e-15)
    np.testing.assert_array_equal(trajectory.Fe, np.zeros(N))


def test_a_parquet_tables_problems_are_named_by_row_and_column(tmp_path):
    columns = own_columns()
    short = parquet_file(tmp_path / "a.parquet", {key: value[:5] for key, value in columns.items()})
    assert str(error_of(lambda: load_trajectory_parquet(short))) == f"{short}: 5 samples; at least 6 are needed"
    beta = BETA.copy()
    beta[3] = np.inf
    bad = parquet_file(tmp_path / "b.parquet", {**columns, "beta_deg": beta})
    error = error_of(lambda: load_trajectory_parquet(bad))
    assert str(error) == f"{bad}, line 5, column 'beta_deg': 'inf' is not finite"
    words = parquet_file(tmp_path / "c.parquet", {**columns, "gamma_deg": [f"{v}" for v in "abcdefgh"]})
    assert (
        str(error_of(lambda: load_trajectory_parquet(words)))
        == f"{words}, column 'gamma_deg': holds string, not numbers"
    )
    other = parquet_file(tmp_path / "d.parquet", {"time": T, **{k: v for k, v in columns.items() if k != "t_s"}})
    error = error_of(lambda: load_trajectory_parquet(other))
    assert error.line == 1 and "no time column 't_s'" in str(error)
    nothing = str(tmp_path / "none.parquet")
    assert str(error_of(lambda: load_trajectory_parquet(nothing))) == f"{nothing}: no such trajectory file"


def test_a_parquet_tables_times_must_be_even_to_the_last_digit(tmp_path):
    # No printed resolution in a binary table: a step 1 % long is uneven.
    t = T.copy()
    t[4:] += 0.0001
    path = parquet_file(tmp_path / "a.parquet", {**own_columns(), "t_s": t})
    error = error_of(lambda: load_trajectory_parquet(path))
    assert error.line == 6 and error.column == "t_s" and "uneven time step" in str(error)


def test_a_parquet_table_through_a_mapping(tmp_path):
    path = parquet_file(tmp_path / "a.parquet", {"Time": T, "FE": ALPHA, "Force": LOAD / 1000.0})
    trajectory = load_trajectory_parquet(path, columns="time=Time,alpha=FE,beta=zero,gamma=zero,load=Force:kN")
    np.testing.assert_allclose(trajectory.q[:, 0], np.radians(ALPHA), rtol=0, atol=1e-15)
    np.testing.assert_array_equal(trajectory.q[:, 1:], 0.0)
    np.testing.assert_allclose(trajectory.Fe, LOAD, rtol=1e-15)
    trajectory = load_trajectory_parquet(
        path, columns="time=Time,alpha=FE,beta=zero,gamma=zero", load_column="Force:kN"
    )
    np.testing.assert_allclose(trajectory.Fe, LOAD, rtol=1e-15)


def test_a_parquet_load_column_without_a_mapping_and_its_errors(tmp_path):
    columns = {**own_columns(False), "Fz": LOAD / 1000.0}
    path = parquet_file(tmp_path / "a.parquet", columns)
    np.testing.assert_allclose(load_trajectory_parquet(path, load_column="Fz:kN").Fe, LOAD, rtol=1e-15)
    error = error_of(
        lambda: load_trajectory_parquet(
            path, columns="time=t_s,alpha=alpha_deg,beta=zero,gamma=zero,load=Fz", load_column="Fz"
        )
    )
    assert str(error) == f"{path}: the load column is named twice (in the column mapping and on its own)"
    other = parquet_file(tmp_path / "b.parquet", {"time": T, "alpha_deg": ALPHA, "beta_deg": BETA, "gamma_deg": GAMMA})
    assert str(error_of(lambda: load_trajectory_parquet(other))).startswith(f"{other}, line 1: no time column 't_s'")
    six = parquet_file(tmp_path / "c.parquet", {key: value[:6] for key, value in own_columns().items()})
    assert len(load_trajectory_parquet(six)) == 6


def test_a_parquet_tables_rows_keep_their_lines_when_a_load_file_cuts_them(tmp_path):
    load = tmp_path / "f.csv"
    load.write_text("time,F\n" + "".join(f"{k / 100},{1000 + k}\n" for k in range(1, 8)))
    path = parquet_file(tmp_path / "a.parquet", own_columns(False))
    with pytest.warns(TrajectoryWarning, match="1 motion samples outside the overlap left out"):
        trajectory = read_trajectory(path, load=load, load_column="F")
    np.testing.assert_array_equal(trajectory.lines, np.arange(3, N + 2))
    np.testing.assert_array_equal(trajectory.Fe, 1000.0 + np.arange(1, 8))
