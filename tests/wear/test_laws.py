"""hipsim.wear.laws by hand on four points written here: Archard's k, k(CS) from a table (held at its ends, the
points beyond counted at the ends' boundary), the contact-area law, the volume over the cells; the table's file
read and refused by line and column, its units at the bounds."""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

from hipsim.exceptions import ArgumentError, FileRowError
from hipsim.wear.kinematics import CupSetup
from hipsim.wear.laws import (
    ContactAreaLaw,
    CrossShearLaw,
    WearFactor,
    predict_wear,
    read_numeric_columns,
    read_wear_law,
)
from hipsim.wear.maps import WearMaps
from hipsim.wear.points import CupPoints

NAN = math.nan


def _maps(area: np.ndarray | None = None, cross_shear=(NAN, 0.1, 0.2, 0.4)) -> WearMaps:
    """Four points; point 0 carries no work."""
    return WearMaps(
        points=CupPoints(np.eye(3)[[2, 0, 1, 2]], area),
        setup=CupSetup(),
        sliding_mm=np.array([5.0, 2.0, 4.0, 6.0]),
        sliding_loaded_mm=np.array([0.0, 2.0, 3.0, 6.0]),
        work_N_per_mm=np.array([0.0, 1.0, 3.0, 2.0]),
        cross_shear=np.array(cross_shear),
        principal=np.zeros((4, 3)),
        force_track_mm=12.0,
        force_track_load_Nm=3.0,
        cycles=1.0,
        duration_s=1.0,
        samples=100,
        name="hand",
        iterations=0,
    )


AREA = np.array([1.0, 2.0, 3.0, 4.0])


def test_archards_law_depth_and_volume_by_hand():
    """depth = 10⁻³·k·W [mm] a cycle; per Mc in µm ×10⁹; volume = depth·dA·10⁶ [mm³/Mc]."""
    wear = predict_wear(_maps(AREA), WearFactor(2e-7))
    assert_allclose(wear.depth_um_per_Mc, 1e-3 * 2e-7 * np.array([0.0, 1.0, 3.0, 2.0]) * 1e9, rtol=1e-12)
    assert wear.volume_mm3_per_Mc is not None
    assert_allclose(wear.volume_mm3_per_Mc, 1e-3 * 2e-7 * np.array([0.0, 2.0, 9.0, 8.0]) * 1e6, rtol=1e-12)
    assert wear.total_mm3_per_Mc == pytest.approx(1e-3 * 2e-7 * 19.0 * 1e6, rel=1e-12)
    assert wear.beyond_table == 0
    assert wear.law == "local (Archard, pin-on-disc: V = ∫k·W dA), k = 2e-07 mm³/(N·m)"
    plain = predict_wear(_maps(None), WearFactor(2e-7))
    assert plain.volume_mm3_per_Mc is None and plain.total_mm3_per_Mc is None
    assert_allclose(plain.depth_um_per_Mc, wear.depth_um_per_Mc)


def test_a_wear_factor_of_zero_is_taken_and_a_negative_one_refused():
    assert WearFactor(0.0).k == 0.0 and ContactAreaLaw(0.0).C == 0.0
    for bad in (-1e-12, math.nan, math.inf, True):
        with pytest.raises(
            ArgumentError, match=rf"^wear factor: expected a wear factor k ≥ 0 in mm³/\(N·m\), got {bad!r}$"
        ):
            WearFactor(bad)
        with pytest.raises(
            ArgumentError, match=rf"^wear coefficient: expected a dimensionless wear coefficient C ≥ 0, got {bad!r}$"
        ):
            ContactAreaLaw(bad)


def test_the_contact_area_law_wears_by_the_sliding_in_contact():
    wear = predict_wear(_maps(AREA), ContactAreaLaw(1e-9))
    assert_allclose(wear.depth_um_per_Mc, 1e-9 * np.array([0.0, 2.0, 3.0, 6.0]) * 1e9, rtol=1e-12)
    assert wear.total_mm3_per_Mc == pytest.approx(1e-9 * (4.0 + 9.0 + 24.0) * 1e6, rel=1e-12)
    assert wear.law == "contact area (V = C·A·s), C = 1e-09"


def test_k_of_cs_between_rows_held_beyond_and_zero_without_work():
    law = CrossShearLaw(np.array([0.1, 0.3]), np.array([1e-7, 3e-7]))
    assert_allclose(law.factor(np.array([NAN, 0.0, 0.1, 0.2, 0.3, 0.5])), [0.0, 1e-7, 1e-7, 2e-7, 3e-7, 3e-7])
    wear = predict_wear(_maps(AREA), law)
    k = np.array([0.0, 1e-7, 2e-7, 3e-7])
    assert_allclose(wear.depth_um_per_Mc, 1e-3 * k * np.array([0.0, 1.0, 3.0, 2.0]) * 1e9, rtol=1e-12)
    assert wear.beyond_table == 1  # 0.4 > 0.3; 0.1 at the table's first row is in it, the unloaded NaN not counted
    assert predict_wear(_maps(AREA, (NAN, 0.1, 0.3, 0.3)), law).beyond_table == 0  # both ends are in the table
    assert predict_wear(_maps(AREA, (0.05, 0.09, 0.31, 0.2)), law).beyond_table == 2  # point 0 carries no work
    assert (
        law.describe() == "local (Archard) with k(CS) from wear law (2 rows, CS 0.1 to 0.3, k 1e-07 to 3e-07 mm³/(N·m))"
    )


