"""Synthetic rig logs made by hipsim's plants: a route other than the inverse dynamics that identification uses.

A plant (the Pinocchio closed-chain plant, or the reduced plant compiled by
numba) with the "true" machine is driven by the augmented PD of a controller
that believes the starting machine, along a desired motion; the log records
what a rig's sensors would: the angles (or encoder heights), the load, and
the motor torques.

Torques in a log. The servo holds each torque over its period [t_k, t_k+1),
while the angles are sampled at t_k; the torque a current sensor sampled at
t_k reads, averaged over one period centred there, is (τ_k−1 + τ_k)/2, and
that is what the noisy logs carry (the held value itself would put the torque
half a period late, a 0.5 ms delay that the fit would read as inertia).
The exact logs instead take the plant's own acceleration at t_k under τ_k,
from its forward dynamics: the inverse dynamics holds there exactly.

Runs whose acceleration no log reads (every noisy log: :func:`write_log`
writes angles, heights, load and torques) take the compiled servo loop, the
same numbers to the last bit as the Python loop that records each state for
the acceleration (checked on the fit's excitation), 2.7× faster; a shorter run
of the fit's excitation is the first seconds of the longest (the loop is
causal: the same numbers to the last bit), so it is simulated once.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
from support import given

from hipsim.analytic.inverse_kinematics import slider_heights
from hipsim.control import AugmentedPD, ReducedPlant, simulate
from hipsim.engine import Plant
from hipsim.machine.parameters import Parameters
from hipsim.motion.trajectories import Trajectory
from hipsim.rig.logs.log import MeasuredLog


class FourierMotion:
    """A periodic motion: each angle a sum of harmonics of one base frequency, and a load that varies.

    Args:
        seed: random seed.
        amplitude_deg: largest amplitude of each angle in [deg].
        harmonics: harmonics per angle.
        base: base frequency in [Hz].
    """

    def __init__(self, seed: int = 0, amplitude_deg: float = 14.0, harmonics: int = 4, base: float = 0.25):
        rng = np.random.default_rng(seed)
        self.base = base
        self.offset = np.radians(rng.uniform(-3.0, 3.0, 3))
        self.amp = np.radians(rng.uniform(0.3, 1.0, (harmonics, 3)) * amplitude_deg / harmonics)
        self.harmonic = np.arange(1, harmonics + 1)[:, None] * np.ones((1, 3))
        self.phase = rng.uniform(0.0, 2 * np.pi, (harmonics, 3))
        self.load_phase = rng.uniform(0.0, 2 * np.pi, 2)

    def __call__(self, t) -> Trajectory:
        t = np.atleast_1d(np.asarray(t, dtype=float))
        w = 2 * np.pi * self.base * self.harmonic
        arg = w * t[:, None, None] + self.phase
        q = self.offset + np.sum(self.amp * np.sin(arg), axis=1)
        qd = np.sum(self.amp * w * np.cos(arg), axis=1)
        qdd = -np.sum(self.amp * w**2 * np.sin(arg), axis=1)
        s = 2 * np.pi * self.base * t
        load = 1650.0 + 900.0 * np.sin(3 * s + self.load_phase[0]) + 400.0 * np.sin(7 * s + self.load_phase[1])
        return Trajectory(t, q, qd, qdd, load, name="Fourier motion")


class _Recording:
    """A plant that remembers every state the servo loop reads."""

    def __init__(self, plant):
        self.plant, self.params, self.name, self.states = plant, plant.params, plant.name, []

    def initial_state(self, desired):
        return self.plant.initial_state(desired)

    def derivative(self, t, x, tau, Fe):
        return self.plant.derivative(t, x, tau, Fe)

    def angles(self, x):
        self.states.append(np.array(x))
        return self.plant.angles(x)


@dataclass
class PlantRun:
    """A closed-loop run, sampled at the servo instants (SI)."""

    t: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray | None  # the plant's acceleration at t_k under the torque held from t_k (None: not recorded)
    tau: np.ndarray  # the torque held over [t_k, t_k+1)
    Fe: np.ndarray
    params: Parameters

    def head(self, n: int) -> PlantRun:
        """The run's first n servo samples: the run of n samples itself, the loop being causal."""
        if not 2 <= n <= len(self.t):
            raise ValueError(f"a head of {n} samples of a run of {len(self.t)}")
        qdd = None if self.qdd is None else self.qdd[:n]
        return PlantRun(self.t[:n], self.q[:n], self.qd[:n], qdd, self.tau[:n], self.Fe[:n], self.params)

    @property
    def tau_centred(self) -> np.ndarray:
        """The torque averaged over one period centred on t_k."""
        previous = np.vstack([self.tau[:1], self.tau[:-1]])
        return 0.5 * (previous + self.tau)

    def exact_log(self, name: str = "exact") -> MeasuredLog:
        qdd = given(self.qdd)  # a run made with accelerations=True
        return MeasuredLog(Trajectory(self.t, self.q, self.qd, qdd, self.Fe, name=name), self.tau, None, name)


