"""What a viewer shows, in words: the offline page's legend (HTML) and the plain-text lines the `view` command prints."""

from __future__ import annotations

import numpy as np

from .meshcat_scene import scale_text
from .motion_frames import Motion

__all__ = ["description_lines", "legend_lines"]


def legend_lines(motion: Motion, scale: float | None, human: bool) -> list[str]:
    """HTML lines of the offline page's legend.

    Args:
        motion: the motion shown.
        scale: arrow scale in [m per N] (used only when the motion has forces).
        human: the human model stands beside the machine.
    """
    import html

    lines = [
        f"hipsim: {html.escape(motion.name)}, {motion.duration:.3g} s in {len(motion)} frames at {motion.fps:g} fps, speed {motion.speed:g}&times;"
    ]
    if motion.forces() is not None and scale is not None:  # the scale is given with forces
        lines.append(
            f"arrows ({scale_text(scale)}): <span style='color:#d91acc'>&#9632;</span> motor thrust 2πτ/p on each screw's carriage, "
            f"<span style='color:#0dbfd9'>&#9632;</span> force of each lever on its platform"
        )
    if motion.cond_inv is not None:
        lines.append(
            "levers: singularity measure (inverse condition number of J) "
            "<span style='color:#d91a1a'>&#9632;</span> 0 singular, <span style='color:#f2d91a'>&#9632;</span> 0.25, "
            "<span style='color:#73e61a'>&#9632;</span> &ge; 0.5"
        )
    if human:
        lines.append("human: the right hip turns as the platforms do (α flexion, β adduction, γ internal rotation)")
    return lines


def description_lines(motion: Motion, scale: float | None, human: bool) -> list[str]:
    """Plain-text lines saying what is shown of ``motion`` (frames, closure gap, arrows, colours, human).

    Args:
        motion: the motion shown.
        scale: arrow scale in [m per N] (used only when the motion has forces).
        human: the human model stands beside the machine.
    """
    lines = [
        f"{motion.name}: {motion.duration:.4g} s in {len(motion)} frames at {motion.fps:g} fps, speed {motion.speed:g}x; "
        f"largest closure gap of the frames shown {float(motion.residual.max()):.1e} m"
    ]
    forces = motion.forces()
    if forces is not None and scale is not None:  # the scale is given with forces
        lines.append(
            f"arrows at {scale_text(scale)}: magenta = motor thrust 2πτ/p on each screw's carriage "
            f"(peak {float(np.abs(forces[0]).max()):.0f} N), cyan = force of each lever on its platform "
            f"(peak {float(np.linalg.norm(forces[1], axis=-1).max()):.0f} N)"
        )
    if motion.cond_inv is not None:
        lines.append(
            "levers coloured by the singularity measure (inverse condition number of J): red 0, yellow 0.25, lime green >= 0.5; "
            f"here {float(np.nanmin(motion.cond_inv)):.3f} to {float(np.nanmax(motion.cond_inv)):.3f}"
        )
    if human:
        lines.append(
            "human model: its right hip turns as the platforms do (alpha flexion, beta adduction, gamma internal rotation)"
        )
    return lines
