"""The ISO 14242-1 compliance check, drawn and written: each cycle over the standard's waveforms and their tolerance bands.

:func:`write_iso_check` writes a folder a lab can hand on, as ``compare``
does: the figure as PNG and SVG, ``index.html`` (one self-contained page, the
PNG embedded) and ``iso_check.json`` (:func:`iso_summary`).
"""

from __future__ import annotations

import base64
import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..files import check_folder, json_ready, output_folder, write_atomic
from ..motion.iso_compliance import IsoCheck
from ..motion.iso_verdict import UNITS, IsoCheckSummary, binding_quantity, iso_check_summary
from ..motion.trajectories import iso14242_angles, iso14242_load
from .figures import save_figure
from .pages import CSS, Verdict, environment
from .provenance import Provenance

__all__ = ["IsoCheckFiles", "iso_summary", "iso_verdict", "plot_iso_check", "write_iso_check"]

#: Most cycles drawn (the first ones; every cycle is in the JSON).
MAX_DRAWN = 50

_LABELS = {
    "alpha": "α flexion/extension [°]",
    "beta": "β abduction/adduction [°]",
    "gamma": "γ rotation [°]",
    "load": "load [N]",
}
_UNITS = UNITS


def iso_summary(check: IsoCheck) -> IsoCheckSummary:
    """The check as a record (:func:`hipsim.motion.iso_verdict.iso_check_summary`)."""
    return iso_check_summary(check)


def plot_iso_check(check: IsoCheck, t: np.ndarray, q: np.ndarray, load: np.ndarray):
    """Each cycle's angles and load over % of the cycle from heel strike, on the standard's waveforms with their bands.

    Args:
        check: the verdict.
        t, q, load: the samples it was made of, in [s], [rad] (N, 3) and [N].
    """
    from matplotlib.figure import Figure

    fig = Figure(figsize=(10.0, 9.0), layout="constrained")
    axes = fig.subplots(4, 1, sharex=True)
    s = np.linspace(0.0, 1.0, 501)
    reference = np.column_stack([np.degrees(iso14242_angles(s)[0]), iso14242_load(s)])
    data = np.column_stack([np.degrees(q), load])
    for k, cycle in enumerate(check.cycles[:MAX_DRAWN]):
        inside = (t >= cycle.start) & (t < cycle.start + 1.0 / cycle.frequency)
        phase = 100.0 * (t[inside] - cycle.start) * cycle.frequency
        for j, name in enumerate(("alpha", "beta", "gamma", "load")):
            good = check.passes(name)[k]
            axes[j].plot(phase, data[inside, j], color="tab:blue" if good else "tab:red", linewidth=0.8, alpha=0.6)
    for j, (ax, name) in enumerate(zip(axes, ("alpha", "beta", "gamma", "load"))):
        band = getattr(check.tolerances, name)
        ax.fill_between(
            100.0 * s, reference[:, j] - band, reference[:, j] + band, color="0.85", linewidth=0, label="tolerance"
        )
        ax.plot(100.0 * s, reference[:, j], color="black", linewidth=1.0, label="ISO 14242-1")
        ok = check.passes(name)
        ax.set_title(
            f"{name}: worst {check.worst(name):.3g} {_UNITS[name]} (tolerance {band:.3g}): "
            + ("pass" if ok.all() else f"FAIL in {int((~ok).sum())} of {ok.size} cycles"),
            fontsize=9,
        )
        ax.set_ylabel(_LABELS[name])
        ax.grid(alpha=0.3)
    axes[0].legend(loc="upper right", fontsize=8)
    axes[-1].set_xlabel("% of the gait cycle from heel strike (blue: cycle within tolerance, red: outside)")
    return fig


@dataclass(frozen=True)
class IsoCheckFiles:
    """What :func:`write_iso_check` wrote."""

    folder: Path
    index: Path
    summary: Path
    figure: tuple[Path, Path]


def iso_verdict(summary: IsoCheckSummary) -> Verdict:
    """The block at the top of the page: the verdict made beside the check (:func:`hipsim.motion.iso_verdict.
    iso_check_verdict`, PASS or FAIL) and the quantity that decides it with its worst deviation, in two sentences."""
    name = binding_quantity(summary.quantities)
    q = summary.quantities[name]
    against = f"{q.worst:.3g} {q.unit} against ±{q.tolerance:.3g} {q.unit}"
    if summary.failing:
        lines = (
            f"{', '.join(summary.failing)} left the tolerance; {name} in {q.cycles_failed} of {summary.cycles} cycle(s).",
            f"Worst {name}: {against}.",
        )
    else:
        lines = (
            f"Every one of {summary.cycles} whole cycle(s) kept every angle, the load and the frequency within tolerance.",
            f"Closest: {name}, worst deviation {against} "
            f"(tolerances assumed: confirm them against your copy of ISO 14242-1).",
        )
    return Verdict.of(summary.verdict, lines)


def write_iso_check(
    out_dir: str | Path,
    check: IsoCheck,
    t: np.ndarray,
    q: np.ndarray,
    load: np.ndarray,
    provenance: Provenance | None = None,
) -> IsoCheckFiles:
    """Write the figure (PNG, SVG), ``index.html`` and ``iso_check.json`` to ``out_dir``, each atomically.

    The page opens with the verdict and the provenance block, as every hipsim page does.

    Args:
        out_dir: the folder (made if missing).
        check: the verdict.
        t, q, load: the samples checked, in [s], [rad] (N, 3), [N].
        provenance: the page's provenance (:func:`hipsim.present.provenance.provenance`); None for one without inputs.
    """
    from .provenance import provenance as make_provenance

    out = Path(out_dir)
    check_folder(out)
    provenance = provenance or make_provenance()
    summary = iso_check_summary(check)
    verdict = iso_verdict(summary)
    # the verdict first, then the provenance, as on every page's JSON (the summary's verdict takes the first key)
    document = {"verdict": None, "provenance": json_ready(provenance.as_dict())} | summary.to_json()
    with output_folder(out):
        png, svg = save_figure(plot_iso_check(check, t, q, load), out, "cycles")
        json_path = write_atomic(out / "iso_check.json", json.dumps(document, indent=2) + "\n")
        page = (
            environment()
            .get_template("iso_check.html.j2")
            .render(
                css=CSS,
                verdict=verdict,
                provenance=provenance,
                title=provenance.title,
                s=summary,
                figure=base64.b64encode(png.read_bytes()).decode("ascii"),
            )
        )
        index = write_atomic(out / "index.html", page)
    return IsoCheckFiles(out, index, json_path, (png, svg))
