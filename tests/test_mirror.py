"""tests/ mirrors hipsim/: the tests of hipsim/<package>/<module>.py are tests/<package>/test_<module>.py (issue 46).

A module's tests may be split by aspect, tests/<package>/test_<module>_<aspect>.py (its laws by hand, its files, its
errors); a file's name claims the longest module name it starts with, so tests/rig/monitoring/test_monitor_fit_errors.py
is monitor_fit's and not a module "monitor"'s. Foundation modules (hipsim/<module>.py) have theirs at the top of tests/,
beside the cross-cutting files that scripts/mirror_tests.toml keeps there. The table places every test file:
scripts/mirror_tests.py moves a new flat file to its row's folder (docs/guide/layout.md).

KNOWN_GAPS lists the modules with logic that have no test file at their mirrored path yet, each with where they are
exercised today; the list only shrinks: a new module without its test file fails here, and so does a gap closed but
still listed.
"""

from __future__ import annotations

import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = ROOT / "hipsim"
TESTS = ROOT / "tests"
TABLE = ROOT / "scripts" / "mirror_tests.toml"

#: Modules without tests of their own, by design (path under hipsim/ -> why). ``__init__.py`` (curated re-exports and
#: lazy imports, checked by tests/test_layers.py) and ``__main__.py`` (``python -m hipsim``) are exempt by rule.
EXEMPT = {
    "version.py": "the version string; tests/analysis/test_streaming.py holds it equal to pyproject's",
    "physics/units.py": "two conversion factors, 60/2π and its inverse: data, no logic",
}

#: Modules with logic still lacking a test file at their mirrored path -> where they are exercised today.
KNOWN_GAPS: dict[str, str] = {}


def modules() -> list[str]:
    """hipsim's modules as paths under hipsim/ ("rig/monitoring/watch.py"), without ``__init__`` and ``__main__``."""
    return sorted(
        path.relative_to(PACKAGE).as_posix()
        for path in PACKAGE.rglob("*.py")
        if "__pycache__" not in path.parts and path.name not in ("__init__.py", "__main__.py")
    )


def claimed(test: Path, names: list[str]) -> str | None:
    """The module a test file's name claims among ``names`` (its folder's modules): the longest that fits."""
    stem = test.stem.removeprefix("test_")
    fits = [name for name in names if stem == name or stem.startswith(name + "_")]
    return max(fits, key=len) if fits else None


def mirrored(module: str) -> list[Path]:
    """The test files at a module's mirrored path: tests/<package>/test_<module>.py or test_<module>_<aspect>.py."""
    path = PACKAGE / module
    folder = TESTS.joinpath(*Path(module).parts[:-1])
    names = [sibling.stem for sibling in path.parent.glob("*.py")]
    return [test for test in sorted(folder.glob("test_*.py")) if claimed(test, names) == path.stem]


def test_a_files_name_claims_the_longest_module_it_starts_with():
    names = ["monitor", "monitor_fit", "monitor_run", "fit"]
    assert claimed(Path("test_monitor_fit_errors.py"), names) == "monitor_fit"
    assert claimed(Path("test_monitor_fit.py"), names) == "monitor_fit"
    assert claimed(Path("test_monitor.py"), names) == "monitor"
    assert claimed(Path("test_monitor_page.py"), names) == "monitor"
    assert claimed(Path("test_monitoring.py"), names) is None  # a longer word is not the module's aspect
    assert claimed(Path("test_fitting.py"), names) is None


def test_every_module_with_logic_has_its_mirrored_test_file():
    missing = [m for m in modules() if m not in EXEMPT and m not in KNOWN_GAPS and not mirrored(m)]
    assert not missing, (
        "modules without a test file at their mirrored path (tests/<package>/test_<module>.py): "
        + ", ".join(missing)
        + "; write it (or, for a module without logic, add it to EXEMPT with the reason)"
    )


def test_the_known_gaps_only_shrink():
    closed = [m for m in KNOWN_GAPS if mirrored(m)]
    assert not closed, f"these modules have their mirrored test file now: remove them from KNOWN_GAPS: {closed}"
    gone = [m for m in [*KNOWN_GAPS, *EXEMPT] if not (PACKAGE / m).is_file()]
    assert not gone, f"no such module under hipsim/ (moved or removed?): {gone}"
    assert not set(KNOWN_GAPS) & set(EXEMPT)


def test_every_test_folder_mirrors_a_package():
    folders = sorted({path.parent for path in TESTS.rglob("test_*.py") if "__pycache__" not in path.parts})
    strays = [
        f.relative_to(TESTS).as_posix() for f in folders if f != TESTS and not (PACKAGE / f.relative_to(TESTS)).is_dir()
    ]
    assert not strays, f"test folders with no hipsim package of that path: {strays}"


def foundation_test(name: str) -> bool:
    """A flat test file's name claims a foundation module (hipsim/<module>.py): its place is the top of tests/."""
    return claimed(Path(name), [path.stem for path in PACKAGE.glob("*.py")]) not in (None, "__init__", "__main__")


def flat_files_waiting(moves: dict[str, str], stay: dict[str, str]) -> list[str]:
    """Flat test files neither kept at the top (a [stay] row, a move to the top, a foundation module's) nor moved yet."""
    placed = set(stay) | {target for target in moves.values() if "/" not in target}
    return sorted(
        path.name
        for path in TESTS.glob("test_*.py")
        if path.name not in placed and (path.name in moves or not foundation_test(path.name))
    )


def test_a_foundation_modules_test_file_stays_at_the_top():
    assert foundation_test("test_files.py") and foundation_test("test_tables_long_fields.py")
    assert not foundation_test("test_wear_summary.py")  # wear is a package
    assert not foundation_test("test_main.py")


def test_every_flat_test_file_has_its_row_in_the_table():
    """A new test file at the top of tests/ is placed by scripts/mirror_tests.toml (or a foundation module's), or waits for the script."""
    table = tomllib.loads(TABLE.read_text(encoding="utf-8"))
    waiting = flat_files_waiting(table["moves"], table["stay"])
    assert not waiting, (
        f"flat test files not placed: {waiting}; add a row to scripts/mirror_tests.toml and run "
        ".venv/bin/python scripts/mirror_tests.py"
    )
    for target in table["moves"].values():
        assert target.startswith("test_") or "/test_" in target, f"{target}: a test file's name starts with test_"


def test_the_files_named_by_path_exist():
    """SLOW_FIRST (tests/conftest.py) and the mutation targets name test files by path; a stale one is silently skipped."""
    from conftest import SLOW_FIRST

    stale = [name for name in SLOW_FIRST if not (TESTS / name).is_file()]
    assert not stale, f"tests/conftest.py's SLOW_FIRST names files that are not under tests/: {stale}"
    targets = tomllib.loads((ROOT / "scripts" / "mutation_targets.toml").read_text(encoding="utf-8"))
    named = [
        test.split("::")[0]
        for target in targets.values()
        for key in ("tests", "deselect")
        for test in target.get(key, [])
    ]
    assert named, "scripts/mutation_targets.toml names no test file"
    stale = sorted({path for path in named if not (ROOT / path).is_file()})
    assert not stale, f"scripts/mutation_targets.toml names test files that do not exist: {stale}"
