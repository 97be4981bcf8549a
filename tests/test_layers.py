"""The package's layers, read from its imports: each rule of the README's layout section, as a test.

Every check is a function of the package's root folder, so that
:func:`test_the_rules_catch_planted_violations` can run it on a copy of the
package with violations planted in it: a rule that cannot fail there is no rule.
Imports are read from the syntax tree of every ``hipsim/**/*.py``, at any depth
(an import inside a function counts as much as one at the top).
"""

from __future__ import annotations

import ast
import functools
import shutil
from dataclasses import dataclass
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[1] / "hipsim"

# --- The rules --------------------------------------------------------------------------

#: The foundation: errors, frozen arrays, files, tables, set-up fingerprints and the clock. Its modules may import one another.
#: ``plausibility`` (the ranges of a hip simulator's data and the unit slips, issue 38) is here because the
#: machine's readers (drive files) and the motion's (trajectories, loads), which may not import each other, share it.
FOUNDATION = frozenset(
    {
        "exceptions",
        "arrays",
        "files",
        "tables",
        "channels",
        "fingerprint",
        "version",
        "result_table",
        "plausibility",
        "records",
        "clock",
        "fit_checks",
    }
)
#: The laws every model shares (vectors, friction, units, the screw transmission, numba's plumbing).
PHYSICS = FOUNDATION | {"physics"}
#: What a run is about, what it returns, and the engine and plant protocols.
SUBJECT = PHYSICS | {"machine", "motion", "results", "engine"}
#: The three engines; they import physics, never one another.
ENGINES = SUBJECT | {"analytic", "closed_chain", "mujoco_engine"}
#: Runs, streaming, the cross-check and the engine registry.
ANALYSIS = ENGINES | {"control", "analysis"}
#: Everything but the command line.
LIBRARY = ANALYSIS | {"rig", "design", "stations", "learning", "wear", "present"}

#: The packages (or top-level modules) each package may import, besides its own modules.
ALLOWED: dict[str, frozenset[str]] = {
    **{name: FOUNDATION for name in FOUNDATION},
    "physics": FOUNDATION,
    "machine": PHYSICS,  # not motion
    "motion": PHYSICS,  # not machine
    "results": PHYSICS | {"machine", "motion"},
    "engine": PHYSICS | {"machine", "motion", "results"},
    "analytic": SUBJECT,
    "closed_chain": SUBJECT,  # not analytic, not mujoco_engine
    "mujoco_engine": SUBJECT,  # not analytic, not closed_chain
    "control": ENGINES,
    "analysis": ANALYSIS,
    "rig": ANALYSIS,  # not design
    "design": ANALYSIS,  # not rig
    # The two stations' calibration and commands: the analyses' level; rig for the one identified-file schema that a
    # calibrated parameter file is written through (a calibration is an identification of the kinematics).
    "stations": ANALYSIS | {"rig"},
    # Learning the cycle from run to run: the stations' commands and logs, design's machine limits for the drive tables.
    "learning": ANALYSIS | {"rig", "design", "stations"},
    # Beside analysis and design: slide tracks and wear need the motion and the laws of rotation, not the machine's
    # models (no engine, no Pinocchio); a rig log or a simulated run reaches it as motion, converted by the caller.
    "wear": PHYSICS | {"motion"},
    "present": LIBRARY,
    "cli": LIBRARY | {"cli", "__init__"},
    "__main__": LIBRARY | {"cli", "__init__"},
    "__init__": LIBRARY | {"cli", "__init__"},
}

#: Imports that break ALLOWED in today's code, as (file under hipsim/, package it imports).
#: The consolidation of issue 25 is removing them: delete each entry as its import goes
#: (test_known_exceptions_still_exist says which), until the set is empty. Never add one.
KNOWN_TODAY: frozenset[tuple[str, str]] = frozenset()

#: Import circles in today's code, each as the set of its modules. Being removed (issue 25):
#: delete each entry as its circle goes, until the set is empty. Never add one.
KNOWN_CYCLES: frozenset[frozenset[str]] = frozenset()

#: The only modules that may load code by name (``importlib``, ``__import__``): the engine registry.
DYNAMIC_IMPORTERS = frozenset({"analysis/registry.py"})
#: importlib's submodules that read data or a distribution's metadata, and load no code.
IMPORTLIB_DATA = frozenset({"importlib.resources", "importlib.metadata"})

#: Third-party packages a package must never import.
FORBIDDEN_THIRD_PARTY = [
    ("analytic", "pinocchio"),
    ("machine", "pinocchio"),
    ("motion", "pinocchio"),
    ("results", "pinocchio"),
    ("physics", "pinocchio"),
    ("analytic", "mujoco"),
]


# --- Reading the imports ----------------------------------------------------------------


