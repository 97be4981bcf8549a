"""Issue 26's accuracy checks: identification from the logs a lab has, on a synthetic rig made by another route.

The rig: the Pinocchio plant of a machine whose masses, inertias and friction
differ from the published ones, screw friction on (:func:`rig_synthetic.mismatched`),
driven by a controller that believes the published machine, logged with 3 N·mm
torque noise and 0.003° angle noise. Each log set is identified with the
default options, and the identified machine predicts a held-out ISO 14242-1 run
at another frequency (1.2 Hz) and load (¾) that no log contains; the error is
against the true machine's torque along it, RMS over RMS per motor, the worst
motor. Logs are short (5 cycles of ISO, 5 periods of the excitation) to keep the
module fast; the margins below were measured on them (see docs/guide/rig.md).
"""

import numpy as np
import pytest
from rig_synthetic import machines, plant_run, write_log

from hipsim.analytic import inverse_dynamics, kinematics
from hipsim.motion.trajectories import Trajectory, iso14242_at
from hipsim.rig import excitation, identify, load_log


def _iso(frequency: float, load: float):
    def at(t):
        trajectory = iso14242_at(t, frequency=frequency)
        return Trajectory(
            trajectory.t, trajectory.q, trajectory.qd, trajectory.qdd, trajectory.Fe * load, name="ISO 14242-1"
        )

    return at


@pytest.fixture(scope="module")
def logs(tmp_path_factory):
    """The logs a lab would record: hipsim's designed excitation (defaults, 5 periods), and ISO runs (5 cycles) at two loads."""
    folder = tmp_path_factory.mktemp("accuracy")
    start, true = machines()
    rng = np.random.default_rng(26)
    design = excitation(start)  # `hipsim excite`'s defaults

    def log(name, desired, duration):
        run = plant_run(true, start, desired, duration, accelerations=False)  # the compiled loop: no log reads qdd
        return load_log(write_log(folder / f"{name}.csv", run, rng), start)

    return {
        "excitation": log("excite", design.at, 5 / design.frequency),
        "iso": log("iso", _iso(1.0, 1.0), 5.0),
        "iso_light": log("iso_light", _iso(0.8, 0.6), 5.0),
    }


@pytest.fixture(scope="module")
def held_out():
    """The held-out run: ISO 14242-1 at 1.2 Hz under ¾ of its load, and the true machine's torques along it."""
    _, true = machines()
    trajectory = _iso(1.2, 0.75)(np.arange(0.0, 2.0, 1e-3))
    return trajectory, inverse_dynamics(true, kinematics(true, trajectory), trajectory.Fe, True).total


def held_out_error(params, held_out) -> float:
    """The worst motor's RMS prediction error over its RMS true torque."""
    trajectory, tau = held_out
    predicted = inverse_dynamics(params, kinematics(params, trajectory), trajectory.Fe, True).total
    return float(np.max(np.sqrt(np.mean((predicted - tau) ** 2, axis=0) / np.mean(tau**2, axis=0))))


def friction_terms(params) -> tuple[float, float]:
    """The weight-dependent friction r_t·μ_t·m_m·g in [N·m] (of the true platform mass) and the load-proportional r_h·μ_h + r_t·μ_t in [m]."""
    _, true = machines()
    f = params.friction
    return (
        f.thrust_radius * f.thrust_mu * true.platform_mass * true.gravity,
        f.hip_radius * f.hip_mu + f.thrust_radius * f.thrust_mu,
    )


@pytest.fixture(scope="module")
def identified(logs):
    start, _ = machines()
    sets = {
        "excitation + ISO": ["excitation", "iso", "iso_light"],
        "ISO only": ["iso"],
        "excitation alone": ["excitation"],
    }
    return {name: identify([logs[k] for k in keys], start) for name, keys in sets.items()}


@pytest.mark.parametrize(
    ("name", "most"), [("excitation + ISO", 0.0015), ("ISO only", 0.01), ("excitation alone", 0.005)]
)
def test_the_identified_machine_predicts_a_held_out_iso_run(identified, held_out, name, most):
    start, _ = machines()
    assert held_out_error(start, held_out) > 0.1  # the published set misses by tens of percent
    assert held_out_error(identified[name].params, held_out) <= most


@pytest.mark.parametrize("name", ["excitation + ISO", "excitation alone"])
def test_friction_terms_are_identified(identified, name):
    """The weight-dependent friction within 5 %, the load-proportional within 2 % (the split of the two needs a varying load)."""
    _, true = machines()
    weight, load = friction_terms(identified[name].params)
    true_weight, true_load = friction_terms(true)
    assert weight == pytest.approx(true_weight, rel=0.05)
    assert load == pytest.approx(true_load, rel=0.02)
    start, _ = machines()
    assert friction_terms(start)[0] != pytest.approx(true_weight, rel=0.05)  # the published set does not pass
