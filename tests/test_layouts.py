"""The layout registry (rig/vehicle/layouts/): the vehicle file's ``layout`` values are the contract's, an unknown one
is refused in one line that lists them, and each layout's corners are the contract's for its axles."""

import pytest

from rig.io.channels import CORNERS
from rig.vehicle.assets import builtin_vehicles
from rig.vehicle.layouts import layouts
from rig.vehicle.tables import VehicleError
from rig.vehicle.vehicle_file import load_vehicle, vehicle_from_dict


def test_the_registry_holds_the_contracts_layouts():
    assert list(layouts()) == ["full", "quarter", "truck"]  # docs/contracts.md: the vehicle file's layout


@pytest.mark.parametrize("value", ["van", 3, ["full"]])
def test_an_unknown_layout_is_refused_in_one_line_that_lists_the_known_ones(value):
    with pytest.raises(VehicleError) as err:
        vehicle_from_dict({"name": "x", "layout": value}, "x.toml")
    assert str(err.value) == f"x.toml: layout must be one of full, quarter, truck, got {value!r}"


def test_each_built_in_vehicles_corners_follow_its_layout():
    """A full car's four corners in contract order, a quarter car's FL, a truck's two per axle front to rear."""
    seen = set()
    for name in builtin_vehicles():
        vehicle = load_vehicle(name)
        seen.add(vehicle.layout)
        expected = {"full": CORNERS, "quarter": ("FL",)}.get(vehicle.layout) or \
            {2: CORNERS, 3: ("FL", "FR", "ML", "MR", "RL", "RR")}[len(vehicle.axles)]
        assert vehicle.corners == expected, name
    assert seen == set(layouts())
