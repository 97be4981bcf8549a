"""The documentation: README.md and docs/**/*.md, their examples, their links and the docstrings they are built from.

- every ```python block runs (blocks of one page in order, in one namespace, in a temporary folder);
- every ```sh / ```console block is run here (``<!-- run -->`` on the line before it), run by a named test
  (``<!-- run by: tests/FILE.py::TEST -->``) or says why not (``<!-- not run: REASON -->``);
- every ``hipsim.x.y`` path named in the prose resolves;
- every public function and class (in a module's ``__all__``) has a docstring;
- ``mkdocs build --strict`` passes (a broken page link or anchor fails it), when mkdocs is installed.
"""

from __future__ import annotations

import argparse
import ast
import importlib
import importlib.util
import os
import re
import shlex
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from conftest import figures_undrawn
from support import given

ROOT = Path(__file__).resolve().parents[1]
README = ROOT / "README.md"
PAGES = [README, *sorted((ROOT / "docs").rglob("*.md"))]

_FENCE = re.compile(r"^```([\w-]*)[^\n]*\n(.*?)^```[ \t]*$", re.M | re.S)
_MARKER = re.compile(r"<!--\s*(run|run by:[^>]*?|not run:[^>]*?)\s*-->\s*\Z")
#: The README's "Two commands" block: CI runs it (.ci/run), and tests/test_results.py holds the two equal.
_TWO_COMMANDS = "python3 -m venv .venv && .venv/bin/pip install -q 'uv>=0.9,<1' && .venv/bin/uv pip install -q --compile-bytecode --python .venv/bin/python -e . && .venv/bin/hipsim torques"
_SHELL = {"sh", "bash", "console", "shell"}


def blocks(page: Path) -> list[tuple[str, str, str, int]]:
    """The fenced blocks of a page: (language, code, marker or "", line)."""
    text = page.read_text(encoding="utf-8")
    found = []
    for match in _FENCE.finditer(text):
        before = text[: match.start()].rstrip("\n")
        marker = _MARKER.search(before.splitlines()[-1] if before else "")
        found.append(
            (match.group(1), match.group(2), marker.group(1) if marker else "", text.count("\n", 0, match.start()) + 1)
        )
    return found


def _name(page: Path) -> str:
    return str(page.relative_to(ROOT))


# --------------------------------------------------------------------------- code blocks


def test_every_block_names_its_language():
    """A block without a language could hide a command from the checks below."""
    bare = [f"{_name(page)}:{line}" for page in PAGES for lang, _, _, line in blocks(page) if not lang]
    assert not bare, f"fenced blocks without a language (use text for output): {bare}"


PYTHON_PAGES = [page for page in PAGES if any(lang == "python" and not marker for lang, _, marker, _ in blocks(page))]


@pytest.mark.parametrize("page", PYTHON_PAGES, ids=_name)
def test_python_blocks_run(page, tmp_path, monkeypatch):
    """Each page's Python blocks, in order, in one namespace, in a temporary working folder.

    The figures they make are built but not drawn (``figures_undrawn``): the one page that draws in this
    process, reports.md, writes the built-in cycle's report, whose drawn figures
    tests/present/test_report.py checks; drawing them here was 4/5 of the page's time.
    """
    monkeypatch.chdir(tmp_path)
    (tmp_path / "docs").symlink_to(ROOT / "docs")
    (tmp_path / "models").symlink_to(ROOT / "models")
    namespace: dict = {"__name__": "__docs__"}
    with figures_undrawn():
        for lang, code, marker, line in blocks(page):
            if lang == "python" and not marker:
                exec(compile("\n" * (line) + code, str(page), "exec"), namespace)


def test_python_blocks_not_run_here_say_where():
    """A Python block skipped above is run by a named test that reads its page, or says why not."""
    for page in PAGES:
        for lang, _, marker, line in blocks(page):
            if lang != "python" or not marker:
                continue
            where = f"{_name(page)}:{line}"
            if marker.startswith("not run:"):
                assert len(marker) > len("not run:") + 5, f"{where}: say why the block is not run"
                continue
            assert marker.startswith("run by:"), f"{where}: a Python block runs here; '{marker}' is not a marker for it"
            _check_run_by(marker, page, where)


def _check_run_by(marker: str, page: Path, where: str) -> None:
    target = marker[len("run by:") :].strip()
    file, _, test = target.partition("::")
    source = (ROOT / file).read_text(encoding="utf-8")
    assert re.search(rf"^def {re.escape(test)}\(", source, re.M), f"{where}: {target} does not exist"
    assert page.name in source, f"{where}: {file} does not read {page.name}"


