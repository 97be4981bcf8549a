"""Make the documentation's figures from the current code: ``python docs/make_figures.py [NAME ...]``.

- ``machine_frames.png``: the machine and its frames at the ISO cycle's first
  sample, drawn from the analytic model's kinematics (matplotlib only).
- ``sweep_pareto.png``: the default design sweep's Pareto front, as
  ``hipsim sweep --pareto tau_peak_max_Nmm,-cond_inv_min`` draws it (needs
  the ``sweep`` extra; about a minute on one core).
- ``iso_cycle.png``: the viewer's offline page of the ISO cycle with force
  arrows and singularity colours, rendered by headless Chromium
  (:func:`hipsim.present.browser.screenshot`; needs ``chromium`` on PATH).

- ``chain_geometry.png``: what each value of the parameter file's ``[geometry]``
  table is (one module's two chains, side and plan views; matplotlib only).

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


def chain_geometry(out: Path) -> None:
    """One module's two chains as built: each value of the ``[geometry]`` table drawn (deviations exaggerated)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    fig, (side, plan) = plt.subplots(1, 2, figsize=(11, 6), gridspec_kw={"width_ratios": [1.25, 1]})
    grey, drawn = "0.45", dict(color="0.7", lw=1.2, ls="--")
    colours = ("tab:green", "tab:purple")

    def arrow(ax, start, end, text, colour, offset=(4, 0), ha="left"):
        ax.annotate("", end, start, arrowprops=dict(arrowstyle="->", color=colour, lw=1.6))
        middle = (np.asarray(start) + np.asarray(end)) / 2
        ax.annotate(text, middle, textcoords="offset points", xytext=offset, color=colour, ha=ha, fontsize=9)

    # Side view (schematic, mm-like units; deviations drawn some 60 times their size).
    screw_x, carriage = 0.0, 560.0
    side.plot([screw_x, screw_x], [0, 1040], color=grey, lw=3)
    side.text(screw_x, 1050, "screw axis of module i (vertical through c_i)", ha="left", va="bottom", fontsize=9)
    side.add_patch(plt.Rectangle((-22, carriage - 445), 44, 490, color="tab:blue", alpha=0.15))
    side.text(
        -30,
        carriage - 200,
        "carriage i\nat reading L_i\n(the encoder's)",
        ha="right",
        va="center",
        fontsize=9,
        color="tab:blue",
    )
    heights = (899.0, 490.0)
    for j, (h, colour) in enumerate(zip(heights, colours)):
        b_drawing = np.array([screw_x, carriage - (heights[0] - h)])
        b = b_drawing + np.array([28.0, 30.0 if j == 0 else -30.0])  # u_ji,x and s_ji
        o_drawing = np.array([420.0, h + 60])
        o = o_drawing + np.array([22.0, 24.0])  # the rotation centre's offset δo_j
        a_drawing = np.array([250.0, h + 60])
        a_moved = a_drawing + (o - o_drawing)  # the drawing's joint, carried by the centre
        a = a_moved + np.array([-24.0, 30.0])  # δr_ji on top
        side.plot(*b_drawing, "o", mfc="white", mec="0.5", ms=7)
        side.plot(*b, "o", color=colour, ms=7)
        side.plot([b_drawing[0], b[0]], [b_drawing[1]] * 2, color=colour, lw=1.2)
        side.text(b[0] + 4, b_drawing[1] + (-30 if j == 0 else 14), f"u_{j + 1}i,x", color=colour, fontsize=9)
        arrow(side, (b[0], b_drawing[1]), b, f"s_{j + 1}i", colour, offset=(8, -4 if j == 0 else -10))
        side.plot([b[0], a[0]], [b[1], a[1]], color=colour, lw=2.5)
        mid = 0.5 * (b + a)
        side.text(mid[0] + 22, mid[1] - 10, f"lever\nl_{j + 1}i = l + δl_{j + 1}i", color=colour, fontsize=9)
        side.plot([a_drawing[0], o_drawing[0] + 60], [h + 60] * 2, **drawn)
        side.plot([a[0], o[0] + 60], [a[1], o[1]], color=colour, lw=5, alpha=0.45)
        side.plot(*o_drawing, "o", mfc="white", mec="0.5", ms=7)
        side.plot(*o, "o", color=colour, ms=7)
        arrow(side, o_drawing, o, f"δo_{j + 1}", colour, offset=(8, -12))
        side.plot(*a_drawing, "o", mfc="white", mec="0.5", ms=7)
        side.plot(*a, "o", color=colour, ms=7)
        arrow(side, a_moved, a, f"δr_{j + 1}i", colour, offset=(-44, 6))
        side.text(
            o[0] + 70, o[1], f"platform m_{j + 1}\ncentre o_{j + 1} at h_{j + 1}", va="center", fontsize=9, color=colour
        )
    side.plot([], [], "o", mfc="white", mec="0.5", label="the drawing's point")
    side.plot([], [], "o", color="0.3", label="as built")
    side.legend(loc="lower right", fontsize=8)
    side.set(xlim=(-170, 620), ylim=(-20, 1130), title="side view of module i (deviations exaggerated)")
    side.set_aspect("equal")
    side.axis("off")

    # Plan view: the screw axis, the U-joint centre's horizontal offset, the platform joint's offset.
    theta, phi = np.radians(-60.0), np.radians(-30.0)
    c = 265.0 * np.array([np.cos(theta), np.sin(theta)])
    r0 = 144.0 * np.array([np.cos(phi), np.sin(phi)])
    plan.plot(*np.array([[0, 0], c]).T, color=grey, lw=0.8, ls=":")
    plan.plot(*c, "s", color=grey, ms=9)
    plan.annotate("screw axis c_i", c, textcoords="offset points", xytext=(8, -14), fontsize=9)
    u = np.array([18.0, 14.0])
    plan.plot(*(c + u), "o", color=colours[0])
    arrow(plan, c, c + u, "", colours[0])
    plan.text(*(c + u + np.array([10.0, 0.0])), "U-joint centre: u_ji = (x, y)", color=colours[0], fontsize=9)
    ring = 144.0 * np.stack([np.cos(np.linspace(0, 2 * np.pi, 200)), np.sin(np.linspace(0, 2 * np.pi, 200))], 1)
    plan.plot(*ring.T, **drawn)
    plan.plot(*r0, "o", mfc="white", mec="0.6")
    dr = np.array([-16.0, 12.0])
    plan.plot(*(r0 + dr), "o", color=colours[0])
    arrow(plan, r0, r0 + dr, "δr_ji (x, y; z up)", colours[0], offset=(-100, 6))
    plan.annotate(
        "r⁰_i = e·[cos φ_i, sin φ_i, 0]\n(platform axes)", r0, textcoords="offset points", xytext=(10, -26), fontsize=9
    )
    plan.plot(0, 0, "+", color="k", ms=12)
    plan.plot(*np.array([c + u, r0 + dr]).T, color=colours[0], lw=2.5, alpha=0.6)
    plan.text(6, 6, "O (δo_j: the centre's offset)", fontsize=9)
    plan.set(xlim=(-170, 230), ylim=(-300, 120), title="plan view (base axes x right, y up)")
    plan.set_aspect("equal")
    plan.grid(alpha=0.2)
    fig.suptitle("[geometry]: each chain ji's deviation from the drawing (platform j, module i), in mm", fontsize=11)
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    plt.close(fig)


FIGURES = {
    "machine_frames": machine_frames,
    "sweep_pareto": sweep_pareto,
    "iso_cycle": iso_cycle,
    "chain_geometry": chain_geometry,
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
