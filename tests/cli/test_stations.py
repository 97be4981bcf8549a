"""The stations command's own checks (hipsim.cli.stations): the weights, the options that exclude each other, the
table's kind. The command through the command line: stations/test_commands.py."""

from __future__ import annotations

from types import SimpleNamespace

import pytest

from hipsim.cli.stations import _check, _file, parse_weights
from hipsim.exceptions import HipsimError


def test_weights_default_to_one_each_and_one_may_be_zero():
    assert parse_weights(SimpleNamespace(weights=None)) == (1.0, 1.0)
    assert parse_weights(SimpleNamespace(weights="0,2.5")) == (0.0, 2.5)


@pytest.mark.parametrize("text", ["0,0", "-1,2", "1", "1,2,3", "a,b"])
def test_bad_weights_name_the_option(text):
    with pytest.raises(HipsimError, match="--weights"):
        parse_weights(SimpleNamespace(weights=text))


def options(**given):
    return SimpleNamespace(
        **({"sliders": None, "tolerance": None, "control": "2", "draws": 200, "table": None} | given)
    )


@pytest.mark.parametrize(
    ("given", "message"),
    [
        ({"sliders": "log.csv", "tolerance": "x=0.1"}, "give --sliders or --bands, not both"),
        ({"control": "all"}, "--control all applies to --bands"),
        ({"tolerance": "x=0.1", "draws": 0}, "--draws: expected at least 1, got 0"),
        ({"table": "t.txt"}, r"--table t.txt: expected a .csv or .parquet file"),
    ],
)
def test_options_that_do_not_go_together(given, message):
    with pytest.raises(HipsimError, match=message):
        _check(options(**given))


def test_options_that_do():
    _check(options(control="all", tolerance="x=0.1", draws=1, table="t.PARQUET"))


def test_a_band_names_a_file_or_a_spread(tmp_path):
    path = tmp_path / "bands.toml"
    path.write_text("")
    assert _file(str(path)) == str(path)
    assert _file("lever.length_mm=0.1") is None and _file(str(tmp_path / "absent.toml")) is None
