"""A simulated wear test, made by its own route (the truth written down, not computed by the code under test).

Two stations on one machine share its motion (the built-in ISO 14242-1
cycle) and carry their own loads: station 1 the ISO load times s₁(c), station
2 times s₂(c), which steps up half-way through the test (a change the
snapshots record). Each wears V = k_j·I(c) with I the sum over cycles of the
local integral ΣW·dA: the ISO cycle's ``I0_LOCAL`` (N·m per cycle at load scale 1,
converged on a fine grid; the work is linear in the load) times the load scale. Plus
bedding-in (an extra volume worn over the first 0.5 Mc), fluid uptake by each
cup equal to its own soak control's (different per station), and balance
noise on every reading. The snapshots (rig logs with the cycle counter, the
motor torques of the analytic model, angles and loads with noise) are what
``hipsim monitor`` reads.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

import hipsim
from hipsim.motion.trajectories import Trajectory

__all__ = ["I0_LOCAL", "I0_TRACK", "TRUTH", "Truth", "platform_i0", "platform_motions", "write_simulated_test"]

#: The built-in ISO cycle's ΣW·dA and ∫F ds per cycle in [N·m], 28 mm head, 1 kHz (ΣW·dA converged: 36.4950 on a
#: 180 x 360 grid, 36.4961 on 90 x 180, 36.5004 on 45 x 90).
I0_LOCAL = 36.4950
I0_TRACK = 28.2980


@dataclass(frozen=True)
class Truth:
    """The simulated test's truth: per station its local k in [mm³/(N·m)], load scale before and after
    ``step_cycle``, bedding-in volume in [mm³], soak uptake in [mg] (saturating with ``soak_cycles``)."""

    k: tuple[float, float] = (4.0e-7, 5.5e-7)
    scale_before: tuple[float, float] = (1.0, 1.1)
    scale_after: tuple[float, float] = (1.0, 1.3)
    step_cycle: float = 2_500_000
    bedding_mm3: tuple[float, float] = (2.0, 1.0)
    soak_mg: tuple[float, float] = (3.0, 1.5)
    soak_cycles: tuple[float, float] = (0.8e6, 1.5e6)
    density: float = 0.935
    noise_mg: float = 0.05
    i0_local: tuple[float, float] = (I0_LOCAL, I0_LOCAL)

    def scale(self, j: int, cycle: float) -> float:
        return (self.scale_before if cycle < self.step_cycle else self.scale_after)[j]

    def exposure(self, j: int, cycle: float) -> float:
        """Σ over cycles 0 … cycle of ΣW·dA in [N·m]."""
        before = min(cycle, self.step_cycle)
        after = max(cycle - self.step_cycle, 0.0)
        return self.i0_local[j] * (self.scale_before[j] * before + self.scale_after[j] * after)

    def volume(self, j: int, cycle: float) -> float:
        """The volume worn by station j by ``cycle`` in [mm³]."""
        return self.k[j] * self.exposure(j, cycle) + self.bedding_mm3[j] * min(cycle / 0.5e6, 1.0)

    def uptake(self, j: int, cycle: float) -> float:
        return self.soak_mg[j] * (1.0 - math.exp(-cycle / self.soak_cycles[j]))

    def rate(self, j: int, c0: float, c1: float) -> float:
        """The true mean rate from c0 to c1 in [mm³/Mc] (the steady state's, after bedding-in)."""
        return (self.volume(j, c1) - self.volume(j, c0)) / (c1 - c0) * 1e6


TRUTH = Truth()


def write_weighings(path: Path, truth: Truth, stops: np.ndarray, rng) -> Path:
    lines = ["# simulated weighings: masses in mg, each cup's own soak control", "cycle,station,mass_mg"]
    for c in stops:
        for j in (0, 1):
            uptake = truth.uptake(j, c)
            cup = 30_000.0 + 500 * j - truth.density * truth.volume(j, c) + uptake + rng.normal(0, truth.noise_mg)
            soak = 29_800.0 + 500 * j + uptake + rng.normal(0, truth.noise_mg)
            lines += [f"{int(c)},{j + 1},{cup:.3f}", f"{int(c)},soak_{j + 1},{soak:.3f}"]
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


def platform_motions(geometry, rate: float, cycles: int = 1) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A per-chain machine whose carriages serve platform 2's ISO cycle: (t, carriages in [m] (N, 3), each platform's
    true attitude in [rad] (N, 2, 3)), by tests/stations_synthetic.py's own forward kinematics."""
    from stations_synthetic import reference_attitude, reference_carriages

    params = hipsim.load_parameters()
    cycle = hipsim.iso14242(rate=rate, cycles=cycles)
    carriages = reference_carriages(params, geometry, 2, cycle.q)
    q = np.stack([reference_attitude(params, geometry, j, carriages, cycle.q) for j in (1, 2)], axis=1)
    return cycle.t, carriages, q


