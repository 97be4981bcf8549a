"""Plausible ranges of the parameter keys: a value outside loads with a warning naming the key, the value and the range."""

import re
import warnings

import pytest

import hipsim
from hipsim.cli.main import main
from hipsim.machine.parameters import ParameterWarning, default_parameters_path, implausible, implausible_message
from hipsim.machine.schema import SCHEMA, plausible_ranges

#: The issue's absurd values, each written into a copy of the published file by the test: (key line, absurd line, key, range).
ABSURD = [
    ("hip_mu = 0.095", "hip_mu = 95", "friction.hip_mu", "95", "0 to 1"),
    ("mass_kg = 1.43", "mass_kg = 1430.0", "lever.mass_kg", "1430 kg", "0.1 to 15 kg"),
    ("lead_mm = 10.0", "lead_mm = 10000.0", "screw.lead_mm", "10000 mm", "1 to 50 mm"),
]


def absurd_file(tmp_path, old, new):
    text = default_parameters_path().read_text(encoding="utf-8")
    assert text.count(old) == 1, old
    path = tmp_path / "absurd.toml"
    path.write_text(text.replace(old, new), encoding="utf-8")
    return path


def test_every_number_has_a_range_and_the_published_machine_is_within():
    for section, keys in SCHEMA.items():
        for key, spec in keys.items():
            assert (spec.plausible is None) == (spec.kind in ("bool", "signs")), (section, key)
            if spec.plausible is not None:
                low, high = spec.plausible
                assert low < high, (section, key)
    with warnings.catch_warnings():
        warnings.simplefilter("error", ParameterWarning)
        params = hipsim.load_parameters()
    assert implausible(params) == []


def test_friction_coefficients_are_zero_to_one():
    assert plausible_ranges()["friction.hip_mu"][:2] == (0.0, 1.0)
    assert plausible_ranges()["friction.thrust_mu"][:2] == (0.0, 1.0)


@pytest.mark.parametrize(("old", "new", "key", "value", "range_"), ABSURD)
def test_an_absurd_value_is_a_warning_naming_key_value_and_range(old, new, key, value, range_, tmp_path, capsys):
    path = absurd_file(tmp_path, old, new)
    with pytest.warns(ParameterWarning) as caught:
        params = hipsim.load_parameters(path)
    assert len(caught) == 1
    message = str(caught[0].message)
    assert f"key '{key}' = {value} is outside the plausible range {range_}" in message and "absurd.toml" in message
    assert [entry[0] for entry in implausible(params)] == [key]
    # The command line: one warning line on standard error, and the run goes on.
    assert main(["torques", "--params", str(path), "--rate", "50", "--out", str(tmp_path / "t.csv")]) == 0
    err = capsys.readouterr().err
    lines = [line for line in err.splitlines() if line.startswith("hipsim: warning:")]
    assert len(lines) == 1 and key in lines[0] and range_ in lines[0], err


def test_the_message_for_a_caller_that_refuses():
    message = implausible_message("lever.mass_kg", 1430.0, (0.1, 15.0))
    assert (
        message
        == "key 'lever.mass_kg' = 1430 kg is outside the plausible range 0.1 to 15 kg for this class of machine (a unit slip?)"
    )


def test_the_ranges_are_documented():
    from pathlib import Path

    text = (Path(__file__).resolve().parents[2] / "docs" / "guide" / "robust-inputs.md").read_text(encoding="utf-8")
    for key, (low, high, unit) in plausible_ranges().items():
        row = re.search(rf"^\| `{re.escape(key)}` \| (.*?) \|", text, re.M)
        assert row, key
        assert row.group(1) == f"{low:g} to {high:g}{' ' + unit if unit else ''}", (key, row.group(1))
