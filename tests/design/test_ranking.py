"""Choosing from catalogues (hipsim.design.ranking): each screw lead reruns the model; candidates rank with the binding constraint named."""

import math
from pathlib import Path

import numpy as np
import pytest
from drive_support import curve, only
from support import given

import hipsim
from hipsim.design.ranking import rank_drives
from hipsim.design.sizing import sizing
from hipsim.design.sizing_summary import candidate_summary
from hipsim.machine.drive_parts import Drive, LeadScrew, Motor, TorqueSpeedCurve
from hipsim.motion.trajectories import iso14242


@pytest.fixture(scope="module")
def params():
    return hipsim.load_parameters()


# ---------------------------------------------------------------------------
# The lead: recomputed, not rescaled


def test_each_screw_lead_reruns_the_model(params):
    trajectory = iso14242(rate=100)
    motor = (Motor("m", peak=TorqueSpeedCurve(np.array([0.0]), np.array([5.0])), rotor_inertia=1e-4), None)
    screws = [LeadScrew("p5", lead=0.005), LeadScrew("p20", lead=0.020, inertia=80e-6)]
    candidates = rank_drives(params, [(trajectory, 1.0)], [motor], screws)
    by_screw = {given(c.drive.screw).name: c for c in candidates}
    for screw in screws:
        machine = params.replace(lead=screw.lead, **({"screw_inertia": screw.inertia} if screw.inertia else {}))
        direct = sizing(hipsim.analyse(machine, trajectory), Drive(motor[0], screw=screw))
        expected = {(c.module, c.name): c.value for c in direct.checks if c.value is not None}
        got = {(c.module, c.name): c.value for c in by_screw[screw.name].checks if c.value is not None}
        assert got == pytest.approx(expected, rel=1e-12, nan_ok=True)
    peak5 = only(by_screw["p5"].checks, "peak_curve").value
    peak20 = only(by_screw["p20"].checks, "peak_curve").value
    # Rescaling the 20 mm torques by 5/20 would miss the screw inertia and the changed reflected inertia.
    assert abs(peak5 - peak20 * 5 / 20) > 0.01 * peak5


# ---------------------------------------------------------------------------
# Ranking


def test_an_undersized_and_a_right_motor_rank_with_the_binding_constraint_named(params):
    small = Motor(
        "small", continuous=curve([0, 3000], [1.0, 1.0]), peak=curve([0, 3000], [0.25, 0.25]), rotor_inertia=1e-4
    )
    right = Motor(
        "right", continuous=curve([0, 3000], [1.3, 1.2]), peak=curve([0, 5000], [3.8, 3.0]), rotor_inertia=1e-4
    )
    trajectory = iso14242(rate=200)
    candidates = rank_drives(params, [(trajectory, 1.0)], [(small, None), (right, None)])
    assert [c.drive.motor.name for c in candidates] == ["right", "small"]
    assert candidates[0].passed is True and candidates[1].passed is False
    binding = given(candidates[1].binding)
    assert binding.name == "peak_curve" and binding.module == 1  # motor 1 needs over 431 N·mm, 250 N·mm on offer
    run = hipsim.analyse(params, trajectory)
    rotor = 1e-4 * 2 * math.pi / params.lead * run.Ldd[:, 0, 0]  # the motor also turns its own rotor
    assert binding.value == pytest.approx(np.abs(run.torques.total[:, 0] + rotor).max() * 1e3, rel=1e-12)
    assert binding.limit == pytest.approx(250.0) and binding.margin == pytest.approx(1 - given(binding.value) / 250.0)
    assert given(candidates[0].margin) > 0 > given(candidates[1].margin)


# ---------------------------------------------------------------------------
# Ranking the way a drive engineer ranks (issue 29): the smallest passing drive first


@pytest.fixture(scope="module")
def example():
    """The example catalogue ranked both ways on a coarse ISO cycle."""
    from importlib import resources

    from hipsim.machine.drive import load_gearbox_catalogue, load_motor_catalogue, load_screw_catalogue

    folder = Path(str(resources.files("hipsim.models")))  # an installed package's folder
    motors = load_motor_catalogue(folder / "motors_example.csv")
    screws = load_screw_catalogue(folder / "screws_example.csv")
    gearboxes = load_gearbox_catalogue(folder / "gearboxes_example.csv")
    params = hipsim.load_parameters()
    cycle = [(iso14242(rate=200), 1.0)]
    return {order: rank_drives(params, cycle, motors, screws, gearboxes, order=order) for order in ("size", "margin")}


def _power_by_hand(motor):
    """Rated torque × rated speed read off the S1 curve's corner: the last point still at the stall torque."""
    corner = max(
        k for k in range(len(motor.continuous.speed)) if motor.continuous.torque[k] == motor.continuous.torque[0]
    )
    return motor.continuous.torque[corner] * motor.continuous.speed[corner]


