"""The package's structure in figures anyone can rerun: the largest modules, import circles, layer violations.

    python scripts/structure.py [CHECKOUT]     (default: this repository; another checkout to compare, e.g. an old commit's worktree)

It reads the same rules as tests/test_layers.py (the table of allowed imports
between packages, circles between modules counting imports inside functions),
so the figures are the ones the suite holds the code to.
"""

from __future__ import annotations

import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))

import test_layers as layers  # noqa: E402


def main(argv: list[str]) -> int:
    checkout = Path(argv[0]).resolve() if argv else ROOT
    package = checkout / "hipsim"
    sizes = sorted(
        (
            (len(path.read_text(encoding="utf-8").splitlines()), path.relative_to(checkout))
            for path in package.rglob("*.py")
        ),
        reverse=True,
    )
    print(f"modules: {len(sizes)}, lines: {sum(n for n, _ in sizes):,}")
    print("largest modules:")
    for lines, path in sizes[:5]:
        print(f"  {lines:5d}  {path}")
    circles = layers.cycles(package)
    print(f"import circles between modules: {len(circles)}")
    for circle in circles:
        print("  " + " -> ".join(sorted(circle)))
    violations = layers.layer_violations(package, known=frozenset())
    print(f"imports the layer table does not allow: {len(violations)}")
    for line in violations:
        print(f"  {line}")
    return 1 if circles or violations or sizes[0][0] > 600 else 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