@dataclass(frozen=True)
class Import:
    """One import of a module of the package, as found in a file.

    Attributes:
        path: the importing file.
        line: its line number.
        source: the importing module's dotted name ("hipsim.cli.main").
        target: the most specific module of the package it imports ("hipsim.machine.parameters",
            or "hipsim.machine" for a name defined in the package's ``__init__``).
    """

    path: Path
    line: int
    source: str
    target: str


def nodes(path: Path) -> tuple[ast.AST, ...]:
    """The nodes of a file's syntax tree that the checks read, at any depth: parsed once for each content."""
    stat = path.stat()
    return _nodes(path, stat.st_mtime_ns, stat.st_size)


@functools.cache
def _nodes(path: Path, mtime_ns: int, size: int) -> tuple[ast.AST, ...]:
    kinds = (ast.Import, ast.ImportFrom, ast.Call, ast.Name, ast.Attribute)
    return tuple(node for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))) if isinstance(node, kinds))


def files(root: Path) -> list[Path]:
    """Every module file of the package at ``root``."""
    return sorted(path for path in root.rglob("*.py") if "__pycache__" not in path.parts)


def module_name(root: Path, path: Path) -> str:
    """The dotted name of the module in ``path`` ("hipsim.machine" for hipsim/machine/__init__.py)."""
    parts = [root.name, *path.relative_to(root).with_suffix("").parts]
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def package_of(root: Path, path_or_module) -> str:
    """The top-level package (or module) a file or dotted name belongs to: "machine", "files", "__init__"."""
    if isinstance(path_or_module, Path):
        return path_or_module.relative_to(root).parts[0].removesuffix(".py")
    parts = path_or_module.split(".")
    return parts[1] if len(parts) > 1 else "__init__"


def where(root: Path, path: Path, line: int | None = None) -> str:
    name = f"{root.name}/{path.relative_to(root).as_posix()}"
    return name if line is None else f"{name}:{line}"


def imports(root: Path) -> list[Import]:
    """Every import of the package's own modules, in every file, at any depth of the file."""
    modules = {module_name(root, path) for path in files(root)}
    found = []
    for path in files(root):
        source = module_name(root, path)
        # The package a relative import starts from: the module's own for an __init__.py.
        here = source.split(".") if path.name == "__init__.py" else source.split(".")[:-1]
        for node in nodes(path):
            if isinstance(node, ast.Import):
                targets = [alias.name for alias in node.names]
            elif isinstance(node, ast.ImportFrom):
                if node.level:
                    if node.level > len(here):
                        continue  # above the package: not ours
                    parts = here[: len(here) - node.level + 1] + (node.module.split(".") if node.module else [])
                else:
                    parts = node.module.split(".") if node.module else []
                base = ".".join(parts)
                # "from a import b" imports the module a.b when there is one, else a name of a.
                targets = [
                    f"{base}.{alias.name}" if f"{base}.{alias.name}" in modules else base for alias in node.names
                ]
            else:
                continue
            for target in targets:
                if target.split(".")[0] != root.name:
                    continue
                while target not in modules and "." in target:  # "import hipsim.a.b" of a name b
                    target = target.rsplit(".", 1)[0]
                found.append(Import(path, node.lineno, source, target))
    return found


def third_party_imports(path: Path):
    """(line, top-level name) of every absolute import in a file."""
    for node in nodes(path):
        if isinstance(node, ast.Import):
            for alias in node.names:
                yield node.lineno, alias.name
        elif isinstance(node, ast.ImportFrom) and not node.level and node.module:
            for alias in node.names:
                yield node.lineno, f"{node.module}.{alias.name}"


# --- The checks: each returns what breaks a rule, as "file:line: what" -------------------


def unknown_packages(root: Path) -> list[str]:
    """Packages that ALLOWED does not place."""
    return sorted({package_of(root, path) for path in files(root)} - ALLOWED.keys())


def layer_violations(root: Path, known=KNOWN_TODAY) -> list[str]:
    """Imports between packages that ALLOWED does not allow, less the known ones."""
    broken = []
    for imp in imports(root):
        importer, imported = package_of(root, imp.path), package_of(root, imp.target)
        if importer == imported or imported in ALLOWED.get(importer, ()):
            continue
        if (imp.path.relative_to(root).as_posix(), imported) in known:
            continue
        broken.append(f"{where(root, imp.path, imp.line)}: {importer} imports {imported} ({imp.target})")
    return broken


