"""Singularity map, trajectory margin and platform-offset sweep (issue 7): physics and bookkeeping."""

import io
import json
import math
import xml.etree.ElementTree as ET
from typing import Any

import numpy as np
import pytest
from support import SmoothMotion, given

import hipsim
import hipsim.design.workspace as ws
from hipsim.analytic.inverse_kinematics import kinematics, slider_heights
from hipsim.cli.workspace import run_workspace
from hipsim.motion.trajectories import Trajectory, iso14242


@pytest.fixture(scope="module")
def params():
    return hipsim.load_parameters()


@pytest.fixture(scope="module")
def iso():
    return iso14242()


def poses(q_deg) -> Trajectory:
    """A trajectory standing still at the given gait orientations in [deg] (one sample each)."""
    q = np.radians(np.atleast_2d(np.asarray(q_deg, dtype=float)))
    n = q.shape[0]
    return Trajectory(np.arange(n) * 1e-3, q, np.zeros_like(q), np.zeros_like(q), np.zeros(n), name="poses")


def test_pose_jacobian_equals_kinematics(params):
    motion = SmoothMotion(seed=5, amplitude_deg=20.0)(np.linspace(0.0, 3.0, 301))
    kin = kinematics(params, motion)
    J, reachable = ws.pose_jacobian(params, motion.q)
    assert reachable.all()
    np.testing.assert_allclose(J, kin.J, rtol=1e-12, atol=1e-14)


def test_map_equals_kinematics_cond_inv_at_grid_poses(params):
    alpha = np.linspace(-30, 35, 14)
    beta = np.linspace(-15, 15, 9)
    gamma = np.array([-12.0, -4.0, 4.0])
    smap = ws.singularity_map(params, alpha, beta, gamma)
    assert smap.cond_inv.shape == (3, 9, 14)
    rng = np.random.default_rng(0)
    picks = [(rng.integers(3), rng.integers(9), rng.integers(14)) for _ in range(12)]
    q_deg = [(alpha[a], beta[b], gamma[g]) for g, b, a in picks]
    expected = kinematics(params, poses(q_deg)).cond_inv
    np.testing.assert_allclose([smap.cond_inv[p] for p in picks], expected, rtol=1e-12)


def test_map_applies_the_angle_signs_like_kinematics(params):
    flipped = params.replace(angle_signs=np.array([-1.0, 1.0, -1.0]))
    alpha, beta, gamma = np.array([-20.0, 5.0, 25.0]), np.array([-7.0, 3.0]), np.array([-8.0, 2.0])
    signed = ws.singularity_map(flipped, alpha, beta, gamma)
    # A flipped α and γ is the unflipped machine at −α, −γ.
    plain = ws.singularity_map(params, -alpha, beta, -gamma)
    np.testing.assert_allclose(signed.cond_inv, plain.cond_inv, rtol=1e-12)
    motion = SmoothMotion(seed=2)(np.linspace(0, 2, 50))
    np.testing.assert_allclose(
        ws.trajectory_margin(flipped, motion).cond_inv, kinematics(flipped, motion).cond_inv, rtol=1e-12
    )


def test_zero_offset_is_singular_at_home_and_the_singularity_follows_gamma(params):
    # δ = 0: platform joints radially in line with the screws; at q = 0 every row
    # (r_i × e_i) of J is horizontal, so J has rank 2 (spec §7.1).
    zero = params.replace(home_offset=0.0)
    home = ws.singularity_map(zero, [0.0], [0.0], [0.0]).cond_inv.item()
    assert home < 1e-12
    # The built machine (δ = 30°) is well conditioned at home ...
    assert ws.singularity_map(params, [0.0], [0.0], [0.0]).cond_inv.item() > 0.3
    # ... and a rotation γ about Z at α = β = 0 is the same as changing δ by γ:
    # the δ = 30° machine is singular at γ = −30°, and only there on this line.
    gamma = np.linspace(-45.0, 15.0, 121)
    line = ws.singularity_map(params, [0.0], [0.0], gamma).cond_inv[:, 0, 0]
    assert gamma[np.argmin(line)] == pytest.approx(-30.0)
    assert line.min() < 1e-12
    assert np.all(line[np.abs(gamma + 30.0) > 5.0] > 0.05)


