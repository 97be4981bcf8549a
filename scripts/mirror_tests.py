"""Move flat test files to the folders that mirror hipsim/ (issue 46), by the table in scripts/mirror_tests.toml.

Usage (from the repository root, rerunnable after every merge that brings new flat files):

    .venv/bin/python scripts/mirror_tests.py            # move, fix paths and references
    .venv/bin/python scripts/mirror_tests.py --check    # only say what would move; exit 1 if anything would
    .venv/bin/python scripts/mirror_tests.py --gaps     # new modules without their test file, as KNOWN_GAPS rows

Each flat ``tests/test_*.py`` is either listed under ``[stay]`` (cross-cutting and foundation tests) or moved with
``git mv`` to its row of ``[moves]``. A flat file with no row is named and the script exits 1: add its row (the
rules are at the top of the table) and rerun. After moving, in every file git tracks:

- ``tests/<old>`` (paths and node ids) becomes ``tests/<new>`` (docs, scripts/mutation_targets.toml, .ci/run,
  other tests' comments); a moved file's bare name in a test file, and a renamed file's old name anywhere, become
  its new path;
- tests/conftest.py's SLOW_FIRST names files by their path under tests/;
- a test file in a subfolder that finds the repository root as ``Path(__file__)...parents[1]`` (or
  ``.parent.parent``) gets the root at its new depth.

Nothing else is edited: the helpers (support.py, *_synthetic.py, ...) stay at the top of tests/, importable from
every folder through pyproject's ``pythonpath = ["tests"]``.
"""

from __future__ import annotations

import argparse
import re
import subprocess
import sys
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
TESTS = ROOT / "tests"
TABLE = Path(__file__).with_suffix(".toml")
sys.path.insert(
    0, str(TESTS)
)  # the rules of the mirror live in its test, as tests/test_layers.py's for scripts/structure.py

import test_mirror as mirror  # noqa: E402

#: Text files whose references to test paths are rewritten (by suffix, or by name for suffix-less scripts).
TEXT_SUFFIXES = {".py", ".md", ".toml", ".sh", ".yml", ".yaml", ".txt", ".cfg", ".ini"}
TEXT_NAMES = {"run"}
#: The repository root from a test file's own path: `Path(__file__)` with or without resolve(), then parents[1]
#: or .parent.parent (both the folder above tests/ for a flat file).
ROOT_FROM_FILE = re.compile(r"(Path\(__file__\)(?:\.resolve\(\))?)(?:\.parents\[1\]|\.parent\.parent)(?![.\w\[])")


def load_table(path: Path = TABLE) -> tuple[dict[str, str], dict[str, str]]:
    """The table's moves (flat name -> path under tests/) and the files that stay (name -> reason)."""
    table = tomllib.loads(path.read_text(encoding="utf-8"))
    return dict(table.get("moves", {})), dict(table.get("stay", {}))


def git(*args: str) -> str:
    return subprocess.run(["git", *args], cwd=ROOT, check=True, capture_output=True, text=True).stdout


def move_flat_files(moves: dict[str, str], stay: dict[str, str], check: bool) -> tuple[list[str], list[str], list[str]]:
    """``git mv`` each flat test file with a row; returns (moved, unmapped, conflicts)."""
    moved, unmapped, conflicts = [], [], []
    for name in mirror.flat_files_waiting(moves, stay):
        path = TESTS / name
        if name not in moves:
            unmapped.append(name)
            continue
        target = TESTS / moves[name]
        if target.exists():
            conflicts.append(f"tests/{name} -> tests/{moves[name]}: the target exists already (merge them by hand)")
            continue
        moved.append(name)
        if not check:
            target.parent.mkdir(parents=True, exist_ok=True)
            git("mv", str(path.relative_to(ROOT)), str(target.relative_to(ROOT)))
    return moved, unmapped, conflicts


def tracked_text_files() -> list[Path]:
    files = []
    for line in git("ls-files").splitlines():
        path = ROOT / line
        if path == TABLE or not path.is_file():
            continue
        if path.suffix in TEXT_SUFFIXES or path.name in TEXT_NAMES:
            files.append(path)
    return files