def cycles(root: Path) -> list[frozenset[str]]:
    """Every import circle between the package's modules, as the set of its modules (Tarjan's strongly connected components)."""
    graph: dict[str, set[str]] = {module_name(root, path): set() for path in files(root)}
    for imp in imports(root):
        if imp.target != imp.source:
            graph[imp.source].add(imp.target)
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    found: list[frozenset[str]] = []

    def visit(node):
        index[node] = low[node] = len(index)
        stack.append(node)
        on_stack.add(node)
        for nxt in graph[node]:
            if nxt not in index:
                visit(nxt)
                low[node] = min(low[node], low[nxt])
            elif nxt in on_stack:
                low[node] = min(low[node], index[nxt])
        if low[node] == index[node]:
            component = set()
            while True:
                member = stack.pop()
                on_stack.discard(member)
                component.add(member)
                if member == node:
                    break
            if len(component) > 1:
                found.append(frozenset(component))

    for node in sorted(graph):
        if node not in index:
            visit(node)
    return found


def describe_cycle(root: Path, cycle: frozenset[str]) -> str:
    """A circle's files and the imports that close it."""
    edges = sorted(
        f"  {where(root, imp.path, imp.line)} imports {imp.target}"
        for imp in imports(root)
        if imp.source in cycle and imp.target in cycle and imp.source != imp.target
    )
    return "circle between " + ", ".join(sorted(cycle)) + ":\n" + "\n".join(edges)


def new_cycles(root: Path, known=KNOWN_CYCLES) -> list[str]:
    """Import circles that are not known, each described by its files and imports."""
    return [describe_cycle(root, cycle) for cycle in cycles(root) if cycle not in known]


def dynamic_imports(root: Path) -> list[str]:
    """Uses of ``importlib`` (but its data and metadata readers) or ``__import__`` outside DYNAMIC_IMPORTERS."""
    found = []
    for path in files(root):
        if path.relative_to(root).as_posix() in DYNAMIC_IMPORTERS:
            continue
        for node in nodes(path):
            if isinstance(node, ast.Import):
                names = [alias.name for alias in node.names]
            elif isinstance(node, ast.ImportFrom) and not node.level and node.module:
                names = [f"{node.module}.{alias.name}" for alias in node.names]
            elif isinstance(node, ast.Name) and node.id == "__import__":
                names = ["__import__"]
            elif isinstance(node, ast.Attribute) and node.attr == "__import__":
                names = ["__import__"]
            else:
                continue
            for name in names:
                if name == "__import__" or (
                    name.split(".")[0] == "importlib"
                    and not any(name == data or name.startswith(data + ".") for data in IMPORTLIB_DATA)
                ):
                    found.append(f"{where(root, path, node.lineno)}: {name}")
    return found


def forbidden_imports(root: Path, package: str, forbidden: str) -> list[str]:
    """Imports of the third-party ``forbidden`` in ``package``."""
    return [
        where(root, path, line)
        for path in files(root)
        if package_of(root, path) == package
        for line, name in third_party_imports(path)
        if name.split(".")[0] == forbidden
    ]


def imports_of_present(root: Path, packages=("analysis", "rig", "design", "stations")) -> list[str]:
    """Imports of ``present`` in the packages that return data."""
    return [
        f"{where(root, imp.path, imp.line)}: {package_of(root, imp.path)} imports present"
        for imp in imports(root)
        if package_of(root, imp.path) in packages and package_of(root, imp.target) == "present"
    ]


def printing_calls(path: Path, streams=("stdout", "stderr", "stdin")):
    """Lines that print: print(), input(), and uses of the named sys streams."""
    for node in nodes(path):
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id in ("print", "input"):
            yield node.lineno
        if (
            isinstance(node, ast.Attribute)
            and node.attr in streams
            and isinstance(node.value, ast.Name)
            and node.value.id == "sys"
        ):
            yield node.lineno


def printing_outside_cli(root: Path) -> list[str]:
    """Lines outside ``cli`` that print or read the terminal (``files`` may write a result to standard output)."""
    found = []
    for path in files(root):
        package = package_of(root, path)
        if package in ("cli", "__main__"):
            continue
        streams = ("stderr", "stdin") if package == "files" else ("stdout", "stderr", "stdin")
        found += [where(root, path, line) for line in printing_calls(path, streams)]
    return found


# --- The tests ----------------------------------------------------------------------------


def test_every_module_belongs_to_a_layer():
    unknown = unknown_packages(PACKAGE)
    assert not unknown, f"add these to ALLOWED and to the README's layout section: {unknown}"


def test_every_import_between_packages_is_allowed():
    broken = layer_violations(PACKAGE)
    assert not broken, "imports that ALLOWED does not allow:\n" + "\n".join(broken)


def test_no_import_circle():
    found = new_cycles(PACKAGE)
    assert not found, "\n".join(found)


def test_no_dynamic_import_outside_the_engine_registry():
    found = dynamic_imports(PACKAGE)
    assert not found, f"importlib / __import__ only in {sorted(DYNAMIC_IMPORTERS)}:\n" + "\n".join(found)


