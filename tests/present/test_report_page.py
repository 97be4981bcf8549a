"""The report page's own text (hipsim.present.report_page): the drive's verdict block, each check's sentence and
margin, the parameter rows with their origin and uncertainty, inputs as written. The whole page: present/test_report.py."""

from __future__ import annotations

import math
from types import SimpleNamespace
from typing import Any, cast

import pytest

import hipsim
from hipsim.design.checks import Check, _check, checks_verdict
from hipsim.design.demand import Duty
from hipsim.design.sizing import ModuleSizing, Sizing
from hipsim.machine.drive_parts import SizingRules
from hipsim.present import report_page as page
from hipsim.present.provenance import IdentifiedValue, InputFile, ParameterOrigin
from hipsim.records import Level

FILE = InputFile("parameters", "fit.toml", "0" * 64, 1)


def test_a_prior_held_parameter_is_marked_with_its_deviation():
    params = hipsim.load_parameters().replace(hip_mu=0.0557)
    origin = ParameterOrigin(
        InputFile("parameters", "fit.toml", "0" * 64, 1),
        "identified",
        held=(("friction.hip_mu", "not determined by these logs: near its prior (0.0557 ± 0.031)"),),
    )
    row = next(r for r in page._parameter_rows(params, origin) if r["cells"][0] == "friction.hip_mu")
    assert row["cells"][1] == "0.056 ± 0.031", row
    assert row["cells"][3].startswith("prior-held (not determined by these logs")
    assert "start value" not in row["cells"][3]


@pytest.mark.parametrize(
    ("margin", "text"), [(None, "—"), (-math.inf, "−∞ %"), (0.278, "+27.8 %"), (-0.05, "−5.0 %"), (0.0, "+0.0 %")]
)
def test_a_margin_in_percent_with_a_true_minus(margin, text):
    assert page._margin(Check(1, "s1_rms", 1.0, 1.0, margin, True)) == text


def test_a_checks_sentence_names_its_bound_and_its_module():
    check = Check(2, "s1_rms", 216.6, 300.0, 0.278, True)
    assert page._check_sentence(check) == (
        "RMS torque under the S1 curve at the mean speed, LN2: 216.6 N·mm against ≤ 300.0 N·mm (margin +27.8 %)"
    )
    beyond = Check(3, "peak_curve", 900.0, 0.0, -math.inf, False, detail="beyond the curve's end")
    assert page._check_sentence(beyond) == (
        "torque under the peak curve (worst point), LN3: beyond the limit (beyond the curve's end)"
    )


def report_verdict(size: Any) -> page.Verdict:
    """The page's block of the drive's verdict on ``size``'s checks, as write_report makes it."""
    name = "the drive" if size.drive is None else size.drive.name
    return page.report_block(size, checks_verdict(size.checks, name))


def sizing(checks, binding=None, drive=None):
    modules = [
        SimpleNamespace(module=1, tau_peak_Nmm=400.0, tau_rms_Nmm=100.0, speed_peak_rpm=3000.0),
        SimpleNamespace(module=2, tau_peak_Nmm=500.0, tau_rms_Nmm=90.0, speed_peak_rpm=3500.0),
        SimpleNamespace(module=3, tau_peak_Nmm=450.0, tau_rms_Nmm=120.0, speed_peak_rpm=2000.0),
    ]
    return SimpleNamespace(checks=checks, modules=modules, binding=binding, drive=drive)


def test_not_rated_names_the_largest_demand_of_each_kind_by_module():
    verdict = report_verdict(sizing([Check(1, "s1_rms", 100.0, None, None, None)]))
    assert (verdict.state, verdict.word) == ("open", "NOT RATED")
    assert verdict.lines[1] == (
        "The cycle asks at most 500.0 N·mm peak (LN2), 120.0 N·mm RMS (LN3) and 3,500 rpm (LN2) at the screw shafts."
    )


def test_pass_and_fail_count_the_checks_made_and_name_the_binding_one():
    ok = Check(1, "s1_rms", 216.6, 300.0, 0.278, True)
    tight = Check(2, "s1_rms", 290.0, 300.0, 1 / 30, True)
    missing = Check(3, "max_speed", None, None, None, None)
    drive = SimpleNamespace(name="M + S")
    passed = report_verdict(sizing([ok, tight, missing], binding=tight, drive=drive))
    assert (passed.state, passed.word) == ("pass", "PASS")
    assert passed.lines[0] == "M + S passes all 2 rating checks made; 1 not made for want of data."
    assert passed.lines[1].startswith("Binding: RMS torque under the S1 curve at the mean speed, LN2: 290.0 N·mm")
    over = Check(2, "s1_rms", 330.0, 300.0, -0.1, False)
    failed = report_verdict(sizing([ok, over, missing], binding=over))  # a check not made is no failure
    assert (failed.state, failed.word) == ("fail", "FAIL")
    assert failed.lines == (
        "the drive fails 1 of the 2 rating checks made; 1 not made for want of data.",
        "Worst: RMS torque under the S1 curve at the mean speed, LN2: 330.0 N·mm against ≤ 300.0 N·mm (margin −10.0 %).",
    )


def test_the_check_rows_mark_the_binding_one_and_the_unchecked():
    ok = Check(1, "s1_rms", 216.6, 300.0, 0.278, True)
    missing = Check(3, "max_speed", 10.0, None, None, None, detail="no top speed")
    size: Any = SimpleNamespace(checks=[ok, missing], binding=ok)
    rows = page._check_rows(size)
    assert [r["css"] for r in rows] == ["binding", "unchecked"]
    assert rows[0]["cells"][3] == "≤ 300.0 N·mm" and rows[0]["cells"][5] == "pass"
    assert rows[1]["cells"][3] == "—" and rows[1]["cells"][5] == "not checked" and rows[1]["cells"][6] == "no top speed"


