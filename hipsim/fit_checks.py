"""Does a fit's result make sense? The gates every fit (identify, calibrate, the monitor's) holds its result to.

A fit always finds *some* parameters; whether they mean anything is told by
what they leave and how far they moved:

- **residuals against the noise** (:func:`residual_gate`): beyond
  :data:`RESIDUAL_FACTOR` = 3 times the noise, the model does not explain the
  data (a swapped column, a unit, another machine). Three times: a fit that
  explains its data leaves residuals at the noise (ratio ≈ 1; the ratio of two
  RMS estimates over hundreds of samples scatters by a few per cent), so 3 is
  far from a right fit's values and far below a slip's (a swapped torque
  column: 74–80 times);
- **each parameter's move against its prior** (:func:`prior_gate`): beyond
  :data:`PRIOR_SIGMA` = 5 prior standard deviations. A prior says where the
  value is believed to be; a 5σ move has a probability of 6e-7 under it. A fit
  that moves that far has absorbed something else (a sensor's 3° zero turned
  into 13 mm of chain, prior 0.5 mm: 26σ);
- **a pattern a quick test can name** (:func:`column_pattern`): the measured
  columns against the model's, swapped in pairs, with a sign flipped, or off by
  a constant; named when it removes more than :data:`PATTERN_GAIN` (half) of the
  squared residual (a half: a real slip removes nearly all of it, chance
  rarely a half);
- **the same input twice** (:func:`duplicate_inputs`): the same bytes given
  twice (SHA-256) count their samples twice and halve the variance stated.

Each gate is a pure function returning its finding in words (None when it
passes); :class:`FitCheck` collects them for a fit. The commands refuse an
implausible fit with the likely cause, or write it with ``--force`` and the
findings kept in the file's provenance.

Part of the foundation (NumPy and :mod:`hipsim.files` only): every fit, in
whichever layer, uses the same gates.
"""

from __future__ import annotations

import hashlib
import itertools
import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from .records import Level, Record, Verdict

__all__ = [
    "NOISE_FLOOR",
    "PATTERN_GAIN",
    "PATTERNS",
    "PRIOR_SIGMA",
    "RESIDUAL_FACTOR",
    "SCALES",
    "FitCheck",
    "FitCheckSummary",
    "column_pattern",
    "difference_noise",
    "duplicate_digests",
    "duplicate_inputs",
    "fit_verdict",
    "prior_gate",
    "residual_gate",
]

#: Residuals beyond this many times the noise: the model does not explain the data.
RESIDUAL_FACTOR = 3.0
#: A parameter beyond this many prior standard deviations from its prior's mean has absorbed something else.
PRIOR_SIGMA = 5.0
#: A pattern (swap, sign, offset) is named when it removes more than this fraction of the squared residual.
PATTERN_GAIN = 0.5
#: The patterns :func:`column_pattern` tries.
PATTERNS = ("swap", "sign", "offset", "scale")
#: Unit slips of a whole log tried by :func:`column_pattern`: (factor that undoes it, the slip in words).
SCALES = (
    (180.0 / math.pi, "like radians read as degrees"),
    (math.pi / 180.0, "like degrees read as radians"),
    (1e3, "1/1000 of the model's (a unit: N·m for N·mm, kN for N?)"),
    (1e-3, "1000 times the model's (a unit: N·mm for N·m?)"),
)
#: The noise is never taken below this fraction of the signal's RMS: a model's own accuracy (friction it lacks, a
#: filter's delay) is a few per cent of what it predicts, so a noiseless synthetic log is not held to zero.
NOISE_FLOOR = 0.05


@dataclass(frozen=True)
class FitCheck:
    """What the gates found of one fit: its findings (each with its likely cause); none when it is plausible.

    Attributes:
        fit: what was fitted ("identify", "calibrate", a monitor snapshot's name).
        findings: one sentence each: the gate, the numbers, the likely cause.
    """

    fit: str
    findings: tuple[str, ...] = ()

    @property
    def plausible(self) -> bool:
        """Whether every gate passed."""
        return not self.findings

    def message(self) -> str:
        """The findings as one line, for a refusal or a file's provenance."""
        return f"{self.fit}: implausible result: " + "; ".join(self.findings)

    def verdict(self, held_out: int = 0) -> str:
        """The check as the summary's line: what held, or what did not (a fit written with ``--force``).

        Args:
            held_out: how many held-out logs were checked (``--validate``).
        """
        if not self.plausible:
            return f"self-check: IMPLAUSIBLE, written with --force: {'; '.join(self.findings)}"
        held = f"; {held_out} held-out log{'s' if held_out != 1 else ''} predicted within it" if held_out else ""
        return (
            f"self-check: plausible: residuals within {RESIDUAL_FACTOR:g} times the noise, no parameter beyond "
            f"{PRIOR_SIGMA:g} prior standard deviations{held}"
        )

    def to_json(self) -> dict:
        """The check as JSON: fit, plausible, findings."""
        return {"fit": self.fit, "plausible": self.plausible, "findings": list(self.findings)}

    def summary(self, held_out: int = 0, not_judged: str = "") -> FitCheckSummary:
        """The check as its record (what ``identify`` and ``calibrate`` print), with its :func:`fit_verdict`."""
        verdict = fit_verdict(self, held_out, not_judged)
        return FitCheckSummary(self.fit, self.plausible, self.findings, verdict)


