"""hipsim.rig.monitoring.reference: the machine the monitor holds fixed and its lever spin, from an identified file."""

from __future__ import annotations

from pathlib import Path

import pytest

import hipsim
from hipsim.exceptions import ArgumentError, ParameterError
from hipsim.rig.identification.identified_file import write_identified_file
from hipsim.rig.monitoring.reference import identified_file, reference

PARAMS = hipsim.load_parameters()


@pytest.mark.parametrize("spin", [True, False])
def test_the_lever_spin_of_an_identified_file(tmp_path, spin):
    path = write_identified_file(tmp_path / "id.toml", PARAMS.replace(lever_mass=1.5), {"lever_spin": spin})
    assert identified_file(path) is spin
    params, lever_spin = reference(path)
    assert lever_spin is spin and params.lever_mass == 1.5 and params.source == str(path)


def test_a_plain_parameter_file_is_refused(tmp_path):
    path = tmp_path / "plain.toml"
    path.write_text(Path(PARAMS.source).read_text())
    with pytest.raises(ParameterError) as refused:
        reference(path)
    assert str(refused.value) == (
        f"{path}: holds no identified values (no [identification] table, no '# Identified by hipsim identify' "
        "header): the monitor holds the machine at identified values; run hipsim identify on a log of the rig first"
    )
    assert refused.value.source == str(path)


def test_parameters_given_are_taken_with_the_lever_spin():
    assert reference(None, PARAMS) == (PARAMS, True)
    with pytest.raises(ArgumentError) as refused:
        reference(None)
    assert str(refused.value) == "path: expected an identified parameter file, or the parameters, got None"