def test_out_of_reach_is_nan_exactly_where_the_slider_height_is(params):
    alpha = np.linspace(-85, 85, 35)
    beta = np.linspace(-80, 80, 33)
    gamma = np.array([-40.0, 0.0, 60.0])
    smap = ws.singularity_map(params, alpha, beta, gamma)
    G, B, A = np.meshgrid(gamma, beta, alpha, indexing="ij")
    q = np.radians(np.stack([A.ravel(), B.ravel(), G.ravel()], axis=1))
    unreachable = np.isnan(slider_heights(params, q)[:, 0]).any(axis=1).reshape(smap.cond_inv.shape)
    assert unreachable.any() and not unreachable.all()  # the grid does reach past the workspace
    np.testing.assert_array_equal(np.isnan(smap.cond_inv), unreachable)
    np.testing.assert_allclose(smap.reachable_fraction(), 1.0 - unreachable.mean(axis=(1, 2)))


def test_chunked_map_equals_one_batch(params, monkeypatch):
    alpha, beta, gamma = np.linspace(-30, 35, 11), np.linspace(-15, 15, 7), np.array([-12.0, 0.0, 4.0])
    whole = ws.singularity_map(params, alpha, beta, gamma).cond_inv
    monkeypatch.setattr(ws, "_CHUNK", 10)  # chunks cut across rows and γ panels
    chunked = ws.singularity_map(params, alpha, beta, gamma, progress=False).cond_inv
    np.testing.assert_array_equal(chunked, whole)


def test_progress_bar_only_when_asked_or_large(params, capsys, monkeypatch):
    ws.singularity_map(params, [0.0, 1.0], [0.0], [0.0], progress=True)
    assert "singularity map" in capsys.readouterr().err
    ws.singularity_map(params, [0.0, 1.0], [0.0], [0.0])
    assert capsys.readouterr().err == ""
    monkeypatch.setattr(ws, "_PROGRESS_ORIENTATIONS", 1)
    ws.singularity_map(params, [0.0, 1.0], [0.0], [0.0])
    assert "singularity map" in capsys.readouterr().err


def test_default_grid_is_at_least_100_by_100_by_5(params):
    smap = ws.singularity_map(params)
    assert smap.alpha_deg.size >= 100 and smap.beta_deg.size >= 100 and smap.gamma_deg.size == 5
    assert smap.alpha_deg[0] == -30 and smap.alpha_deg[-1] == 35
    assert smap.beta_deg[0] == -15 and smap.beta_deg[-1] == 15
    # The ISO range of γ (+2°/−10°) lies within the panels.
    assert smap.gamma_deg.min() <= -10 and smap.gamma_deg.max() >= 2


def test_trajectory_margin_is_the_minimum_of_kinematics(params, iso):
    margin = ws.trajectory_margin(params, iso)
    kin = kinematics(params, iso)
    np.testing.assert_allclose(margin.cond_inv, kin.cond_inv, rtol=1e-12)
    k = int(np.argmin(kin.cond_inv))
    assert margin.index == k
    assert margin.cond_inv_min == pytest.approx(kin.cond_inv[k])
    assert margin.t_s == pytest.approx(iso.t[k])
    np.testing.assert_allclose(margin.q_deg, np.degrees(iso.q[k]))
    assert margin.clear and margin.crossings == 0


def test_crossing_a_singularity_between_samples_is_detected(params):
    # The δ = 30° machine is singular at α = β = 0, γ = −30°; sweep γ across it
    # with samples that step over the singular pose itself.
    gamma = np.linspace(-40.0, -20.0, 40)  # even count: no sample at −30°
    motion = poses(np.column_stack([np.zeros(40), np.zeros(40), gamma]))
    margin = ws.trajectory_margin(params, motion)
    assert margin.singular == 0 and margin.out_of_reach == 0  # no sample is singular ...
    assert margin.crossings == 1 and not margin.clear  # ... but the motion passes through one
    # A motion that turns back before the singularity crosses nothing.
    short = poses(np.column_stack([np.zeros(20), np.zeros(20), np.linspace(-20.0, -28.0, 20)]))
    assert ws.trajectory_margin(params, short).crossings == 0


def test_sweep_at_the_built_offset_equals_the_iso_run(params, iso):
    sweep = ws.offset_sweep(params, [30.0], iso)
    result = hipsim.analyse(params, iso)
    assert sweep.feasible[0]
    assert sweep.cond_inv_min[0] == pytest.approx(result.cond_inv.min(), rel=1e-12)
    peaks = np.abs(result.torques.total).max(axis=0) * 1e3
    assert sweep.tau_peak_Nmm[0] == pytest.approx(peaks.max(), rel=1e-12)
    assert sweep.tau_peak_motor[0] == int(np.argmax(peaks)) + 1
    summary = result.summary()
    assert sweep.stroke_max_mm[0] == pytest.approx(max(s.stroke_mm for s in summary.sliders.values()), rel=1e-12)


