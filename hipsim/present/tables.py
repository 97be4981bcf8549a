"""Plain-text tables: columns aligned for a terminal, and the number formats their cells use.

The command line prints what these functions return; nothing here prints.
"""

from __future__ import annotations

import math

__all__ = ["format_margin", "format_quantity", "format_table"]


def format_table(header: list[str], rows: list[list], title: str = "") -> str:
    """A table as text: the first column left-aligned, the others right-aligned, a rule under the header.

    Args:
        header: the column names.
        rows: one list of cells a row; a cell is text as it stands or a number printed with two decimals.
        title: a line above the table; none when empty.
    """
    cells = [header] + [[c if isinstance(c, str) else f"{c:.2f}" for c in row] for row in rows]
    widths = [max(len(row[k]) for row in cells) for k in range(len(header))]
    lines = [title] if title else []
    for n, row in enumerate(cells):
        lines.append("  ".join(c.rjust(w) if k else c.ljust(w) for k, (c, w) in enumerate(zip(row, widths))))
        if n == 0:
            lines.append("  ".join("-" * w for w in widths))
    return "\n".join(lines)


def format_quantity(value: float | None, unit: str) -> str:
    """A checked value or limit in its unit: three significant digits (whole numbers from 100 up), — when unknown, ∞ when unbounded.

    Args:
        value: the number in ``unit``; None when unknown.
        unit: the unit's label; ``"cycles"`` prints without thousands separators.
    """
    if value is None:
        return "—"
    if math.isinf(value):
        return "∞" if value > 0 else "−∞"
    if unit == "cycles":
        return f"{value:.3g}"
    return f"{value:,.3g}" if abs(value) < 100 else f"{value:,.0f}"


def format_margin(margin: float | None) -> str:
    """A margin as a signed percentage of its limit (margin: a fraction; None when unknown)."""
    if margin is None:
        return "—"
    return "−∞" if math.isinf(margin) else f"{100 * margin:+.1f} %"
