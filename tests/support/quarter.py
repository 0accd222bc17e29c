"""A quarter car given as a vehicle file's tables (Proton X front-left, Nurhadiyanto's Table 4.2) with sections
added, and the force its suspension puts on the body at a compression and rate."""

import mujoco

from rig.vehicle.vehicle_file import vehicle_from_dict

QUARTER = {
    "name": "q", "layout": "quarter", "sprung": {"mass": 355.31},
    "front": {"unsprung_mass": 35.19, "spring_rate": 23000.0, "parasitic_rate": 6000.0, "damping": 3959.0,
              "tyre_rate": 208500.0},
}


def quarter_with(**sections):
    return vehicle_from_dict({**QUARTER, **sections}, "test")


def suspension_force(sim, compression, velocity):
    """Upward force (N) on the body from the suspension at ``compression`` m and compression rate ``velocity`` m/s."""
    model = sim.rig.model
    data = mujoco.MjData(model)
    data.qpos[:] = sim.static.qpos
    heave = model.joint("car.heave").qposadr[0]
    data.qpos[heave] -= compression
    data.qvel[model.joint("car.heave").dofadr[0]] = -velocity
    mujoco.mj_forward(model, data)
    # generalised force on the heave DOF from passive springs/dampers and the damper actuators, minus static
    return (data.qfrc_passive[model.joint("car.heave").dofadr[0]]
            + data.qfrc_actuator[model.joint("car.heave").dofadr[0]])
