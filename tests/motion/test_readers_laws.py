"""Laws of the reader chosen by suffix (hipsim.motion.readers) and the noise check (hipsim.motion.noise_check);
the sources handed out in pieces and Parquet tables: test_sources.py, test_parquet.py.

The files are tiny tables (motion_support: eight rows at 100 Hz, whole-number angles and loads), the noise
check's signals sines at whole frequency bins whose share of power is worked out by hand.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
from motion_support import ALPHA, LOAD, N, Q, csv_file, error_of, mot_file, own_columns, parquet_file, quiet
from support import given

from hipsim.motion.build import NoiseWarning, SampledMotion
from hipsim.motion.noise_check import MOTION_BAND, NOISE_SHARE, SUGGESTED_CUTOFF, NoiseCheck, check_noise
from hipsim.motion.readers import OPENSIM_SUFFIXES, PARQUET_SUFFIX, read_trajectory

# --------------------------------------------------------------------------- the reader by suffix


def test_each_suffix_has_its_reader(tmp_path):
    assert OPENSIM_SUFFIXES == (".mot", ".sto") and PARQUET_SUFFIX == ".parquet"
    for name in ("a.csv", "a.txt", "a.CSV"):
        trajectory = read_trajectory(csv_file(tmp_path / name))
        np.testing.assert_allclose(trajectory.q, Q, rtol=0, atol=1e-15)
        np.testing.assert_array_equal(trajectory.Fe, LOAD)
    for name in ("a.parquet", "b.PARQUET"):
        trajectory = read_trajectory(parquet_file(tmp_path / name, own_columns()))
        np.testing.assert_allclose(trajectory.q, Q, rtol=0, atol=1e-15)
        np.testing.assert_array_equal(trajectory.lines, np.arange(2, N + 2))
    for name in ("a.mot", "b.STO"):
        # Flexion alone is a rotation about Z: α = flexion, the right hip by default.
        trajectory = read_trajectory(mot_file(tmp_path / name), load_column="F")
        np.testing.assert_allclose(trajectory.q[:, 0], np.radians(ALPHA), rtol=0, atol=1e-12)
        np.testing.assert_array_equal(trajectory.Fe, LOAD)
    left = read_trajectory(mot_file(tmp_path / "c.mot"), side="left", load_column="F")
    np.testing.assert_allclose(left.q[:, 0], -np.radians(ALPHA), rtol=0, atol=1e-12)


def test_arguments_that_do_not_apply_are_named(tmp_path):
    csv = csv_file(tmp_path / "a.csv")
    mot = mot_file(tmp_path / "a.mot")
    assert str(error_of(lambda: read_trajectory(csv, side="left"))) == (
        f"{csv}: the side (left or right hip) applies to OpenSim .mot/.sto files"
    )
    assert str(error_of(lambda: read_trajectory(csv, load_scale="2"))) == f"{csv}: a load scale applies to a load file"
    assert str(error_of(lambda: read_trajectory(mot, side="left", columns="time=time,alpha=a,beta=b,gamma=c"))) == (
        f"{mot}: a column mapping names the columns itself: the side does not apply"
    )
    assert str(error_of(lambda: read_trajectory(csv, load="f.csv"))) == (
        "f.csv: name the load file's column (load_column: a column, or NAME for NAME_fx/_fy/_fz)"
    )


def test_the_options_reach_every_reader(tmp_path):
    paths = [
        csv_file(tmp_path / "a.csv", closing=False),
        parquet_file(tmp_path / "a.parquet", own_columns()),
    ]
    for path in paths:
        base = read_trajectory(path)
        assert not base.periodic
        np.testing.assert_allclose(
            quiet(lambda: read_trajectory(path, frequency=2.0)).t, np.arange(N) / 16.0, atol=1e-15
        )
        np.testing.assert_allclose(quiet(lambda: read_trajectory(path, period=4.0)).t, np.arange(N) * 0.5, atol=1e-15)
        np.testing.assert_allclose(read_trajectory(path, resample=200.0).t, np.arange(15) / 200.0, atol=1e-15)
        assert isinstance(read_trajectory(path, lazy=True), SampledMotion)
        assert np.abs(read_trajectory(path, cutoff=10.0).q - base.q).max() > 1e-4
        assert "periodic was asked for" in str(error_of(lambda: read_trajectory(path, periodic=True)))
        assert "a body weight was given" in str(error_of(lambda: read_trajectory(path, body_weight=70.0)))
        mapped = read_trajectory(path, columns="time=t_s,alpha=alpha_deg,beta=zero,gamma=zero,load=Fe_N")
        np.testing.assert_array_equal(mapped.q[:, 1:], 0.0)
        weighted = read_trajectory(
            path, columns="time=t_s,alpha=alpha_deg,beta=zero,gamma=zero", load_column="Fe_N:%BW", body_weight=50.0
        )
        np.testing.assert_allclose(weighted.Fe, LOAD / 2.0, rtol=1e-15)
    mot = mot_file(tmp_path / "b.mot")
    base = read_trajectory(mot, load_column="F")
    np.testing.assert_allclose(quiet(lambda: read_trajectory(mot, frequency=2.0)).t, np.arange(N) / 16.0, atol=1e-15)
    np.testing.assert_allclose(quiet(lambda: read_trajectory(mot, period=4.0)).t, np.arange(N) * 0.5, atol=1e-15)
    np.testing.assert_allclose(quiet(lambda: read_trajectory(mot, resample=200.0)).t, np.arange(15) / 200.0, atol=1e-15)
    assert isinstance(quiet(lambda: read_trajectory(mot, lazy=True)), SampledMotion)
    assert np.abs(quiet(lambda: read_trajectory(mot, load_column="F", cutoff=10.0)).q - base.q).max() > 1e-4
    assert "periodic was asked for" in str(error_of(lambda: read_trajectory(mot, periodic=True)))
    np.testing.assert_allclose(read_trajectory(mot, load_column="F:%BW", body_weight=50.0).Fe, LOAD / 2.0, rtol=1e-15)
    mapped = quiet(lambda: read_trajectory(mot, columns="time=time,alpha=hip_flexion_l,beta=zero,gamma=zero"))
    np.testing.assert_allclose(mapped.q[:, 0], -np.radians(ALPHA), rtol=0, atol=1e-15)


def test_a_load_file_takes_the_load_column_body_weight_and_scale(tmp_path):
    load = tmp_path / "f.csv"
    load.write_text("time,Fz\n" + "".join(f"{k / 100},{-10 * k}\n" for k in range(N)))
    for motion in (
        csv_file(tmp_path / "a.csv", load=False),
        parquet_file(tmp_path / "a.parquet", own_columns(False)),
        mot_file(tmp_path / "a.mot", load=False),
    ):
        trajectory = read_trajectory(motion, load=load, load_column="-Fz", body_weight=50.0, load_scale="2")
        np.testing.assert_allclose(trajectory.Fe, 2.0 * 0.5 * 10.0 * np.arange(N), rtol=1e-15)
        trajectory = read_trajectory(motion, load=load, load_column="-Fz", load_scale="300:1000")
        np.testing.assert_allclose(trajectory.Fe, 300.0 + 100.0 * np.arange(N), rtol=1e-15)
        from hipsim.motion.load_file import LoadScale

        trajectory = read_trajectory(motion, load=load, load_column="-Fz", load_scale=LoadScale(3.0))
        np.testing.assert_allclose(trajectory.Fe, 30.0 * np.arange(N), rtol=1e-15)
        trajectory = read_trajectory(motion, load=load, load_column="-Fz")
        np.testing.assert_allclose(trajectory.Fe, 10.0 * np.arange(N), rtol=1e-15)


# --------------------------------------------------------------------------- the noise check


def sines(rate, n, *parts):
    """Columns of sums of a·sin(2π f t) for (a, f) pairs."""
    t = np.arange(n) / rate
    return t, np.column_stack([sum(a * np.sin(2 * np.pi * f * t) for a, f in part) for part in parts])


def test_the_share_of_power_above_the_band_by_hand():
    # 202 samples at 100 Hz: 200 second differences, bins 0.5 Hz apart. A sine's second difference is the sine
    # times −4 sin²(π f / rate); at whole bins the Hann window spreads each alike, so the share is the powers' ratio.
    gain5, gain30 = 4 * math.sin(math.pi * 0.05) ** 2, 4 * math.sin(math.pi * 0.3) ** 2
    b = gain5 / gain30  # 30 Hz at this amplitude has the 5 Hz sine's acceleration
    t, q = sines(100.0, 202, [(1.0, 5.0)], [(1.0, 5.0), (b, 30.0)], [(1.0, 5.0), (b / 3, 30.0)])
    check = check_noise(t, q)
    np.testing.assert_allclose(check.share, [0.0, 0.5, 0.1], atol=1e-6)
    assert check.rate == pytest.approx(100.0, rel=1e-12)
    assert check.noisy


def test_the_band_starts_above_twelve_hertz():
    # 12.5 Hz is bin 25; the Hann window puts 1/4, 1/2, 1/4 of its amplitude on 12, 12.5 and 13 Hz: 12 Hz is not above.
    t, q = sines(100.0, 202, [(1.0, 12.5)], [(1.0, 11.5)], [(1.0, 5.0)])
    share = check_noise(t, q).share
    assert share[0] == pytest.approx(5 / 6, abs=0.01)
    assert share[1] < 1e-5 and share[2] < 1e-5
    assert MOTION_BAND == 12.0 and NOISE_SHARE == 0.1 and SUGGESTED_CUTOFF == 6.0


def test_the_threshold_both_ways():
    gain5, gain30 = 4 * math.sin(math.pi * 0.05) ** 2, 4 * math.sin(math.pi * 0.3) ** 2
    b = gain5 / gain30
    # Shares of 1/11 and 1/9 (powers 1:10 and 1:8) either side of 10 %.
    below = sines(100.0, 202, [(1.0, 5.0), (b / math.sqrt(10), 30.0)], [(1.0, 5.0)], [(1.0, 5.0)])
    above = sines(100.0, 202, [(1.0, 5.0)], [(1.0, 5.0)], [(1.0, 5.0), (b / math.sqrt(8), 30.0)])
    low, high = check_noise(*below), check_noise(*above)
    assert low.share[0] == pytest.approx(1 / 11, abs=1e-6) and not low.noisy
    assert high.share[2] == pytest.approx(1 / 9, abs=1e-6) and high.noisy


def test_the_mean_acceleration_is_not_counted():
    # A parabola's constant acceleration, and an alternation at the Nyquist rate: all the rest is above the band.
    t = np.arange(202) / 100.0
    q = np.column_stack([1000.0 * t**2 + 1e-3 * (-1.0) ** np.arange(202), np.zeros(202), 5.0 * t])
    check = check_noise(t, q)
    assert check.share[0] == pytest.approx(1.0, abs=1e-9)
    assert check.share[1] == 0.0  # no acceleration at all: no share, not NaN
    assert not np.isnan(check.share).any()


def test_too_slow_or_too_short_to_tell_at_the_edges():
    alternating = np.column_stack([(-1.0) ** np.arange(16)] * 3)
    assert check_noise(np.arange(16) / 25.0, alternating).noisy
    slow = check_noise(np.arange(16) / 24.0, alternating)  # at 24 Hz nothing lies above 12 Hz
    assert not slow.noisy and slow.rate == 24.0
    np.testing.assert_array_equal(slow.share, np.zeros(3))
    short = check_noise(np.arange(15) / 100.0, alternating[:15])
    assert not short.noisy and short.rate == 100.0
    one = check_noise(np.array([0.0]), alternating[:1])
    assert one.rate == 0.0 and not one.noisy


def test_the_warning_names_the_worst_angle():
    check = NoiseCheck(np.array([0.2, 0.5, 0.1]), 60.0, True)
    assert check.warning("walk.mot") == (
        "walk.mot: 50 % of the beta acceleration lies above 12 Hz, where gait has none: measurement noise, "
        "amplified by differentiation at 60 Hz; filter it with --cutoff 6"
    )
    assert NoiseCheck(np.array([0.2, 0.5, 0.1]), 60.0, False).warning("walk.mot") is None


def test_a_noisy_file_is_warned_of_once_with_the_cutoff(tmp_path):
    t = np.arange(40) / 100.0
    alpha = 10.0 + 0.5 * (-1.0) ** np.arange(40)
    path = tmp_path / "n.csv"
    path.write_text(
        "t_s,alpha_deg,beta_deg,gamma_deg\n" + "".join(f"{t[k]:g},{alpha[k]:g},{k},{-k}\n" for k in range(40))
    )
    with pytest.warns(NoiseWarning) as record:
        read_trajectory(path)
    noise = [w for w in record if issubclass(w.category, NoiseWarning)]
    assert len(noise) == 1 and "--cutoff 6" in str(noise[0].message)
    with warnings.catch_warnings():
        warnings.simplefilter("error", NoiseWarning)
        quiet_enough = read_trajectory(path, cutoff=6.0)
    assert quiet_enough.q.shape == (40, 3)


# --------------------------------------------------------------------------- survivors of the first run


def test_the_warning_names_alpha_or_gamma_and_rounds_the_percentage():
    assert given(NoiseCheck(np.array([0.8, 0.5, 0.1]), 60.0, True).warning("w")).startswith(
        "w: 80 % of the alpha acceleration"
    )
    assert given(NoiseCheck(np.array([0.1, 0.2, 0.306]), 60.0, True).warning("w")).startswith(
        "w: 31 % of the gamma acceleration"
    )


def test_the_band_edge_on_exact_bins_and_tiny_or_zero_motions():
    # At 64 Hz the times and the rate are exact: 128 second differences, bins 0.5 Hz apart, 12 Hz one of them.
    t = np.arange(130) / 64.0
    q = np.column_stack([np.sin(2 * np.pi * 12.5 * t), 1e-9 * np.sin(2 * np.pi * 20 * t), np.zeros(130)])
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no division by a zero total
        check = check_noise(t, q)
    assert check.rate == 64.0
    assert check.share[0] == pytest.approx(5 / 6, abs=0.01)  # the bin at 12 Hz is not above the band
    assert check.share[1] == pytest.approx(1.0, abs=1e-6)  # a tiny motion's share is a share all the same
    assert check.share[2] == 0.0
    assert check.noisy is True
    two = check_noise(np.array([0.0, 0.01]), np.zeros((2, 3)))
    assert two.rate == 100.0 and two.noisy is False
    assert check_noise(np.arange(16) / 24.0, np.zeros((16, 3))).noisy is False
