"""IRI with the project's own quarter-car model against the published figures for road_profile_1.txt."""

import numpy as np
import pytest

from rig.road.roads import measured_profile
from rig.sim.roughness import golden_quarter_car, iri

# Sroubek, Sorel, Zak, Int. J. Pavement Res. Technol. 2021 (data/README.md), mm/m
PUBLISHED = [3.2985, 2.4421, 3.5551, 4.0855, 2.7079]


def test_iri_of_road_profile_1_reproduces_the_published_values(real_data):
    road = measured_profile(real_data / "road_profile_1.txt")
    values = iri(road.left, road.spacing, segment=100.0)
    assert values.size == 5
    np.testing.assert_allclose(values, PUBLISHED, rtol=0.01)


def test_golden_car_is_the_astm_e1926_reference():
    car = golden_quarter_car()
    m = car.sprung_mass
    assert car.front.tyre_rate / m == pytest.approx(653.0)
    assert car.front.suspension_rate / m == pytest.approx(63.3)
    assert car.front.damping / m == pytest.approx(6.0)
    assert car.front.unsprung_mass / m == pytest.approx(0.15)


def test_iri_of_a_smooth_plane_is_zero_and_scales_linearly():
    spacing = 0.25
    x = np.arange(2000) * spacing
    assert iri(0.01 * x, spacing).max() < 1e-4  # a constant slope has no roughness (real roads: 1-10 m/km)
    bumpy = 0.002 * np.sin(2 * np.pi * x / 5.0)
    np.testing.assert_allclose(iri(3 * bumpy, spacing), 3 * iri(bumpy, spacing), rtol=1e-6)
