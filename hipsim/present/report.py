"""Design reports: one folder a designer can hand on.

:func:`write_report` takes the runs the caller made (torques from one model,
joint forces from the Pinocchio model when there is one) and writes every
figure as PNG and SVG, ``index.html`` (one self-contained page: the PNGs are
embedded as data URIs, so it works offline and after the folder is moved or
the page is mailed alone), ``report.json`` (the summary and sizing numbers)
and ``torques.csv`` (the columns of spec §7.5). The numbers come from
:mod:`hipsim.design.sizing`, the figures from :mod:`hipsim.present.figures`,
the page from :mod:`hipsim.present.report_page` (``templates/report.html.j2``):
the verdict at the top, then where the numbers came from
(:mod:`hipsim.present.provenance`, also in ``report.json``), then the tables.
With ``pdf=True`` the same page is printed to ``report.pdf`` by headless
Chromium (:func:`hipsim.present.pages.print_pdf`).

The folder is written whole or not at all: everything goes to a temporary
folder beside it, which then takes its place. A report interrupted halfway
leaves the folder as it was; a report re-run into its folder leaves no figure
of the earlier run behind. An existing folder is replaced only when it is
empty or holds a hipsim report, never a folder of other files.
"""

from __future__ import annotations

import dataclasses
import json
import os
import shutil
import tempfile
import uuid
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ..design.sizing import Sizing, sizing
from ..design.sizing_summary import sizing_summary
from ..exceptions import HipsimError, OutputError
from ..files import check_folder, json_ready, output_folder, write_atomic
from ..machine.drive import Drive
from ..machine.parameters import file_values
from ..records import Verdict
from ..results import Run, peak_and_rms
from .figures import (
    plot_axial_load_histogram,
    plot_input_motion,
    plot_joint_forces,
    plot_load_friction,
    plot_singularity,
    plot_slider_motion,
    plot_torque_parts,
    plot_torque_speed,
    plot_tracking,
    save_figure,
    tracking_arrays,
)
from .pages import print_pdf, require_pdf_renderer
from .provenance import Provenance
from .provenance import provenance as make_provenance
from .report_page import report_block, report_html

__all__ = ["ReportFiles", "write_report"]

#: Marks a folder as a hipsim report, which a later report may replace.
MARKER = ".hipsim-report"
#: What an earlier report folder (before the marker) holds.
_REPORT_SUFFIXES = {".png", ".svg", ".html", ".json", ".csv", ".pdf"}


@dataclass(frozen=True)
class ReportFiles:
    """What :func:`write_report` wrote.

    Attributes:
        folder: the output folder.
        index: the HTML page.
        figures: figure stem → (PNG path, SVG path).
        data: the other files (report.json, torques.csv, and report.pdf when asked).
        notes: the notes shown on the page (model fallbacks, estimates).
        sizing: the sizing table.
        verdict: the drive's verdict (:func:`hipsim.design.checks.checks_verdict`: PASS, FAIL, or NOT MADE without a
            drive), the block at the top of the page.
    """

    folder: Path
    index: Path
    figures: dict[str, tuple[Path, Path]]
    data: tuple[Path, ...]
    notes: tuple[str, ...] = field(default_factory=tuple)
    sizing: Sizing | None = None
    verdict: Verdict | None = None


