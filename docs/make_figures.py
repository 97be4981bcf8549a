"""Make the documentation's figures from the current code: ``python docs/make_figures.py [NAME ...]``.

- ``machine_frames.png``: the machine and its frames at the ISO cycle's first
  sample, drawn from the analytic model's kinematics (matplotlib only).
- ``sweep_pareto.png``: the default design sweep's Pareto front, as
  ``hipsim sweep --pareto tau_peak_max_Nmm,-cond_inv_min`` draws it (needs
  the ``sweep`` extra; about a minute on one core).
- ``iso_cycle.png``: the viewer's offline page of the ISO cycle with force
  arrows and singularity colours, rendered by headless Chromium
  (:func:`hipsim.present.browser.screenshot`; needs ``chromium`` on PATH).

- ``wear_slide_tracks.png`` and ``wear_cup_maps.png``: the slide tracks,
  force track and maps of sliding, work and cross-shear of the built-in ISO
  cycle, as ``hipsim wear --report`` draws them.

With no name, all of them. Each is written next to this script.
"""

from __future__ import annotations

import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent


def machine_frames(out: Path) -> None:
    """Side and top views of the machine at the ISO cycle's first sample: screws, sliders, levers, platforms, base frame."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    import hipsim
    from hipsim.analytic import kinematics

    params = hipsim.load_parameters()
    kin = kinematics(params, hipsim.iso14242(rate=100))
    a, b = kin.a[0] * 1e3, kin.b[0] * 1e3  # (2, 3, 3) in mm: platform joints, universal joints
    theta = np.asarray(params.screw_angles)
    c = params.screw_radius * 1e3 * np.stack([np.cos(theta), np.sin(theta), np.zeros(3)], axis=1)
    heights = np.asarray(params.heights) * 1e3
    top = max(heights) + 150.0

    fig = plt.figure(figsize=(10, 5))
    side = fig.add_subplot(1, 2, 1, projection="3d")
    plan = fig.add_subplot(1, 2, 2)
    colours = ("tab:blue", "tab:orange")
    for i in range(3):
        side.plot([c[i, 0]] * 2, [c[i, 1]] * 2, [0.0, top], color="0.4", lw=2)
        side.text(c[i, 0], c[i, 1], top + 20, f"LN{i + 1}", ha="center")
        plan.plot(c[i, 0], c[i, 1], "s", color="0.4")
        plan.annotate(
            f"LN{i + 1}  θ{i + 1} = {np.degrees(theta[i]):.0f}°", c[i, :2], textcoords="offset points", xytext=(6, 6)
        )
    for j in range(2):
        ring = np.vstack([a[j], a[j][:1]])
        side.plot(ring[:, 0], ring[:, 1], ring[:, 2], color=colours[j], lw=2, label=f"platform {j + 1}")
        side.plot([0.0], [0.0], [heights[j]], "o", color=colours[j])
        plan.plot(ring[:, 0], ring[:, 1], color=colours[j], lw=2, label=f"platform {j + 1} (joints a_{j + 1}i)")
        for i in range(3):
            side.plot(*zip(b[j, i], a[j, i]), color=colours[j], lw=1)  # lever
            side.plot(*b[j, i], "v", color=colours[j])  # slider's universal joint
            plan.plot(*zip(b[j, i, :2], a[j, i, :2]), color=colours[j], lw=1)
    circle = np.linspace(0.0, 2.0 * np.pi, 200)
    radius = params.screw_radius * 1e3
    side.plot(radius * np.cos(circle), radius * np.sin(circle), 0.0 * circle, ":", color="0.5")
    plan.plot(radius * np.cos(circle), radius * np.sin(circle), ":", color="0.5")
    for axis, colour, name in ((0, "r", "X"), (1, "g", "Y"), (2, "b", "Z")):
        tip = np.zeros(3)
        tip[axis] = 150.0
        side.quiver(0, 0, 0, *tip, color=colour)
        side.text(*(tip * 1.15), name, color=colour)
        if axis < 2:
            plan.annotate("", tip[:2], (0, 0), arrowprops={"arrowstyle": "->", "color": colour})
            plan.text(*(tip[:2] * 1.2), name, color=colour)
    side.set(xlabel="X [mm]", ylabel="Y [mm]", zlabel="Z [mm]", title="the machine, O-XYZ at the base")
    side.set_box_aspect((1, 1, 1.4))
    side.view_init(elev=15, azim=-60)
    side.legend(loc="upper left", fontsize=8)
    plan.set(xlabel="X [mm]", ylabel="Y [mm]", title="from above: screws, levers, platform joints")
    plan.set_aspect("equal")
    plan.legend(loc="lower left", fontsize=8)
    fig.suptitle("ISO 14242-1 cycle, first sample: α, β, γ = 25°, 5.7°, −10°", fontsize=10)
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    plt.close(fig)


def sweep_pareto(out: Path) -> None:
    """The default sweep (403 variants) through the command line, its Pareto figure kept."""
    with tempfile.TemporaryDirectory() as folder:
        table = Path(folder) / "sweep.csv"
        subprocess.run(
            [
                sys.executable,
                "-m",
                "hipsim",
                "sweep",
                "--workers",
                "1",
                "--out",
                str(table),
                "--pareto",
                "tau_peak_max_Nmm,-cond_inv_min",
            ],
            check=True,
        )
        shutil.copyfile(Path(folder) / "sweep_pareto.png", out)


def iso_cycle(out: Path) -> None:
    """The viewer's offline page of the ISO cycle, forces and singularity colours on, photographed at t = 0.12 s (the first load peak)."""
    import hipsim
    from hipsim.present.browser import screenshot
    from hipsim.present.viewer import Viewer

    with Viewer(serve=False) as viewer:
        page = viewer.record(hipsim.iso14242(rate=1000), forces=True, singularity=True)
    with tempfile.TemporaryDirectory() as folder:
        html = Path(folder) / "iso.html"
        html.write_text(page, encoding="utf-8")
        screenshot(html, out, time_s=0.12)


def _wear_iso():
    import hipsim
    from hipsim.wear import CupSetup, wear_maps
    from hipsim.wear.tracks import cycle_tracks

    cycle = hipsim.iso14242(rate=1000)
    return wear_maps(cycle, 1.0), cycle_tracks(cycle, 1.0, CupSetup())


def wear_slide_tracks(out: Path) -> None:
    """Slide tracks and the force track of the built-in ISO cycle on a 28 mm head's cup."""
    from hipsim.present.wear_figures import plot_slide_tracks

    maps, tracks = _wear_iso()
    plot_slide_tracks(tracks, maps.setup.radius_mm, "ISO 14242-1 (built-in cycle), 28 mm head").savefig(out, dpi=110)


def wear_cup_maps(out: Path) -> None:
    """Sliding distance, work and cross-shear per cycle of the built-in ISO cycle on a 28 mm head's cup."""
    from hipsim.present.wear_figures import plot_cup_maps

    maps, _ = _wear_iso()
    plot_cup_maps(maps, "ISO 14242-1 (built-in cycle), 28 mm head: per cycle").savefig(out, dpi=90)


FIGURES = {
    "machine_frames": machine_frames,
    "sweep_pareto": sweep_pareto,
    "iso_cycle": iso_cycle,
    "wear_slide_tracks": wear_slide_tracks,
    "wear_cup_maps": wear_cup_maps,
}


def main(names: list[str]) -> None:
    """Make the named figures (all by default) next to this script."""
    for name in names or list(FIGURES):
        FIGURES[name](HERE / f"{name}.png")
        print(f"wrote {HERE / name}.png")


if __name__ == "__main__":
    main(sys.argv[1:])