def test_sweep_reports_infeasible_offsets_instead_of_crashing(params, iso):
    # δ = 0 and 5°: the ISO rotation γ ∈ [−10°, +2°] takes the platform through
    # the singularity at γ = −δ. δ = 110°: the levers no longer reach for part of
    # the cycle; δ = 150°: for all of it.
    sweep = ws.offset_sweep(params, [0.0, 5.0, 30.0, 110.0, 150.0], iso)
    np.testing.assert_array_equal(sweep.feasible, [False, False, True, False, False])
    assert sweep.crossings[0] > 0 and sweep.crossings[1] > 0
    assert 0 < sweep.out_of_reach[3] < len(iso) and np.isfinite(sweep.cond_inv_min[3])
    assert sweep.out_of_reach[4] == len(iso) and math.isnan(sweep.cond_inv_min[4])
    bad = [0, 1, 3, 4]
    assert np.isnan(sweep.tau_peak_Nmm[bad]).all() and np.isnan(sweep.stroke_max_mm[bad]).all()
    assert np.isfinite(sweep.tau_peak_Nmm[2])
    rows = sweep.rows()
    assert rows[4].out_of_reach_samples == len(iso) and rows[0].singularity_crossings > 0


def test_sweep_shows_why_the_offset_is_needed(params, iso):
    # Around δ = 0 the margin collapses; at the built δ = 30° it is comfortable.
    sweep = ws.offset_sweep(params, np.arange(-5.0, 36.0, 5.0), iso)
    built = sweep.cond_inv_min[sweep.deltas_deg == 30.0][0]
    assert built > 0.3
    assert np.nanmin(sweep.cond_inv_min[np.abs(sweep.deltas_deg) <= 5.0]) < 0.01


def test_run_workspace_writes_figures_json_and_summary(params, iso, tmp_path):
    out = tmp_path / "ws"
    stream = io.StringIO()
    run = run_workspace(
        params,
        iso,
        out,
        alpha_deg=np.linspace(-30, 35, 40),
        beta_deg=np.linspace(-15, 15, 30),
        gamma_deg=[-12.0, -4.0, 4.0],
        deltas_deg=np.arange(-30.0, 61.0, 10.0),
        stream=stream,
    )
    names = {p.name for p in run.files}
    assert names == {
        "singularity_map.png",
        "singularity_map.svg",
        "offset_sweep.png",
        "offset_sweep.svg",
        "workspace.json",
    }
    for stem in ("singularity_map", "offset_sweep"):
        png, svg = out / f"{stem}.png", out / f"{stem}.svg"
        assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and png.stat().st_size > 20_000
        assert ET.parse(svg).getroot().tag.endswith("svg") and svg.stat().st_size > 20_000
    document = json.loads((out / "workspace.json").read_text())
    assert document["trajectory_margin"]["cond_inv_min"] == pytest.approx(given(run.map.margin).cond_inv_min)
    assert [row["delta_deg"] for row in document["offset_sweep"]] == list(np.arange(-30.0, 61.0, 10.0))
    assert document["offset_sweep"][3]["tau_peak_Nmm"] is None  # δ = 0 is infeasible: null, not NaN
    text = stream.getvalue()
    assert "smallest inverse condition number" in text and "built" in text and "passes through a singularity" in text


def test_a_workspace_run_failing_at_its_first_write_takes_back_only_the_folders_it_made(
    params, iso, tmp_path, monkeypatch
):
    def refuse_to_write(*args, **kwargs):  # as on a full disk: after the folder is made, before anything is in it
        raise hipsim.HipsimError("singularity_map.png: cannot write (No space left on device)")

    monkeypatch.setattr("hipsim.present.figures.save_figure", refuse_to_write)
    small: dict[str, Any] = dict(
        alpha_deg=[0.0, 10.0], beta_deg=[0.0, 5.0], gamma_deg=[0.0], deltas_deg=[30.0], stream=io.StringIO()
    )
    with pytest.raises(hipsim.HipsimError, match="No space left"):
        run_workspace(params, iso.slice(slice(0, 50)), tmp_path / "deep" / "ws", **small)
    assert list(tmp_path.iterdir()) == []

    (tmp_path / "ws").mkdir()  # there before the run: never removed
    with pytest.raises(hipsim.HipsimError, match="No space left"):
        run_workspace(params, iso.slice(slice(0, 50)), tmp_path / "ws", **small)
    assert [p.name for p in tmp_path.iterdir()] == ["ws"]