def platform_i0(geometry, rate: float = 1000.0, grid: tuple[int, int] = (90, 180)) -> tuple[float, float]:
    """Each platform's true ΣW·dA per cycle at load scale 1 in [N·m]: its true motion (at ``rate``, derivatives of
    the periodic spline through it) on a ``grid``."""
    from scipy.interpolate import make_interp_spline

    from hipsim.wear import cup_grid, wear_maps
    from hipsim.wear.factors import motion_integrals

    t, _, q = platform_motions(geometry, rate)
    load = hipsim.iso14242(rate=rate).Fe
    out = []
    for j in (0, 1):
        closed = np.concatenate([q[:, j], q[:1, j]])
        spline = make_interp_spline(np.append(t, 1.0), closed, k=5, bc_type="periodic", axis=0)
        motion = Trajectory(t, q[:, j], spline(t, 1), spline(t, 2), load, f"platform {j + 1}", periodic=True)
        out.append(motion_integrals(wear_maps(motion, 1.0, points=cup_grid(*grid))).load_slide_integral_Nm)
    return out[0], out[1]


def write_snapshots(
    folder: Path, truth: Truth, cycles: np.ndarray, rng, rate: float = 250.0, geometry=None
) -> list[Path]:
    """One rig log of 3 ISO cycles per snapshot cycle: torques (analytic model), angles (0.003° noise), loads; with
    ``geometry`` (a per-chain machine) the carriages (L_1i_mm) instead of the angles, each platform its own motion."""
    folder.mkdir(parents=True, exist_ok=True)
    params = hipsim.load_parameters()
    trajectory = hipsim.iso14242(rate=rate, cycles=3)
    carriages = platform_motions(geometry, rate, 3)[1] if geometry is not None else None
    torques: dict[float, np.ndarray] = {}  # the machine's torques under the mean of the stations' loads, by its scale
    paths = []
    for c in cycles:
        loads = [trajectory.Fe * truth.scale(j, c) for j in (0, 1)]
        mean = 0.5 * (truth.scale(0, c) + truth.scale(1, c))
        if mean not in torques:
            loaded = Trajectory(trajectory.t, trajectory.q, trajectory.qd, trajectory.qdd, trajectory.Fe * mean)
            torques[mean] = hipsim.analyse(params, loaded, lever_spin=True).torques.total * 1e3
        tau = torques[mean]
        columns = {
            "t_s": trajectory.t,
            "cycle": c + np.floor(trajectory.t).astype(int),
            "Fe_N": 0.5 * (loads[0] + loads[1]),
            "Fe_1_N": loads[0],
            "Fe_2_N": loads[1],
        }
        noisy = tau + rng.normal(0.0, 3.0, tau.shape)
        columns |= {f"tau_{i + 1}_Nmm": noisy[:, i] for i in range(3)}
        if carriages is None:
            angles = np.degrees(trajectory.q) + rng.normal(0.0, 0.003, trajectory.q.shape)
            columns |= {f"{name}_deg": angles[:, k] for k, name in enumerate(("alpha", "beta", "gamma"))}
        else:  # encoders of 0.1 µm
            heights = carriages * 1e3 + rng.normal(0.0, 1e-4, carriages.shape)
            columns |= {f"L_1{i + 1}_mm": heights[:, i] for i in range(3)}
        names = list(columns)
        rows = np.column_stack([columns[name] for name in names])
        path = folder / f"snap_{int(c):08d}.csv"
        with open(path, "w", encoding="utf-8") as stream:
            stream.write(",".join(names) + "\n")
            for row in rows:
                stream.write(",".join(f"{v:.0f}" if n == "cycle" else f"{v:.10g}" for n, v in zip(names, row)) + "\n")
        paths.append(path)
    return paths


def write_identified(path: Path, geometry=None) -> Path:
    """The published machine as an identified file (the monitor's requirement; the wear needs only the encoders),
    with ``geometry`` its [geometry] table."""
    from hipsim.machine.chains import geometry_table

    published = Path(hipsim.load_parameters().source).read_text(encoding="utf-8")
    table = ""
    if geometry is not None:
        rows = geometry_table(geometry)
        table = "\n[geometry]\n" + "".join(f"{key} = {value!r}\n".replace("'", '"') for key, value in rows.items())
    path.write_text(
        "# Identified by hipsim identify: a parameter file every hipsim command accepts (--params).\n"
        "# Model: analytic, lever spin on; regressor condition number 10.\n\n" + published + table,
        encoding="utf-8",
    )
    return path


def write_simulated_test(
    folder: Path,
    truth: Truth = TRUTH,
    stops: np.ndarray | None = None,
    snapshots: np.ndarray | None = None,
    seed: int = 11,
    rate: float = 250.0,
    geometry=None,
) -> Path:
    """A test folder: weighings.csv, snapshots/, params.toml (the layout ``hipsim wear --test`` reads). With
    ``geometry`` the machine is per-chain: the logs hold carriages, each platform moves its own way and wears by its
    own ΣW·dA (``truth.i0_local`` should hold :func:`platform_i0`'s)."""
    folder.mkdir(parents=True, exist_ok=True)
    rng = np.random.default_rng(seed)
    stops = np.arange(0, 5_000_001, 500_000) if stops is None else stops
    snapshots = np.arange(0, 5_000_000, 250_000) if snapshots is None else snapshots
    write_weighings(folder / "weighings.csv", truth, stops, rng)
    write_snapshots(folder / "snapshots", truth, snapshots, rng, rate, geometry)
    write_identified(folder / "params.toml", geometry)
    return folder
