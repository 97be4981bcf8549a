"""One option of the command line (hipsim.cli.options): its range in words, and a typed number judged against the
hard range (refused) and the plausible range (warned of) at each edge, open or closed; options made here by hand.
The shipped table's options and their slips: test_option_table_slips.py."""

from __future__ import annotations

import math

import pytest

from hipsim.cli.options import Option, judge, likely_slip, read_number

CUTOFF = Option("--cutoff", "the filter's cutoff", "Hz", hard=(0.0, 1e5), open_low=True, plausible=(1.0, 100.0))
HEAD = Option(
    "--head", "the head's diameter", "mm", hard=(1.0, 100.0), plausible=(22.0, 60.0), typical="heads are 22–60 mm"
)
COUNT = Option("--cycles", "cycles run", "", kind="integer", hard=(1.0, math.inf), unit_slips=False)
RANGE = Option(
    "--range", "a range", "deg", kind="numbers", separator=":", count=2, hard=(-90.0, 90.0), plausible=(-45.0, 45.0)
)


def test_the_range_in_words_open_or_closed_with_its_unit():
    assert CUTOFF.range_text() == "above 0 and at most 100000 Hz"
    assert HEAD.range_text() == "at least 1 and at most 100 mm"
    assert COUNT.range_text() == "at least 1"
    assert Option("--x", "x", "1", hard=(-math.inf, 5.0), open_high=True).range_text() == "below 5"
    assert Option("--x", "x").range_text() == "any value"
    assert CUTOFF.help_suffix() == " [unit: Hz; typical 1 to 100]"
    assert Option("--x", "x", "1").help_suffix() == " [unit: dimensionless]" and COUNT.help_suffix() == ""


@pytest.mark.parametrize(
    ("option", "value", "refused", "warned"),
    [
        (CUTOFF, 0.0, True, False),  # open: the edge itself is refused
        (CUTOFF, 1e-300, False, True),
        (CUTOFF, 1e5, False, True),  # closed: the edge is in
        (CUTOFF, 1e5 * (1 + 1e-15), True, False),
        (CUTOFF, 1.0, False, False),  # the plausible edges are plausible
        (CUTOFF, 100.0, False, False),
        (CUTOFF, math.nan, True, False),
        (CUTOFF, math.inf, True, False),
        (HEAD, 1.0, False, True),
        (HEAD, 0.999, True, False),
    ],
)
def test_each_edge_of_the_two_ranges(option, value, refused, warned):
    verdict = judge(option, value)
    assert (verdict.refusal is not None, verdict.warning is not None) == (refused, warned)


def test_a_refusal_names_option_value_unit_range_and_the_likely_slip():
    assert judge(HEAD, 0.028).refusal == (
        "--head 0.028 mm: the head's diameter must be at least 1 and at most 100 mm; in metres?; heads are 22–60 mm"
    )
    assert judge(HEAD, 80.0).warning == "--head 80 mm: unusual; heads are 22–60 mm"
    assert judge(CUTOFF, 500.0).warning == "--cutoff 500 Hz: in rad/s? typical values are 1 to 100 Hz"  # 79.6 Hz
    assert judge(CUTOFF, 0.5).warning == "--cutoff 0.5 Hz: unusual; typical values are 1 to 100 Hz"  # no slip fits
    assert judge(CUTOFF, 0.02).warning == "--cutoff 0.02 Hz: in kHz? typical values are 1 to 100 Hz"


def test_a_special_value_is_accepted_without_a_word():
    period = Option("--log-period", "the period", "s", hard=(0.1, 100.0), plausible=(0.5, 2.0), special=(0.0,))
    assert judge(period, 0.0).refusal is None and judge(period, 0.0).warning is None
    assert judge(period, 0.05).refusal is not None


def test_the_likely_slip_tries_the_options_own_then_its_units_then_a_prefix():
    own = Option("--k", "k", "mm", plausible=(1.0, 2.0), slips=((1e3, "per µm"),))
    assert likely_slip(own, 1500.0) == "per µm?"  # its own slip first (the unit's "in µm" has the same factor)
    assert likely_slip(HEAD, 0.03) == "in metres?"
    bare = Option("--q", "q", "kg", plausible=(1.0, 2.0))
    assert likely_slip(bare, 1500.0) == "1000 times the usual: a unit slip?"
    assert likely_slip(bare, 0.0) is None and likely_slip(bare, 7.0) is None
    assert likely_slip(Option("--q", "q", "Hz", plausible=(1.0, 2.0), unit_slips=False), 1500.0) == (
        "1000 times the usual: a unit slip?"
    )


def test_a_whole_number_and_what_is_not_one():
    assert read_number(COUNT, "1e6") == ([1e6], [], None)
    for text in ("0.5", "nan", "1_0", "ten"):
        values, _, refusal = read_number(COUNT, text)
        assert values == [] and refusal == f"--cycles '{text}': expected a whole number in no unit"


def test_a_list_names_itself_then_the_value_in_it():
    assert read_number(RANGE, "-30:30") == ([-30.0, 30.0], [], None)
    values, warnings, refusal = read_number(RANGE, "-60:30")
    assert refusal is None and warnings == ["--range '-60:30': -60 deg: unusual; typical values are -45 to 45 deg"]
    assert (
        read_number(RANGE, "-100:30")[2]
        == "--range '-100:30': -100 deg: a range must be at least -90 and at most 90 deg"
    )
    assert read_number(RANGE, "1:2:3")[2] == "--range '1:2:3': expected N:N in deg"


def test_the_words_after_the_tail_are_the_commands_own():
    law = Option("--wear-law", "k", "mm³/(N·m)", hard=(0.0, math.inf), open_low=True, tail=":")
    assert read_number(law, "8e-8:local") == ([8e-8], [], None)
    assert str(read_number(law, "0:local")[2]).startswith("--wear-law 0 mm³/(N·m): k must be above 0")
