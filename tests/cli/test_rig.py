"""The rig commands' own checks (hipsim.cli.rig): the cutoff, the angle tolerance and torque constant, an output
that is one of the inputs. The commands through the command line: tests/test_cli.py and rig/test_compare.py."""

from __future__ import annotations

import math
from types import SimpleNamespace

import pytest

from hipsim.cli.rig import DEFAULT_CUTOFF, _check_log_options, _cutoff, _not_an_input
from hipsim.exceptions import ArgumentError, OutputError


def test_the_cutoff_none_when_not_filtered_and_positive_otherwise():
    assert _cutoff(SimpleNamespace(no_filter=True, cutoff=20.0)) is None
    assert _cutoff(SimpleNamespace(no_filter=False, cutoff=None)) is None
    assert _cutoff(SimpleNamespace(no_filter=False, cutoff=1e-9)) == 1e-9
    assert DEFAULT_CUTOFF == 20.0
    for bad in (0.0, -1.0, math.inf, math.nan):
        with pytest.raises(ArgumentError, match="--cutoff"):
            _cutoff(SimpleNamespace(no_filter=False, cutoff=bad))


@pytest.mark.parametrize(
    ("tolerance", "constant", "option"),
    [(0.0, None, "--angle-tolerance"), (math.nan, None, "--angle-tolerance"), (0.5, 0.0, "--torque-constant")],
)
def test_the_log_options_must_be_positive(tolerance, constant, option):
    with pytest.raises(ArgumentError, match=option):
        _check_log_options(SimpleNamespace(tolerance=tolerance, torque_constant=constant))


def test_positive_log_options_pass():
    _check_log_options(SimpleNamespace(tolerance=1e-6, torque_constant=None))
    _check_log_options(SimpleNamespace(tolerance=0.5, torque_constant=0.1))


def test_an_output_that_is_an_input_is_refused(tmp_path):
    log = tmp_path / "log.csv"
    log.write_text("t\n")
    with pytest.raises(OutputError, match=r"is the input .*log.csv itself \(--out\)"):
        _not_an_input(str(tmp_path / "." / "log.csv"), ["", str(log)], "--out")
    _not_an_input(str(tmp_path / "new.csv"), [str(log)], "--out")  # not there yet: another file
