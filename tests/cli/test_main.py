"""The command line's entry (hipsim.cli.main): signed values joined to their option, --plant-params refused where
there is no plant, usage errors and no command as status 2, errors of a run one line, an interrupt 130."""

from __future__ import annotations

import importlib

import pytest

from hipsim.exceptions import ParameterError

#: the module (``hipsim.cli.main`` as an attribute is the function main, re-exported by hipsim.cli)
entry = importlib.import_module("hipsim.cli.main")


def test_a_signed_value_is_joined_to_its_option_and_only_there():
    assert entry._join_signed_values(["workspace", "--deltas", "-90:90:1", "--gamma", "-10"]) == [
        "workspace",
        "--deltas=-90:90:1",
        "--gamma=-10",
    ]
    assert entry._join_signed_values(["wear", "--load-column", "-Fz", "--rate", "100"]) == [
        "wear",
        "--load-column=-Fz",
        "--rate",
        "100",
    ]
    assert entry._join_signed_values(["x", "--rate", "-5"]) == ["x", "--rate", "-5"]  # the parser's own rule
    assert entry._join_signed_values(["--deltas"]) == ["--deltas"]


def test_plant_params_only_for_simulate():
    assert entry._misplaced_plant_option(["simulate", "--plant-params", "p.toml"]) is None
    assert entry._misplaced_plant_option(["torques", "--params", "p.toml"]) is None
    assert entry._misplaced_plant_option(["torques", "--plant-params=p.toml"]).startswith(
        "--plant-params: torques has no plant to give it"
    )
    assert entry._misplaced_plant_option(["--plant-params", "x"]).startswith("--plant-params: x has no plant")


def test_status_2_for_usage_errors_and_no_command(capsys):
    assert entry.main(["torques", "--plant-params", "p.toml"]) == 2
    assert capsys.readouterr().err.startswith("hipsim: error: --plant-params: torques has no plant")
    assert entry.main(["sweep", "--seed", "3"]) == 2
    assert capsys.readouterr().err == (
        "hipsim: error: sweep: --seed applies to --sample: give --sample, or drop --seed\n"
    )
    assert entry.main([]) == 2
    assert capsys.readouterr().out.startswith("usage: hipsim")


@pytest.mark.parametrize(
    ("raised", "status", "err"),
    [
        (ParameterError("bad", key="a.b"), 2, "hipsim: error: key 'a.b': bad\n"),
        (KeyboardInterrupt(), 130, "hipsim: interrupted\n"),
    ],
)
def test_what_a_run_raises_becomes_its_status(monkeypatch, capsys, raised, status, err):
    def run(args):
        raise raised

    parser = entry.build_parser()
    real = parser.parse_args

    def parse(words):
        args = real(words)
        args.run = run
        return args

    monkeypatch.setattr(parser, "parse_args", parse)
    monkeypatch.setattr(entry, "build_parser", lambda: parser)
    assert entry.main(["params"]) == status
    assert capsys.readouterr().err == err