RUN_BLOCKS = [
    (page, code, line)
    for page in PAGES
    for lang, code, marker, line in blocks(page)
    if lang in _SHELL and marker == "run"
]


def test_shell_blocks_are_run_or_say_why_not():
    """Every shell block is run (here or by a named test) or says why not."""
    for page in PAGES:
        for lang, code, marker, line in blocks(page):
            if lang not in _SHELL:
                continue
            where = f"{_name(page)}:{line}"
            if page == README and _TWO_COMMANDS in code:
                continue  # CI runs it; tests/test_results.py::test_ci_runs_the_readme_test_command
            assert marker, (
                f"{where}: a shell block needs <!-- run -->, <!-- run by: tests/FILE::TEST --> or <!-- not run: REASON --> on the line before it"
            )
            if marker.startswith("not run:"):
                assert len(marker) > len("not run:") + 5, f"{where}: say why the block is not run"
            elif marker.startswith("run by:"):
                _check_run_by(marker, page, where)


def commands(code: str) -> list[list[str]]:
    """The hipsim commands of a shell block: one a line (continued with a backslash), comments dropped."""
    found = []
    for line in code.replace("\\\n", " ").splitlines():
        words = shlex.split(line, comments=True)
        if words:
            assert words[0] == "hipsim", f"only hipsim commands run here: {line}"
            found.append(words)
    return found


@pytest.mark.parametrize(("page", "code", "line"), RUN_BLOCKS, ids=[f"{_name(p)}:{n}" for p, _, n in RUN_BLOCKS])
def test_shell_blocks_run(page, code, line, tmp_path, monkeypatch, capsys):
    """Each command of a block marked <!-- run --> finishes with status 0 or 1 (done; 1: a check failed), never 2 (bad input).

    The commands run through ``hipsim``'s main() in this process, in a temporary
    folder: a process a command would cost 1–2 s of imports and numba cache
    loads each (the console script itself runs as a process in tests/test_cli.py).
    """
    from hipsim.cli.main import main

    (tmp_path / "docs").symlink_to(ROOT / "docs")
    (tmp_path / "models").symlink_to(ROOT / "models")
    monkeypatch.chdir(tmp_path)
    for words in commands(code):
        try:
            status = main(words[1:])
        except SystemExit as exit:  # argparse: a usage error
            status = exit.code if isinstance(exit.code, int) else 1
        err = capsys.readouterr().err
        assert status in (0, 1), f"{_name(page)}:{line}: {shlex.join(words)} exited {status}: {err[-2000:]}"


# --------------------------------------------------------------------------- names and links

#: Dotted names in the prose that are not Python paths: the Parquet file's metadata keys.
_NOT_PATHS = {"hipsim.version", "hipsim.parameters"}
_PATH = re.compile(r"`(hipsim(?:\.\w+)+)")


def resolve(path: str) -> object:
    """The object a dotted path names: the longest importable module, then attributes."""
    parts = path.split(".")
    for cut in range(len(parts), 0, -1):
        try:
            value = importlib.import_module(".".join(parts[:cut]))
        except ModuleNotFoundError:
            continue
        for name in parts[cut:]:
            value = getattr(value, name)
        return value
    raise ModuleNotFoundError(path)


def test_every_named_path_resolves():
    """`hipsim.x.y` in README.md and the docs names a module, class, function or attribute that exists."""
    missing = []
    for page in PAGES:
        for path in sorted(set(_PATH.findall(page.read_text(encoding="utf-8"))) - _NOT_PATHS):
            if path.startswith("hipsim.mujoco_engine") and importlib.util.find_spec("mujoco") is None:
                continue
            try:
                resolve(path)
            except (ImportError, AttributeError) as error:
                missing.append(f"{_name(page)}: {path} ({error})")
    assert not missing, "\n".join(missing)


def test_readme_is_a_front_door():
    """At most ~250 lines, and every command in its table links to its guide page (which exists)."""
    text = README.read_text(encoding="utf-8")
    assert len(text.splitlines()) <= 250
    rows = re.findall(r"^\| \[`hipsim ([\w-]+)[^`]*`\]\((docs/guide/[\w-]+\.md)(#[\w-]+)?\) \|", text, re.M)
    names = {name for name, _, _ in rows}
    from hipsim.cli.main import build_parser

    choices = next(a.choices for a in build_parser()._actions if isinstance(a, argparse._SubParsersAction))
    assert names == set(choices), (
        f"commands without a row in the README's table: {set(choices) - names}; rows of no command: {names - set(choices)}"
    )
    for _, target, anchor in rows:
        assert (ROOT / target).is_file(), target
        if anchor:
            assert anchor[1:] in headings(ROOT / target), f"{target}{anchor}: no such heading"


