"""Numbers as a rig engineer reads them: a few significant figures, or as many as the uncertainty allows.

Every page (the design report, the comparison) prints its values through
these functions, so a value has the same form wherever it appears: 3–4
significant figures with thousands separators (trailing zeros kept: they are figures), powers of
ten only outside 10⁻³ … 10⁷, and, with an uncertainty, the value rounded to
the uncertainty's second significant figure ("0.05097 ± 0.00012").
"""

from __future__ import annotations

import math

__all__ = ["quantity", "significant", "with_uncertainty"]

_SUPERSCRIPT = str.maketrans("-0123456789", "⁻⁰¹²³⁴⁵⁶⁷⁸⁹")


def _missing(value) -> str | None:
    """The text of a value that is not a finite number (— for none, ∞ for an infinity), or None for a number."""
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return "—"
    if isinstance(value, float) and math.isinf(value):
        return "∞" if value > 0 else "−∞"
    return None


def _strip(text: str) -> str:
    """Trailing zeros of a decimal fraction dropped ("82.60" → "82.6", "3.0" → "3")."""
    return text.rstrip("0").rstrip(".") if "." in text else text


def _minus(text: str) -> str:
    return text.replace("-", "−")


def significant(value, digits: int = 4, zeros: bool = True) -> str:
    """``value`` to ``digits`` significant figures: "1,639", "0.3587", "562.0", "1.2 × 10⁸"; — for none, ∞ for an infinity.

    Args:
        value: a number (or None).
        digits: significant figures, 3 or 4 for a result.
        zeros: keep trailing zeros ("562.0"); False drops them ("0.02" for a small error read at a glance).
    """
    text = _missing(value)
    if text is not None:
        return text
    value = float(value)
    if value == 0:
        return "0"
    exponent = math.floor(math.log10(abs(value)))
    rounded = float(f"{value:.{digits - 1}e}")  # the rounding may carry into the next power of ten
    exponent = math.floor(math.log10(abs(rounded)))
    if exponent >= 7 or exponent < -3:
        mantissa, power = f"{rounded:.{digits - 1}e}".split("e")
        mantissa = _strip(mantissa) if not zeros else mantissa
        return _minus(f"{mantissa} × 10{str(int(power)).translate(_SUPERSCRIPT)}")
    decimals = max(digits - 1 - exponent, 0)
    text = f"{rounded:,.{decimals}f}"
    return _minus(text if zeros else _strip(text))


def with_uncertainty(value, std, digits: int = 4) -> str:
    """``value ± std``, both rounded at the second significant figure of ``std``; without a usable std, :func:`significant`.

    Args:
        value: the value.
        std: its standard deviation in the same unit (None, 0 or not finite: none known).
        digits: significant figures when no uncertainty is known.
    """
    text = _missing(value)
    if text is not None:
        return text
    if std is None or not math.isfinite(std) or std <= 0:
        return significant(value, digits)
    exponent = math.floor(math.log10(float(f"{std:.1e}")))
    decimals = 1 - exponent
    if decimals > 0:
        return _minus(f"{value:,.{decimals}f} ± {std:,.{decimals}f}")
    step = 10.0 ** (-decimals)
    return _minus(f"{round(value / step) * step:,.0f} ± {round(std / step) * step:,.0f}")


def quantity(value, unit: str, digits: int = 4) -> str:
    """A value with its unit: "431.1 N·mm", "2.3 %"; a unit of ":1" (a ratio) is joined without a space."""
    text = significant(value, digits)
    if text == "—" or not unit:
        return text
    return f"{text}{unit}" if unit.startswith(":") else f"{text} {unit}"
