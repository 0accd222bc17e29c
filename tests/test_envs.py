"""Gymnasium environments (rig/envs/): registered ids, physics against closed forms and against ``rig track``,
causal actions, reproducible resets, and the batched vector env equal bit for bit to gymnasium's own."""

import warnings

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import rig
from rig.envs import ENVIRONMENTS
from rig.road.roads import RoadProfile, road_from_spec
from rig.signal.comfort import weighted_rms
from rig.signal.metrics import tddi
from rig.sim.track import track_run

ROAD = "iso8608:class=C,length=30,seed=3"  # 1.5 s at 20 m/s: 768 steps at 512 Hz
QUARTER = rig.load_vehicle("proton_x_quarter")


def _episode(env, action) -> tuple[np.ndarray, dict[str, np.ndarray], dict]:
    """Observations and the contract quantities of a whole episode holding ``action`` (or action(k))."""
    obs, info = env.reset(seed=0)
    plant = env.unwrapped.episodes
    observations, quantities = [obs], {q: [v[0].copy()] for q, v in plant.quantities.items()}
    k, truncated = 0, False
    while not truncated:
        obs, _, terminated, truncated, info = env.step(action(k) if callable(action) else action)
        assert not terminated
        observations.append(obs)
        for q, v in plant.quantities.items():
            quantities[q].append(v[0].copy())
        k += 1
    return np.array(observations), {q: np.array(v) for q, v in quantities.items()}, info


def test_ids_are_registered_by_import_rig():
    for env_id in ENVIRONMENTS:
        assert env_id in gym.registry
    assert set(ENVIRONMENTS) == {"FourPoster/ActiveSuspension-v0", "FourPoster/SemiActiveSuspension-v0",
                                 "FourPoster/DriveTracking-v0"}


@pytest.mark.parametrize("env_id", list(ENVIRONMENTS))
def test_check_env_passes_without_a_warning(env_id):
    env = gym.make(env_id, road="iso8608:class=C,length=10")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        check_env(env.unwrapped)


def test_zero_force_reproduces_rig_track_bit_for_bit():
    env = gym.make("FourPoster/ActiveSuspension-v0", road=ROAD)
    _, quantities, info = _episode(env, np.zeros(1))
    record = track_run(QUARTER, road_from_spec(ROAD), 20.0).record
    for q in ("sprung_acc", "unsprung_acc", "susp_travel", "susp_velocity", "tyre_force", "road"):
        np.testing.assert_array_equal(quantities[q][:, 0], record[f"FL/{q}"], err_msg=q)
    # the running a_w of info is the ISO 2631 a_w of the whole record
    assert info["a_w"] == pytest.approx(weighted_rms(record["FL/sprung_acc"], record.rate), rel=1e-12)


def test_semi_active_damper_at_nominal_damping_equals_the_passive_car():
    env = gym.make("FourPoster/SemiActiveSuspension-v0", road=ROAD, physical_actions=True)
    _, quantities, _ = _episode(env, np.array([QUARTER.front.damping]))
    record = track_run(QUARTER, road_from_spec(ROAD), 20.0).record
    for q in ("sprung_acc", "unsprung_acc", "susp_travel", "tyre_force"):
        assert tddi(quantities[q][:, 0], record[f"FL/{q}"]) < 1e-9, q
    assert np.all(quantities["control_force"][1:, 0] * quantities["susp_velocity"][1:, 0] >= 0)  # dissipative


def test_constant_force_shifts_static_travel_by_force_over_suspension_rate():
    flat = RoadProfile(0.05, np.zeros(2001), np.zeros(2001), "flat")
    env = gym.make("FourPoster/ActiveSuspension-v0", road=flat, speed=20.0, duration=4.0, physical_actions=True)
    force = 1500.0
    _, quantities, _ = _episode(env, np.array([force]))
    expected = -force / QUARTER.front.suspension_rate  # the tyre still carries the whole weight
    assert quantities["susp_travel"][-1, 0] == pytest.approx(expected, rel=1e-6)
    static = env.unwrapped.plant.sim.static.tyre_force[0]
    assert quantities["tyre_force"][-1, 0] == pytest.approx(static, rel=1e-7)


@pytest.mark.parametrize("env_id, lag", [("FourPoster/ActiveSuspension-v0", 1),
                                         ("FourPoster/SemiActiveSuspension-v0", 1),
                                         ("FourPoster/DriveTracking-v0", 2)])
