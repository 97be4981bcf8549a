"""A drive check in words and numbers, the way an engineer says why a drive fails: "LN1 needs 6,556 rpm; the motor's top speed is 6,000".

Each kind of :data:`hipsim.design.checks.CHECKS` has one sentence naming what
the cycle needs and what the part offers, in the check's unit, through
:func:`hipsim.present.numbers.significant` (4 significant figures).
"""

from __future__ import annotations

from ..design.checks import Check
from .numbers import significant

__all__ = ["check_sentence"]

# What the cycle needs ({value}) and what the part offers ({limit}), per check, after the check's label.
_SENTENCES = {
    "peak_curve": "needs {value} N·mm {detail}; the peak curve gives {limit} N·mm there",
    "s1_rms": "needs {value} N·mm RMS ({detail}); the S1 curve gives {limit} N·mm",
    "max_speed": "needs {value} rpm; the motor's top speed is {limit}",
    "inertia_ratio": "{value} : 1; at most {limit} : 1 allowed",
    "winding_rise": "rises {value} K; at most {limit} K allowed",
    "amplifier_peak_current": "needs {value} A; the amplifier gives {limit} A peak",
    "amplifier_rms_current": "needs {value} A RMS; the amplifier gives {limit} A continuous",
    "regen_energy": "{value} J per cycle; the DC link takes {limit} J",
    "regen_power_mean": "{value} W; the braking resistor takes {limit} W",
    "regen_power_peak": "{value} W; the braking resistor takes {limit} W peak",
    "screw_life": "{value} cycles; {limit} needed",
    "critical_speed": "turns at {value} rpm; {limit} rpm allowed ({detail})",
    "buckling": "{value} N; {limit} N allowed ({detail})",
    "stroke": "needs {value} mm; the screw gives {limit} mm",
    "axial_force": "{value} N; the screw takes {limit} N",
}


def check_sentence(check: Check) -> str:
    """A made check (value and limit given) as its label, module and a sentence: what the cycle needs against what the part offers.

    "peak motor speed, LN2: needs 7,478 rpm; the motor's top speed is 6,000".
    """
    detail = check.detail.split(",")[0] if check.name == "peak_curve" else check.detail
    value, limit = (significant(x, 4, zeros=False) for x in (check.value, check.limit))
    text = _SENTENCES[check.name].format(value=value, limit=limit, detail=detail).replace(" ()", "")
    return f"{check.kind.label}, LN{check.module}: {text}"