def test_the_first_ranked_passing_drive_is_the_smallest_that_passes(example):
    ranked = example["size"]
    passing = [c for c in ranked if c.passed]
    assert passing and all(c.passed for c in ranked[: len(passing)])  # every passing one before every failing one
    # Brute force: every combination whose every check passes, by its checks alone.
    every = [
        c
        for c in ranked
        if all(check.passed is not False for check in c.checks) and any(check.passed for check in c.checks)
    ]
    assert {c.drive.name for c in every} == {c.drive.name for c in passing}
    smallest = min(_power_by_hand(c.drive.motor) for c in every)
    assert _power_by_hand(ranked[0].drive.motor) == smallest
    assert ranked[0].rated_power[0] == pytest.approx(smallest, rel=1e-12)
    assert ranked[0].rated_power[1].startswith("S1 curve")  # the example catalogue gives no rated_power_W
    assert ranked[0].drive.motor.name == "EX-S200 (example 200 W)"  # 0.64 N·m × 3000 rpm = 201 W
    powers = [c.rated_power[0] for c in passing]
    assert powers == sorted(powers)


def test_the_screw_checks_break_no_tie(example):
    """Carriage stroke is the same for every motor: the passing 750 W drives are told apart by their motor's checks."""
    from hipsim.design.checks import MOTOR_INDEPENDENT
    from hipsim.design.ranking import screw_checks

    ranked = example["size"]
    for c in ranked:
        if c.motor_binding is not None:
            assert c.motor_binding.name not in MOTOR_INDEPENDENT
    per_screw = screw_checks(ranked)
    assert len(per_screw) == 3 and all({c.name for c in checks} <= MOTOR_INDEPENDENT for _, checks in per_screw)
    for screw, checks in per_screw:
        for c in ranked:
            if c.drive.screw is screw:
                mine = [(k.module, k.name, k.value, k.limit) for k in c.checks if k.name in MOTOR_INDEPENDENT]
                assert mine == [(k.module, k.name, k.value, k.limit) for k in checks]


def test_an_overspeeding_motor_names_the_speed_it_needs_and_its_top_speed(example, params):
    from hipsim.present.check_text import check_sentence

    # The 2:1 belt on the 5 mm screw: the motor turns 2 × 60/5 mm × the carriage speed.
    over = next(
        c
        for c in example["size"]
        if c.drive.motor.name == "EX-S200 (example 200 W)"
        and c.drive.gearbox.ratio == 2
        and c.drive.screw.lead == pytest.approx(0.005)
    )
    failure = over.failure
    assert failure.name == "max_speed" and over.passed is False
    run = hipsim.analyse(params.replace(lead=0.005), iso14242(rate=200))
    needed = np.abs(run.Ld).max(axis=0) * 2 / 0.005 * 60  # rpm per module
    assert failure.value == pytest.approx(needed.max(), rel=1e-9) and failure.module == int(np.argmax(needed)) + 1
    text = check_sentence(failure)
    assert f"needs {needed.max():,.0f} rpm" in text and "the motor's top speed is 6,000" in text
    assert "∞" not in text and "/ 0" not in text


def test_rank_margin_keeps_the_order_by_the_smallest_margin(example):
    ranked = example["margin"]
    margins = [c.margin for c in ranked]
    assert margins == sorted(margins, reverse=True)
    assert ranked[0].drive.motor.name == "EX-S750 (example 750 W)"  # the largest motor, bound by the carriage stroke
    assert {c.drive.name for c in ranked} == {c.drive.name for c in example["size"]}


def test_a_catalogue_rated_power_and_cost_rank_before_the_s1_curve(params):
    """Two motors with the same curves: the catalogue's rated power decides, then the cost."""
    a = Motor(
        "a",
        continuous=curve([0, 3000], [1.3, 1.2]),
        peak=curve([0, 5000], [3.8, 3.0]),
        rotor_inertia=1e-4,
        rated_power=400.0,
        cost=9.0,
    )
    b = Motor(
        "b",
        continuous=curve([0, 3000], [1.3, 1.2]),
        peak=curve([0, 5000], [3.8, 3.0]),
        rotor_inertia=1e-4,
        rated_power=400.0,
        cost=5.0,
    )
    c = Motor(
        "c",
        continuous=curve([0, 3000], [1.3, 1.2]),
        peak=curve([0, 5000], [3.8, 3.0]),
        rotor_inertia=1e-4,
        rated_power=500.0,
        cost=1.0,
    )
    ranked = rank_drives(params, [(iso14242(rate=100), 1.0)], [(c, None), (a, None), (b, None)])
    assert [x.drive.motor.name for x in ranked] == ["b", "a", "c"]
    assert ranked[0].rated_power == (400.0, "catalogue")
    document = candidate_summary(ranked[0]).to_json()
    assert (
        document["rated_power_W"] == 400.0
        and document["cost"] == 5.0
        and "margin" in document
        and "binding" in document
    )
