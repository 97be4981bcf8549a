"""Wear laws: the volume a cycle wears from each point's work or sliding, and the cup's total.

- :class:`WearFactor` (Archard, a local factor as pin-on-disc tests give it): depth per cycle k·W, k in
  [mm³/(N·m)], so V = ∫k·W dA (a simulator's global factor, V = k·∫F ds, is
  :class:`~hipsim.wear.factors.ForceTrackFactor`: never mix the two);
- :class:`CrossShearLaw`: the same with k(CS) interpolated linearly in a table
  of k against CS (Kang et al.: the wear factor of UHMWPE rises with CS);
  beyond the table's CS the end values hold, and :class:`Wear` counts the points so held;
- :class:`ContactAreaLaw` (Liu, Fisher & Jin 2012, V = C·A·s): depth per
  cycle C·s_loaded, C dimensionless, s_loaded the sliding while in contact.

No default factor: a law is what a user gives and cites.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Protocol

import numpy as np

from ..exceptions import ArgumentError, FileRowError
from ..plausibility import factor_name, unit_slip
from ..tables import cells, data_lines, detect_separator, number, read_text_lines
from .maps import WearMaps

__all__ = [
    "ContactAreaLaw",
    "CrossShearLaw",
    "Wear",
    "WearFactor",
    "WearLaw",
    "predict_wear",
    "read_numeric_columns",
    "read_wear_law",
]

#: mm of depth per cycle from k [mm³/(N·m)] times W [N/mm]: (mm³/(N·m))·(N/mm) = mm²/m.
_DEPTH_PER_KW = 1e-3
#: Cycles in a million cycles (Mc).
MC = 1e6


class WearLaw(Protocol):
    """A wear law: the depth each point loses per cycle, from its sums."""

    def describe(self) -> str:
        """The law in words, with its constants and units."""
        ...

    def depth_mm(self, maps: WearMaps) -> np.ndarray:
        """Depth worn per cycle in [mm], (P,)."""
        ...


@dataclass(frozen=True)
class WearFactor:
    """Archard's law with a constant local wear factor k in [mm³/(N·m)]: V = ∫k·W dA per cycle."""

    k: float

    def __post_init__(self):
        if isinstance(self.k, bool) or not (math.isfinite(self.k) and self.k >= 0):
            raise ArgumentError("wear factor", self.k, "a wear factor k ≥ 0 in mm³/(N·m)")

    def describe(self) -> str:
        return f"local (Archard, pin-on-disc: V = ∫k·W dA), k = {self.k:.4g} mm³/(N·m)"

    def depth_mm(self, maps: WearMaps) -> np.ndarray:
        return _DEPTH_PER_KW * self.k * maps.work_N_per_mm


@dataclass(frozen=True, eq=False)
class CrossShearLaw:
    """Archard's law with k(CS) from a table (module docstring).

    Attributes:
        cross_shear: CS, strictly increasing, (K,).
        k: the wear factor at each in [mm³/(N·m)], ≥ 0, (K,).
        source: the table's file, for messages.
    """

    cross_shear: np.ndarray
    k: np.ndarray
    source: str = "wear law"

    def __post_init__(self):
        cs, k = np.asarray(self.cross_shear, dtype=float), np.asarray(self.k, dtype=float)
        if cs.ndim != 1 or cs.shape != k.shape or cs.size < 1:
            raise ArgumentError(self.source, cs, "a table of CS and k, one k per CS")
        if not (np.all(np.isfinite(cs)) and np.all(np.isfinite(k))):
            raise ArgumentError(self.source, cs, "finite CS and k")
        if np.any(np.diff(cs) <= 0):
            j = int(np.argmax(np.diff(cs) <= 0)) + 1
            raise ArgumentError(
                f"{self.source}, row {j + 1}", float(cs[j]), f"CS increasing (the row before has {cs[j - 1]:g})"
            )
        if np.any(k < 0):
            j = int(np.argmax(k < 0))
            raise ArgumentError(f"{self.source}, row {j + 1}", float(k[j]), "a wear factor k ≥ 0 in mm³/(N·m)")
        object.__setattr__(self, "cross_shear", cs)
        object.__setattr__(self, "k", k)

    def describe(self) -> str:
        return (
            f"local (Archard) with k(CS) from {self.source} ({self.cross_shear.size} rows, CS {self.cross_shear[0]:g} to "
            f"{self.cross_shear[-1]:g}, k {self.k.min():.4g} to {self.k.max():.4g} mm³/(N·m))"
        )

    def factor(self, cross_shear: np.ndarray) -> np.ndarray:
        """k at each CS in [mm³/(N·m)], linear between rows, the end values beyond them; 0 where CS is NaN (no work)."""
        return np.where(np.isnan(cross_shear), 0.0, np.interp(np.nan_to_num(cross_shear), self.cross_shear, self.k))

    def beyond(self, maps: WearMaps) -> int:
        """Points whose CS lies outside the table (their k held at its end value)."""
        cs = maps.cross_shear[maps.loaded]
        return int(np.sum((cs < self.cross_shear[0]) | (cs > self.cross_shear[-1])))

    def depth_mm(self, maps: WearMaps) -> np.ndarray:
        return _DEPTH_PER_KW * self.factor(maps.cross_shear) * maps.work_N_per_mm


