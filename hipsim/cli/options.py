"""One option of the command line: its name, its one meaning, its unit, and the ranges its values are held to.

Every option any ``hipsim`` command takes is declared once in
:mod:`hipsim.cli.option_table` as an :class:`Option`; the parser is checked
against that table (:func:`hipsim.cli.parser.apply_table`), so a name has one
meaning and one unit in every command.

A number is held to two ranges:

- the **hard range**: outside it the value has no meaning (a cutoff of 0 Hz,
  a head of 0.028 mm, a friction rise of 1 per cycle) and it is refused, one
  line naming option, value, unit and range, exit status 2, nothing written;
- the **plausible range**: what a hip simulator's lab types. Outside it the
  run goes on with a warning naming the typical range and the likely slip
  (a factor of 1000, degrees for radians, a fraction for a percentage).

This module imports only the standard library (``hipsim --help`` stays fast);
:func:`judge` is pure, so each boundary is tested directly.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

__all__ = ["Judgement", "Option", "judge", "likely_slip", "read_number"]

#: Unit slips a lab makes, per unit: the factor the typed value is off by (typed = meant × factor) → the slip in words.
UNIT_SLIPS: dict[str, tuple[tuple[float, str], ...]] = {
    "mm": ((1e-3, "in metres"), (1e3, "in µm")),
    "mm/s": ((1e-3, "in m/s"),),
    "mm/s²": ((1e-3, "in m/s²"),),
    "N·mm": ((1e-3, "in N·m"),),
    "N·m/A": ((1e3, "in N·mm/A"),),
    "N": ((1e-3, "in kN"), (1e3, "in mN")),
    "Hz": ((1e-3, "in kHz"), (1e3, "in mHz"), (2 * math.pi, "in rad/s")),
    "s": ((1e3, "in ms"), (1e-3, "in ks")),
    "ms": ((1e-3, "in s"), (1e3, "in µs")),
    "deg": ((math.pi / 180.0, "in radians"),),
    "%": ((1e-2, "a fraction, not a percentage"),),
    "mm³/(N·m)": ((1e-3, "per N·mm"), (1e3, "in mm³/(N·km)"), (1e-9, "in m³/(N·m)")),
    "cycles": ((1e-6, "in millions of cycles (Mc)"), (1e-3, "in thousands of cycles")),
    "1/cycle": ((1e2, "a percentage, not a fraction"),),
}


@dataclass(frozen=True)
class Option:
    """One command-line option, as every command that takes it reads it.

    Attributes:
        name: the option as typed, ``--head-diameter``.
        meaning: what it is, in a few words (one meaning: the table test holds every command to it).
        unit: the unit of its number(s), shown in ``--help``; "" for options that are no quantity (files, choices, flags).
        kind: "number", "integer", "numbers" (a list of ``separator``-separated numbers, each held to the ranges),
            "choice", "file", "flag" or "text".
        hard: (low, high): the values that have a meaning; outside, refused.
        open_low: the hard range excludes ``low`` (a cutoff must be > 0, not ≥ 0).
        open_high: the hard range excludes ``high``.
        plausible: (low, high): what a lab types; outside, a warning.
        typical: the plausible range in words for the warning ("heads are 22–60 mm").
        separator: the separator of a "numbers" option's values (``:`` of FROM:TO, ``x`` of 90x180).
        count: how many numbers a "numbers" option holds (None: any).
        deprecated: for an old spelling kept one minor version: what to write instead.
        corpus: False for numbers that are no quantity (a random seed): the corpus of slips leaves them out.
        slips: this option's own slips, tried before its unit's: (factor, words), typed = meant × factor.
        special: values with a meaning of their own, accepted without a word (``--log-period 0``: not periodic).
        example: a right value as a user types it (the corpus of slips is made from it; default: the plausible range's middle).
        undetectable: the corpus's slips (``x0.001``, ``deg->rad`` …) that give a value as right as the example
            (a cup mount of 0.02° is as plausible as 20°): the corpus holds them accepted, and the docs name them.
        tail: the separator of words after the number that the command reads itself (``:`` of ``8e-8:local``).
        unit_slips: whether the unit's slips (:data:`UNIT_SLIPS`) are tried: not for a count whose small values are
            as meant as its large ones (a hundredth of a built-in cycle for a quick run is no "millions of cycles").
    """

    name: str
    meaning: str
    unit: str = ""
    kind: str = "number"
    hard: tuple[float, float] = (-math.inf, math.inf)
    open_low: bool = False
    open_high: bool = False
    plausible: tuple[float, float] | None = None
    typical: str = ""
    separator: str = ","
    count: int | None = None
    deprecated: str | None = None
    corpus: bool = True
    slips: tuple[tuple[float, str], ...] = ()
    special: tuple[float, ...] = ()
    example: str = ""
    undetectable: tuple[str, ...] = ()
    tail: str = ""
    unit_slips: bool = True

    @property
    def numeric(self) -> bool:
        """Whether the option's value is a number or a list of them (held to the ranges)."""
        return self.kind in ("number", "integer", "numbers")

    @property
    def shown_unit(self) -> str:
        """The unit as messages show it after a number: " mm", or "" for a dimensionless number (unit "1")."""
        return "" if self.unit in ("", "1") else f" {self.unit}"

    def range_text(self) -> str:
        """The hard range in words, with the unit: ``above 0 and at most 100000 Hz``, ``at least 1``."""
        low, high = self.hard
        lo = "" if low == -math.inf else (f"above {low:g}" if self.open_low else f"at least {low:g}")
        hi = "" if high == math.inf else (f"below {high:g}" if self.open_high else f"at most {high:g}")
        return (f"{lo} and {hi}" if lo and hi else lo or hi or "any value") + self.shown_unit

    def help_suffix(self) -> str:
        """What ``--help`` adds to the command's text: the unit and the typical range."""
        parts = [f"unit: {'dimensionless' if self.unit == '1' else self.unit}"] if self.unit else []
        if self.plausible is not None:
            low, high = self.plausible
            parts.append(f"typical {low:g} to {high:g}")
        return f" [{'; '.join(parts)}]" if parts else ""


@dataclass(frozen=True)
class Judgement:
    """What a typed number is: refused (with why), warned of (with why), or fine (both None)."""

    refusal: str | None = None
    warning: str | None = None


def _inside(value: float, low: float, high: float, open_low: bool = False, open_high: bool = False) -> bool:
    above = value > low if open_low else value >= low
    under = value < high if open_high else value <= high
    return above and under


def likely_slip(option: Option, value: float) -> str | None:
    """The unit slip that brings ``value`` into the option's plausible range, in words, or None.

    Args:
        option: the option (its unit and plausible range).
        value: the number as typed, in the option's unit.
    """
    if option.plausible is None or not math.isfinite(value) or value == 0.0:
        return None
    low, high = option.plausible
    for factor, words in (*option.slips, *(UNIT_SLIPS.get(option.unit, ()) if option.unit_slips else ())):
        if low <= value / factor <= high:
            return f"{words}?"
    for factor, words in ((1e-3, "1/1000 of"), (1e3, "1000 times")):  # a quantity's unit: the factor of a prefix
        if option.kind == "number" and low <= value / factor <= high:
            return f"{words} the usual: a unit slip?"
    return None


def judge(option: Option, value: float) -> Judgement:
    """A typed number against the option's hard and plausible ranges.

    Args:
        option: the option (ranges, unit, typical range in words).
        value: the number as typed, in the option's unit.

    Returns:
        A refusal outside the hard range (NaN and infinities too, unless the range
        includes them), a warning outside the plausible range, else neither.
    """
    shown = f"{option.name} {value:g}{option.shown_unit}"
    slip = likely_slip(option, value)
    hint = f" {slip}" if slip else ""
    if value in option.special:
        return Judgement()
    low, high = option.hard
    if math.isnan(value) or not _inside(value, low, high, option.open_low, option.open_high):
        typical = f"; {option.typical}" if option.typical else ""
        return Judgement(
            refusal=f"{shown}: {option.meaning} must be {option.range_text()}{';' + hint if slip else ''}{typical}"
        )
    if option.plausible is not None and not _inside(value, *option.plausible):
        plo, phi = option.plausible
        typical = option.typical or f"typical values are {plo:g} to {phi:g}{option.shown_unit}"
        return Judgement(warning=f"{shown}:{hint or ' unusual;'} {typical}")
    return Judgement()


def read_number(option: Option, text: str) -> tuple[list[float], list[str], str | None]:
    """The numbers in an option's text: (values, warnings, refusal); refusal is None when every value is in range.

    Args:
        option: a numeric option of the table.
        text: what the user typed.
    """
    if option.tail:
        text = text.split(option.tail, 1)[0]
    words = text.split(option.separator) if option.kind == "numbers" else [text]
    if option.count is not None and len(words) != option.count:
        shape = option.separator.join(["N"] * option.count)
        return [], [], f"{option.name} '{text}': expected {shape} in {option.unit or 'numbers'}"
    values: list[float] = []
    warnings: list[str] = []
    for word in words:
        try:
            if "_" in word:  # float() reads "1_0" as 10; a user would not mean that
                raise ValueError(word)
            value = float(word)
            if option.kind == "integer" and not value.is_integer():  # 1e6 is a whole number; 0.5 and NaN are not
                raise ValueError(word)
        except ValueError:
            what = "a whole number" if option.kind == "integer" else "a number"
            return [], [], f"{option.name} '{text}': expected {what} in {option.unit or 'no unit'}"
        verdict = judge(option, value)
        whole = f"{option.name} '{text}': " if option.kind == "numbers" else ""  # the list, then the value in it
        if verdict.refusal:
            return [], [], whole + verdict.refusal.removeprefix(f"{option.name} " if whole else "")
        if verdict.warning:
            warnings.append(whole + verdict.warning.removeprefix(f"{option.name} " if whole else ""))
        values.append(value)
    return values, warnings, None
