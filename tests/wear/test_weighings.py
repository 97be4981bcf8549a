"""hipsim.wear.weighings by hand: a test's weighings read (stations in the order of their first row, soak controls by
name or by column, the loss corrected by the soak control's gain), and each refusal at its boundary with its line
and column."""

from __future__ import annotations

import pytest
from numpy.testing import assert_allclose

from hipsim.exceptions import FileRowError
from hipsim.wear.weighings import read_weighings

HEAD = "cycle,station,mass_mg\n"
ROWS = "0,B,31000\n0,A,30000\n0,soak,29000\n0,soak_B,28000\n5,B,30990\n5,A,29995\n5,soak,29000.5\n5,soak_B,28000.2\n"


def _read(tmp_path, text: str):
    path = tmp_path / "w.csv"
    path.write_text(text)
    return read_weighings(path)


def test_stations_their_soak_controls_and_losses(tmp_path):
    w = _read(tmp_path, "# a test\n" + HEAD + ROWS)
    assert w.source == str(tmp_path / "w.csv")
    assert [(s.station, s.soak_control) for s in w.stations] == [("B", "soak_B"), ("A", "soak")]
    b, a = w.stations
    assert b.cycles.tolist() == [0.0, 5.0] and b.lines.tolist() == [3, 7]
    assert b.mass_mg.tolist() == [31000.0, 30990.0] and b.soak_mg.tolist() == [28000.0, 28000.2]
    assert_allclose(b.loss_mg, [0.0, 10.2], atol=1e-9)  # the cup's 10 mg and its soak control's 0.2 mg gain
    assert_allclose(a.loss_mg, [0.0, 5.5], atol=1e-9)


def test_a_soak_column_with_decimal_commas(tmp_path):
    w = _read(tmp_path, "cycle;station;mass_mg;soak_mg\n0;A;30000;29000\n7;A;29990,5;29000,25\n")
    (a,) = w.stations
    assert a.soak_control == "soak_mg" and a.cycles.tolist() == [0.0, 7.0]
    assert_allclose(a.loss_mg, [0.0, 9.75])


@pytest.mark.parametrize(
    ("text", "message"),
    [
        (HEAD, "w.csv: expected a header cycle, station, mass_mg (soak_mg) and rows"),
        ("cycle,mass_mg\n0,1\n", "line 1: no column station (the header has cycle, mass_mg)"),
        (HEAD + "0,A,3e4x\n", "line 2, column 'mass_mg': expected a number, got '3e4x'"),
        (HEAD + "0,A\n", "line 2, column 'mass_mg': expected a number, got ''"),
        (HEAD + "nan,A,30000\n", "line 2, column 'cycle': expected a finite number, got 'nan'"),
        (HEAD + "0,,30000\n", "line 2, column 'station': no station name"),
        (HEAD + "0, ,30000\n", "line 2, column 'station': no station name"),
        (HEAD + "-1,A,30000\n", "line 2, column 'cycle': cycle -1: a cycle counter is a whole number ≥ 0"),
        (HEAD + "1.5,A,30000\n", "line 2, column 'cycle': cycle 1.5: a cycle counter is a whole number ≥ 0"),
        (HEAD + "0,A,0\n", "line 2, column 'mass_mg': a mass of 0 mg: a cup weighs more than 0"),
        ("cycle,station,mass_mg,soak_mg\n0,A,30000,0\n", "line 2, column 'soak_mg': a mass of 0 mg"),
        (HEAD + "5,A,30000\n5,A,29990\n", "line 3, column 'cycle': station A: cycle 5 after 5 (line 2): weighings out"),
        (
            HEAD + "0,A,1000\n0,soak,900\n5,A,499.9\n5,soak,900\n",
            "line 4, column 'mass_mg': station A: 499.9 mg after 1000 mg at cycle 0: a change larger than the cup",
        ),
        (
            "cycle,station,mass_mg,soak_mg\n0,A,1000,900\n5,A,1000,449\n",
            "line 3, column 'soak_mg': station A: 449 mg after 900 mg",
        ),
        (HEAD + "0,A,1000\n5,A,999\n", "line 2, column 'station': station A has no soak control: add rows of station"),
        (
            HEAD + "0,A,1000\n0,soak,900\n5,A,999\n",
            "line 4, column 'cycle': station A is weighed at cycle 5 and its soak control 'soak' is not",
        ),
        (HEAD + "0,A,1000\n0,soak,900\n", "line 2: station A is weighed once: a wear rate needs at least two stops"),
        (HEAD + "0,soak,900\n5,soak,900\n", "w.csv: no station besides soak controls"),
        (
            "cycle,station,mass_mg,soak_mg\n0,A,1000,900\n5,A,999,\n",
            "line 3, column 'soak_mg': station A has no soak control at this stop: give its soak_mg",
        ),
    ],
)
def test_refusals_name_their_line_and_column(tmp_path, text, message):
    with pytest.raises(FileRowError) as caught:
        _read(tmp_path, text)
    assert message in str(caught.value)
    assert caught.value.source == str(tmp_path / "w.csv") and str(caught.value).startswith(str(tmp_path / "w.csv"))


def test_the_boundaries_that_pass(tmp_path):
    # A change of exactly the lighter reading (1000 → 500 mg) passes; soak_A wins over soak for station A.
    w = _read(tmp_path, HEAD + "0,A,1000\n0,soak,900\n0,soak_A,800\n5,A,500\n5,soak,450\n5,soak_A,800.5\n")
    assert w.stations[0].soak_control == "soak_A" and w.stations[0].loss_mg.tolist() == [0.0, 500.5]
