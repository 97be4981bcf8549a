"""The weighings' regression checks itself (hipsim.wear.weighings_checks): each gate at its boundary on hand-made
weighings, and through ``hipsim wear --weighings`` (a finding kept in the notes, one cup twice refused); the option
table's warnings kept in a page's provenance."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from hipsim.cli.main import main
from hipsim.wear.gravimetric import gravimetry, line_fit, station_rate
from hipsim.wear.weighings import StationWeighings, Weighings
from hipsim.wear.weighings_checks import (
    CUP_MASS_RANGE_MG,
    NEIGHBOUR_MIN_DOF,
    RATE_MAX_MM3_PER_MC,
    check_gravimetry,
    duplicate_stations,
    mass_findings,
    rate_findings,
    residual_findings,
    swap_findings,
)

CYCLES = np.array([0, 500_000, 1_000_000, 1_500_000, 2_000_000])
WOBBLE = np.array([0.0, 0.1, -0.1, 0.05, -0.05])  # a balance's scatter in [mg]


def _station(name, rate_mg_per_Mc=10.0, start=40_000.0, wobble=WOBBLE, soak=None, cycles=CYCLES):
    mass = start - rate_mg_per_Mc * cycles / 1e6 + wobble[: cycles.size]
    soak_mg = np.full(cycles.size, 39_000.0) if soak is None else np.asarray(soak, dtype=float)
    return StationWeighings(name, "soak", cycles, mass, soak_mg, np.arange(cycles.size) + 2)


def _weighings(*stations):
    return Weighings("hand-made", tuple(stations))


def test_a_right_test_passes_every_gate():
    w = _weighings(_station("1"), _station("2", 12.0, 41_000.0, -WOBBLE), _station("3", 11.0, 39_500.0, WOBBLE[::-1]))
    check = check_gravimetry(w, gravimetry(w), balance_noise_mg=0.1)
    assert check.plausible, check.findings
    assert duplicate_stations(w) is None


def test_residuals_against_a_stated_balance_noise_at_the_boundary():
    rate = station_rate(_station("1"), 1.0)
    s = line_fit(CYCLES / 1e6, np.array(rate.loss_mg)).s
    ratio = s / (math.sqrt(2.0) * 0.01)  # a loss is two readings: √2 times one reading's noise
    assert residual_findings([rate], 0.01, factor=ratio * (1 + 1e-9)) is None
    found = residual_findings([rate], 0.01, factor=ratio * (1 - 1e-9))
    assert found and "station 1" in found and "√2 × the balance noise 0.01 mg" in found


EIGHT = np.arange(8) * 500_000  # 8 stops: NEIGHBOUR_MIN_DOF = 6 degrees of freedom
WOBBLE8 = np.array([0.0, 0.1, -0.1, 0.05, -0.05, 0.08, -0.02, 0.03])


def test_without_a_stated_noise_a_station_is_held_to_the_others():
    def rate(name, factor, cycles=EIGHT):
        return station_rate(_station(name, wobble=WOBBLE8 * factor, cycles=cycles), 1.0)

    rates = [rate("1", 1.0), rate("2", 1.0), rate("3", 10.0)]
    assert NEIGHBOUR_MIN_DOF == 6 and rates[0].dof == NEIGHBOUR_MIN_DOF
    found = residual_findings(rates)
    assert found and "station 3" in found and "station 1 " not in found and "other stations' median" in found
    assert residual_findings(rates[:1]) is None  # one station alone: nothing to hold it to
    # 7 stops (5 degrees of freedom): too few to hold stations to each other
    assert residual_findings([rate(n, f, EIGHT[:7]) for n, f in (("1", 1.0), ("2", 1.0), ("3", 10.0))]) is None
    two = [rate("1", 3.0), rates[0]]
    assert residual_findings(two, factor=3.0 * (1 + 1e-9)) is None  # 3 times its neighbour's scatter passes
    assert residual_findings(two, factor=3.0 * (1 - 1e-9))


def test_a_negative_rate_names_the_soak_control():
    zero = station_rate(_station("1", 0.0, wobble=np.zeros(2), cycles=CYCLES[:2]), 1.0)
    assert zero.rate_mg_per_Mc == 0.0 and rate_findings(zero) is None  # 0 passes
    gaining = station_rate(_station("1", -1e-3, wobble=np.zeros(2), cycles=CYCLES[:2]), 1.0)
    found = rate_findings(gaining)
    assert found and "below 0" in found and "soak control's sign" in found
    # the cup and its soak control swapped: the soak control loses mass, the cup gains
    right = _station("1", soak=39_000.0 + 0.4 * CYCLES / 1e6)
    swapped = StationWeighings("1", "soak", CYCLES, right.soak_mg, right.mass_mg, right.lines)
    assert "swapped" in str(rate_findings(station_rate(swapped, 1.0)))


def test_a_rate_beyond_a_hip_cups_at_the_boundary():
    rate = station_rate(_station("1", RATE_MAX_MM3_PER_MC, wobble=np.zeros(5)), 1.0)
    assert rate_findings(rate, rate.rate_mm3_per_Mc) is None
    found = rate_findings(rate, rate.rate_mm3_per_Mc * (1 - 1e-9))
    assert found and "µg" in found


def test_a_mass_outside_a_cups_names_the_unit():
    low, high = CUP_MASS_RANGE_MG
    assert mass_findings(_station("1", 0.0, low, np.zeros(5))) is None
    assert "in g, not mg" in str(mass_findings(_station("1", 0.0, low * (1 - 1e-9), np.zeros(5))))
    assert mass_findings(_station("1", 0.0, high, np.zeros(5), soak=np.full(5, high))) is None
    assert "in µg, not mg" in str(
        mass_findings(_station("1", 0.0, 40_000.0, np.zeros(5), soak=np.full(5, high * 1.01)))
    )


def test_two_stations_swapped_at_a_stop_are_named():
    a, b = _station("1"), _station("2", 12.0, 40_600.0, -WOBBLE)
    ma, mb = a.mass_mg.copy(), b.mass_mg.copy()
    ma[2], mb[2] = b.mass_mg[2], a.mass_mg[2]
    w = _weighings(
        StationWeighings("1", "soak", CYCLES, ma, a.soak_mg, a.lines),
        StationWeighings("2", "soak", CYCLES, mb, b.soak_mg, b.lines),
    )
    assert swap_findings(w) == ("stations 1 and 2 look swapped at cycle 1000000",)
    assert swap_findings(_weighings(a, b)) == ()
    check = check_gravimetry(w, gravimetry(w))
    assert not check.plausible and any("look swapped" in f for f in check.findings)


def test_a_station_swapped_with_its_soak_control_at_a_stop_is_named():
    a = _station("1")
    mass, soak = a.mass_mg.copy(), a.soak_mg.copy()
    mass[3], soak[3] = a.soak_mg[3], a.mass_mg[3]
    found = swap_findings(_weighings(StationWeighings("1", "soak", CYCLES, mass, soak, a.lines)))
    assert found == ("station 1 and its soak control 'soak' look swapped at cycle 1500000 (line 5)",)


def test_one_cup_given_twice_is_found():
    a = _station("1")
    assert "one cup given twice" in str(duplicate_stations(_weighings(a, _station("2"))))
    assert duplicate_stations(_weighings(a, _station("2", wobble=WOBBLE + np.array([0, 0, 0, 0, 1e-3])))) is None


def test_a_swap_at_the_first_stop_and_on_three_stops_with_a_small_residual():
    """Three stops (the fewest with a residual), the exchange at the first stop, residuals under 1 mg²: still named."""
    cycles = CYCLES[:3]
    # Station 1 truly 1000, 990, 980 mg and station 2 1000.3, 989.3, 978.3: their first readings exchanged.
    a = StationWeighings("1", "soak", cycles, np.array([1000.3, 990.0, 980.0]), np.full(3, 900.0), np.array([2, 4, 6]))
    b = StationWeighings("2", "soak", cycles, np.array([1000.0, 989.3, 978.3]), np.full(3, 900.0), np.array([3, 5, 7]))
    assert swap_findings(_weighings(a, b)) == ("stations 1 and 2 look swapped at cycle 0",)
    mass, soak = np.array([1000.0, 990.0, 980.0]), np.array([999.8, 999.5, 999.5])
    mass[0], soak[0] = soak[0], mass[0]
    cup = StationWeighings("1", "soak", cycles, mass, soak, np.array([2, 4, 6]))
    assert swap_findings(_weighings(cup)) == ("station 1 and its soak control 'soak' look swapped at cycle 0 (line 2)",)
    two = StationWeighings("1", "soak", cycles[:2], mass[:2], soak[:2], np.array([2, 4]))
    assert swap_findings(_weighings(two)) == ()  # two stops: no residual to remove


def _sse(cycles, loss):
    fitted = np.polyval(np.polyfit(cycles / 1e6, loss, 1), cycles / 1e6)
    return float(np.sum((loss - fitted) ** 2))


def test_an_exchange_that_removes_less_than_half_the_residual_is_not_named():
    """Station 2's scatter at stop 2 is partly station 1's: exchanging them removes some of the two lines' squared
    residual (worked out here with numpy's polyfit), but less than half: no swap named."""
    a = _station("1", wobble=np.array([0.0, 0.17, 0.02, -0.29, -0.03]))
    b = _station("2", wobble=np.array([0.0, -0.28, 0.05, -0.11, -0.21]))
    base = _sse(CYCLES, a.loss_mg) + _sse(CYCLES, b.loss_mg)
    exchanged = []
    for k in range(CYCLES.size):
        ma, mb = a.mass_mg.copy(), b.mass_mg.copy()
        ma[k], mb[k] = b.mass_mg[k], a.mass_mg[k]
        exchanged.append(_sse(CYCLES, ma[0] - ma) + _sse(CYCLES, mb[0] - mb))  # the soak controls do not change
    assert 0.5 * base < min(exchanged) < 0.8 * base  # at stop 3: 0.114 of 0.154 mg²
    assert swap_findings(_weighings(a, b)) == ()


def test_a_rate_below_zero_is_judged_by_its_intervals_upper_end():
    rate = station_rate(_station("1", -1.0, wobble=np.array([0.0, 1.0, -1.0, 1.0, 0.0])), 1.0)
    assert rate.rate_mm3_per_Mc < 0 < rate.ci95_mm3_per_Mc[1] and rate_findings(rate) is None
    high = rate_findings(station_rate(_station("1", 400.0, wobble=np.zeros(5)), 1.0))
    assert high == (
        "station 1: steady rate 400 mm³/Mc, beyond 300 mm³/Mc (hip cups wear under 150): masses in µg rather than mg, "
        "or cups swapped at a stop?"
    )


def test_the_residual_gate_in_words_and_a_station_of_three_stops_held_to_a_stated_noise():
    rate = station_rate(_station("1", wobble=np.array([0.0, 3.0, -3.0]), cycles=CYCLES[:3]), 1.0)
    assert rate.dof == 1
    found = residual_findings([rate], 0.01)
    assert found is not None and found.startswith("residuals beyond 3 times") and " mg" in found
    assert found.endswith(
        "against √2 × the balance noise 0.01 mg (a stop misread, cups mixed up, or a balance out of its calibration?)"
    )


def test_every_gate_is_collected_in_one_check():
    """A mass in g, a scatter 3 times the stated noise, a gaining cup, a swap: each named, in that order."""
    grams = _station("g", 0.0, 900.0, np.zeros(5))  # 900 mg: grams in the mg column
    noisy = _station("n", wobble=np.array([0.0, 2.0, -2.0, 2.0, -2.0]))
    gaining = _station("up", -5.0, wobble=np.zeros(5))
    mass, soak = noisy.mass_mg.copy(), noisy.soak_mg.copy()
    w = _weighings(grams, noisy, gaining)
    result = gravimetry(w, 1.0)
    check = check_gravimetry(w, result, balance_noise_mg=0.1)
    assert check.fit == "weighings" and not check.plausible
    assert [f.split(" ")[0:2] for f in check.findings] == [
        ["station", "g"],
        ["residuals", "beyond"],
        ["station", "up:"],
    ]
    assert "station n" in check.findings[1] and "0.1 mg" in check.findings[1]
    assert check_gravimetry(w, result).findings[1].startswith("station up:")  # no stated noise: 5 stops are too few
    mass[2], soak[2] = soak[2], mass[2]
    swapped = _weighings(StationWeighings("s", "soak", CYCLES, mass, soak, noisy.lines))
    assert check_gravimetry(swapped, gravimetry(swapped, 1.0)).findings[-1].startswith("station s and its soak")


def test_one_cup_twice_names_the_first_lines():
    a = _station("1")
    b = StationWeighings("2", "soak", CYCLES, a.mass_mg.copy(), a.soak_mg, a.lines + 10)
    assert duplicate_stations(_weighings(a, b)) == (
        "stations 1 and 2 have the same masses at every stop (lines 2 and 12 on): one cup given twice counts its "
        "stops twice; give each cup once"
    )


ROWS = "cycle,station,mass_mg\n" + "".join(
    f"{c},{name},{m:.2f}\n{c},soak,{29000 + 0.4 * c / 1e6:.2f}\n" if name == "1" else f"{c},{name},{m:.2f}\n"
    for c in (0, 500_000, 1_000_000, 1_500_000)
    for name, m in (("1", 30_000 - 20 * c / 1e6), ("2", 31_000 - 22 * c / 1e6))
)


def _wear(capsys, tmp_path, text, *words):
    (tmp_path / "w.csv").write_text(text)
    status = main(
        ["wear", "--cup-grid", "12x24", "--weighings", str(tmp_path / "w.csv"), "--out", str(tmp_path / "t.csv")]
        + [*words, "--summary-format", "json"]
    )
    captured = capsys.readouterr()
    return status, captured.out, captured.err


def test_the_command_keeps_a_finding_in_its_notes_and_refuses_one_cup_twice(tmp_path, capsys):
    status, out, err = _wear(capsys, tmp_path, ROWS, "--balance-noise", "0.05")
    assert status in (0, 1), err  # 1: the two stations' rates differ (the verdict), not a refusal
    assert not [n for n in json.loads(out)["notes"] if "self-check" in n]
    slip = ROWS.replace("500000,2,30989.00", "500000,2,30999.90")  # a stop misread by 11 mg
    status, out, err = _wear(capsys, tmp_path, slip, "--balance-noise", "0.05")
    assert status in (0, 1), err
    assert any("self-check: IMPLAUSIBLE: residuals beyond 3 times" in n for n in json.loads(out)["notes"]), out
    twice = ROWS.replace(",31000.00", ",30000.00").replace(",30989.00", ",29990.00").replace(",30978.00", ",29980.00")
    twice = twice.replace(",30967.00", ",29970.00")
    (tmp_path / "t.csv").unlink()
    status, out, err = _wear(capsys, tmp_path, twice)
    assert status == 2 and "one cup given twice" in err and len(err.strip().splitlines()) == 1
    assert not (tmp_path / "t.csv").exists()


@pytest.mark.parametrize("value", ["0", "-0.1", "101"])
def test_balance_noise_outside_its_range_is_refused(tmp_path, capsys, value):
    status, _, err = _wear(capsys, tmp_path, ROWS, f"--balance-noise={value}")
    assert status == 2 and "--balance-noise" in err and "mg" in err and len(err.strip().splitlines()) == 1


def test_balance_noise_without_weighings_is_refused(capsys):
    assert main(["wear", "--balance-noise", "0.05"]) == 2
    assert "--balance-noise applies to --weighings or --test" in capsys.readouterr().err


def test_an_option_warning_is_kept_in_the_pages_provenance(tmp_path, capsys):
    report = tmp_path / "report"
    status = main(
        ["wear", "--cup-grid", "12x24", "--head-diameter", "14", "--out", str(tmp_path / "t.csv")]
        + ["--report", str(report), "--summary-format", "json"]
    )
    out, err = capsys.readouterr()
    assert status == 0, err
    document = json.loads((report / "wear.json").read_text())
    # one run's verdict, NOT MADE (not rated), the same record in wear.json and the JSON printed; the page says NOT RATED
    assert document["verdict"] == json.loads(out)["verdict"] and document["verdict"]["level"] == "NOT MADE"
    assert (
        list(document)[:2] == ["verdict", "provenance"] and "– NOT RATED</span>" in (report / "index.html").read_text()
    )
    warnings = document["provenance"]["warnings"]
    assert len(warnings) == 1 and "--head-diameter 14" in warnings[0] and warnings[0] in err
    assert "Made on values the command line was warned of" in (report / "index.html").read_text()