def test_inputs_as_written_when_short():
    assert page._input_value(0.0557) == "0.0557"
    assert page._input_value(328) == "328"
    assert page._input_value(0.123456789) == page._input_value(0.123456789)  # 11 characters: to 4 figures
    assert page._input_value(0.123456789) != "0.123456789"
    assert page._input_value(True) == "true" and page._input_value("x") == '"x"'
    assert page._input_value([1.5, [2, 3]]) == "[1.5, [2, 3]]"


def test_a_long_combination_keeps_three_terms_and_counts_the_rest():
    assert page._shorter("a + b − c") == "a + b − c"
    assert page._shorter("a + b − c + d") == "a + b − c + d"  # three terms after the first: all kept
    assert page._shorter("a + b − c + d + e + f") == "a + b − c + d … (2 more)"


def test_an_inertias_identified_components_carry_their_deviation():
    assert page._inertia_text([1.0, 2.0, 3.0], {(1, 1): 0.5}) == "[1.0, 2.00 ± 0.50, 3.0]"
    matrix = [[1.0, 0.25, 0.0], [0.25, 2.0, 0.0], [0.0, 0.0, 3.0]]
    text = page._inertia_text(matrix, {(0, 1): 0.11})  # xy: both off-diagonal cells
    assert text == "[[1.0, 0.25 ± 0.11, 0.0], [0.25 ± 0.11, 2.0, 0.0], [0.0, 0.0, 3.0]]"


def test_a_held_reason_reads_the_posterior_deviation():
    origin = ParameterOrigin(FILE, "identified", held=(("a.b", "near its prior (1 ± 2.5e-3)"), ("c.d", "no effect")))
    assert page._held_reason(origin, "a.b") == ("prior-held (near its prior (1 ± 2.5e-3))", 2.5e-3)
    assert page._held_reason(origin, "c.d") == ("prior-held (no effect)", None)
    assert page._held_reason(origin, "e.f") is None


def test_an_identified_value_and_its_combination_in_the_rows():
    params = hipsim.load_parameters()
    origin = ParameterOrigin(
        FILE,
        "identified",
        identified=(
            IdentifiedValue("lever.mass_kg", "m_l", 0.9, 0.01, "kg"),
            IdentifiedValue("slider.mass_kg", "m_L", 2.5, 0.02, "kg", "m_L + 0.5 m_l + x + y + z"),
        ),
    )
    rows = {r["cells"][0]: r for r in page._parameter_rows(params, origin)}
    assert rows["lever.mass_kg"]["css"] == "identified" and "±" in rows["lever.mass_kg"]["cells"][1]
    how = rows["slider.mass_kg"]["cells"][3]
    assert how.startswith("identified as m_L + 0.5 m_l + x + y … (1 more) = 2.500 ± 0.020 kg (this value")
    assert rows["lever.length_mm"]["css"] == "" and rows["lever.length_mm"]["cells"][3] == "start value"


def _module(i: int, peak_Nmm: float, rms_Nmm: float, speed_rpm: float) -> ModuleSizing:
    return ModuleSizing(i, peak_Nmm, rms_Nmm, speed_rpm, 0.5 * speed_rpm, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 10.0)


def _sizing(checks: tuple[Check, ...]) -> Sizing:
    modules = (_module(1, 431.1, 216.6, 950.0), _module(2, 500.0, 100.0, 40.0), _module(3, 20.0, 10.0, 30.0))
    return Sizing(modules, None, checks, None, SizingRules(), cast(Duty, None))  # the block reads no duty


MISSING = Check(2, "max_speed", None, None, None, None, "no top speed given")


def test_a_check_at_its_limit_passes_and_binds():
    size = _sizing((_check(1, "peak_curve", 300.0, 300.0), _check(2, "s1_rms", 200.0, 250.0), MISSING))
    block = page.report_block(size, checks_verdict(size.checks))
    assert (block.word, block.state, block.symbol) == ("PASS", "pass", "✔")
    assert block.lines == (
        "the drive passes all 2 rating checks made; 1 not made for want of data.",
        "Binding: torque under the peak curve (worst point), LN1: 300.0 N·mm against ≤ 300.0 N·mm (margin +0.0 %).",
    )


def test_a_check_beyond_its_limit_fails_and_is_named_worst():
    size = _sizing((_check(1, "peak_curve", 303.0, 300.0), _check(2, "s1_rms", 200.0, 250.0)))
    verdict = checks_verdict(size.checks)
    block = page.report_block(size, verdict)
    assert verdict.level == Level.FAIL and (block.word, block.state, block.symbol) == ("FAIL", "fail", "✘")
    assert block.lines[0] == "the drive fails 1 of the 2 rating checks made."
    assert block.lines[1] == (
        "Worst: torque under the peak curve (worst point), LN1: 303.0 N·mm against ≤ 300.0 N·mm (margin −1.0 %)."
    )


def test_no_check_made_is_not_rated_with_what_the_cycle_asks():
    size = _sizing((MISSING,))
    verdict = checks_verdict(size.checks)
    block = page.report_block(size, verdict)
    assert verdict.level == Level.NOT_MADE and (block.word, block.state, block.symbol) == ("NOT RATED", "open", "–")
    assert block.lines[1] == (
        "The cycle asks at most 500.0 N·mm peak (LN2), 216.6 N·mm RMS (LN1) and 950.0 rpm (LN1) at the screw shafts."
    )