def plant_run(
    true,
    model,
    desired_at,
    duration: float,
    plant: str = "pinocchio",
    servo_rate: float = 1000.0,
    accelerations: bool = True,
) -> PlantRun:
    """Drive the plant of the ``true`` machine with an augmented PD that believes ``model``.

    ``accelerations``: record every state and take the plant's acceleration at each
    servo instant (for :meth:`PlantRun.exact_log`); without, the compiled loop runs.
    """
    if plant == "pinocchio":
        from hipsim.closed_chain.plant import PinocchioPlant

        pinocchio = PinocchioPlant(true)
        inner: Plant = pinocchio
        platform_rate = pinocchio.nq + given(pinocchio.chain.layout).platform_v[0]  # the platform's rates in dx/dt
    else:
        inner = ReducedPlant(true)
        platform_rate = None
    controller = AugmentedPD(model, desired_at, servo_rate, duration)
    if not accelerations:
        sim = simulate(inner, controller, desired_at, duration, servo_rate=servo_rate)
        return PlantRun(sim.t, sim.q, sim.qd, None, sim.tau, sim.desired.Fe, true)
    recording = _Recording(inner)
    sim = simulate(recording, controller, desired_at, duration, servo_rate=servo_rate)
    Fe = sim.desired.Fe
    qdd = np.empty_like(sim.q)
    for k, x in enumerate(recording.states):
        rate = inner.derivative(sim.t[k], x, sim.tau[k], Fe[k])
        qdd[k] = rate[platform_rate] * true.angle_signs if platform_rate is not None else rate[3:]
    return PlantRun(sim.t, sim.q, sim.qd, qdd, sim.tau, Fe, true)


def write_log(
    path: Path,
    run: PlantRun,
    rng: np.random.Generator,
    torque_noise_Nmm: float = 3.0,
    angle_noise_deg: float = 0.003,
    motion: str = "angles",
    extra: dict | None = None,
) -> Path:
    """Write a rig log CSV with noise: angles (attitude sensor) and/or encoder heights, the load and the motor torques."""
    columns = {"t_s": run.t, "Fe_N": run.Fe}
    tau = run.tau_centred * 1e3 + rng.normal(0.0, torque_noise_Nmm, run.tau.shape)
    for i in range(3):
        columns[f"tau_{i + 1}_Nmm"] = tau[:, i]
    if motion in ("angles", "both"):
        angles = np.degrees(run.q) + rng.normal(0.0, angle_noise_deg, run.q.shape)
        for k, name in enumerate(("alpha", "beta", "gamma")):
            columns[f"{name}_deg"] = angles[:, k]
    if motion in ("encoders", "both"):
        heights = np.round(
            slider_heights(run.params, run.q * run.params.angle_signs)[:, 0] * 1e3, 4
        )  # a 0.1 µm encoder
        for i in range(3):
            columns[f"L_1{i + 1}_mm"] = heights[:, i]
    columns.update(extra or {})
    names = list(columns)
    data = np.column_stack([columns[name] for name in names])
    with open(path, "w", encoding="utf-8") as stream:
        stream.write(",".join(names) + "\n")
        np.savetxt(stream, data, delimiter=",", fmt="%.12g")
    return path


