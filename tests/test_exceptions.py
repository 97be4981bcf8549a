"""The errors hipsim raises (hipsim.exceptions): where each names the problem, and messages made safe to print."""

from __future__ import annotations

import numpy as np
import pytest

from hipsim.exceptions import (
    MAX_MESSAGE,
    MAX_QUOTE,
    ArgumentError,
    FileRowError,
    IdentificationError,
    MissingDependencyError,
    OutputError,
    ParameterError,
    PoseError,
    TrajectoryError,
    printable,
)


def test_control_and_format_characters_are_shown_escaped():
    assert printable("a\x00b\nc\x1b[31m") == "a\\x00b\\nc\\x1b[31m"
    assert printable("zero\u200bwidth") == "zero\\u200bwidth"  # a format character (Cf), not ASCII
    assert printable("line\u2028sep") == "line\\u2028sep"  # a line separator (Zl)
    assert printable("tab-free ünïcode ° ±") == "tab-free ünïcode ° ±"  # printable text untouched


def test_a_quote_longer_than_the_limit_keeps_its_start_and_end():
    exact = "x" * MAX_QUOTE
    assert printable(f"got '{exact}'") == f"got '{exact}'"  # at the limit: whole
    longer = "a" * 60 + "m" * (MAX_QUOTE + 1 - 80) + "z" * 20
    assert printable(f"got '{longer}'") == f"got '{'a' * 60}…{'z' * 20}' (101 characters)"
    # an apostrophe inside a word does not open a quote
    words = "the drive's " + "s" * 200 + " screw's end"
    assert printable(words) == words


def test_a_message_longer_than_the_limit_is_cut_in_its_middle():
    assert printable("m" * MAX_MESSAGE) == "m" * MAX_MESSAGE
    text = "h" * 800 + "x" * 101 + "t" * 300  # MAX_MESSAGE + 1 characters: 2/3 kept at the head, 1/4 at the tail
    assert MAX_MESSAGE == 1200
    assert printable(text) == "h" * 800 + " … [101 characters left out] … " + "t" * 300


def test_printable_is_idempotent():
    text = "\x00" * 50 + "'" + "q" * 500 + "'" + "w" * 3000
    once = printable(text)
    assert printable(once) == once


def test_an_errors_str_is_printable():
    assert str(OutputError("out\x00.csv", "exists")) == "out\\x00.csv: exists"


def test_an_argument_error_shows_an_arrays_shape_and_a_scalars_repr():
    error = ArgumentError("q", np.zeros((4, 2)), "shape (N, 3)")
    assert str(error) == "q: expected shape (N, 3), got shape (4, 2)"
    assert (error.name, error.expected) == ("q", "shape (N, 3)")
    assert str(ArgumentError("gain", 0.0, "> 0")) == "gain: expected > 0, got 0.0"
    assert str(ArgumentError("x", np.float64(2.5), "< 1")) == "x: expected < 1, got np.float64(2.5)"  # 0-d: repr
    assert isinstance(error, ValueError)


def test_the_place_names_only_the_known_parts_in_order():
    assert str(ParameterError("bad", key="a.b", source="f.toml")) == "f.toml, key 'a.b': bad"
    assert str(ParameterError("bad")) == "bad"
    assert str(FileRowError("bad", "f.csv", 0, "t_s")) == "f.csv, line 0, column 't_s': bad"  # line 0 is a line
    assert str(TrajectoryError("bad", column="t_s")) == "column 't_s': bad"
    assert str(PoseError("out of reach", 0.25, 3, "f.csv", 12)) == "f.csv, t = 0.25 s, line 12: out of reach"
    pose = PoseError("singular", 1e-7, 0)
    assert str(pose) == "t = 1e-07 s: singular" and pose.reason == "singular" and pose.index == 0
    assert str(IdentificationError("too few", ("a.csv", "b.csv"))) == "a.csv, b.csv: too few"


def test_a_missing_dependency_says_how_to_install_it():
    error = MissingDependencyError("mujoco", "mujoco", "The MuJoCo engine")
    assert str(error) == (
        "The MuJoCo engine needs the optional package 'mujoco' (it is not installed): pip install -U 'hipsim[mujoco]'"
    )
    old = MissingDependencyError("pin", "pinocchio", "x", found="2.7")
    assert "(version 2.7 is too old)" in str(old) and old.found == "2.7"


@pytest.mark.parametrize("kind", [TrajectoryError, ParameterError])
def test_errors_are_hipsim_errors(kind):
    from hipsim.exceptions import HipsimError

    assert issubclass(kind, HipsimError)