@dataclass(frozen=True)
class FitCheckSummary(Record):
    """A fit's self-check: what was fitted, whether every gate passed, the findings, and its verdict.

    Attributes:
        fit: what was fitted ("identify", "calibrate").
        plausible: every gate passed.
        findings: one sentence per failed gate (a fit written with ``--force``).
        verdict: PASS when plausible, else FAIL (:func:`fit_verdict`).
    """

    fit: str
    plausible: bool
    findings: tuple[str, ...]
    verdict: Verdict

    @property
    def level(self) -> Level:
        """The verdict's level (for :func:`hipsim.records.exit_status`)."""
        return self.verdict.level


def fit_verdict(check: FitCheck, held_out: int = 0, not_judged: str = "") -> Verdict:
    """A fit's verdict: PASS when every gate passed, FAIL when one did (a fit refused, or written with ``--force``).

    Args:
        check: the gates' findings.
        held_out: how many held-out logs the gates judged (``--validate``).
        not_judged: what the gates do not cover, in words (the fit's own caveat).

    Returns:
        The verdict, its numbers the gates' thresholds, the held-out logs and the count of findings.
    """
    held = f"; {held_out} held-out log{'s' if held_out != 1 else ''} against the same gate" if held_out else ""
    judged = (
        f"{check.fit}: residuals against {RESIDUAL_FACTOR:g} times the noise, each parameter's move against "
        f"{PRIOR_SIGMA:g} prior standard deviations{held}"
    )
    if check.findings:
        judged += ": " + "; ".join(check.findings)
    numbers = {
        "residual_factor": RESIDUAL_FACTOR,
        "prior_sigma": PRIOR_SIGMA,
        "held_out_logs": float(held_out),
        "findings": float(len(check.findings)),
    }
    return Verdict(Level.PASS if check.plausible else Level.FAIL, judged, not_judged, numbers)


def difference_noise(signal) -> np.ndarray:
    """Each column's white-noise standard deviation from its fourth differences (a smooth motion's cancel).

    The robust scale (1.4826 × median absolute deviation) of
    x[k−2] − 4x[k−1] + 6x[k] − 4x[k+1] + x[k+2], divided by √70 (its standard
    deviation for white noise of unit variance). Fourth differences: a gait
    motion sampled at 100 Hz leaves under 0.01° in them, second differences 0.5°.

    Args:
        signal: samples (N,) or (N, k) at an even rate, any unit.

    Returns:
        The noise per column, (k,) (a scalar's shape for (N,)), in the signal's unit; NaN for fewer than 5 samples (a fourth difference needs five).
    """
    x = np.asarray(signal, dtype=float)
    if x.shape[0] < 5:
        return np.full(x.shape[1:], np.nan)
    d4 = x[:-4] - 4.0 * x[1:-3] + 6.0 * x[2:-2] - 4.0 * x[3:-1] + x[4:]
    mad = np.median(np.abs(d4 - np.median(d4, axis=0)), axis=0)
    return 1.4826 * mad / math.sqrt(70.0)


def residual_gate(residual_rms, noise, names: Sequence[str], unit: str, factor: float = RESIDUAL_FACTOR) -> str | None:
    """Residuals beyond ``factor`` times the noise, in words, or None.

    Args:
        residual_rms: each signal's RMS residual, (k,), in ``unit``.
        noise: each signal's noise, (k,) (or a scalar), in ``unit``.
        names: each signal's name (column), (k,).
        unit: the unit, for the message.
        factor: the gate (:data:`RESIDUAL_FACTOR`); a ratio equal to it passes.
    """
    r = np.atleast_1d(np.asarray(residual_rms, dtype=float))
    n = np.broadcast_to(np.asarray(noise, dtype=float), r.shape)
    ratio = np.where(n > 0, r / np.where(n > 0, n, 1.0), np.where(r > 0, np.inf, 0.0))
    over = [k for k in range(r.size) if not ratio[k] <= factor]
    if not over:
        return None
    shown = ", ".join(f"{names[k]} {r[k]:.3g} {unit} ({ratio[k]:.3g}×)" for k in over)
    return f"residuals beyond {factor:g} times the noise: {shown}"