def mismatched(start):
    """The "true" machine of the synthetic tests: masses and inertias ±10 %, friction changed, screw friction on."""
    return start.replace(
        platform_inertia=start.platform_inertia * np.sqrt(np.outer([1.10, 0.92, 1.08], [1.10, 0.92, 1.08])),
        slider_mass=start.slider_mass * 1.10,
        screw_inertia=start.screw_inertia * 0.90,
        lever_mass=start.lever_mass * 0.90,
        lever_inertia=start.lever_inertia * 1.10,
        hip_mu=start.friction.hip_mu * 1.30,
        thrust_mu=start.friction.thrust_mu * 0.70,
        screw_coulomb=0.040,  # 40 N·mm
        screw_viscous=2e-4,  # 0.2 N·mm·s/rad
    )


def relative_to_size(estimate: np.ndarray, truth: np.ndarray, size: np.ndarray) -> np.ndarray:
    """|estimate − truth| / max(|truth|, size): relative error, against a typical size for values near zero."""
    return np.abs(estimate - truth) / np.maximum(np.abs(truth), size)


__all__ = ["FourierMotion", "PlantRun", "mismatched", "plant_run", "relative_to_size", "write_log"]


# --- The runs the tests share (each made once per test process) -----------------------------------

import functools  # noqa: E402

import hipsim  # noqa: E402
from hipsim.motion.trajectories import iso14242_at  # noqa: E402


@functools.cache
def machines():
    """(starting machine: the published one, true machine: :func:`mismatched`)."""
    start = hipsim.load_parameters()
    return start, mismatched(start)


#: The fit's excitation: five harmonics of 0.5 Hz, up to 24° per angle, the load swinging 350–2950 N.
FIT_MOTION = FourierMotion(3, amplitude_deg=24.0, harmonics=5, base=0.5)


#: The longest run of the fit's excitation the tests take [s]; a shorter one is its head.
FIT_SECONDS = 20.0


@functools.cache
def _fit_run_longest() -> PlantRun:
    start, true = machines()
    return plant_run(true, start, FIT_MOTION, FIT_SECONDS, accelerations=False)


def fit_run(duration: float = FIT_SECONDS) -> PlantRun:
    """The Pinocchio plant of the true machine along the fit's excitation, driven by a controller that believes the start.

    Up to :data:`FIT_SECONDS`, the head of the one longest run (the same numbers to the last bit as a run of that length).
    """
    if duration > FIT_SECONDS:
        start, true = machines()
        return plant_run(true, start, FIT_MOTION, duration, accelerations=False)
    return _fit_run_longest().head(int(round(duration * 1000.0)))


@functools.cache
def iso_run(duration: float = 4.0) -> PlantRun:
    """The same along the ISO 14242-1 cycle: the held-out trajectory."""
    start, true = machines()
    return plant_run(true, start, lambda t: iso14242_at(t), duration, accelerations=False)


@functools.cache
def exact_run(duration: float = 6.0, constant_load: bool = False) -> PlantRun:
    """The reduced plant (compiled by numba, a route of its own) along the fit's excitation, for exact logs."""
    start, true = machines()
    if constant_load:

        def motion(t):
            trajectory = FIT_MOTION(t)
            return Trajectory(
                trajectory.t, trajectory.q, trajectory.qd, trajectory.qdd, np.full(trajectory.t.shape, 1500.0)
            )
    else:
        motion = FIT_MOTION
    return plant_run(true, start, motion, duration, plant="reduced")