def test_an_action_never_acts_before_it_is_taken(env_id, lag):
    env = gym.make(env_id, road=ROAD)
    k = 200
    base, _, _ = _episode(env, lambda i: np.zeros(1))
    stepped, _, _ = _episode(env, lambda i: np.full(1, 0.5 if i >= k else 0.0))
    # observation i is at sample i, before the action of step i: nothing before observation k + 1 may change;
    # a force shows at once in the accelerations, a post drive after the servo's input delay (2 samples here)
    changed = np.flatnonzero(np.any(stepped != base, axis=1))
    assert changed[0] == k + lag


def test_reset_with_a_seed_is_reproducible():
    env = gym.make("FourPoster/SemiActiveSuspension-v0", road=ROAD)
    actions = np.random.default_rng(1).uniform(-1, 1, (800, 1))
    first, _, _ = _episode(env, lambda i: actions[i])
    again, _, _ = _episode(env, lambda i: actions[i])
    np.testing.assert_array_equal(first, again)


@pytest.mark.parametrize("env_id, kwargs", [
    *[(env_id, {"road": "iso8608:class=C,length=4,seed=1"}) for env_id in ENVIRONMENTS],  # 102 steps, autoreset
    ("FourPoster/ActiveSuspension-v0", {"road": "iso8608:class=C,length=4", "random_road": True, "preview": 0.02}),
])
def test_vector_env_equals_sync_vector_env_bit_for_bit(env_id, kwargs):
    n = 3
    batched = gym.make_vec(env_id, num_envs=n, vectorization_mode="vector_entry_point", **kwargs)
    synced = gym.make_vec(env_id, num_envs=n, vectorization_mode="sync", **kwargs)
    actions = np.random.default_rng(0).uniform(-1, 1, (120, n, 1))
    results = []
    for envs in (batched, synced):
        obs, infos = envs.reset(seed=5)
        run = [(obs, infos)]
        for a in actions:
            run.append(envs.step(a))
        results.append(run)
    assert any(step[3].all() for step in results[0][1:])  # the episode ended and autoreset within the run
    for got, want in zip(*results):
        for g, w in zip(got, want):
            if isinstance(w, dict):
                assert set(g) == set(w)
                for key in w:
                    np.testing.assert_array_equal(g[key], w[key], err_msg=key)
            else:
                np.testing.assert_array_equal(g, w)


@pytest.mark.parametrize("kwargs, message", [
    ({"force_limit": -1.0}, "force_limit must be positive"),
    ({"speed": 0.0}, "speed must be positive"),
    ({"travel_limit": 0.0}, "travel_limit must be positive"),
    ({"reward_weights": {"comfort": -1.0}}, "reward weight comfort"),
    ({"road": "iso8608:class=C,length=10", "duration": 5.0}, "road is 10.00 m long"),
])
def test_bad_arguments_are_refused_with_a_clear_message(kwargs, message):
    with pytest.raises(ValueError, match=message):
        gym.make("FourPoster/ActiveSuspension-v0", **kwargs)


def test_semi_active_bounds_must_dissipate():
    with pytest.raises(ValueError, match="c_min must be >= 0"):
        gym.make("FourPoster/SemiActiveSuspension-v0", c_min=-10.0)


def test_drive_tracking_refuses_a_target_channel_that_is_zero_throughout():
    from rig.io.record import Record

    target = track_run(QUARTER, road_from_spec(ROAD), 20.0).record
    zero = np.zeros(target.n_samples)
    flat = Record(target.rate, {"FL/sprung_acc": target["FL/sprung_acc"], "FL/unsprung_acc": zero})
    with pytest.raises(ValueError, match="FL/unsprung_acc are zero throughout"):
        gym.make("FourPoster/DriveTracking-v0", target=flat)


def test_passive_a_w_equals_the_spectral_prediction():
    """a_w of the passive car on an ISO 8608 road = sqrt(integral |H_acc(f) Wk(f)|^2 Gz(f) df): the quarter
    car's road-to-body-acceleration FRF (linearised model) times the road's temporal PSD Gd(f / V) / V.
    The run is ``rig track``'s, which the env with zero force reproduces bit for bit (above), in C."""
    from rig.road.roads import ISO_8608_CLASSES
    from rig.signal.comfort import wk_response
    from rig.sim.linearize import car_state_matrix

    speed = 20.0
    road = "iso8608:class=C,length=500"
    env = gym.make("FourPoster/ActiveSuspension-v0", road=road, speed=speed)
    record = track_run(QUARTER, road_from_spec(road), speed).record
    a_w = weighted_rms(record["FL/sprung_acc"], record.rate)
    a = car_state_matrix(env.unwrapped.plant.sim)  # (body, wheel) heights over the road and velocities
    frequency = np.linspace(0.01, 10.0, 20_000) * speed  # the road's band, 0.01-10 cycle/m, in Hz
    s = 2j * np.pi * frequency
    road_velocity = np.array([-1.0, -1.0, 0.0, 0.0])
    states = np.linalg.solve(s[:, None, None] * np.eye(4) - a, road_velocity)  # per unit road velocity
    body_acc = (states @ a[2]) * s  # per unit road height
    psd = ISO_8608_CLASSES["C"] * (frequency / speed / 0.1) ** -2 / speed
    predicted = np.sqrt(np.trapezoid(np.abs(body_acc * wk_response(frequency)) ** 2 * psd, frequency))
    # measured: 1.651 simulated against 1.656 predicted (0.3 %)
    assert a_w == pytest.approx(predicted, rel=0.03)