def headings(page: Path) -> set[str]:
    """The anchors of a page's headings, as GitHub and mkdocs' toc make them (lower case, punctuation dropped, spaces to hyphens)."""
    found = set()
    for line in page.read_text(encoding="utf-8").splitlines():
        if line.startswith("#"):
            title = line.lstrip("#").strip().lower()
            found.add(re.sub(r"[\s]+", "-", re.sub(r"[^\w\s-]", "", title)))
    return found


# --------------------------------------------------------------------------- docstrings


def public_definitions() -> list[tuple[str, int, str, bool]]:
    """(module file, line, name, has a docstring) of every function and class a module lists in ``__all__``."""
    found = []
    for path in sorted((ROOT / "hipsim").rglob("*.py")):
        tree = ast.parse(path.read_text(encoding="utf-8"))
        names: list[str] = []
        for node in tree.body:
            targets = (
                node.targets
                if isinstance(node, ast.Assign)
                else [node.target]
                if isinstance(node, ast.AnnAssign)
                else []
            )
            value = node.value if isinstance(node, (ast.Assign, ast.AnnAssign)) else None
            if any(isinstance(t, ast.Name) and t.id == "__all__" for t in targets) and value is not None:
                names = list(ast.literal_eval(value))
        defined = {n.name: n for n in tree.body if isinstance(n, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef))}
        for name in names:
            if name in defined:  # names imported from elsewhere are checked where they are defined
                found.append(
                    (str(path.relative_to(ROOT)), defined[name].lineno, name, bool(ast.get_docstring(defined[name])))
                )
    return found


def test_public_functions_and_classes_have_docstrings():
    definitions = public_definitions()
    assert len(definitions) > 300  # the walk found the package
    missing = [f"{file}:{line} {name}" for file, line, name, documented in definitions if not documented]
    assert not missing, "public, in __all__, without a docstring:\n" + "\n".join(missing)


def test_a_missing_docstring_is_found(tmp_path, monkeypatch):
    """The check above, on a planted module: it sees a public function without a docstring."""
    package = tmp_path / "hipsim"
    package.mkdir()
    (package / "planted.py").write_text(
        '__all__ = ["f", "g"]\n\ndef f():\n    """Documented."""\n\ndef g():\n    pass\n'
    )
    monkeypatch.setattr(sys.modules[__name__], "ROOT", tmp_path)
    assert [(name, documented) for _, _, name, documented in public_definitions()] == [("f", True), ("g", False)]


# --------------------------------------------------------------------------- the site


def _mkdocs() -> str | None:
    here = Path(sys.executable).with_name("mkdocs")
    return str(here) if here.is_file() else shutil.which("mkdocs")


def test_the_site_builds_strictly(tmp_path):
    """`mkdocs build --strict`: a missing page or anchor, or a docstring griffe cannot read, fails the build."""
    mkdocs = _mkdocs()
    if mkdocs is None:
        pytest.skip("mkdocs is not installed: pip install -e '.[docs]' (the test extra includes it)")
    done = subprocess.run(
        [mkdocs, "build", "--strict", "-d", str(tmp_path / "site")],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=600,
        env={**os.environ, "NO_MKDOCS_2_WARNING": "1"},
    )
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-5000:]
    assert (tmp_path / "site" / "api" / "rig" / "index.html").stat().st_size > 10_000  # the reference was generated


def test_a_broken_link_fails_the_build(tmp_path):
    """The strict build fails on a link to a missing page and on a missing anchor (mkdocs' validation settings)."""
    mkdocs = _mkdocs()
    if mkdocs is None:
        pytest.skip("mkdocs is not installed: pip install -e '.[docs]' (the test extra includes it)")
    (tmp_path / "docs").mkdir()
    (tmp_path / "docs" / "index.md").write_text("# Home\n\n## Here\n")
    config = (ROOT / "mkdocs.yml").read_text(encoding="utf-8")
    validation = given(re.search(r"(?ms)^validation:.*?(?=^\S)", config)).group(0)
    for link in ("[a](missing.md)", "[a](index.md#nowhere)"):
        (tmp_path / "docs" / "other.md").write_text(f"# Other\n\n{link}\n")
        (tmp_path / "mkdocs.yml").write_text(f"site_name: t\nstrict: true\n{validation}")
        done = subprocess.run(
            [mkdocs, "build", "--strict", "-d", str(tmp_path / "site")],
            cwd=tmp_path,
            capture_output=True,
            text=True,
            timeout=120,
        )
        assert done.returncode != 0, link