def prior_gate(values, means, stds, names: Sequence[str], unit: str, sigma: float = PRIOR_SIGMA) -> str | None:
    """Parameters that moved beyond ``sigma`` prior standard deviations, in words (the largest first), or None.

    Args:
        values: the fitted values, (p,).
        means: the prior's means, (p,).
        stds: the prior's standard deviations, (p,); a zero (a value held) is skipped.
        names: each value's name, (p,).
        unit: the unit of values and stds, for the message.
        sigma: the gate (:data:`PRIOR_SIGMA`); a move of exactly ``sigma`` passes.
    """
    v, m, s = (np.atleast_1d(np.asarray(a, dtype=float)) for a in (values, means, stds))
    moved = np.where(s > 0, np.abs(v - m) / np.where(s > 0, s, 1.0), 0.0)
    over = [k for k in np.argsort(-moved) if moved[k] > sigma]
    if not over:
        return None
    shown = ", ".join(f"{names[k]} {v[k] - m[k]:+.3g} {unit} ({moved[k]:.3g}σ)" for k in over[:4])
    more = f" and {len(over) - 4} more" if len(over) > 4 else ""
    return f"beyond {sigma:g} prior standard deviations: {shown}{more}"


def _ss(measured: np.ndarray, model: np.ndarray) -> float:
    return float(np.sum((measured - model) ** 2))


def column_pattern(
    measured,
    model,
    names: Sequence[str],
    unit: str = "",
    gain: float = PATTERN_GAIN,
    kinds: Sequence[str] = PATTERNS,
) -> str | None:
    """The slip that explains measured columns against the model's: a swap, a sign flip or a constant offset, or None.

    Tried: each pair of columns swapped, the two halves swapped (six columns:
    the two platforms' sensors), each column's sign flipped, each column's
    mean difference removed (an offset), every column scaled by a unit's
    factor (:data:`SCALES`: radians read as degrees, 1000). The best is named
    when it removes more than ``gain`` of the squared residual.

    Args:
        measured: the measured columns, (N, k), finite.
        model: what the model predicts for them, (N, k), same unit.
        names: the columns' names, (k,).
        unit: their unit, for an offset's value.
        gain: the fraction of the squared residual a pattern must remove (:data:`PATTERN_GAIN`).
        kinds: the patterns to try, of :data:`PATTERNS` ("swap", "sign", "offset", "scale"). Swaps and signs
            only, for a check made whatever the fit's residual: a fit absorbs them, and a right log has none,
            where offsets and scales a machine's real deviations can mimic.
    """
    y, q = np.asarray(measured, dtype=float), np.asarray(model, dtype=float)
    base = _ss(y, q)
    if not (base > 0 and np.isfinite(base)):
        return None
    k = y.shape[1]
    tries: list[tuple[float, str]] = [(base, "")]
    for a, b in itertools.combinations(range(k), 2) if "swap" in kinds else ():
        order = list(range(k))
        order[a], order[b] = b, a
        tries.append((_ss(y[:, order], q), f"columns {names[a]} and {names[b]} look swapped"))
    if "swap" in kinds and k % 2 == 0 and k > 2:
        half = k // 2
        order = [*range(half, k), *range(half)]
        tries.append(
            (
                _ss(y[:, order], q),
                f"the two halves ({', '.join(names[:half])}) and ({', '.join(names[half:])}) look swapped",
            )
        )
    for a in range(k) if "sign" in kinds else ():
        flipped = y.copy()
        flipped[:, a] *= -1.0
        tries.append((_ss(flipped, q), f"column {names[a]} looks sign-flipped"))
    offsets = np.mean(y - q, axis=0)
    for a in range(k) if "offset" in kinds else ():
        shifted = y.copy()
        shifted[:, a] -= offsets[a]
        tries.append(
            (
                _ss(shifted, q),
                f"column {names[a]} looks offset by {offsets[a]:+.3g}{' ' + unit if unit else ''} (a zero?)",
            )
        )
    for factor, what in SCALES if "scale" in kinds else ():
        tries.append((_ss(y * factor, q), f"the columns look {what}"))
    best, words = min(tries, key=lambda t: t[0])
    return words if words and best < (1.0 - gain) * base else None


def duplicate_digests(files: Sequence[tuple[str, str]]) -> str | None:
    """The first file whose SHA-256 an earlier one has, in words, or None.

    Args:
        files: (path, SHA-256 hex digest) of each input in the order given (logs, then held-out logs).
    """
    seen: dict[str, str] = {}
    for path, key in files:
        if key in seen:
            return (
                f"{path} holds the same bytes as {seen[key]} (SHA-256 {key[:12]}…): a log given twice counts its "
                "samples twice and halves the stated variance; give each log once"
            )
        seen[key] = path
    return None


def duplicate_inputs(paths: Sequence[str]) -> str | None:
    """The first file given twice (the same bytes, by SHA-256), in words, or None; a file that cannot be read is left
    to its reader to name.

    Args:
        paths: the input files in the order given (logs, then held-out logs).
    """
    files = []
    for path in paths:
        digest = hashlib.sha256()
        try:
            with open(path, "rb") as stream:
                for block in iter(lambda: stream.read(1 << 20), b""):
                    digest.update(block)
        except OSError:
            continue
        files.append((path, digest.hexdigest()))
    return duplicate_digests(files)
