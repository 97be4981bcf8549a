"""``hipsim mjcf``: the machine as a MuJoCo model, and the MuJoCo parts of ``simulate`` and ``check``.

Everything MuJoCo is imported inside the functions, so that the rest of the
command line works without the optional ``mujoco`` package; without it these
commands stop with one line saying how to install it.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from .common import add_machine_options, parameters

__all__ = ["add_parser", "add_simulate_options", "format_gaps", "run"]

_INTEGRATORS = ("RK4", "Euler", "implicitfast", "implicit")


def add_parser(subparsers) -> None:
    """Register ``hipsim mjcf``."""
    parser = subparsers.add_parser(
        "mjcf",
        help="the machine as a MuJoCo model (MJCF) with its six loop closures",
        description="Writes the MJCF of the parameter set: the URDF's tree (same joints, masses, inertias and drawing), "
        "the six lever-tip/platform-joint closures as connect equalities, the screws' rotor inertia as armature, the "
        "motors as actuators in N·m (gear 2π/lead), and a keyframe 'iso_start' at the ISO 14242-1 cycle's first sample "
        "with the closures closed. Needs the optional mujoco package (pip install 'hipsim[mujoco]').",
    )
    add_machine_options(parser)
    parser.add_argument(
        "--out", default="hip_simulator.xml", metavar="FILE", help="MJCF to write (default hip_simulator.xml)"
    )
    parser.add_argument(
        "--timestep", type=float, default=0.5, metavar="MS", help="MuJoCo's time step in ms (default 0.5)"
    )
    parser.add_argument("--integrator", choices=_INTEGRATORS, default="RK4", help="MuJoCo's integrator (default RK4)")
    parser.set_defaults(run=run)


def run(args) -> int:
    """Write the MJCF and say what is in it."""
    import numpy as np

    from ..exceptions import HipsimError

    params = parameters(args)
    if not (np.isfinite(args.timestep) and args.timestep > 0):
        raise HipsimError(f"--timestep must be a positive number of ms, got {args.timestep!r}")
    if Path(args.out).is_dir():
        raise HipsimError(f"--out {args.out} is a folder; give an .xml file name")
    from ..files import write_atomic
    from ..mujoco_engine.mjcf import KEYFRAME, MjcfSettings, compile_mjcf, keyframe_gap, mjcf_text

    settings = MjcfSettings(timestep=args.timestep * 1e-3, integrator=args.integrator)
    text = mjcf_text(params, settings)
    model = compile_mjcf(text)
    path = write_atomic(args.out, text)
    tc, ratio = settings.closure_solref
    print(f"wrote {path}")
    print(
        f"  {model.njnt} joints, {model.neq} connect closures, {model.nu} motors (control in N·m, gear 2π/p = {model.actuator_gear[0, 0]:.4g} /m)"
    )
    print(
        f"  {settings.integrator}, time step {settings.timestep * 1e3:g} ms; closures solref ({tc * 1e3:g} ms, {ratio:g}), "
        f"solimp {settings.solimp[0]:g}"
    )
    print(f"  keyframe '{KEYFRAME}': ISO 14242-1 at t = 0, closure gap {keyframe_gap(model):.1e} m")
    return 0


def add_simulate_options(parser: argparse.ArgumentParser) -> None:
    """The MuJoCo plant's option of ``hipsim simulate``."""
    parser.add_argument(
        "--integrator",
        choices=_INTEGRATORS,
        help="with --plant mujoco: MuJoCo's integrator, stepped at --step (default RK4)",
    )


def format_gaps(controller: str, plant) -> str:
    """One line on the closure gap along the last run of a MuJoCo plant."""
    import numpy as np

    times, gaps = plant.gap_history()
    k = int(np.argmax(gaps))
    return (
        f"{controller}: closure gap (MuJoCo's soft connect constraints) at the servo instants: "
        f"largest {gaps[k]:.2e} m at t = {times[k]:.3f} s, RMS {np.sqrt(np.mean(gaps**2)):.2e} m"
    )
