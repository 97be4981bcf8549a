"""The command line's parser (hipsim.cli.parser): one-line usage errors naming the option, no abbreviations, negative
numbers as values, the table's checks applied to each option, old spellings rewritten, idle options named."""

from __future__ import annotations

import argparse

import pytest

from hipsim.cli.main import build_parser
from hipsim.cli.parser import (
    HipsimParser,
    UsageError,
    apply_table,
    command_parsers,
    idle_option,
    rewrite_aliases,
    undeclared,
)


def small_parser() -> HipsimParser:
    parser = HipsimParser(prog="hipsim")
    commands = parser.add_subparsers(dest="command", parser_class=HipsimParser)
    sub = commands.add_parser("iso-check")
    sub.add_argument("--cutoff", type=float, help="cutoff")
    sub.add_argument("--controller", default="pd")
    sub.add_argument("--weights")
    sub.add_argument("--brand-new", help="not in the table")
    return parser


def test_a_usage_error_is_one_line_naming_the_command_and_the_option():
    parser = small_parser()
    with pytest.raises(UsageError) as caught:
        parser.parse_args(["iso-check", "--cutoff"])
    assert str(caught.value) == "iso-check: argument --cutoff: expected one argument"
    with pytest.raises(UsageError, match="^the following arguments are required|^argument command|invalid choice"):
        parser.parse_args(["nothing"])


def test_no_abbreviation_and_a_negative_number_is_a_value():
    parser = small_parser()
    with pytest.raises(UsageError, match="unrecognized arguments: --control"):
        parser.parse_args(["iso-check", "--control", "2"])
    assert parser.parse_args(["iso-check", "--weights", "-1,1"]).weights == "-1,1"
    assert parser.parse_args(["iso-check", "--weights", "-.5"]).weights == "-.5"


def test_the_table_checks_a_number_as_it_is_read_and_adds_its_unit_to_the_help(capsys):
    parser = small_parser()
    notes = apply_table(parser)
    assert parser.parse_args(["iso-check", "--cutoff", "10"]).cutoff == 10.0
    with pytest.raises(UsageError) as caught:
        parser.parse_args(["iso-check", "--cutoff", "0"])
    assert str(caught.value).startswith("iso-check: --cutoff 0 Hz:")  # "argument --cutoff: " left out
    assert "\n" not in str(caught.value)
    sub = command_parsers(parser)["iso-check"]
    cutoff = next(a for a in sub._actions if "--cutoff" in a.option_strings)
    assert str(cutoff.help).startswith("cutoff [unit: Hz")
    assert notes == [] and capsys.readouterr().err == ""
    assert undeclared(parser) == ["hipsim iso-check --brand-new"]


def test_every_shipped_option_is_declared():
    assert undeclared(build_parser()) == []


def test_an_old_spelling_is_rewritten_with_a_warning(capsys):
    notes: list[str] = []
    words = rewrite_aliases(["torques", "--model=pinocchio", "--rate", "100"], notes)
    assert words == ["torques", "--engine=pinocchio", "--rate", "100"]
    assert notes == ["--model is deprecated in 'hipsim torques': use --engine"]
    assert capsys.readouterr().err == "hipsim: warning: --model is deprecated in 'hipsim torques': use --engine\n"
    assert rewrite_aliases(["report", "--engine", "x"]) == ["report", "--engine", "x"]
    assert rewrite_aliases(["--version"]) == ["--version"] and rewrite_aliases([]) == []
    assert rewrite_aliases(["iso-check", "--model"]) == ["iso-check", "--model"]  # not an alias of that command


def test_an_option_that_would_do_nothing_without_another_is_named():
    assert idle_option(["sweep", "--seed", "3"]) == "sweep: --seed applies to --sample: give --sample, or drop --seed"
    assert idle_option(["sweep", "--seed=3", "--sample=10"]) is None
    assert (
        idle_option(["torques", "--seed", "3"]) is None and idle_option(["--help"]) is None and idle_option([]) is None
    )


def test_a_default_given_as_a_number_is_not_checked():
    parser = HipsimParser(prog="hipsim")
    commands = parser.add_subparsers(dest="command", parser_class=HipsimParser)
    commands.add_parser("iso-check").add_argument("--cutoff", type=float, default=0.0)  # 0 is refused when typed
    apply_table(parser)
    assert parser.parse_args(["iso-check"]).cutoff == 0.0
    assert isinstance(parser, argparse.ArgumentParser)