def test_known_exceptions_still_exist():
    """KNOWN_TODAY and KNOWN_CYCLES hold only what the code still does: each entry gone is deleted."""
    edges = {(imp.path.relative_to(PACKAGE).as_posix(), package_of(PACKAGE, imp.target)) for imp in imports(PACKAGE)}
    gone_edges = sorted(KNOWN_TODAY - edges)
    gone_cycles = [sorted(cycle) for cycle in KNOWN_CYCLES - set(cycles(PACKAGE))]
    assert not gone_edges, f"these imports are gone: delete them from KNOWN_TODAY: {gone_edges}"
    assert not gone_cycles, f"these circles are gone (or changed): delete them from KNOWN_CYCLES: {gone_cycles}"


@pytest.mark.parametrize(("package", "forbidden"), FORBIDDEN_THIRD_PARTY)
def test_the_analytic_side_never_imports_pinocchio(package, forbidden):
    found = forbidden_imports(PACKAGE, package, forbidden)
    assert not found, found


def test_analysis_rig_and_design_never_import_present():
    found = imports_of_present(PACKAGE)
    assert not found, "\n".join(found)


def test_only_the_cli_prints():
    """Only hipsim.cli talks to the terminal; hipsim.files may write a result to standard output (``--out -``), nothing else."""
    found = printing_outside_cli(PACKAGE)
    assert not found, "only hipsim.cli prints or reads the terminal:\n" + "\n".join(found)


# --- The test of the tests ------------------------------------------------------------------


def plant(path: Path, text: str) -> None:
    """Append ``text`` to the module at ``path`` (creating it if need be)."""
    before = path.read_text(encoding="utf-8").rstrip("\n") + "\n" if path.exists() else ""
    path.write_text(before + text, encoding="utf-8")


def test_the_rules_catch_planted_violations(tmp_path):
    """Each check passes on an unchanged copy of the package and fails on each violation planted in it."""
    root = tmp_path / "hipsim"
    shutil.copytree(PACKAGE, root, ignore=shutil.ignore_patterns("__pycache__"))
    assert not unknown_packages(root)
    assert not layer_violations(root)
    assert not new_cycles(root)
    assert not dynamic_imports(root)
    assert not printing_outside_cli(root)

    plant(root / "motion" / "__init__.py", "from ..machine import parameters as _planted\n")
    plant(root / "mujoco_engine" / "__init__.py", "import hipsim.closed_chain\n")
    plant(root / "machine" / "__init__.py", "def _planted():\n    from hipsim.motion import trajectories\n")
    plant(root / "rig" / "__init__.py", "from .. import design as _planted\n")
    plant(root / "physics" / "laws.py", "import importlib\n")
    plant(root / "physics" / "vectors.py", "def _planted():\n    return __import__('os')\n")
    # A circle inside physics, closed by an import inside a function.
    plant(root / "physics" / "planted_a.py", "from . import planted_b\n")
    plant(root / "physics" / "planted_b.py", "def f():\n    from .planted_a import g\n    return g\n")
    plant(root / "analytic" / "planted.py", "import pinocchio as pin\nprint('hello')\n")
    plant(root / "rig" / "planted.py", "from hipsim.present import figures\n")

    broken = "\n".join(layer_violations(root))
    for expected in [
        "hipsim/motion/__init__.py:",
        "motion imports machine",
        "hipsim/mujoco_engine/__init__.py:",
        "mujoco_engine imports closed_chain",
        "hipsim/machine/__init__.py:",
        "machine imports motion",
        "rig imports design",
    ]:
        assert expected in broken, (expected, broken)
    assert [cycle for cycle in cycles(root) if cycle not in KNOWN_CYCLES] == [
        frozenset({"hipsim.physics.planted_a", "hipsim.physics.planted_b"})
    ]
    described = "\n".join(new_cycles(root))
    assert "hipsim/physics/planted_a.py:1 imports hipsim.physics.planted_b" in described
    assert "hipsim/physics/planted_b.py:2 imports hipsim.physics.planted_a" in described
    dynamic = "\n".join(dynamic_imports(root))
    assert "hipsim/physics/laws.py:" in dynamic and ": importlib" in dynamic
    assert "hipsim/physics/vectors.py:" in dynamic and ": __import__" in dynamic
    assert forbidden_imports(root, "analytic", "pinocchio") == ["hipsim/analytic/planted.py:1"]
    assert imports_of_present(root) == ["hipsim/rig/planted.py:1: rig imports present"]
    assert printing_outside_cli(root) == ["hipsim/analytic/planted.py:2"]
    # An unknown package, and the registry's licence to import by name.
    plant(root / "newcomer.py", "import importlib\n")
    assert unknown_packages(root) == ["newcomer"]
    plant(root / "analysis" / "registry.py", "import importlib\n")
    assert "registry.py" not in "\n".join(dynamic_imports(root))