def test_random_roads_follow_the_reset_seed():
    env = gym.make("FourPoster/SemiActiveSuspension-v0", road="iso8608:class=C,length=20", random_road=True,
                   preview=0.1)
    roads = []
    for seed in (1, 1, 2):
        obs, _ = env.reset(seed=seed)
        roads.append(obs[4:].copy())  # the road preview
    np.testing.assert_array_equal(roads[0], roads[1])
    assert np.any(roads[0] != roads[2])
    with pytest.raises(ValueError, match="random_road needs an iso8608 road spec without a seed"):
        gym.make("FourPoster/SemiActiveSuspension-v0", road="iso8608:class=C,length=20,seed=3", random_road=True)


def test_vector_env_refuses_a_partial_reset():
    envs = gym.make_vec("FourPoster/ActiveSuspension-v0", num_envs=2, vectorization_mode="vector_entry_point",
                        road="iso8608:class=C,length=4")
    with pytest.raises(ValueError, match="lockstep"):
        envs.reset(options={"reset_mask": np.array([True, False])})


def test_sensor_map_converts_sensors_as_sensor_responses_bit_for_bit():
    """One gather and one multiply-add per step give the contract quantities sensor_responses gives, on the car
    with its controller actuators and on the rig with servo posts: random sensor data, zeros of both signs."""
    from rig.envs.sensing import SensorMap
    from rig.sim.simulate import sensor_responses

    for env_id in ("FourPoster/ActiveSuspension-v0", "FourPoster/DriveTracking-v0"):
        plant = gym.make(env_id, vehicle="proton_x", road="iso8608:class=C,length=4,seed=1").unwrapped.plant
        sensors = SensorMap.of(plant.sim, plant.observed)
        assert sensors.names[:len(plant.observed)] == plant.observed
        data = np.random.default_rng(2).normal(0.0, 50.0, (64, plant.model.nsensordata))
        data[0], data[1] = 0.0, -0.0
        converted = sensors.quantities(sensors.convert(data))
        expected = sensor_responses(plant.sim.rig, plant.sim.static.suspension_length, data)
        assert list(converted) == list(expected)
        for name, values in expected.items():
            assert np.ascontiguousarray(converted[name]).tobytes() == values.tobytes(), name


def test_sensor_map_refuses_a_quantity_that_is_not_one_sensor_value(monkeypatch):
    from rig.envs import sensing

    plant = gym.make("FourPoster/ActiveSuspension-v0", road="iso8608:class=C,length=4,seed=1").unwrapped.plant
    responses = sensing.sensor_responses

    def squared_travel(rig, length, sensors):
        out = responses(rig, length, sensors)
        out["susp_travel"] = out["susp_travel"] ** 2
        return out

    monkeypatch.setattr(sensing, "sensor_responses", squared_travel)
    with pytest.raises(ValueError, match="susp_travel is not one sensor value"):
        sensing.SensorMap.of(plant.sim)


def test_ride_metrics_weight_every_copy_as_sosfilt_bit_for_bit():
    """RideMetrics steps the Wk sections of all copies and corners at once; its running a_w equals scipy's
    sosfilt of each whole signal, squared and summed in time order, bit for bit, and the step's reward is minus
    the comfort weight times the weighted acceleration squared, averaged over corners."""
    from scipy import signal

    from rig.envs.ride_metrics import RideMetrics
    from rig.envs.sensing import SensorMap
    from rig.signal.comfort import wk_filter

    plant = gym.make("FourPoster/ActiveSuspension-v0", vehicle="proton_x", road=ROAD).unwrapped.plant
    sensors = SensorMap.of(plant.sim, plant.observed)
    copies, samples = 5, 600
    metrics = plant.new_metrics(copies, sensors)
    assert isinstance(metrics, RideMetrics)
    acceleration = np.random.default_rng(4).normal(0.0, 2.0, (samples, copies, 4))
    weighted = signal.sosfilt(wk_filter(plant.rate), acceleration, axis=0)
    sensed = np.zeros((copies, sensors.columns.size))
    sensed[:, sensors.slice("tyre_force")] = plant.sim.static.tyre_force  # no dynamic load, no travel, no power
    sums = np.zeros((copies, 4))
    for k in range(samples):
        sensed[:, sensors.slice("sprung_acc")] = acceleration[k]
        reward = metrics.update(k, sensed, np.zeros((copies, 4)))
        sums += weighted[k] ** 2
    assert metrics.summary().a_w.tobytes() == np.sqrt((sums / samples).max(-1)).tobytes()
    np.testing.assert_allclose(reward, -plant.weights.comfort * np.mean(weighted[-1] ** 2, axis=-1), rtol=1e-14)


