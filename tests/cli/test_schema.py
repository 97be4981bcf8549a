"""``hipsim schema`` (hipsim/cli/schema.py): the list of commands with a JSON summary, one schema printed, an unknown
command refused naming it. Every schema against its command's output: tests/test_schemas.py."""

from __future__ import annotations

import json

from hipsim.cli.documents import SCHEMAS
from hipsim.cli.main import main


def test_the_list_names_every_schema(capsys):
    assert main(["schema"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert [line.split()[0] for line in lines] == list(SCHEMAS)
    # each with the first line of its record's docstring, after the name padded to 22 characters
    name, record = next(iter(SCHEMAS.items()))
    assert lines[0] == f"{name:22s} {(record.__doc__ or '').strip().splitlines()[0]}"


def test_one_schema_is_printed_and_an_unknown_command_refused(capsys):
    name = next(iter(SCHEMAS))
    assert main(["schema", name]) == 0
    assert json.loads(capsys.readouterr().out)["title"] == f"hipsim {name} --summary-format json"
    assert main(["schema", "no-such-command"]) == 2
    captured = capsys.readouterr()
    assert not captured.out
    lines = captured.err.strip().splitlines()
    assert len(lines) == 1 and "no command 'no-such-command' prints a JSON summary" in lines[0]
