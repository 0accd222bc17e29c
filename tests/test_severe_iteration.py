"""Drive iteration on severe targets: the measured Belgian-block target on proton_x, where the tyres must leave the
posts; the demands beyond the model, quantified and checked against the physics of an airborne wheel; damage and
peak matching; per-channel band gains; the FRF update that lift-off does not corrupt."""

import itertools

import numpy as np
import pytest
from scipy import signal

from controllers.band_gains import BandGains, band_errors
from controllers.frf_update import normalised, updated_spectra, usable_window
from controllers.reachability import Unreachable, limit_demands
from controllers.rpc import DriveIteration, IterationSettings
from rig.io.channel_map import map_from_option
from rig.io.files import read_record
from rig.io.record import Record
from rig.signal.frf import estimate_frf, spectral_matrices
from rig.signal.metrics import damage_ratio, peak_error_pct
from rig.sim.drive_limits import LimitHit
from rig.vehicle.vehicle_file import load_vehicle

G = 9.80665
WHEELS = ["FL/unsprung_acc", "FR/unsprung_acc", "RL/unsprung_acc", "RR/unsprung_acc"]


@pytest.fixture(scope="module")
def belgian_block():
    """The 20-40 s section of the measured Belgian-block record (a truck's outer wheels, 256 Hz), on proton_x."""
    mapping = map_from_option(["LF_=FL/unsprung_acc", "RF_=FR/unsprung_acc", "LR_=RL/unsprung_acc",
                               "RR_=RR/unsprung_acc"])
    full = read_record("data/belgian_block_20kph_wheel_acc.rsp", channel_map=mapping)
    section = slice(int(20 * full.rate), int(40 * full.rate))
    target = Record(full.rate, {n: v[section] for n, v in full.channels.items()}, dict(full.units))
    return load_vehicle("proton_x"), target


@pytest.fixture(scope="module")
def iterated(belgian_block, tmp_path_factory):
    vehicle, target = belgian_block
    job = DriveIteration(vehicle, target, WHEELS, tmp_path_factory.mktemp("bb"), IterationSettings(iterations=10))
    return job, job.run(progress=False)


def test_the_belgian_block_stops_on_lift_off_and_says_how_much_the_target_asks_beyond_it(iterated):
    """Before: the first play's 14.8 % was never improved on ("stagnated on the post limits"). Now the error the
    drive can act on is iterated away (the rest of the record within 3 %, measured 2.2 % after the second play),
    and the run stops on lift-off at every corner, the target's wheels falling faster than proton_x's can."""
    job, result = iterated
    assert result.status == "limited" and result.stop_reason.startswith("limited by the model: lift-off at FL")
    best = result.best
    assert max(best.rest_rms_error_pct.values()) <= 3.0 < best.worst_rms_error_pct
    assert best.rest_share > 0.9
    assert best.worst_rms_error_pct < result.history[0].worst_rms_error_pct
    lift_offs = {u.corner: u for u in result.unreachable if u.kind == "lift-off"}
    assert set(lift_offs) == {"FL", "FR", "RL", "RR"}
    played = result.replay.record
    for corner, demand in lift_offs.items():
        assert demand.demanded > demand.available
        airborne = played[f"{corner}/tyre_force"][job.span] <= 0
        assert 0 < demand.duration <= airborne.sum() / job.rate
        # the airborne wheel falls under its suspension's push alone: m_t a = -(F_static + k x + c v) - m_t g,
        # with the suspension force from the car's linear law and its static load from the car at rest; within 5 %:
        # the travel's rate by finite differences at 256 Hz (measured 3.3 % on FL; without the damper's term, 124 %)
        axle = job.vehicle.axle(corner)
        travel = played[f"{corner}/susp_travel"]
        rate = np.gradient(travel, 1 / job.rate)
        static = played[f"{corner}/tyre_force"][0] - axle.unsprung_mass * G
        pushed = -(static + axle.suspension_rate * travel + axle.damping * rate) / axle.unsprung_mass - G
        off = played[f"{corner}/tyre_force"] <= 0
        wheel = played[f"{corner}/unsprung_acc"]
        assert np.sqrt(np.mean((wheel[off] - pushed[off]) ** 2)) < 0.05 * np.sqrt(np.mean(wheel[off] ** 2))