def write_report(
    out_dir: str | Path,
    run: Run,
    joint_forces_run: Run | None = None,
    simulations: Mapping[str, Any] | None = None,
    drive: Drive | None = None,
    notes: tuple[str, ...] = (),
    cycles: float = 1.0,
    provenance: Provenance | None = None,
    pdf: bool = False,
) -> ReportFiles:
    """Write the design report folder of a run.

    Writes ``out_dir`` whole (its parents created if missing): ``input_motion``,
    ``slider_motion``, ``motor_torques``, ``load_friction``, ``singularity``,
    ``torque_speed``, ``axial_load`` and, when available, ``joint_forces`` and
    ``tracking_errors``, each as ``.png`` and ``.svg``; ``index.html``;
    ``report.json`` (verdict, provenance, summary and sizing), ``torques.csv``
    (spec §7.5 columns) and, with ``pdf``, ``report.pdf`` (the page printed).

    Args:
        out_dir: the folder to write; if it exists it must be empty or an earlier report, which this one replaces whole.
        run: the run whose torques, motion and singularity measure are reported.
        joint_forces_run: a run along the same trajectory whose joint forces
            are reported with ``run``'s torques (the Pinocchio model's, when
            ``run`` is analytic); None to use ``run``'s own, if it has any.
        simulations: tracking simulations to plot: {controller name: object
            with ``t`` (N,) in [s] and ``err`` (N, 3) in [rad], and optionally
            ``tau`` (N, 3) in [N·m]}; None for no tracking section.
        drive: the drive train to check the sizing against; None for no check.
        notes: sentences shown at the top of the page (model fallbacks, estimates).
        cycles: test cycles the trajectory holds (screw life in cycles, energy per cycle).
        provenance: where the numbers came from (:func:`hipsim.present.provenance.provenance`), shown
            under the verdict and written to ``report.json``; None: a page without it.
        pdf: also print the page to ``report.pdf`` with headless Chromium.

    Returns:
        The :class:`ReportFiles`.

    Raises:
        HipsimError: for inputs that do not fit, a folder that holds other files, a write that fails, or
            ``pdf`` without a Chromium to print with.
    """
    out = Path(out_dir)
    check_folder(out)  # fail now, not after the plotting
    _check_replaceable(out)
    browser = require_pdf_renderer() if pdf else None
    if provenance is None:  # the version and the time on every page, even one made from Python
        provenance = make_provenance()
    page_notes = list(notes)
    if run.params.platform_mass > 0:
        page_notes.append(
            f"The platform mass m_m = {run.params.platform_mass:g} kg is an estimate (not published); it enters only the thrust-bearing friction."
        )
    combined = run
    joint_model = run.model
    if joint_forces_run is not None and joint_forces_run is not run:
        if joint_forces_run.joint_forces is None:
            raise HipsimError(f"the {joint_forces_run.model} run has no joint forces to report")
        if joint_forces_run.trajectory.t.shape != run.trajectory.t.shape or np.any(
            joint_forces_run.trajectory.t != run.trajectory.t
        ):
            raise HipsimError("the joint-force run is not along the report's trajectory")
        total, other = run.torques.total, joint_forces_run.torques.total
        difference = np.abs(other - total).max() / np.abs(total).max()
        page_notes.append(
            f"Torques are from the {run.model} model; joint forces from the {joint_forces_run.model} model, whose motor "
            f"torques differ from these by at most {difference:.2e} of the peak (the analytic lever does not spin, spec §7.4)."
        )
        # One run for the sizing and the figures: these torques with those joint forces.
        combined = dataclasses.replace(run, joint_forces=joint_forces_run.joint_forces)
        joint_model = joint_forces_run.model
    if simulations is not None:
        if not isinstance(simulations, Mapping) or not simulations:
            raise HipsimError("simulations must be a non-empty mapping {controller name: result with t and err}")
        for name, sim in simulations.items():
            tracking_arrays(name, sim)
    size = sizing(combined, drive, cycles=cycles)

    plots = [
        ("input_motion", lambda: plot_input_motion(combined)),
        ("slider_motion", lambda: plot_slider_motion(combined)),
        ("motor_torques", lambda: plot_torque_parts(combined)),
        ("load_friction", lambda: plot_load_friction(combined)),
        ("singularity", lambda: plot_singularity(combined)),
        ("torque_speed", lambda: plot_torque_speed(size)),
        ("axial_load", lambda: plot_axial_load_histogram(size)),
    ]
    if combined.joint_forces is not None:
        plots.append(("joint_forces", lambda: plot_joint_forces(combined, joint_model)))
    if simulations is not None:
        plots.append(("tracking_errors", lambda: plot_tracking(simulations)))
    summary = combined.summary()
    tracking = _tracking_table(simulations) if simulations is not None else None
    sized = sizing_summary(size)
    verdict = sized.verdict  # the drive's verdict, made beside the sizing (checks_verdict)

    def write(folder: Path) -> tuple[list[str], list[str]]:
        figures = {stem: save_figure(make(), folder, stem) for stem, make in plots}
        document = {
            "verdict": verdict.to_json(),
            "provenance": None if provenance is None else provenance.as_dict(),
            "summary": summary.to_json(),
            "sizing": sized.to_json(),
            "tracking": tracking,
            "page_notes": page_notes,
            "parameters": file_values(combined.params),
            "figures": {stem: [p.name for p in paths] for stem, paths in figures.items()},
        }
        write_atomic(folder / "report.json", json.dumps(json_ready(document), indent=2, default=_plain) + "\n")
        combined.write_csv(folder / "torques.csv")
        block = report_block(size, verdict)
        page = report_html(combined, summary, size, tracking, figures, page_notes, joint_model, provenance, block)
        write_atomic(folder / "index.html", page)
        data = ["report.json", "torques.csv"]
        if browser is not None:
            print_pdf(folder / "index.html", folder / "report.pdf", browser)
            data.append("report.pdf")
        write_atomic(folder / MARKER, "a hipsim report: `hipsim report` may replace this folder whole\n")
        return list(figures), data

    stems, data = _write_whole(out, write)
    folder = out
    figures = {stem: (folder / f"{stem}.png", folder / f"{stem}.svg") for stem in stems}
    return ReportFiles(
        folder, folder / "index.html", figures, tuple(folder / name for name in data), tuple(page_notes), size, verdict
    )


