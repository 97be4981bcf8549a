"""The loop on the machine as built (hipsim.control.machine_loop) as it calls its parts: the plant (its own steps, or
RK4 through its derivative; its name or its class's), the feedback (started at the desired first attitude, asked
at each period's time) and the desired motion (at the periods, then its load at every half step and no further)."""

import numpy as np
import pytest

import hipsim
from hipsim.control.feedback import SensorFeedback
from hipsim.control.machine_loop import ModelPD, run_machine
from hipsim.control.simulation import ReducedPlant
from hipsim.motion.trajectories import Trajectory

Q0 = np.radians([3.0, -1.0, 2.0])


@pytest.fixture(scope="module")
def drawing():
    return hipsim.load_parameters()


def _desired(t):
    """A slow turn from Q0 under a load of 1000 + 500·t N."""
    t = np.asarray(t, dtype=float)
    rate = np.array([0.1, 0.05, -0.2])
    return Trajectory(t, Q0 + t[:, None] * rate, np.tile(rate, (t.size, 1)), np.zeros((t.size, 3)), 1000.0 + 500.0 * t)


class Stepped:
    """The drawing's reduced plant without ``advance`` and without a name: the loop steps it by RK4 itself."""

    def __init__(self, params):
        self.params, self._plant = params, ReducedPlant(params, lever_spin=False)

    def initial_state(self, desired):
        return self._plant.initial_state(desired)

    def derivative(self, t, x, tau, Fe):
        return self._plant.derivative(t, x, tau, Fe)

    def readings(self, x):
        return self._plant.readings(x)


class Counted(ReducedPlant):
    """The reduced plant, its own steps recorded: (time [s], loads [N], step [s], steps)."""

    def __init__(self, params):
        super().__init__(params, lever_spin=False)
        self.steps: list[tuple[float, list[float], float, int]] = []

    def advance(self, t, x, tau, loads, h, substeps):
        self.steps.append((t, loads.tolist(), h, substeps))
        return super().advance(t, x, tau, loads, h, substeps)


def test_a_plant_s_own_steps_or_rk4_through_its_derivative(drawing):
    """At 1 kHz with steps of 0.5 ms: the plant's ``advance`` is called each period at its start with the five loads
    of its half steps, 1000 + 500·(k·1 ms + i·0.25 ms) N; a plant without one is stepped by the loop's RK4 through
    its derivative (the same arithmetic) and named by its class."""
    counted = Counted(drawing)

    def run(plant):
        return run_machine(
            plant, ModelPD(drawing, 2), SensorFeedback(2, noise=0.0), _desired, 0.003, servo_rate=1000.0, step=5e-4
        )

    own, stepped = run(counted), run(Stepped(drawing))
    assert [(t, h, substeps) for t, _, h, substeps in counted.steps] == [
        (0.0, 5e-4, 2),
        (pytest.approx(0.001, abs=1e-18), 5e-4, 2),
        (pytest.approx(0.002, abs=1e-18), 5e-4, 2),
    ]
    for k, (_, loads, _, _) in enumerate(counted.steps):
        assert loads == pytest.approx([1000.0 + 500.0 * (k * 1e-3 + i * 2.5e-4) for i in range(5)], abs=1e-9)
    assert stepped.attitudes == pytest.approx(own.attitudes, abs=1e-14)
    assert stepped.rates == pytest.approx(own.rates, abs=1e-12) and stepped.rates[2, 1] != pytest.approx(0.0)
    assert (own.plant, stepped.plant) == ("reduced", "Stepped")


def test_the_feedback_and_the_desired_motion_as_the_loop_asks_them(drawing):
    """The feedback starts with the periods' times and the desired first attitude, and measures period k at its time
    k/500 s; the desired motion is asked at the periods' times, then for its load at the 2·2·3 + 1 half steps of
    0.5 ms up to the run's end (6 ms), no further."""
    asked: list[list[float]] = []

    def desired_at(t):
        asked.append(np.asarray(t).tolist())
        return _desired(t)

    class Seen(SensorFeedback):
        def start(self, t, q0):
            self.started = (t.tolist(), q0.tolist())
            self.times = []
            super().start(t, q0)

        def measure(self, k, t, L, Ld, q, qd):
            self.times.append((k, t))
            return super().measure(k, t, L, Ld, q, qd)

    feedback = Seen(2, noise=0.0)
    run_machine(ReducedPlant(drawing), ModelPD(drawing, 2), feedback, desired_at, 0.006, servo_rate=500.0, step=1e-3)
    assert feedback.started == ([0.0, 0.002, 0.004], Q0.tolist())
    assert feedback.times == [(0, 0.0), (1, 0.002), (2, 0.004)]
    assert asked[0] == [0.0, 0.002, 0.004]
    assert asked[1] == pytest.approx([i * 5e-4 for i in range(13)], abs=1e-18)


@pytest.mark.parametrize("control", [1, 2])
def test_the_model_s_pd_by_virtual_work(drawing, control):
    """On a built model the PD's motor torques do the work of its workspace moment M = K_p·Δq + K_d·Δq̇ (about the
    axes of the gait angles p = s·q, s the angle signs): (2π/p_s)·J_qᵀ·τ = s·T(p)ᵀ·(s·M), J_q = ∂L/∂q of the model's
    carriages for the controlled platform by central differences (another route than the kernel's Jacobian), T the
    map ω = T(p)·ṗ; with K_d = 0 the rates do nothing, and K_p doubled doubles the torques."""
    from stations_synthetic import deviated

    from hipsim.analytic.stations import carriages_for_platform
    from hipsim.physics.orientation import angular_velocity_map

    model = drawing.replace(geometry=deviated(seed=7))
    kp, kd = np.array([200.0, 300.0, 400.0]), np.array([2.0, 3.0, 5.0])
    q, qd = Q0, np.array([0.1, -0.2, 0.05])
    q_desired, qd_desired = Q0 + np.radians([0.5, -0.3, 0.2]), np.array([0.0, 0.1, 0.0])
    tau = ModelPD(model, control, kp=kp, kd=kd).torques(q, qd, q_desired, qd_desired)

    def carriages(angles):
        return carriages_for_platform(model, angles[None], control)[0]

    e = 1e-6
    J = np.column_stack([(carriages(q + e * d) - carriages(q - e * d)) / (2 * e) for d in np.eye(3)])
    signs = model.angle_signs
    moment = kp * (q_desired - q) + kd * (qd_desired - qd)
    T = angular_velocity_map((signs * q)[None])[0]
    assert 2 * np.pi / model.lead * (J.T @ tau) == pytest.approx(signs * (T.T @ (signs * moment)), rel=1e-6)
    soft, stiff = ModelPD(model, control, kp=kp, kd=0.0), ModelPD(model, control, kp=2 * kp, kd=0.0)
    still = soft.torques(q, np.zeros(3), q_desired, np.zeros(3))
    assert soft.torques(q, qd, q_desired, qd_desired) == pytest.approx(still, rel=1e-14)
    assert stiff.torques(q, qd, q_desired, qd_desired) == pytest.approx(2 * still, rel=1e-14)