def test_a_table_of_three_rows_names_its_ends():
    law = CrossShearLaw(np.array([0.1, 0.2, 0.3]), np.array([3e-7, 1e-7, 2e-7]), "k.csv")
    assert law.describe() == "local (Archard) with k(CS) from k.csv (3 rows, CS 0.1 to 0.3, k 1e-07 to 3e-07 mm³/(N·m))"
    assert predict_wear(_maps(AREA, (NAN, 0.25, 0.3, 0.31)), law).beyond_table == 1


def test_a_table_is_refused_by_its_row():
    with pytest.raises(ArgumentError, match=r"table, row 3: expected CS increasing \(the row before has 0\.2\)"):
        CrossShearLaw(np.array([0.1, 0.2, 0.2]), np.array([1e-7, 2e-7, 3e-7]), "table")
    with pytest.raises(ArgumentError, match=r"table, row 2: expected a wear factor k ≥ 0"):
        CrossShearLaw(np.array([0.1, 0.2]), np.array([1e-7, -1e-12]), "table")
    with pytest.raises(ArgumentError, match="one k per CS"):
        CrossShearLaw(np.array([0.1, 0.2]), np.array([1e-7]))
    with pytest.raises(ArgumentError, match="one k per CS"):
        CrossShearLaw(np.array([]), np.array([]))
    with pytest.raises(ArgumentError, match="finite CS and k"):
        CrossShearLaw(np.array([0.1, 0.2]), np.array([1e-7, math.inf]))
    with pytest.raises(ArgumentError, match="finite CS and k"):
        CrossShearLaw(np.array([NAN, 0.2]), np.array([1e-7, 1e-7]))
    one = CrossShearLaw(np.array([0.2]), np.array([0.0]))  # one row, k = 0: allowed
    assert one.factor(np.array([0.5])).tolist() == [0.0]


def _write(tmp_path, text: str):
    path = tmp_path / "law.csv"
    path.write_text(text)
    return path


def test_a_wear_law_file_read_with_comments_and_any_separator(tmp_path):
    law = read_wear_law(_write(tmp_path, "# Kang 2008\nk_mm3_per_Nm;cross_shear\n1e-7;0.0\n\n3e-7;0.2\n"))
    assert law.cross_shear.tolist() == [0.0, 0.2] and law.k.tolist() == [1e-7, 3e-7]
    assert law.source == str(tmp_path / "law.csv")
    table, lines = read_numeric_columns(_write(tmp_path, "a\tb\n1\t2\n3\t4\n"), ("b", "a"), "table")
    assert table.tolist() == [[2.0, 1.0], [4.0, 3.0]] and lines.tolist() == [2, 3]


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("", "law.csv: an empty wear-law table: expected a header cross_shear, k_mm3_per_Nm and rows"),
        ("cross_shear,k\n0.1,1e-7\n", "line 1: no column k_mm3_per_Nm (the header has cross_shear, k)"),
        ("cross_shear,k_mm3_per_Nm\n", "line 1: the wear-law table has a header and no rows"),
        ("cross_shear,k_mm3_per_Nm\n0.1,x\n", "line 2, column 'k_mm3_per_Nm': expected a number, got 'x'"),
        ("cross_shear,k_mm3_per_Nm\n0.1\n", "line 2, column 'k_mm3_per_Nm': expected a number, got ''"),
        ("cross_shear,k_mm3_per_Nm\n0.1,inf\n", "line 2, column 'k_mm3_per_Nm': expected a finite number, got 'inf'"),
        (
            "cross_shear,k_mm3_per_Nm\n0.1,1e-7\n#\n0.1,2e-7\n",
            "line 4, column 'cross_shear': CS 0.1 does not increase (the row before has 0.1)",
        ),
        (
            "cross_shear,k_mm3_per_Nm\n0.1,1e-7\n0.2,-1e-7\n",
            "line 3, column 'k_mm3_per_Nm': a negative wear factor -1e-07 mm³/(N·m)",
        ),
        (
            "cross_shear,k_mm3_per_Nm\n0.5,1e-7\n20,2e-7\n1.5,3e-7\n",
            "line 4, column 'cross_shear': CS 1.5 does not increase (the row before has 20)",
        ),
    ],
)
def test_a_bad_wear_law_file_is_refused_by_line_and_column(tmp_path, text, message):
    path = _write(tmp_path, text)
    with pytest.raises(FileRowError) as caught:
        read_wear_law(path)
    assert message in str(caught.value) and str(caught.value).startswith(str(path))
    assert caught.value.source == str(path)