def test_batch_substeps_without_sensors_keep_delayed_sensors_as_the_loop_does():
    """The batch's substeps skip MuJoCo's sensor stage; delayed sensors (their history kept every substep) and
    undelayed ones read at the end of each step exactly what the loop of mj_step with sensors reads."""
    import mujoco

    from rig.envs.stepping import STATE_SPEC, BatchStepper, LoopStepper

    model = mujoco.MjModel.from_xml_string("""
    <mujoco><option timestep="0.005" integrator="RK4"/>
      <worldbody><body><joint name="j" type="slide" axis="0 0 1" stiffness="100" damping="2"/>
        <geom size="0.1" mass="1"/><site name="s"/></body></worldbody>
      <actuator><motor joint="j"/></actuator>
      <sensor><jointpos joint="j" delay="0.02" nsample="8"/><accelerometer site="s" delay="0.01" nsample="4"/>
        <jointvel joint="j" delay="0.012" nsample="5" interp="linear"/><accelerometer site="s"/></sensor>
    </mujoco>""")
    state = np.zeros(mujoco.mj_stateSize(model, STATE_SPEC))
    ctrl = np.random.default_rng(0).normal(0.0, 10.0, (2, 40, 4, model.nu))  # copies, steps, substeps + 1
    batch, loops = BatchStepper(model, 2, 1), [LoopStepper(model) for _ in range(2)]
    batch.reset(state, ctrl[:, 0, 0])
    for i, loop in enumerate(loops):
        loop.reset(state, ctrl[i:i + 1, 0, 0])
    for k in range(40):
        batch.advance(ctrl[:, k])
        for i, loop in enumerate(loops):
            loop.advance(ctrl[i:i + 1, k])
            assert batch.outputs()[0][i].tobytes() == loop.outputs()[0][0].tobytes()
    assert np.any(batch.outputs()[0][:, 0] != 0.0)


@pytest.mark.parametrize("per_thread, forward_threads", [(256, 1), (2, 2)])
def test_batch_forward_on_its_own_threads_equals_the_loop_bit_for_bit(monkeypatch, per_thread, forward_threads):
    """The forward of a period runs in a second batch that takes the substeps' state rows, on the caller's thread
    or on threads of its own: the car's sensors and actuator forces and velocities equal those of a loop of
    mj_step and mj_forward on one MjData per copy, bit for bit, with forces that change every step."""
    from rig.envs import stepping

    monkeypatch.setattr(stepping, "FORWARD_COPIES_PER_THREAD", per_thread)
    plant = gym.make("FourPoster/ActiveSuspension-v0", road=ROAD).unwrapped.plant
    copies, n = 4, plant.substeps
    batch = stepping.BatchStepper(plant.model, copies, 2)
    assert batch.observer.nthread == forward_threads
    loops = [stepping.LoopStepper(plant.model) for _ in range(copies)]
    ctrl = np.repeat(plant.inputs[:, :40 * n + 1], copies, axis=0)
    ctrl[:, :, plant.action_ctrl] = np.random.default_rng(1).uniform(-3000.0, 3000.0, (copies, 40 * n + 1, 1))
    batch.reset(plant.sim.static.state, ctrl[:, 0])
    for i, loop in enumerate(loops):
        loop.reset(plant.sim.static.state, ctrl[i:i + 1, 0])
    for k in range(40):
        period = ctrl[:, k * n:(k + 1) * n + 1]
        batch.advance(period)
        for i, loop in enumerate(loops):
            loop.advance(period[i:i + 1])
            for got, want in zip(batch.outputs(), loop.outputs()):
                assert got[i].tobytes() == want[0].tobytes()
    assert np.ptp(batch.outputs()[1][:, plant.action_ids]) > 1000.0  # the copies' forces differ
