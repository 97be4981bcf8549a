"""The readers' keyword options, declared once (hipsim.motion.read_options): a misspelt one is refused, never ignored."""

from __future__ import annotations

import numpy as np
import pytest

from hipsim.motion.build import Table, build_trajectory
from hipsim.motion.columns import ColumnMap, parse_columns
from hipsim.motion.csv_table import load_trajectory_csv
from hipsim.motion.opensim import load_opensim
from hipsim.motion.parquet import load_trajectory_parquet
from hipsim.motion.read_options import BuildOptions, ReadOptions
from hipsim.motion.readers import read_trajectory


def test_the_declarations():
    assert set(ReadOptions.__annotations__) == set(BuildOptions.__annotations__) | {"columns", "load_column"}
    assert set(BuildOptions.__annotations__) == {
        "periodic",
        "frequency",
        "period",
        "resample",
        "body_weight",
        "cutoff",
        "load_curve",
    }


@pytest.mark.parametrize(
    ("reader", "suffix"),
    [
        (load_trajectory_csv, ".csv"),
        (load_trajectory_parquet, ".parquet"),
        (load_opensim, ".mot"),
        (read_trajectory, ".csv"),
    ],
)
def test_a_misspelt_option_is_refused_before_the_file_is_read(tmp_path, reader, suffix):
    missing = tmp_path / f"nowhere{suffix}"  # never opened: the keyword is checked first
    with pytest.raises(TypeError, match=rf"^{reader.__name__}\(\) got an unexpected keyword argument 'periodc'$"):
        reader(missing, periodc=True)


def test_build_trajectory_refuses_the_columns_and_a_misspelt_option():
    t = np.arange(10) / 100.0
    mapping = parse_columns("time=t,alpha=a,beta=b,gamma=g")
    assert isinstance(mapping, ColumnMap)
    table = Table("x.csv", np.arange(2, 12), t, np.zeros((10, 3)), None, mapping)
    for name in ("columns", "cutof"):  # the columns are the reader's business, read before
        with pytest.raises(TypeError, match=f"^build_trajectory\\(\\) got an unexpected keyword argument '{name}'$"):
            build_trajectory(table, **{name: None})  # type: ignore[call-overload]  # unknown keywords on purpose
