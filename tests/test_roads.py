"""Road profiles: ISO 8608 levels, coherence, obstacles of the seeds, measured profiles and specs."""

import numpy as np
import pytest
from scipy.signal import coherence, welch

from rig.road.roads import (
    ISO_8608_CLASSES,
    RoadError,
    bar_obstacle,
    iso8608_road,
    measured_profile,
    plywood_road,
    road_from_spec,
    sine_sweep,
    step,
)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_iso8608_class_c_psd_is_within_1_db_of_the_class_mean(seed):
    road = iso8608_road("C", length=1000.0, spacing=0.05, seed=seed)
    assert ISO_8608_CLASSES["C"] == pytest.approx(256e-6)
    for track in (road.left, road.right):
        frequency, psd = welch(track, fs=1 / road.spacing, nperseg=8192)
        band = (frequency >= 0.05) & (frequency <= 2.0)
        target = 256e-6 * (frequency[band] / 0.1) ** -2
        level_db = 10 * np.log10(np.mean(psd[band] / target))
        assert abs(level_db) < 1.0, level_db


def test_iso8608_classes_step_by_6_db_and_seeds_reproduce():
    a = iso8608_road("A", 200.0, seed=4)
    b = iso8608_road("B", 200.0, seed=4)
    np.testing.assert_allclose(b.left, 2 * a.left)  # 4x the PSD = 2x the amplitude
    np.testing.assert_array_equal(iso8608_road("C", 200.0, seed=4).left, iso8608_road("C", 200.0, seed=4).left)


@pytest.mark.parametrize("target", [0.0, 0.5, 1.0])
def test_iso8608_left_right_coherence(target):
    road = iso8608_road("C", length=4000.0, spacing=0.05, seed=1, coherence=target)
    frequency, gamma2 = coherence(road.left, road.right, fs=20.0, nperseg=2048)
    measured = gamma2[(frequency > 0.05) & (frequency < 2.0)].mean()
    assert measured == pytest.approx(target, abs=0.05)


def test_bar_is_forsens_200_by_50_mm_in_the_chosen_wheel_path():
    road = bar_obstacle(sides="right")
    assert road.right.max() == pytest.approx(0.05) and road.left.max() == 0.0
    assert np.sum(road.right > 0) * road.spacing == pytest.approx(0.2)


def test_plywood_sweep_and_step_shapes():
    plywood = plywood_road(beams=5, beam_height=0.02, beam_width=0.1)
    edges = np.flatnonzero(np.diff(plywood.left) > 0)
    assert edges.size == 5 and plywood.left.max() == pytest.approx(0.02)
    sweep = sine_sweep(start_wavelength=10.0, end_wavelength=1.0, amplitude=0.004, length=100.0)
    assert np.abs(sweep.left).max() == pytest.approx(0.004, rel=1e-3)
    crossings = np.flatnonzero(np.diff(np.sign(sweep.left[-200:])) != 0)  # last 2 m: wavelength ~1 m
    assert 3 <= crossings.size <= 5
    ramp = step(height=0.03, position=5.0, rise=0.5)
    assert ramp.left[-1] == pytest.approx(0.03) and ramp.left[int(5.25 / ramp.spacing)] == pytest.approx(0.015)


def test_measured_profile_reads_the_shipped_file(real_data):
    road = measured_profile(real_data / "road_profile_1.txt")
    assert road.spacing == pytest.approx(0.25)
    assert road.left.size == 2177
    assert road.length == pytest.approx(2176 * 0.25)


def test_bad_profiles_and_specs_are_refused(tmp_path):
    bad = tmp_path / "bad.txt"
    bad.write_text("0 1\n0.25 1\n0.5 1\n0.8 1\n1.0 1\n1.25 1\n")
    with pytest.raises(RoadError, match="not uniformly increasing at row 4"):
        measured_profile(bad)
    with pytest.raises(RoadError, match="class must be one of A, B"):
        iso8608_road("Z")
    with pytest.raises(RoadError, match="kind 'gravel' is not one of"):
        road_from_spec("gravel")
    with pytest.raises(RoadError, match="unknown option\\(s\\) colour for bar"):
        road_from_spec("bar:colour=red")
    with pytest.raises(RoadError, match="iso8608 needs class"):
        road_from_spec("iso8608:length=100")


def test_spec_builds_the_named_road():
    road = road_from_spec("iso8608:class=D,length=100,seed=3")
    np.testing.assert_array_equal(road.left, iso8608_road("D", 100.0, seed=3).left)
