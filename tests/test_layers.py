"""The package's layers, read from its imports: each rule of the README's layout section, as a test."""

import ast
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[1] / "hipsim"

#: Lowest first. A module may import its own layer and the layers below it, never one above.
LAYERS = [
    {"exceptions", "arrays", "files", "tables", "fingerprint"},
    {"physics"},
    {"machine", "motion"},
    {"results", "engine"},
    {"analytic"},
    {"closed_chain", "mujoco_engine"},
    {"control"},
    {"analysis"},
    {"rig", "design"},
    {"present"},
    {"cli", "__main__", "__init__"},
]
RANK = {name: rank for rank, names in enumerate(LAYERS) for name in names}


def modules():
    for path in sorted(PACKAGE.rglob("*.py")):
        yield path, path.relative_to(PACKAGE).parts[0].removesuffix(".py")


def hipsim_imports(path: Path):
    """(line, first part under hipsim) of every import of hipsim, at any depth of the file."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    depth = len(path.relative_to(PACKAGE).parts) - 1  # package depth below hipsim
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            if node.level:  # relative: climb to hipsim, then name the subpackage
                climbed = node.level - 1
                here = list(path.relative_to(PACKAGE).parts[:-1])
                if climbed > depth:
                    continue
                base = here[: depth - climbed] + (node.module.split(".") if node.module else [])
                if not base:  # "from .. import x": x is the subpackage
                    for alias in node.names:
                        yield node.lineno, alias.name
                else:
                    yield node.lineno, base[0]
            elif node.module and node.module.split(".")[0] == "hipsim":
                parts = node.module.split(".")
                yield node.lineno, parts[1] if len(parts) > 1 else "__init__"
        elif isinstance(node, ast.Import):
            for alias in node.names:
                parts = alias.name.split(".")
                if parts[0] == "hipsim":
                    yield node.lineno, parts[1] if len(parts) > 1 else "__init__"


def third_party_imports(path: Path):
    tree = ast.parse(path.read_text(encoding="utf-8"))
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for alias in node.names:
                yield node.lineno, alias.name.split(".")[0]
        elif isinstance(node, ast.ImportFrom) and not node.level and node.module:
            yield node.lineno, node.module.split(".")[0]


def test_every_module_belongs_to_a_layer():
    unknown = {layer for _, layer in modules() if layer not in RANK}
    assert not unknown, f"add these to LAYERS and to the README's layout section: {sorted(unknown)}"


def test_no_layer_imports_a_higher_one():
    broken = []
    for path, layer in modules():
        for line, imported in hipsim_imports(path):
            if imported in RANK and RANK[imported] > RANK[layer]:
                broken.append(f"{path.relative_to(PACKAGE.parent)}:{line}: {layer} imports {imported}")
    assert not broken, "\n".join(broken)


@pytest.mark.parametrize(
    "layer, forbidden",
    [("analytic", "pinocchio"), ("machine", "pinocchio"), ("motion", "pinocchio"), ("results", "pinocchio"), ("analytic", "mujoco")],
)
def test_the_analytic_side_never_imports_pinocchio(layer, forbidden):
    found = [
        f"{path.relative_to(PACKAGE.parent)}:{line}"
        for path, name in modules() if name == layer
        for line, module in third_party_imports(path) if module == forbidden
    ]
    assert not found, found


def test_analysis_never_imports_present():
    found = [
        f"{path.relative_to(PACKAGE.parent)}:{line}"
        for path, layer in modules() if layer == "analysis"
        for line, imported in hipsim_imports(path) if imported == "present"
    ]
    assert not found, found


def printing_calls(path: Path, streams=("stdout", "stderr", "stdin")):
    """Lines that print: print(), input(), and uses of the named sys streams."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    for node in ast.walk(tree):
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id in ("print", "input"):
            yield node.lineno
        if isinstance(node, ast.Attribute) and node.attr in streams and isinstance(node.value, ast.Name) and node.value.id == "sys":
            yield node.lineno


def test_only_the_cli_prints():
    """Only hipsim.cli talks to the terminal; hipsim.files may write a result to standard output (``--out -``), nothing else."""
    found = [
        f"{path.relative_to(PACKAGE.parent)}:{line}"
        for path, layer in modules() if layer not in ("cli", "__main__")
        for line in printing_calls(path, ("stderr", "stdin") if layer == "files" else ("stdout", "stderr", "stdin"))
    ]
    assert not found, "only hipsim.cli prints or reads the terminal:\n" + "\n".join(found)


def test_the_rules_catch_a_violation(tmp_path, monkeypatch):
    """The checks above can fail: a planted upward import and a planted print are found."""
    fake = tmp_path / "hipsim"
    (fake / "analytic").mkdir(parents=True)
    (fake / "analytic" / "bad.py").write_text("import pinocchio\nfrom ..present import viewer\nprint('hello')\n")
    monkeypatch.setattr(__import__(__name__), "PACKAGE", fake)
    with pytest.raises(AssertionError, match="analytic imports present"):
        test_no_layer_imports_a_higher_one()
    with pytest.raises(AssertionError, match="bad.py:1"):
        test_the_analytic_side_never_imports_pinocchio("analytic", "pinocchio")
    with pytest.raises(AssertionError, match="bad.py:3"):
        test_only_the_cli_prints()
