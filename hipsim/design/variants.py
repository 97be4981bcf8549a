"""Design variants for a sweep: a grid, a Latin hypercube, a tolerance study, or a CSV file of parameter values.

A variant is a set of values for a few keys of the parameter file, in the
file's units (``lever.length_mm``, ``platform.home_offset_deg``, …), the keys
``--set`` takes. A key naming a list in the file takes one of its numbers
with a 1-based index, as the file's comments count them:
``platform.heights_mm[2]`` is h_2. The values are only generated here; each
is checked when the variant's machine is built
(:func:`hipsim.machine.parameters.override_parameters`), so an impossible
variant is a result of the sweep, not an error.

Example:
    >>> from hipsim.design.variants import grid
    >>> grid({"lever.length_mm": (300.0, 360.0, 30.0)}).values.ravel().tolist()
    [300.0, 330.0, 360.0]
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..arrays import readonly
from ..exceptions import ArgumentError, FileRowError, ParameterError
from ..machine.parameters import SCHEMA, Parameters, check_key, file_values
from ..tables import cells, data_lines, detect_separator, number, read_text_lines

__all__ = [
    "MAX_VARIANTS",
    "KeyRef",
    "Variants",
    "grid",
    "key_ref",
    "latin_hypercube",
    "nominal",
    "parse_axis",
    "parse_tolerance",
    "read_variants",
    "tolerance_study",
]

#: The most variants one sweep generates (a typo in a step is caught before memory is).
MAX_VARIANTS = 10_000_000


@dataclass(frozen=True)
class KeyRef:
    """One swept number of the parameter file.

    Attributes:
        name: as typed, e.g. ``"lever.length_mm"`` or ``"platform.heights_mm[2]"``.
        dotted: the file's key, e.g. ``"platform.heights_mm"``.
        index: the 0-based position in a list key, or None for a single number.
    """

    name: str
    dotted: str
    index: int | None = None


def key_ref(name: str, source: str = "sweep") -> KeyRef:
    """A swept key checked against the parameter file's keys.

    Args:
        name: ``section.key`` of a number, or ``section.key[i]`` (i from 1) of one number of a list.
        source: where it was given, for errors (the command line says the option).

    Raises:
        ParameterError: naming the key when it is unknown, not a number, or its index is out of the list.
    """
    match = re.fullmatch(r"\s*([^\[\]\s]+)\s*(?:\[\s*(\d+)\s*\])?\s*", name)
    if not match:
        raise ParameterError(
            "expected section.key or section.key[i], e.g. lever.length_mm or platform.heights_mm[2]",
            key=name,
            source=source,
        )
    dotted, index = match.group(1), match.group(2)
    section, key = check_key(dotted, source)
    spec = SCHEMA[section][key]
    if spec.kind == "float":
        if index is not None:
            raise ParameterError("is a single number: give it without [i]", key=name, source=source)
        return KeyRef(f"{dotted}", dotted)
    if spec.kind == "vector":
        if index is None:
            raise ParameterError(
                f"is a list of {spec.length} numbers: sweep one at a time, e.g. {dotted}[1]", key=name, source=source
            )
        if not 1 <= int(index) <= spec.length:
            raise ParameterError(
                f"index {index} is out of the list of {spec.length} numbers (counted from 1)", key=name, source=source
            )
        return KeyRef(f"{dotted}[{int(index)}]", dotted, int(index) - 1)
    raise ParameterError(
        f"cannot be swept (a {spec.kind}); a sweep varies numbers and numbers of lists", key=name, source=source
    )


@dataclass(frozen=True, eq=False)
class Variants:
    """Variants of a machine: one row of values per variant, one column per key.

    Attributes:
        keys: the swept keys.
        values: (n, k) values in the file's units (the unit is in each key's name).
    """

    keys: tuple[KeyRef, ...]
    values: np.ndarray

    def __post_init__(self):
        values = readonly(
            np.asarray(self.values, dtype=float).reshape(-1, len(self.keys)) if self.keys else np.zeros((0, 0))
        )
        names = [k.name for k in self.keys]
        if len(set(names)) != len(names):
            raise ArgumentError("keys", names, "each key once")
        if not np.all(np.isfinite(values)):
            raise ArgumentError("values", values, "finite numbers")
        object.__setattr__(self, "values", values)

    def __len__(self) -> int:
        return self.values.shape[0]

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(k.name for k in self.keys)


def nominal(params: Parameters, keys: Sequence[KeyRef]) -> np.ndarray:
    """The machine's own values of the keys, in the file's units, (k,)."""
    values = file_values(params)
    return np.array([values[k.dotted] if k.index is None else values[k.dotted][k.index] for k in keys], dtype=float)


def _count(total: int) -> None:
    if total > MAX_VARIANTS:
        raise ArgumentError("variants", total, f"at most {MAX_VARIANTS:,}")


def _tidy(values: np.ndarray) -> np.ndarray:
    """Round-off of start + k·step cleaned to 12 significant digits: 0.1·3 is 0.3, as typed."""
    return np.array([float(f"{x:.12g}") for x in np.ravel(values)]).reshape(np.shape(values))


def grid(axes: Mapping[str | KeyRef, tuple[float, float, float]]) -> Variants:
    """Every combination of evenly spaced values, the stop included.

    Args:
        axes: per key (start, stop, step) in the key's file unit; stop is
            included when it lies on the grid (to 1e-9 of a step).

    Raises:
        ArgumentError: a step that is not positive, a stop below the start, or too many variants.
    """
    keys, columns = [], []
    for name, (start, stop, step) in axes.items():
        key = name if isinstance(name, KeyRef) else key_ref(name)
        if not all(map(math.isfinite, (start, stop, step))) or step <= 0 or stop < start:
            raise ArgumentError(
                key.name, f"{start:g}:{stop:g}:{step:g}", "START:STOP:STEP with STOP >= START and STEP > 0"
            )
        n = math.floor((stop - start) / step + 1e-9) + 1
        _count(n)
        keys.append(key)
        columns.append(_tidy(start + step * np.arange(n)))
    _count(math.prod(len(c) for c in columns))
    mesh = np.meshgrid(*columns, indexing="ij") if columns else []
    return Variants(tuple(keys), np.stack([m.ravel() for m in mesh], axis=1) if columns else np.zeros((0, 0)))


def latin_hypercube(ranges: Mapping[str | KeyRef, tuple[float, float]], count: int, seed: int | None = 1) -> Variants:
    """A Latin hypercube sample (scipy.stats.qmc) of ``count`` variants over the ranges.

    Args:
        ranges: per key (low, high) in the key's file unit.
        count: number of variants.
        seed: the random generator's seed (the same seed gives the same variants).

    Raises:
        ArgumentError: a range with high not above low, or a count below 1.
    """
    from scipy.stats import qmc

    keys, low, high = _ranges(ranges)
    _positive_count(count)
    rng = np.random.default_rng(seed)
    try:
        engine = qmc.LatinHypercube(d=len(keys), rng=rng)
    except TypeError:  # SciPy before 1.15 calls it seed
        engine = qmc.LatinHypercube(d=len(keys), seed=rng)
    sample = engine.random(count)
    return Variants(keys, qmc.scale(sample, low, high))


def _ranges(ranges) -> tuple[tuple[KeyRef, ...], np.ndarray, np.ndarray]:
    keys, low, high = [], [], []
    for name, (lo, hi) in ranges.items():
        key = name if isinstance(name, KeyRef) else key_ref(name)
        if not (math.isfinite(lo) and math.isfinite(hi) and hi > lo):
            raise ArgumentError(key.name, f"{lo:g}:{hi:g}", "LOW:HIGH with HIGH > LOW")
        keys.append(key)
        low.append(lo)
        high.append(hi)
    if not keys:
        raise ArgumentError("ranges", {}, "at least one key")
    return tuple(keys), np.array(low), np.array(high)


def _positive_count(count: int) -> None:
    if not (isinstance(count, (int, np.integer)) and count >= 1):
        raise ArgumentError("count", count, "a whole number of variants, at least 1")
    _count(int(count))


def tolerance_study(
    params: Parameters, tolerances: Mapping[str | KeyRef, tuple[str, float]], count: int, seed: int | None = 1
) -> Variants:
    """Random variants around the machine's own values: machining and assembly tolerances.

    Args:
        params: the nominal machine.
        tolerances: per key ("normal", σ) for a normal spread of standard
            deviation σ, or ("uniform", x) for a uniform spread within ±x, in the key's file unit.
        count: number of variants.
        seed: the random generator's seed.

    Raises:
        ArgumentError: a spread that is not positive, or a count below 1.
    """
    _positive_count(count)
    keys = tuple(name if isinstance(name, KeyRef) else key_ref(name) for name in tolerances)
    if not keys:
        raise ArgumentError("tolerances", {}, "at least one key")
    centre = nominal(params, keys)
    rng = np.random.default_rng(seed)
    columns = []
    for key, (kind, width) in zip(keys, tolerances.values()):
        if kind not in ("normal", "uniform") or not (math.isfinite(width) and width > 0):
            raise ArgumentError(key.name, f"{kind} {width:g}", "a positive σ (normal) or ±x (uniform)")
        columns.append(rng.normal(0.0, width, count) if kind == "normal" else rng.uniform(-width, width, count))
    return Variants(keys, centre + np.stack(columns, axis=1))


def parse_axis(text: str, option: str, parts: int) -> tuple[str, list[float]]:
    """``KEY=A:B[:C]`` → the key and its ``parts`` numbers (``--grid`` takes three, ``--range`` two).

    Raises:
        ArgumentError: naming the option when the text is not of that form.
    """
    shape = "KEY=START:STOP:STEP" if parts == 3 else "KEY=LOW:HIGH"
    key, equals, numbers = text.partition("=")
    fields = numbers.split(":")
    try:
        values = [float(f) for f in fields]
    except ValueError:
        values = []
    if not equals or not key.strip() or len(values) != parts or not all(map(math.isfinite, values)):
        raise ArgumentError(
            option, text, f"{shape}, e.g. lever.length_mm=" + ("300:360:5" if parts == 3 else "300:360")
        )
    return key.strip(), values


def parse_tolerance(text: str, option: str = "--spread") -> tuple[str, tuple[str, float]]:
    """``KEY=SIGMA`` (normal) or ``KEY=±X`` / ``KEY=+-X`` (uniform) → the key and (kind, width).

    Raises:
        ArgumentError: naming the option when the text is not of that form.
    """
    key, equals, spread = text.partition("=")
    spread = spread.strip()
    kind = "normal"
    for prefix in ("±", "+-", "+/-"):
        if spread.startswith(prefix):
            kind, spread = "uniform", spread[len(prefix) :]
            break
    try:
        width = float(spread)
    except ValueError:
        width = math.nan
    if not equals or not key.strip() or not (math.isfinite(width) and width > 0):
        raise ArgumentError(option, text, "KEY=SIGMA (normal) or KEY=±X (uniform), positive, e.g. lever.length_mm=0.05")
    return key.strip(), (kind, width)


def read_variants(path: str | Path) -> Variants:
    """Variants from a CSV file: a header of keys, then one variant a line.

    Read by :mod:`hipsim.tables`' rules, as trajectory files are: UTF-8,
    lines starting with ``#`` and blank lines skipped, separated by commas,
    semicolons or tabs (then possibly with decimal commas), no line longer
    than :data:`hipsim.tables.MAX_LINE_BYTES`.

    Raises:
        FileRowError: naming the file, line and column of an unknown key, a
            missing or extra cell, or a cell that is not a finite number.
        ParameterError: the file is missing or unreadable.
    """
    source = str(path)
    try:
        lines = read_text_lines(path, "variants file", FileRowError)
    except FileRowError as error:
        if error.line is not None:  # a byte that is not UTF-8, a line too long: the file's content, on its line
            raise
        raise ParameterError(str(error).removeprefix(f"{source}: "), source=source) from None
    rows = data_lines(lines)
    if not rows:
        raise FileRowError("no header: expected a line of keys, e.g. lever.length_mm,platform.home_offset_deg", source)
    header_line, header_text = rows[0]
    separator = detect_separator(header_text, rows[1][1] if len(rows) > 1 else None)
    header = cells(header_text, separator, 0)
    keys = []
    for name in header:
        try:
            keys.append(key_ref(name, source))
        except ParameterError as error:
            raise FileRowError(str(error).removeprefix(f"{source}, "), source, header_line, name.strip()) from None
    decimal_comma = separator != ","
    values = []
    for line_number, line in rows[1:]:
        row = cells(line, separator, len(keys))
        if len(row) != len(keys):
            raise FileRowError(f"{len(row)} cells, the header has {len(keys)}", source, line_number)
        numbers = []
        for key, cell in zip(keys, row):
            try:
                value = number(cell, decimal_comma)
            except ValueError:
                value = math.nan
            if not math.isfinite(value):
                raise FileRowError(f"expected a number, got '{cell.strip()}'", source, line_number, key.name)
            numbers.append(value)
        values.append(numbers)
    if not values:
        raise FileRowError("no variants below the header", source, header_line)
    return Variants(tuple(keys), np.array(values))
