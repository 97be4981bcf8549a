"""The ``[tool.mutmut]`` table of a mutation target's copy of the tree (scripts/mutation.sh calls it).

Usage (from scripts/mutation.sh; the copy is build/mutation/PACKAGE/):

    python scripts/mutation_config.py write TARGETS PACKAGE WORK      # a full run: the table from the target
    python scripts/mutation_config.py survivors TARGETS PACKAGE WORK  # a survivors rerun: the table renewed

A full run writes the target's files to mutate, its pytest arguments (``deselect``) and its test selection (the test
files it names that exist in the copy) into WORK/pyproject.toml.

A survivors rerun writes the target's *current* test list the same way, so that test files added to the target
since the first run run on the survivors too. mutmut 3 resets every verdict when its test selection changes (it
cannot tell a selection that only grew from one that lost tests), which would make the rerun's killed mutants
unknown. So: a selection that only grew keeps the first run's verdicts (a test added can only kill more) and has
its fingerprint in WORK/mutants/mutmut-stats.json renewed, so that mutmut collects the new tests' coverage
(its incremental stats) and runs them on the survivors; a test dropped from the target, or a changed
``deselect``, could let a killed mutant survive: refused (exit 2), run the target in full.
"""

from __future__ import annotations

import json
import os
import re
import sys
import tomllib
from collections.abc import Callable
from pathlib import Path
from typing import Any

#: pytest's arguments for every mutant (the target's ``deselect`` follow).
PYTEST_ARGS = ["-n", "0", "-q", "-p", "no:cacheprovider", "-W", "ignore::DeprecationWarning"]


class Refused(Exception):
    """A survivors rerun that cannot keep the first run's verdicts: its one-line reason."""


def table(targets: Path, package: str, work: Path) -> dict[str, Any]:
    """The ``[tool.mutmut]`` table of ``package`` in ``targets``, for the copy of the tree at ``work``.

    Test files the target names that are missing from the copy are left out (an older checkout measured with today's
    targets).
    """
    target = tomllib.loads(targets.read_text(encoding="utf-8"))[package]
    args = PYTEST_ARGS + [f"--deselect={test}" for test in target.get("deselect", [])]
    return {
        "source_paths": ["hipsim"],
        "only_mutate": target["mutate"],
        "pytest_add_cli_args": args,
        "pytest_add_cli_args_test_selection": [
            test for test in target["tests"] if (work / test.split("::")[0]).exists()
        ],
        "use_git_change_detection": False,
    }


def written(pyproject: Path) -> dict[str, Any]:
    """The ``[tool.mutmut]`` table a copy's pyproject.toml has (empty: none)."""
    tool: dict[str, Any] = tomllib.loads(pyproject.read_text(encoding="utf-8")).get("tool", {})
    return dict(tool.get("mutmut", {}))


def write(pyproject: Path, mutmut: dict[str, Any]) -> None:
    """Replace the ``[tool.mutmut]`` table of ``pyproject`` by ``mutmut``."""
    text = re.sub(r"(?ms)^\[tool\.mutmut\].*?(?=^\[|\Z)", "", pyproject.read_text(encoding="utf-8"))
    lines = ["", "[tool.mutmut]"] + [f"{key} = {json.dumps(value)}" for key, value in mutmut.items()]
    pyproject.write_text(text.rstrip() + "\n" + "\n".join(lines) + "\n", encoding="utf-8")


def renewed(old: dict[str, Any], new: dict[str, Any]) -> list[str]:
    """The tests ``new`` adds to ``old``'s selection.

    Raises:
        Refused: a test of ``old`` not in ``new``, or other pytest arguments (a changed ``deselect``).
    """
    if not old:
        raise Refused("the copy's pyproject.toml has no [tool.mutmut] table: run the target in full")
    if old["pytest_add_cli_args"] != new["pytest_add_cli_args"]:
        raise Refused(
            "the target's deselect list changed since the first run (a test deselected may have killed a mutant): "
            "run the target in full"
        )
    before, after = old["pytest_add_cli_args_test_selection"], new["pytest_add_cli_args_test_selection"]
    dropped = [test for test in before if test not in after]
    if dropped:
        raise Refused(
            f"the target no longer runs {', '.join(dropped)} (it may have killed a mutant the rerun keeps killed): "
            "run the target in full"
        )
    return [test for test in after if test not in before]


def mutmut_fingerprint(work: Path) -> dict[str, str]:
    """mutmut's own fingerprint of the configuration WORK/pyproject.toml holds (mutmut reads it from the folder)."""
    from mutmut.configuration import config, reset_config

    here = Path.cwd()
    os.chdir(work)
    try:
        reset_config()
        return config().config_fingerprint()
    finally:
        os.chdir(here)


def survivors(
    targets: Path, package: str, work: Path, fingerprint: Callable[[Path], dict[str, str]] = mutmut_fingerprint
) -> list[str]:
    """Renew the copy's table from the target's current list, keeping the first run's verdicts; the tests added.

    Raises:
        Refused: as :func:`renewed`; or mutmut's stats file without the fingerprint this relies on (another mutmut).
    """
    pyproject = work / "pyproject.toml"
    new = table(targets, package, work)
    added = renewed(written(pyproject), new)
    if not added:
        return added
    stats_file = work / "mutants" / "mutmut-stats.json"
    stats = json.loads(stats_file.read_text(encoding="utf-8")) if stats_file.exists() else {}
    if "test_selection" not in stats.get("config_fingerprint", {}):
        raise Refused(
            f"{stats_file} has no test-selection fingerprint (another mutmut version?): cannot keep the first run's "
            "verdicts with new tests; run the target in full"
        )
    write(pyproject, new)
    # mutmut compares this with the configuration's: equal, it keeps every verdict and collects the new tests only.
    stats["config_fingerprint"] = fingerprint(work)
    stats_file.write_text(json.dumps(stats, indent=4), encoding="utf-8")
    return added


def main(argv: list[str]) -> int:
    if len(argv) != 4 or argv[0] not in ("write", "survivors"):
        print(__doc__.split("\n\n")[1], file=sys.stderr)
        return 2
    mode, targets, package, work = argv[0], Path(argv[1]), argv[2], Path(argv[3])
    if mode == "write":
        write(work / "pyproject.toml", table(targets, package, work))
        return 0
    try:
        added = survivors(targets, package, work)
    except Refused as refusal:
        print(f"{package}: survivors rerun refused: {refusal}", file=sys.stderr)
        return 2
    if added:
        print(f"{package}: tests added since the first run, run on the survivors: {', '.join(added)}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
