"""``hipsim params``: what it prints is a parameter file that loads back to the same machine, each key with its
meaning and unit, a per-chain machine's [geometry] table included."""

from __future__ import annotations

import numpy as np

import hipsim
from hipsim.cli.main import main
from hipsim.machine.parameters import file_values
from hipsim.machine.toml_writer import parameter_toml


def printed(capsys, *args: str) -> str:
    assert main(["params", *args]) == 0
    return capsys.readouterr().out


def test_the_printout_is_a_parameter_file_of_the_same_machine(capsys, tmp_path):
    text = printed(capsys, "--set", "lever.length_mm=330")
    assert "\nlength_mm = 330.0" in text
    line = next(line for line in text.splitlines() if line.startswith("screw_radius_mm = "))
    assert line.index("#") == 60 and line.endswith("# E, screw axes radius [mm]")  # comments in one column
    again = tmp_path / "again.toml"
    again.write_text(text, encoding="utf-8")
    loaded = hipsim.load_parameters(again)
    expected = file_values(hipsim.load_parameters())
    assert file_values(loaded) == {**expected, "lever.length_mm": 330.0}


def test_a_per_chain_machine_prints_its_geometry_table(capsys, tmp_path):
    source = tmp_path / "chains.toml"
    rows = "[[0.5, 0], [0, 0], [0, 0], [0, 0], [0, 0], [0, 0]]"
    source.write_text(parameter_toml(hipsim.load_parameters()) + f"[geometry]\nujoint_offset_mm = {rows}\n")
    text = printed(capsys, "--params", str(source))
    assert "\n[geometry]\n" in text and "ujoint_offset_mm = " in text
    again = tmp_path / "again.toml"
    again.write_text(text, encoding="utf-8")
    first, second = hipsim.load_parameters(source), hipsim.load_parameters(again)
    assert first.geometry is not None and second.geometry is not None
    assert np.array_equal(first.geometry.as_vector(), second.geometry.as_vector())
    assert second.geometry.as_vector()[0] == 0.0005  # 0.5 mm, chain 11's U-joint x, in [m]
