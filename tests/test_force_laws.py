"""Force laws measured from the data (rig/diagnosis/rig_test/force_laws.py): a known law recovered exactly, and the
independent simulator's hidden laws (tests/independent_rig.py) recognised by their shape, not their form."""

import tomllib
from types import SimpleNamespace

import numpy as np
import pytest
from independent_rig import Hidden, independent_records

from rig.causes import CAUSES, Shape, causes_seen_on, with_extension
from rig.diagnosis.rig_test.force_laws import G, measure_force_laws
from rig.diagnosis.rig_test.selection import ruled_out
from rig.io.channels import CORNERS
from rig.io.record import Record
from rig.vehicle.vehicle_file import load_vehicle, vehicle_from_dict, vehicle_to_toml

RATE = 512.0


@pytest.fixture(scope="module")
def proton_x():
    return load_vehicle("proton_x")


def known_law_record(vehicle, duration=20.0):
    """One corner whose suspension force is a bilinear spring (25 kN/m, 75 kN/m beyond 15 mm of compression)
    and an asymmetric damper (2000 N s/m in compression, 5000 in rebound), seen through the wheel's
    equilibrium with a still wheel."""
    t = np.arange(int(duration * RATE)) / RATE
    x = 0.03 * np.sin(2 * np.pi * 1.3 * t) + 0.01 * np.sin(2 * np.pi * 4.1 * t + 1.0)
    v = (0.03 * 2 * np.pi * 1.3 * np.cos(2 * np.pi * 1.3 * t)
         + 0.01 * 2 * np.pi * 4.1 * np.cos(2 * np.pi * 4.1 * t + 1.0))
    a = -0.03 * (2 * np.pi * 1.3) ** 2 * np.sin(2 * np.pi * 1.3 * t) - 0.01 * (2 * np.pi * 4.1) ** 2 * np.sin(
        2 * np.pi * 4.1 * t + 1.0)
    force = 25e3 * x + 50e3 * np.maximum(x - 0.015, 0.0) + np.where(v > 0, 2000.0, 5000.0) * v
    m_u = vehicle.axle("FL").unsprung_mass
    channels = {"FL/susp_travel": x, "FL/susp_velocity": v, "FL/unsprung_acc": np.zeros_like(t),
                "FL/sprung_acc": -a, "FL/tyre_force": 4000.0 + force + m_u * G}
    return Record(RATE, channels)


def test_a_known_law_is_recovered(proton_x):
    laws = measure_force_laws(known_law_record(proton_x), proton_x)
    law = laws.corners["FL"]
    assert law.stiffness[-1].value == pytest.approx(75e3, rel=0.05)
    assert law.stiffness[0].value == pytest.approx(25e3, rel=0.05)
    assert law.damping[-1].value == pytest.approx(2000.0, rel=0.05)
    assert law.damping[0].value == pytest.approx(5000.0, rel=0.05)
    assert "stiffens in compression" in law.shapes and "asymmetric damping" in law.shapes
    assert "stiffens both ways" not in law.shapes and "friction step" not in law.shapes
    assert np.interp(0.035, *law.travel_points) == pytest.approx(law.law_at(law.stiffness, np.array([0.035]))[0],
                                                                 rel=0.05)


CASES = {"none": Hidden(), "duffing": Hidden(cubic_spring=3.0e7), "bump": Hidden(smooth_bump=(0.010, 4.0e6)),
         "friction": Hidden(tanh_friction=(250.0, 0.01)), "compliance": Hidden(hydraulic_compliance=2.0e5),
         "payload": Hidden(payload=(180.0, -1.0, 0.2)), "bar": Hidden(anti_roll_bar=(15000.0, 7000.0)),
         "tyre": Hidden(tyre_damping=300.0)}


class _Measured(dict):
    """The force laws of each case of ``CASES`` and its simulator, simulated when a test first reads it (a test
    process runs only the cases of the tests it is given)."""

    def __init__(self, vehicle):
        super().__init__()
        self.vehicle = vehicle

    def __missing__(self, name):
        record, _, sim = independent_records(self.vehicle, CASES[name], seed=1, duration=20.0, holdout=2.0)
        self[name] = (measure_force_laws(record, self.vehicle), sim)
        return self[name]


@pytest.fixture(scope="module")
def measured(proton_x):
    return _Measured(proton_x)