def test_damage_matching_brings_every_channel_within_5_percent_of_the_target_damage(belgian_block, iterated,
                                                                                    tmp_path):
    """The time history is out of reach where the tyres lift off (RMS matching leaves FL at a damage ratio of 0.87);
    matching the damage drives the rest harder until the rainflow damage agrees (measured 0.98-1.03 in 4 plays)."""
    vehicle, target = belgian_block
    job = DriveIteration(vehicle, target, WHEELS, tmp_path, IterationSettings(iterations=8, match="damage",
                                                                             target_error_pct=5.0))
    result = job.run(progress=False)
    assert result.status == "converged" and "damage ratio of 0.952-1.05" in result.stop_reason
    blended = job.weight * result.response + (1 - job.weight) * job.target
    ratios = [damage_ratio(job.target[job.span, j], blended[job.span, j]) for j in range(len(WHEELS))]
    assert all(1 / 1.05 <= r <= 1.05 for r in ratios), ratios
    rms_ratios = [m.damage_ratio for m in iterated[1].best.channels.values()]
    assert min(rms_ratios) < 1 / 1.05


def test_peak_matching_stops_when_every_peak_is_within_tolerance(belgian_block, tmp_path):
    """Peaks judged as the user asks: here the right front's and rear wheels' extremes (in reach) within 6 %."""
    vehicle, target = belgian_block
    channels = ["FR/unsprung_acc", "RL/unsprung_acc"]
    job = DriveIteration(vehicle, target, channels, tmp_path, IterationSettings(iterations=6, match="peak",
                                                                               target_error_pct=6.0))
    result = job.run(progress=False)
    assert result.status == "converged" and "6 % peak error" in result.stop_reason
    blended = job.weight * result.response + (1 - job.weight) * job.target
    for j in range(len(channels)):
        wanted, got = job.target[job.span, j], blended[job.span, j]
        miss = max(abs(got.max() - wanted.max()), abs(got.min() - wanted.min())) / np.abs(wanted).max()
        assert 100 * miss <= 6.0
        assert peak_error_pct(wanted, got) == pytest.approx(100 * miss)


def test_cli_iterate_matches_damage_and_reports_what_is_beyond_the_model(belgian_block, tmp_path, capsys):
    import json

    from rig.cli.main import main
    from rig.io.files import write_record

    _vehicle, target = belgian_block
    path = tmp_path / "bb.csv"
    write_record(path, target)
    out = tmp_path / "run"
    assert main(["iterate", "--vehicle", "proton_x", "--target", str(path), "--out", str(out), "--iterations", "2",
                 "--match", "damage", "--quiet"]) == 0
    printed = capsys.readouterr().out
    assert "beyond the model: FL: the target's wheel falls at up to" in printed
    assert "damage ratio: FL/unsprung_acc" in printed
    document = json.loads((out / "history.json").read_text())
    assert document["settings"]["match"] == "damage" and document["settings"]["target_error_pct"] == 25.0
    demands = document["iterations"][-1]["unreachable"]
    assert {d["kind"] for d in demands} >= {"lift-off"} and all(d["duration"] > 0 for d in demands)


def test_demands_read_as_the_rig_engineer_says_them():
    hits = [LimitHit("FL", "velocity", 3.1, 2.38, 1.2, 205), LimitHit("RR", "stroke", 0.0912, 0.075, 3.0, 20)]
    reached = [LimitHit("RR", "stroke", 0.075, 0.075, 3.0, 12), LimitHit("FR", "force", 5e4, 5e4, 4.0, 5)]
    demands = limit_demands(hits, reached, 512.0)
    assert [d.describe() for d in demands] == [
        "FL needs 3.1 m/s where the post gives 2.38 m/s, for 0.4 s in total",
        "RR needs 91.2 mm of stroke where the post gives ±75 mm, for 0.039 s in total",
        "FR: the post force reaches its 50 kN rating for 0.0098 s in total"]
    lift = Unreachable("lift-off", "FL", 89.3, 64.7, "m/s^2", 0.33)
    assert ("falls at up to 89.3 m/s^2 (9.1 g) where the airborne wheel then falls at 64.7 m/s^2 (6.6 g)"
            in lift.describe())


