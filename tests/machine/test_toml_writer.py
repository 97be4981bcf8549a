"""hipsim.machine.toml_writer: the one writer of parameter files."""

import numpy as np

import hipsim
from hipsim.cli.main import main
from hipsim.machine.parameters import file_values, load_parameters
from hipsim.machine.toml_writer import parameter_toml, toml_value


def test_values_as_toml_spells_them():
    assert toml_value(True) == "true" and toml_value(False) == "false"
    assert toml_value(float("inf")) == "inf" and toml_value(float("-inf")) == "-inf"
    assert toml_value([[1.0, 0.5], [0.5, 2.0]]) == "[[1.0, 0.5], [0.5, 2.0]]"
    assert toml_value('a "b" \\') == '"a \\"b\\" \\\\"'
    assert toml_value(0.1 + 0.2) == "0.3"  # 15 significant digits hide the round-off


def test_a_written_machine_reads_back_the_same(tmp_path):
    params = hipsim.load_parameters(
        overrides={"lever.length_mm": 331.5, "platform.inertia_kgmm2": [[300, 2, 0], [2, 310, 0], [0, 0, 200]]}
    )
    path = tmp_path / "machine.toml"
    path.write_text(parameter_toml(params))
    again = load_parameters(path)
    assert file_values(again) == file_values(params)
    np.testing.assert_array_equal(again.platform_inertia, params.platform_inertia)


def test_the_params_command_layout(capsys):
    """With a title, units and a comment column, the text is what ``hipsim params`` prints."""
    assert main(["params"]) == 0
    params = hipsim.load_parameters()
    assert capsys.readouterr().out == parameter_toml(
        params, title=f"parameters: {params.source}", units=True, comment_column=60
    )
