"""mkdocs hook: expand ``<!-- api: hipsim.PACKAGE -->`` into mkdocstrings directives for the package and its modules.

The modules are found on disk, not listed by hand, so a module that is split,
added or renamed shows up in the reference without editing the page. A package
gets its docstring; each of its public modules (no leading underscore) gets its
docstring and the members of its ``__all__`` (mkdocstrings' ``filters: public``).
Nothing is imported: griffe reads the source, so optional extras (MuJoCo) need
not be installed to build the docs.
"""

from __future__ import annotations

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
_MARKER = re.compile(r"^<!-- api: (hipsim(?:\.\w+)*) -->$", re.M)


def modules(package: str) -> list[str]:
    """The dotted names of a package's public modules, sorted (the package itself not included)."""
    folder = ROOT.joinpath(*package.split("."))
    if not folder.is_dir():
        return []
    return sorted(f"{package}.{path.stem}" for path in folder.glob("*.py") if not path.stem.startswith("_"))


def directives(package: str) -> str:
    """The mkdocstrings directives of one package (or plain module): its own page, then one section per module."""
    subs = modules(package)
    if not subs:  # a plain module: its members
        return f"::: {package}\n    options:\n      show_root_heading: false\n      show_root_toc_entry: false\n"
    parts = [
        f"::: {package}\n    options:\n      members: false\n      show_root_heading: false\n      show_root_toc_entry: false\n"
    ]
    parts += [f"::: {name}\n" for name in subs]
    return "\n".join(parts)


def on_page_markdown(markdown: str, page, config, files) -> str:  # mkdocs' signature
    """Replace each API marker on a page by its directives."""
    return _MARKER.sub(lambda match: directives(match.group(1)), markdown)