@pytest.mark.parametrize(
    ("rows", "refused"),
    [
        ("0.5,1e-7\n1.0,1e-7\n", None),  # CS up to 1 taken (a ratio)
        ("0.5,1e-7\n1.01,1e-7\n", "line 3, column 'cross_shear': cross-shear 1.01: CS is a ratio from 0 to 0.5"),
        ("0.1,1e-9\n0.2,1e-5\n", None),  # k at both ends of UHMWPE's plausible range
        ("0.1,0\n0.2,0\n", None),  # no positive k: nothing to judge
        ("0.1,1e-12\n0.2,1e-7\n", "line 2, column 'k_mm3_per_Nm': a wear factor 1e-12 mm³/(N·m) is 1/1000 of"),
        ("0.1,9e-13\n0.2,1e-7\n", None),  # a thousand times it is still not UHMWPE's: no unit explains it
        ("0.1,1e-7\n0.2,1e-2\n", "line 3, column 'k_mm3_per_Nm': a wear factor 0.01 mm³/(N·m) is 1000 times"),
        # Beyond 1e-3 with no unit to explain it: refused all the same, by its ratio to the range's top.
        ("0.1,1e-7\n0.2,1.5e-2\n", "a wear factor 0.015 mm³/(N·m) is 1500 times UHMWPE's (1e-09 to 1e-05)"),
    ],
)
def test_a_wear_law_in_other_units_at_the_bounds(tmp_path, rows, refused):
    path = _write(tmp_path, "cross_shear,k_mm3_per_Nm\n" + rows)
    if refused is None:
        read_wear_law(path)
        return
    with pytest.raises(FileRowError) as caught:
        read_wear_law(path)
    assert refused in str(caught.value) and caught.value.source == str(path)


def test_the_unit_hints_say_which_way():
    with pytest.raises(FileRowError, match=r"k looks given per N·mm: give it per N·m \(1000 times the figure\)$"):
        read_wear_law_text("0.1,5e-12\n")
    with pytest.raises(FileRowError, match=r"UHMWPE's \(1e-09 to 1e-05\): k looks 1000 times too large \(a unit\?\)$"):
        read_wear_law_text("0.1,5e-3\n0.2,1e-3\n")
    # The smallest positive k is judged (a k of 0 is no unit's), unless the largest is beyond the range.
    with pytest.raises(FileRowError, match="a wear factor 1e-12 mm³/"):
        read_wear_law_text("0.1,0\n0.2,1e-12\n")
    with pytest.raises(FileRowError, match="a wear factor 1e-12 mm³/"):
        read_wear_law_text("0.1,1e-12\n0.2,1e-5\n")


def test_a_missing_wear_law_file_is_named(tmp_path):
    with pytest.raises(FileRowError, match=r"law\.csv: no such wear-law table$"):
        read_wear_law(tmp_path / "law.csv")


def read_wear_law_text(rows: str):
    import tempfile
    from pathlib import Path

    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "law.csv"
        path.write_text("cross_shear,k_mm3_per_Nm\n" + rows)
        return read_wear_law(path)


def test_a_tables_refusals_whole_and_its_columns_as_arrays():
    with pytest.raises(ArgumentError, match=r"^t\.csv: expected a table of CS and k, one k per CS, got shape \(2,\)$"):
        CrossShearLaw(np.array([0.1, 0.2]), np.array([1e-7]), "t.csv")
    with pytest.raises(ArgumentError, match=r"^t\.csv: expected finite CS and k, got shape \(2,\)$"):
        CrossShearLaw(np.array([0.1, 0.2]), np.array([1e-7, NAN]), "t.csv")
    with pytest.raises(
        ArgumentError, match=r"^t\.csv, row 2: expected CS increasing \(the row before has 0\.2\), got 0\.1$"
    ):
        CrossShearLaw(np.array([0.2, 0.1]), np.array([1e-7, 1e-7]), "t.csv")
    with pytest.raises(ArgumentError, match=r"^t\.csv, row 3: expected a wear factor k ≥ 0 in mm³/\(N·m\), got -1\.0$"):
        CrossShearLaw(np.array([0.1, 0.2, 0.3]), np.array([1e-7, 0.0, -1.0]), "t.csv")  # the first negative, not the 0
    law = CrossShearLaw([0.0, 0.5], [1, 2])  # type: ignore[arg-type]
    assert isinstance(law.cross_shear, np.ndarray) and law.k.dtype == float
    assert law.describe().endswith("(2 rows, CS 0 to 0.5, k 1 to 2 mm³/(N·m))")