@dataclass(frozen=True)
class ContactAreaLaw:
    """Liu, Fisher & Jin (2012): V = C·A·s with a dimensionless wear coefficient C."""

    C: float

    def __post_init__(self):
        if isinstance(self.C, bool) or not (math.isfinite(self.C) and self.C >= 0):
            raise ArgumentError("wear coefficient", self.C, "a dimensionless wear coefficient C ≥ 0")

    def describe(self) -> str:
        return f"contact area (V = C·A·s), C = {self.C:.4g}"

    def depth_mm(self, maps: WearMaps) -> np.ndarray:
        return self.C * maps.sliding_loaded_mm


@dataclass(frozen=True, eq=False)
class Wear:
    """A law's prediction.

    Attributes:
        law: the law, in words.
        depth_um_per_Mc: depth per million cycles in [µm], (P,).
        volume_mm3_per_Mc: each point's cell's volume per million cycles in [mm³], (P,); None for points without cells.
        total_mm3_per_Mc: the cup's volume per million cycles in [mm³]; None for points without cells.
        beyond_table: points whose CS lay outside a table's range (their k held at its end).
    """

    law: str
    depth_um_per_Mc: np.ndarray
    volume_mm3_per_Mc: np.ndarray | None
    total_mm3_per_Mc: float | None
    beyond_table: int = 0


def predict_wear(maps: WearMaps, law: WearLaw) -> Wear:
    """The wear ``law`` predicts from ``maps``: V = Σ depth·dA over the cup (the grid's cells)."""
    depth = law.depth_mm(maps)
    area = maps.points.area_mm2
    volume = None if area is None else depth * area * MC
    total = None if volume is None else float(np.sum(volume))
    beyond = law.beyond(maps) if isinstance(law, CrossShearLaw) else 0
    return Wear(law.describe(), depth * MC * 1e3, volume, total, beyond)


def read_numeric_columns(path: str | Path, names: tuple[str, ...], what: str) -> tuple[np.ndarray, np.ndarray]:
    """The named columns of a small CSV table (comma, semicolon or tab; ``#`` comments), as floats (rows, columns),
    and each row's 1-based line in the file.

    Raises:
        FileRowError: naming the file, line and column: a missing column, a cell that is not a number, no rows.
    """
    source = str(path)
    rows = data_lines(read_text_lines(path, what, FileRowError))
    if not rows:
        raise FileRowError(f"an empty {what}: expected a header {', '.join(names)} and rows", source=source)
    separator = detect_separator(rows[0][1], rows[1][1] if len(rows) > 1 else None)
    header = [cell.strip() for cell in cells(rows[0][1], separator)]
    missing = [name for name in names if name not in header]
    if missing:
        raise FileRowError(
            f"no column {', '.join(missing)} (the header has {', '.join(header)})", source=source, line=rows[0][0]
        )
    index = [header.index(name) for name in names]
    if len(rows) < 2:
        raise FileRowError(f"the {what} has a header and no rows", source=source, line=rows[0][0])
    out = np.empty((len(rows) - 1, len(names)))
    lines = np.array([line for line, _ in rows[1:]])
    for r, (line, text) in enumerate(rows[1:]):
        row = cells(text, separator)
        for c, (name, j) in enumerate(zip(names, index, strict=True)):
            try:
                out[r, c] = number(row[j])
            except (IndexError, ValueError):
                cell = row[j] if j < len(row) else ""
                raise FileRowError(f"expected a number, got '{cell}'", source=source, line=line, column=name) from None
            if not math.isfinite(out[r, c]):
                raise FileRowError(f"expected a finite number, got '{row[j]}'", source=source, line=line, column=name)
    return out, lines