def _check_replaceable(out: Path) -> None:
    """Refuse to replace a folder that is neither empty nor a hipsim report."""
    target = _target(out)
    if not target.is_dir():
        return
    entries = list(target.iterdir())
    if not entries or (target / MARKER).is_file():
        return
    looks_like_report = [p.is_file() and p.suffix in _REPORT_SUFFIXES for p in entries]
    if all(looks_like_report) and {"index.html", "report.json"} <= {p.name for p in entries}:
        return  # a report from before the marker
    other = next(
        (p.name for p, ok in sorted(zip(entries, looks_like_report)) if not ok), sorted(p.name for p in entries)[0]
    )
    raise OutputError(
        out,
        f"the folder holds other files (e.g. '{other}'), and a report replaces its folder whole: "
        "choose a new or empty folder",
    )


def _target(out: Path) -> Path:
    """The folder to replace: a symbolic link's target (the link is kept), as an absolute path."""
    try:
        return Path(os.path.realpath(out)) if out.is_symlink() else Path(os.path.abspath(out))
    except OSError:
        return Path(os.path.abspath(out))


def _write_whole(out: Path, write):
    """Run ``write(folder)`` into a fresh folder beside ``out``, then put that folder in ``out``'s place.

    On any failure (a write refused, Ctrl-C) the fresh folder is removed and
    ``out`` is as it was; parents made for it are taken back if empty.
    """
    target = _target(out)
    with output_folder(target.parent):
        try:
            staging = Path(tempfile.mkdtemp(dir=target.parent, prefix=f".{target.name}.", suffix=".part"))
        except OSError as error:
            raise OutputError(out, f"cannot make the output folder ({error.strerror or error})") from None
        try:
            umask = os.umask(0)
            os.umask(umask)
            os.chmod(staging, 0o777 & ~umask)  # mkdtemp makes it private; give it a new folder's permissions
            result = write(staging)
            if target.exists():
                old = target.parent / f".{target.name}.{uuid.uuid4().hex[:8]}.old"
                os.rename(target, old)
                try:
                    os.rename(staging, target)
                except BaseException:
                    os.rename(old, target)
                    raise
                shutil.rmtree(old, ignore_errors=True)
            else:
                os.rename(staging, target)
        except OSError as error:
            shutil.rmtree(staging, ignore_errors=True)
            raise OutputError(out, f"cannot write the report ({error.strerror or error})") from None
        except BaseException:
            shutil.rmtree(staging, ignore_errors=True)
            raise
    return result


def _plain(value):
    """JSON for what json does not know (NumPy numbers and arrays)."""
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, np.generic):
        return value.item()
    raise TypeError(f"not JSON: {type(value).__name__}")


def _tracking_table(sims: Mapping[str, Any]) -> dict[str, dict[str, float]]:
    """Per controller: peak and RMS error of each angle in [deg] (and torque when the result has ``tau``)."""
    table = {}
    for name, sim in sims.items():
        _, err = tracking_arrays(name, sim)
        peak, rms = peak_and_rms(np.degrees(err))
        row = {}
        for k, angle in enumerate(("alpha", "beta", "gamma")):
            row[f"{angle}_err_peak_deg"] = float(peak[k])
            row[f"{angle}_err_rms_deg"] = float(rms[k])
        tau = getattr(sim, "tau", None)
        if tau is not None and np.shape(tau) == (err.shape[0], 3):
            peak, rms = peak_and_rms(np.asarray(tau, dtype=float) * 1e3)
            row |= {f"tau_peak_{i + 1}_Nmm": float(peak[i]) for i in range(3)}
            row |= {f"tau_rms_{i + 1}_Nmm": float(rms[i]) for i in range(3)}
        table[name] = row
    return table