def test_no_effect_no_shape_and_the_data_sheet_recovered(measured, proton_x):
    laws, sim = measured["none"]
    for i, (corner, law) in enumerate(laws.corners.items()):
        assert law.shapes == [], (corner, law.shapes)
        n = len(law.stiffness) // 2
        assert law.stiffness[n].value == pytest.approx(sim.car.spring[i], rel=0.03)
        assert law.damping[n].value == pytest.approx(sim.car.damping[i], rel=0.03)
        assert laws.tyres[corner].rate[0] == pytest.approx(sim.car.tyre[i], rel=0.06)
    assert laws.body.mass[0] == pytest.approx(sim.car.mass, rel=0.005)
    assert laws.body.pitch_inertia[0] == pytest.approx(sim.car.pitch_inertia, rel=0.01)
    assert laws.body.roll_inertia[0] == pytest.approx(sim.car.roll_inertia, rel=0.01)
    assert laws.departures(proton_x) == []


def test_shapes_outside_the_fitted_forms(measured, proton_x):
    duffing, bump = measured["duffing"][0], measured["bump"][0]
    assert sum("stiffens both ways" in law.shapes for law in duffing.corners.values()) >= 2
    assert sum("stiffens in compression" in law.shapes for law in bump.corners.values()) >= 1
    assert not any("rebound" in s or "both" in s for law in bump.corners.values() for s in law.shapes)
    assert {"bump_stop", "progressive_spring"} <= set(bump.to_json(proton_x)["corners"]["RL"]["suggests"])
    assert all("friction step" in law.shapes for law in measured["friction"][0].corners.values())
    assert all("force lags the rate" in law.shapes for law in measured["compliance"][0].corners.values())
    bar = measured["bar"][0].corners
    assert bar["FL"].coupling[0] == pytest.approx(15000.0, rel=0.05)
    assert bar["RR"].coupling[0] == pytest.approx(7000.0, rel=0.05)


def test_a_shape_at_every_corner_is_widely_shown_and_a_beam_axles_laws_are_no_evidence(measured, proton_x):
    """``widely_shown``: friction measured at all four corners is evidence beyond noise, nothing is where nothing
    is hidden; the same laws said of a truck's beam axles (whose corner laws misread the axle's roll) show nothing."""
    assert Shape.FRICTION_STEP in measured["friction"][0].widely_shown(proton_x)
    assert measured["none"][0].widely_shown(proton_x) == set()
    assert measured["friction"][0].widely_shown(load_vehicle("truck_6x4")) == set()


def test_the_first_round_leaves_out_only_causes_whose_shapes_no_corner_shows(measured, proton_x):
    """``ruled_out``: with nothing hidden, the causes that would show only a corner law's shape are not screened and
    those with a departure or no shape are; friction measured at the corners keeps strut friction in; where a
    corner's law could not be formed (no travel channel), nothing is ruled out."""
    def run(laws):
        return SimpleNamespace(force_laws=laws, vehicle=proton_x, test=SimpleNamespace(corners=CORNERS))

    names = causes_seen_on("rig")
    ruled = ruled_out(run(measured["none"][0]), names)
    assert {"bump_stop", "rebound_stop", "strut_friction", "top_mount_compliance", "damper_asymmetry",
            "anti_roll_bar"} <= set(ruled)
    assert not {"progressive_spring", "mass_error", "tyre_damping", "secondary_mass", "sensor_gain",
                "actuator_lag"} & set(ruled)
    assert "strut_friction" not in ruled_out(run(measured["friction"][0]), names)
    record, _, _ = independent_records(proton_x, Hidden(), seed=1, duration=20.0, holdout=2.0)
    no_travel = Record(record.rate, {n: v for n, v in record.channels.items() if not n.endswith("susp_travel")})
    assert ruled_out(run(measure_force_laws(no_travel, proton_x)), names) == {}


def test_payload_and_tyre_damping_depart_from_the_data_sheet(measured, proton_x):
    laws, sim = measured["payload"]
    mass, x, y = 180.0, -1.0, 0.2
    total = sim.car.mass + mass
    assert laws.body.mass[0] == pytest.approx(total, rel=0.005)
    assert laws.body.cg_x[0] == pytest.approx(mass * x / total, abs=0.005)
    assert laws.body.cg_y[0] == pytest.approx(mass * y / total, abs=0.002)
    assert {d.what for d in laws.departures(proton_x)} >= {"sprung mass", "CG x", "CG y"}
    start = {p.name: p.initial for p in CAUSES["mass_error"].fit_parameters(proton_x, {"body": laws.body})}
    added = total - proton_x.sprung_mass  # the payload, and the truth car's own few percent
    assert start["mass"] == pytest.approx(added, rel=0.01)
    assert (start["x"] == pytest.approx(mass * x / added, abs=0.02)
            and start["y"] == pytest.approx(mass * y / added, abs=0.01))
    tyres = measured["tyre"][0]
    assert all(t.damping[0] == pytest.approx(300.0, rel=0.05) for t in tyres.tyres.values())
    assert {d.what for d in tyres.departures(proton_x)} == {f"{c} tyre damping" for c in proton_x.corners}
    assert all(d.suggests == ["tyre_damping"] for d in tyres.departures(proton_x))
    assert all(d.suggests == ["mass_error"] for d in laws.departures(proton_x)
               if d.what.startswith(("CG", "sprung")))