def test_band_errors_split_the_energy_by_octave_and_gains_follow_each_band():
    rate, n = 256.0, 4096
    t = np.arange(n) / rate
    error = np.column_stack([np.sin(2 * np.pi * 3.0 * t), np.sin(2 * np.pi * 12.0 * t)])
    gains = BandGains.uniform((0.5, 50.0), 2, 1.0)
    np.testing.assert_allclose(gains.edges, [0.5, 1, 2, 4, 8, 16, 32, 50])
    energy = band_errors(error, rate, gains.edges)
    total = np.abs(np.fft.rfft(error, axis=0)) ** 2
    np.testing.assert_allclose(energy.sum(axis=0), total.sum(axis=0), rtol=1e-12)  # every line in one band
    assert energy[2, 0] / energy[:, 0].sum() > 0.999 and energy[4, 1] / energy[:, 1].sum() > 0.999
    before = energy.copy()
    now = energy.copy()
    now[2, 0] *= 2  # channel 0 got worse at 2-4 Hz only
    now[4, 1] *= 0.5
    gains.values[:] = 0.5
    gains.adapt(now, before)
    assert gains.values[2, 0] == 0.25 and gains.values[4, 1] == 1.0
    lines = gains.on_lines(np.array([0.1, 3.0, 12.0, 60.0]))
    assert lines[1, 0] == 0.25 and lines[2, 1] == 1.0 and lines[0, 0] == gains.values[0, 0]


def test_the_frf_update_ignores_what_lift_off_does_to_the_increments():
    """A resonant system (2 Hz, 20 % damping) whose output collapses while a 'tyre' is off (a quarter of the time):
    four plays' increments pull a naive update (every sample) away from the truth; the robust update, which fades
    the airborne stretches out and weights the rest by coherence, moves the starting FRF (70 % of the truth)
    towards it (median misfit over 1-10 Hz: from 0.30 to 0.13 robust, 0.27 naive)."""
    rate, nperseg, band = 128.0, 1024, (0.5, 20.0)
    b, a = signal.bilinear([(2 * np.pi * 2.0) ** 2], [1, 2 * 0.2 * 2 * np.pi * 2.0, (2 * np.pi * 2.0) ** 2], rate)
    rng = np.random.default_rng(0)
    n = int(240 * rate)
    airborne = np.zeros((n, 1), bool)
    for begin in rng.integers(0, n - 64, 200):
        airborne[begin:begin + 48] = True

    def play(drive):
        return np.where(airborne, 0.1 * signal.lfilter(b, a, drive, axis=0), signal.lfilter(b, a, drive, axis=0))

    identification = rng.standard_normal((n, 1))
    start = normalised(spectral_matrices(identification, 0.7 * signal.lfilter(b, a, identification, axis=0),
                                         rate, nperseg), band)
    drives = [rng.standard_normal((n, 1)) for _ in range(5)]
    robust, naive = start, start
    for before, after in itertools.pairwise(drives):
        step = (after - before, play(after) - play(before))
        robust, _ = updated_spectra(robust, *step, usable_window(airborne, airborne, rate), rate, nperseg, band)
        naive, _ = updated_spectra(naive, *step, np.ones(n), rate, nperseg, band)
    inside = (start.frequency >= 1.0) & (start.frequency <= 10.0)
    truth = signal.freqz(b, a, worN=start.frequency, fs=rate)[1][inside]

    def misfit(spectra):
        return float(np.median(np.abs(estimate_frf(spectra).h1[inside, 0, 0] / truth - 1)))

    assert airborne.mean() > 0.2
    assert misfit(robust) < 0.5 * misfit(start) and misfit(robust) < 0.5 * misfit(naive), (
        misfit(start), misfit(robust), misfit(naive))
