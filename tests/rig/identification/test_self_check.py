"""Does an identification make sense (hipsim.rig.identification.self_check): the gates held to an identification's
numbers, made by hand here, at the edge of each gate (3 times 5 % of a motor's RMS, 5 prior standard deviations)."""

from __future__ import annotations

from types import SimpleNamespace
from typing import Any

from hipsim.fit_checks import NOISE_FLOOR, PRIOR_SIGMA, RESIDUAL_FACTOR
from hipsim.rig.identification.self_check import TORQUE_COLUMNS, check_identification


def identification(residual=(0.0, 0.0, 0.0), torque_rms=(1.0, 1.0, 1.0), moved=0.0, validation=()):
    estimate = SimpleNamespace(name="m_m", value=2.0 + moved, prior=2.0, prior_std=0.5)
    held = SimpleNamespace(name="slider", value=3.0, prior=1.0, prior_std=0.0)  # held: never judged
    return SimpleNamespace(
        residual_rms=residual, torque_rms=torque_rms, estimates=[estimate, held], validation=list(validation)
    )


def held_out(error_Nmm, measured_Nmm):
    motors = {str(i + 1): {"rms_error_Nmm": error_Nmm[i], "measured_rms_Nmm": measured_Nmm[i]} for i in range(3)}
    return SimpleNamespace(statistics={"motors": motors}), None


#: a held-out log as the check uses it: its name
WALK: Any = SimpleNamespace(name="walk.csv")


def test_the_gates_are_three_times_five_percent_and_five_sigma():
    assert (NOISE_FLOOR, RESIDUAL_FACTOR, PRIOR_SIGMA) == (0.05, 3.0, 5.0)
    assert TORQUE_COLUMNS == ("tau_1", "tau_2", "tau_3")


def test_a_residual_at_the_gate_passes_and_just_beyond_it_fails():
    # torque RMS 2 N·m: the noise is 0.1 N·m, the gate 0.3 N·m = 300 N·mm
    at = check_identification(identification(residual=(0.3, 0.0, 0.0), torque_rms=(2.0, 2.0, 2.0)))
    assert at.plausible and at.fit == "identify"
    beyond = check_identification(identification(residual=(0.0, 0.0, 0.3001), torque_rms=(2.0, 2.0, 2.0)))
    assert beyond.findings == ("the fit's residuals beyond 3 times the noise: tau_3 300 N·mm (3×)",)


def test_without_the_torques_rms_no_residual_is_judged():
    assert check_identification(identification(residual=(9.0, 9.0, 9.0), torque_rms=None)).plausible


def test_a_move_of_five_prior_deviations_passes_and_more_fails():
    assert check_identification(identification(moved=5 * 0.5)).plausible
    (finding,) = check_identification(identification(moved=-5.01 * 0.5)).findings
    assert finding.startswith("base parameters beyond 5 prior standard deviations: m_m -2.5 (file units) (5.01σ)")
    assert "slider" not in finding


def test_a_held_out_log_is_named_and_judged_on_its_own_measured_rms(monkeypatch):
    ok = held_out((15.0, 0.0, 0.0), (100.0, 100.0, 100.0))  # 15 N·mm = 3 × 5 % of 100 N·mm: at the gate
    bad = held_out((0.0, 15.1, 0.0), (100.0, 100.0, 100.0))
    check = check_identification(identification(validation=[ok, bad]), validate=[WALK])
    (finding,) = check.findings
    assert finding.startswith("held-out held-out log 2: residuals beyond 3 times the noise: tau_2 15.1 N·mm")
    from hipsim.rig.identification import self_check

    monkeypatch.setattr(self_check, "_pattern", lambda result, logs: "")  # the cause needs a real log: not here
    named = check_identification(identification(validation=[bad]), validate=[WALK]).findings[0]
    assert named.startswith("held-out walk.csv: residuals")
    both = check_identification(identification(validation=[bad, bad]), validate=[WALK]).findings
    assert [f.split(":")[0] for f in both] == ["held-out walk.csv", "held-out held-out log 2"]  # each log judged