def rewrite_references(moves: dict[str, str]) -> list[str]:
    """Every ``tests/<old>`` becomes ``tests/<new>``; a renamed file's bare name in tests/ its path under tests/."""
    renamed = {old: new for old, new in moves.items() if old != new}
    if not renamed:
        return []
    names = "|".join(re.escape(old) for old in sorted(renamed, key=len, reverse=True))
    in_path = re.compile(rf"(?<![\w/.-])tests/({names})(?![\w])")
    # Bare names (not preceded by a path or word): in tests/, every moved file's; elsewhere only the old names of
    # files whose name changed (a kept name still names the file).
    bare = re.compile(rf"(?<![\w/.-])({names})(?![\w])")
    changed = {old for old, new in renamed.items() if Path(new).name != old}
    bare_changed = re.compile(
        rf"(?<![\w/.-])({'|'.join(re.escape(old) for old in sorted(changed, key=len, reverse=True)) or '(?!)'})(?![\w])"
    )
    slow_first = re.compile(rf'^(\s*)"({names})",', re.MULTILINE)
    edited = []
    for path in tracked_text_files():
        if path == TESTS / "test_mirror.py":  # its examples of names are names, not references
            continue
        text = path.read_text(encoding="utf-8", errors="surrogateescape")
        new = in_path.sub(lambda m: "tests/" + renamed[m.group(1)], text)
        if path == TESTS / "conftest.py":
            new = slow_first.sub(lambda m: f'{m.group(1)}"{renamed[m.group(2)]}",', new)
        elif TESTS in path.parents and path.name.startswith("test_"):
            new = bare.sub(lambda m: "tests/" + renamed[m.group(1)], new)
        else:
            new = bare_changed.sub(lambda m: "tests/" + renamed[m.group(1)], new)
        if new != text:
            path.write_text(new, encoding="utf-8", errors="surrogateescape")
            edited.append(str(path.relative_to(ROOT)))
    return edited


def fix_roots() -> tuple[list[str], list[str]]:
    """Test files in subfolders that find the repository root from their own path: the root at their depth."""
    edited, look = [], []
    for path in sorted(TESTS.rglob("test_*.py")):
        depth = len(path.relative_to(TESTS).parts) - 1
        if depth == 0 or "__pycache__" in path.parts:
            continue
        text = path.read_text(encoding="utf-8")
        new = ROOT_FROM_FILE.sub(rf"\g<1>.parents[{depth + 1}]", text)
        if new != text:
            path.write_text(new, encoding="utf-8")
            edited.append(str(path.relative_to(ROOT)))
        for number, line in enumerate(new.splitlines(), 1):
            if "Path(__file__)" in line and f"parents[{depth + 1}]" not in line and "with_name(" not in line:
                look.append(f"{path.relative_to(ROOT)}:{number}: {line.strip()}")
    for path in sorted(TESTS.rglob("test_*.py")):  # a test reading the other test files sees the top folder only
        if path.name == "test_mirror.py" or "__pycache__" in path.parts:
            continue
        for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
            if '.glob("test_' in line:
                look.append(f"{path.relative_to(ROOT)}:{number}: {line.strip()} (rglob for every folder?)")
            if line.startswith(("import test_", "from test_")):  # only the helpers at the top import by name
                look.append(f"{path.relative_to(ROOT)}:{number}: {line.strip()} (a test module: import it by its path)")
    return edited, look


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--check", action="store_true", help="only list what would move; exit 1 if anything would")
    parser.add_argument(
        "--gaps",
        action="store_true",
        help="print the modules without a mirrored test file and not yet listed, as KNOWN_GAPS rows",
    )
    args = parser.parse_args(argv)
    if args.gaps:
        new = [
            m
            for m in mirror.modules()
            if m not in mirror.EXEMPT and m not in mirror.KNOWN_GAPS and not mirror.mirrored(m)
        ]
        for module in new:
            print(f'    "{module}": "WHERE IT IS TESTED TODAY",')
        return 1 if new else 0
    moves, stay = load_table()
    moved, unmapped, conflicts = move_flat_files(moves, stay, args.check)
    for name in moved:
        print(f"{'would move' if args.check else 'moved'} tests/{name} -> tests/{moves[name]}")
    if not args.check:
        for name in rewrite_references(moves):
            print(f"references updated: {name}")
        edited, look = fix_roots()
        for name in edited:
            print(f"repository root at the new depth: {name}")
        for line in look:
            print(f"check by hand (a path from __file__): {line}")
    for line in conflicts:
        print(f"conflict: {line}", file=sys.stderr)
    for name in unmapped:
        print(
            f"no row for tests/{name}: add it to {TABLE.relative_to(ROOT)} ([moves] or [stay]) and rerun",
            file=sys.stderr,
        )
    print(
        f"{len(moved)} files {'to move' if args.check else 'moved'}, {len(unmapped)} without a row, {len(conflicts)} conflicts"
    )
    return 1 if unmapped or conflicts or (args.check and moved) else 0


if __name__ == "__main__":
    sys.exit(main())