def test_evidence_that_cannot_be_formed_is_named(proton_x):
    record, _, _ = independent_records(proton_x, Hidden(), seed=2, duration=8.0, holdout=2.0)
    without = Record(record.rate, {n: v for n, v in record.channels.items()
                                   if n not in ("RL/tyre_force", "FR/susp_travel")})
    laws = measure_force_laws(without, proton_x, saturated=("FL/unsprung_acc",))
    assert set(laws.corners) == {"RL", "RR"} and laws.body is None  # RL's from the tyre's rate
    assert laws.assumed[0].startswith("suspension force at RL from the tyre's data-sheet rate")
    assert any(m.startswith("tyre force-deflection at RL not formed: RL/tyre_force is not in") for m in laws.missing)
    assert "suspension force law at FR not formed: FR/susp_travel is not in the record" in laws.missing
    assert "suspension force law at FL not formed: FL/unsprung_acc is saturated" in laws.missing
    assert any(m.startswith("body mass properties not formed") for m in laws.missing)
    short = measure_force_laws(Record(record.rate, {n: v[:1024] for n, v in record.channels.items()}), proton_x)
    assert short.missing == ["no force laws: the record lasts 2.0 s, shorter than the 5 s they need"]


def test_without_load_cells_the_tyre_rate_gives_the_forces_and_says_what_it_assumes(proton_x):
    """A displacement-controlled rig without wheel-pan load cells: the wheel's equilibrium takes the tyre's force from
    its data-sheet rate on the measured deflection. The truth's tyre rates are within 3 % of the data sheet's, so the
    body's mass is within that (a scale of the forces); its CG, a ratio of moments, within what the corners' own
    differences of tyre rate move it (3 % across half the track: 11 mm), and the laws' shapes, ratios of slopes, are as
    a load cell gives them."""
    payload = (180.0, -1.0, 0.2)
    record, _, sim = independent_records(proton_x, Hidden(payload=payload, damper_ratio=2.5), seed=1, duration=20.0,
                                         holdout=2.0)
    cells = measure_force_laws(record, proton_x)
    rates = measure_force_laws(Record(record.rate, {n: v for n, v in record.channels.items()
                                                    if not n.endswith("/tyre_force")}), proton_x)
    assert set(rates.corners) == set(proton_x.corners) and not rates.tyres and rates.body is not None
    assert rates.body.mass[0] == pytest.approx(sim.car.mass + payload[0], rel=0.03)
    assert rates.body.cg_x[0] == pytest.approx(cells.body.cg_x[0], abs=0.01)
    assert rates.body.cg_y[0] == pytest.approx(cells.body.cg_y[0], abs=0.01)
    assert {d.what for d in rates.departures(proton_x)} >= {"CG x", "CG y"}
    assert all(Shape.ASYMMETRIC_DAMPING in law.shapes for law in rates.corners.values())
    assert len(rates.assumed) == 4 and "FL/tyre_force is not in the record" in rates.assumed[0]


def test_a_side_the_travel_never_reaches_adds_nothing_and_still_makes_a_vehicle_file(proton_x):
    """A travel channel not zeroed at ride height (the known law's travel read 60 mm high: all compression):
    the rebound side has no data, its segments say nothing, the measured range's stiffness is still found,
    and the measured law is a vehicle file that reads back. The law is found on the front axle only, and
    the generic element is fitted on that axle alone."""
    record = known_law_record(proton_x)
    shifted = Record(record.rate, {**record.channels, "FL/susp_travel": record["FL/susp_travel"] + 0.06})
    law = measure_force_laws(shifted, proton_x).corners["FL"]
    assert all(s.error == 0.0 for s in law.stiffness if s.high <= 0.0)  # no data below zero: nothing resolved
    assert law.stiffness[-1].value == pytest.approx(75e3, rel=0.05)
    assert "stiffens in rebound" not in law.shapes and "softens in rebound" not in law.shapes
    laws = measure_force_laws(shifted, proton_x).measured_laws(proton_x)
    assert set(laws) == {"front"} and np.all(np.diff(laws["front"].travel_knots) > 0)
    extended = with_extension(proton_x, "measured_law", laws)
    assert vehicle_from_dict(tomllib.loads(vehicle_to_toml(extended)), "round trip").extensions["measured_law"] == laws
    stiffness, damping = CAUSES["measured_law"].fit_parameters(proton_x, {"measured_laws": laws})
    fitted = damping.apply(stiffness.apply(proton_x, 0.5), 0.8).extensions["measured_law"]
    assert set(fitted) == {"front"} and fitted["front"] == laws["front"].scaled(0.5, 0.8)