#: The columns of a wear-law table.
LAW_COLUMNS = ("cross_shear", "k_mm3_per_Nm")


def read_wear_law(path: str | Path) -> CrossShearLaw:
    """A table of k against CS (columns ``cross_shear``, ``k_mm3_per_Nm``), checked: CS increasing, k ≥ 0.

    Raises:
        FileRowError: as :func:`read_numeric_columns`, or a row out of order or with a negative k, by its line.
    """
    table, lines = read_numeric_columns(path, LAW_COLUMNS, "wear-law table")
    cs, k = table[:, 0], table[:, 1]
    for j in range(1, cs.size):
        if cs[j] <= cs[j - 1]:
            raise FileRowError(
                f"CS {cs[j]:g} does not increase (the row before has {cs[j - 1]:g}): list CS in increasing order",
                source=str(path),
                line=int(lines[j]),
                column=LAW_COLUMNS[0],
            )
    for j in range(k.size):
        if k[j] < 0:
            raise FileRowError(
                f"a negative wear factor {k[j]:g} mm³/(N·m): k is at least 0",
                source=str(path),
                line=int(lines[j]),
                column=LAW_COLUMNS[1],
            )
    _check_units(path, cs, k, lines)
    return CrossShearLaw(cs, k, str(path))


#: Cross-shear is a ratio of at most 0.5 (Kang): a table reaching beyond 1 is in per cent.
CS_MAX = 0.5
#: UHMWPE's wear factors in [mm³/(N·m)] (1e-8 to 1e-6, with a decade's margin each way): a table 1000 times off is a unit.
K_PLAUSIBLE = (1e-9, 1e-5)
#: No wear factor in [mm³/(N·m)] is above this (``--wear-factor``'s hard range).
K_MAX = 1e-3


def _check_units(path, cs: np.ndarray, k: np.ndarray, lines) -> None:
    """Refuse a wear-law table in per cent of cross-shear, or with k per N·mm (or m³), naming the row (issue 48)."""
    j = int(np.argmax(cs))
    if cs[j] > 1.0:
        raise FileRowError(
            f"cross-shear {cs[j]:g}: CS is a ratio from 0 to {CS_MAX:g}; is the column in per cent? (divide by 100)",
            source=str(path),
            line=int(lines[j]),
            column=LAW_COLUMNS[0],
        )
    positive = k[k > 0]
    if positive.size == 0:
        return
    low, high = K_PLAUSIBLE
    worst = float(positive.max()) if positive.max() > high else float(positive.min())
    slip = unit_slip(worst, low, high)
    if slip is None and worst > K_MAX:  # no unit explains it: no material wears so
        slip = worst / high
    if slip is not None:
        j = int(np.flatnonzero(k == worst)[0])
        hint = (
            "given per N·mm: give it per N·m (1000 times the figure)" if slip < 1 else "1000 times too large (a unit?)"
        )
        raise FileRowError(
            f"a wear factor {worst:g} mm³/(N·m) is {factor_name(slip)} UHMWPE's ({low:g} to {high:g}): k looks {hint}",
            source=str(path),
            line=int(lines[j]),
            column=LAW_COLUMNS[1],
        )
