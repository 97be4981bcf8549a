"""scripts/mutation_config.py: a mutation target's [tool.mutmut] table, and a survivors rerun that reads the target's
test list again (tests added run on the survivors, the first run's verdicts kept; a test dropped refused)."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "scripts"))

from mutation_config import PYTEST_ARGS, Refused, main, renewed, survivors, table, write, written

TARGET = """
[laws]
mutate = ["hipsim/physics/laws.py"]
tests = ["tests/test_a.py", "tests/test_b.py::test_one", "tests/test_gone.py"]
deselect = ["tests/test_a.py::test_slow"]
"""


@pytest.fixture
def work(tmp_path: Path) -> Path:
    """A target's table and a copy of the tree with tests/test_a.py, tests/test_b.py and tests/test_c.py."""
    (tmp_path / "targets.toml").write_text(TARGET)
    work = tmp_path / "work"
    (work / "tests").mkdir(parents=True)
    for name in ("test_a.py", "test_b.py", "test_c.py"):
        (work / "tests" / name).write_text("")
    (work / "pyproject.toml").write_text(
        '[project]\nname = "x"\n\n[tool.mutmut]\nold = 1\n\n[tool.ruff]\nline-length = 9\n'
    )
    return work


def test_a_targets_table_names_its_tests_that_exist(work):
    mutmut = table(work.parent / "targets.toml", "laws", work)
    assert mutmut["only_mutate"] == ["hipsim/physics/laws.py"]
    assert mutmut["pytest_add_cli_args"] == [*PYTEST_ARGS, "--deselect=tests/test_a.py::test_slow"]
    assert mutmut["pytest_add_cli_args_test_selection"] == ["tests/test_a.py", "tests/test_b.py::test_one"]
    write(work / "pyproject.toml", mutmut)
    text = (work / "pyproject.toml").read_text()
    assert "old = 1" not in text and "line-length = 9" in text and 'name = "x"' in text  # the rest kept
    assert written(work / "pyproject.toml") == mutmut


def test_a_rerun_keeps_the_verdicts_only_for_a_selection_that_grew(work):
    old = table(work.parent / "targets.toml", "laws", work)
    grown = {**old, "pytest_add_cli_args_test_selection": [*old["pytest_add_cli_args_test_selection"], "tests/c.py"]}
    assert renewed(old, grown) == ["tests/c.py"] and renewed(old, old) == []
    with pytest.raises(Refused, match=r"no longer runs tests/test_b\.py::test_one"):
        renewed(old, {**old, "pytest_add_cli_args_test_selection": ["tests/test_a.py"]})
    with pytest.raises(Refused, match="deselect list changed"):
        renewed(old, {**old, "pytest_add_cli_args": PYTEST_ARGS})
    with pytest.raises(Refused, match=r"no \[tool\.mutmut\] table"):
        renewed({}, old)


def test_a_survivors_rerun_runs_the_test_files_added_to_the_target(work, capsys):
    targets = work.parent / "targets.toml"
    write(work / "pyproject.toml", table(targets, "laws", work))
    (work / "mutants").mkdir()
    stats = {"duration_by_test": {"t": 1.0}, "config_fingerprint": {"test_selection": "old", "timeout": "t"}}
    (work / "mutants" / "mutmut-stats.json").write_text(json.dumps(stats))
    assert survivors(targets, "laws", work, lambda _: {"test_selection": "never called"}) == []  # nothing added
    targets.write_text(TARGET.replace('"tests/test_gone.py"', '"tests/test_gone.py", "tests/test_c.py"'))
    added = survivors(targets, "laws", work, lambda folder: {"test_selection": "new", "of": str(folder)})
    assert added == ["tests/test_c.py"]
    assert written(work / "pyproject.toml")["pytest_add_cli_args_test_selection"][-1] == "tests/test_c.py"
    renewed_stats = json.loads((work / "mutants" / "mutmut-stats.json").read_text())
    assert renewed_stats == {**stats, "config_fingerprint": {"test_selection": "new", "of": str(work)}}
    # The test list shrunk: refused in one line naming the package, exit 2, the table left as it was.
    targets.write_text(TARGET.replace('"tests/test_a.py", ', ""))
    assert main(["survivors", str(targets), "laws", str(work)]) == 2
    err = capsys.readouterr().err.strip()
    assert (
        err.startswith("laws: survivors rerun refused: the target no longer runs tests/test_a.py") and "\n" not in err
    )
    assert written(work / "pyproject.toml")["pytest_add_cli_args_test_selection"][0] == "tests/test_a.py"


def test_a_stats_file_without_the_fingerprint_is_refused(work):
    targets = work.parent / "targets.toml"
    write(work / "pyproject.toml", table(targets, "laws", work))
    targets.write_text(TARGET.replace('"tests/test_gone.py"', '"tests/test_c.py"'))
    with pytest.raises(Refused, match="no test-selection fingerprint"):
        survivors(targets, "laws", work, lambda _: {})
