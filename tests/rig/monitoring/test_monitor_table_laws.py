"""hipsim.rig.monitoring.monitor_table: the monitor's table written and read back to the bit, its set-up beside it.

Rows made by hand (two snapshots, every column of :data:`COLUMNS`); what must hold: the values read back equal the
values written (NaN as NaN, texts as texts), the set-up read back is the one written, and :func:`table_rows` gives
the estimate rows with whole numbers for the counts.
"""

from __future__ import annotations

import math

import pytest

from hipsim.rig.monitoring.monitor_fit import ESTIMATE_COLUMNS
from hipsim.rig.monitoring.monitor_table import (
    COLUMNS,
    CSV_METADATA,
    PARTS,
    TEXT_COLUMNS,
    read_metadata,
    read_table,
    table_rows,
    write_table,
)

SETUP = {"parameters": "ab12", "model": "cd34", "window": None, "estimator": "monitor-2"}


def columns():
    """Two rows: every number column 0.1·(k + 1) + column index (a third of one in one cell), texts by name."""
    out: dict[str, list] = {}
    for j, name in enumerate(COLUMNS):
        if name in TEXT_COLUMNS:
            out[name] = [f"{name}-{k}" for k in range(2)]
        else:
            out[name] = [0.1 * (k + 1) + j for k in range(2)]
    out["cycle"], out["last_cycle"], out["samples"], out["bytes"] = [0, 500_000], [499_999, 999_999], [10, 20], [7, 8]
    out["load_friction_mm"] = [1 / 3, math.nan]
    return out


def test_the_columns():
    assert COLUMNS[:5] == ("cycle", "last_cycle", "file", "samples", "phase")
    assert COLUMNS[-2:] == ("bytes", "sha256") and len(set(COLUMNS)) == len(COLUMNS)
    assert set(ESTIMATE_COLUMNS) <= set(COLUMNS)
    assert TEXT_COLUMNS == ("file", "phase", "stations", "flag", "state", "note", "sha256")
    assert "hip_mu_change_1" in COLUMNS and "hip_mu_change_2_std" in COLUMNS
    assert COLUMNS.index("ewma_1_mm") + 2 == COLUMNS.index("ucl_1_mm")
    assert CSV_METADATA == "# hipsim monitor: "
    assert set(PARTS) == {"parameters", "model", "window", "estimator"}


@pytest.mark.parametrize("suffix", [".csv", ".parquet"])
def test_written_and_read_back_to_the_bit(tmp_path, suffix):
    if suffix == ".parquet":
        pytest.importorskip("pyarrow")
    path = tmp_path / f"monitor{suffix}"
    written = columns()
    assert write_table(path, written, SETUP) == path
    back = read_table(path)
    assert list(back) == list(COLUMNS)
    for name in COLUMNS:
        for a, b in zip(written[name], back[name]):
            assert (a == b) or (math.isnan(a) and math.isnan(b)), (name, a, b)
    assert read_metadata(path) == SETUP
    if suffix == ".csv":
        assert path.read_text().startswith(CSV_METADATA + '{"parameters":"ab12",')


def test_the_estimate_rows(tmp_path):
    path = tmp_path / "monitor.csv"
    write_table(path, columns(), SETUP)
    rows = table_rows(read_table(path))
    assert len(rows) == 2
    assert list(rows[1]) == list(ESTIMATE_COLUMNS)
    assert rows[1]["cycle"] == 500_000 and type(rows[1]["cycle"]) is int
    for name in ("last_cycle", "samples", "bytes"):
        assert type(rows[0][name]) is int
    assert (rows[0]["last_cycle"], rows[0]["samples"], rows[0]["bytes"]) == (499_999, 10, 7)
    assert rows[0]["load_friction_mm"] == 1 / 3 and math.isnan(rows[1]["load_friction_mm"])
    assert rows[1]["file"] == "file-1"
