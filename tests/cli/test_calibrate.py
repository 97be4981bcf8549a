"""The calibrate command's option checks (hipsim.cli.calibrate._check): the output's kind, the prior, logs given
twice, an output that is one of the logs. The calibration through the command line: stations/test_calibration.py."""

from __future__ import annotations

import math
from types import SimpleNamespace

import pytest

from hipsim.cli.calibrate import _check
from hipsim.exceptions import HipsimError


@pytest.fixture
def logs(tmp_path):
    paths = []
    for name in ("a.csv", "b.csv"):
        (tmp_path / name).write_text(f"t\n{name}\n")  # different bytes: two logs
        paths.append(str(tmp_path / name))
    return paths


def options(tmp_path, logs, **given):
    base = dict(out=str(tmp_path / "c.toml"), prior=0.5, json=None, log=[logs[0]], validate=[logs[1]])
    return SimpleNamespace(**(base | given))


def test_good_options_pass(tmp_path, logs):
    _check(options(tmp_path, logs, out=str(tmp_path / "C.TOML"), prior=1e-9, json=str(tmp_path / "c.json")))


@pytest.mark.parametrize(
    ("given", "message"),
    [
        ({"out": "c.csv"}, r"--out c.csv: expected a .toml parameter file"),
        ({"prior": 0.0}, "--prior: expected a positive standard deviation in mm, got 0.0"),
        ({"prior": math.nan}, "--prior"),
    ],
)
def test_bad_options_one_line(tmp_path, logs, given, message):
    with pytest.raises(HipsimError, match=message):
        _check(options(tmp_path, logs, **given))


def test_a_folder_a_log_twice_and_a_log_as_output_are_refused(tmp_path, logs):
    folder = tmp_path / "out.toml"
    folder.mkdir()
    with pytest.raises(HipsimError, match="is a folder; give a .toml file name"):
        _check(options(tmp_path, logs, out=str(folder)))
    with pytest.raises(HipsimError, match="--log/--validate: "):
        _check(options(tmp_path, logs, validate=[logs[0]]))
    with pytest.raises(HipsimError, match="is one of the logs read; give another output file"):
        _check(options(tmp_path, logs, json=logs[1]))
