"""LQR of a quarter car from its linearised MuJoCo model, and the cost the Riccati solution predicts.

State x = (body and wheel height over the road, body and wheel velocity), deviations from static ride
height; input u = the active force (N, pushing body and wheel apart); disturbance: the road velocity w,
which enters as dx/dt = A x + B u + g w with g = (-1, -1, 0, 0). A (posts held) comes from
``rig.sim.linearize.car_state_matrix``: moving car and road together changes no force, so the same A holds
for heights over the road. B is the finite difference of the accelerations in the actuator's control.

Cost rate: q_acc a_body^2 + q_tyre (dynamic tyre load / static load)^2 + q_travel travel^2 + r u^2, with
a_body = A[2] x + B[2] u (a cross term N). On an ISO 8608 road the road velocity is white: a two-sided
intensity W = 2 pi^2 Gd(n0) n0^2 V (m^2/s) at speed V; the optimal mean cost rate is W g' P g, P the
solution of the continuous algebraic Riccati equation.
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np
from scipy import linalg

from rig.road.roads import ISO_8608_N0
from rig.sim.linearize import car_state_matrix

ROAD_INPUT = np.array([-1.0, -1.0, 0.0, 0.0])


@dataclass(frozen=True)
class LqrDesign:
    a: np.ndarray         # (4, 4) 1/s^2, 1/s: state matrix
    b: np.ndarray         # (4, 1) input matrix (m/s^2 per N in the velocity rows)
    q: np.ndarray         # (4, 4) state weight
    r: np.ndarray         # (1, 1) input weight
    n: np.ndarray         # (4, 1) cross weight
    gain: np.ndarray      # (1, 4) u = -gain x
    riccati: np.ndarray   # (4, 4) P

    def predicted_cost(self, road_intensity: float) -> float:
        """Mean cost rate of the closed loop under white road velocity of two-sided intensity ``road_intensity``."""
        return float(road_intensity * ROAD_INPUT @ self.riccati @ ROAD_INPUT)


def road_velocity_intensity(gd_n0: float, speed: float) -> float:
    """Two-sided intensity (m^2/s) of the road velocity under a tyre on an ISO 8608 road of Gd(n0) ``gd_n0``
    (m^3) at ``speed`` m/s: the one-sided PSD (2 pi f)^2 Gd(f / V) / V = 4 pi^2 Gd(n0) n0^2 V, halved."""
    return 2 * np.pi**2 * gd_n0 * ISO_8608_N0**2 * speed


def lqr_design(plant, q_acc: float = 1.0, q_tyre: float = 10.0, q_travel: float = 0.0,
               r: float = 1e-8, sampled: bool = False) -> LqrDesign:
    """The LQR of the quarter car ``plant`` (a CarOnRoad with force actuators) for the cost weights.

    ``sampled``: the optimal gain for the force held over each control period of the plant (the same
    continuous cost, integrated over the period with the held force: Van Loan), instead of the
    continuous-time gain; ``riccati`` stays the continuous solution, the prediction of ``predicted_cost``.
    """
    if plant.control != "force" or len(plant.corners) != 1:
        raise ValueError("the LQR is designed for a quarter car with a force actuator (ActiveSuspension)")
    if min(q_acc, q_tyre, q_travel) < 0 or not r > 0:
        raise ValueError(f"LQR weights must be >= 0 and r > 0, got q_acc={q_acc}, q_tyre={q_tyre}, "
                         f"q_travel={q_travel}, r={r}")
    a = car_state_matrix(plant.sim)
    b = np.zeros((4, 1))
    b[2:, 0] = _input_column(plant)
    axle = plant.vehicle.axle(plant.corners[0])
    tyre = np.array([0.0, -axle.tyre_rate, 0.0, 0.0]) / plant.sim.static.tyre_force[0]
    travel = np.array([-1.0, 1.0, 0.0, 0.0])
    acc_x, acc_u = a[2], b[2]
    q = q_acc * np.outer(acc_x, acc_x) + q_tyre * np.outer(tyre, tyre) + q_travel * np.outer(travel, travel)
    n = q_acc * np.outer(acc_x, acc_u)
    rr = q_acc * np.outer(acc_u, acc_u) + r
    p = linalg.solve_continuous_are(a, b, q, rr, s=n)
    gain = _sampled_gain(a, b, q, rr, n, 1.0 / plant.rate) if sampled else np.linalg.solve(rr, b.T @ p + n.T)
    return LqrDesign(a, b, q, rr, n, gain, p)


def _sampled_gain(a, b, q, r, n, period: float) -> np.ndarray:
    """Discrete LQR gain of (A, B) under a zero-order hold of ``period`` s, for the continuous cost integrated
    over each period (Van Loan's block exponential gives the discrete system and cost together)."""
    states, inputs = b.shape
    size = states + inputs
    held = np.zeros((size, size))
    held[:states, :states], held[:states, states:] = a, b
    weight = np.block([[q, n], [n.T, r]])
    block = linalg.expm(np.block([[-held.T, weight], [np.zeros((size, size)), held]]) * period)
    transition = block[size:, size:]
    cost = transition.T @ block[:size, size:]
    cost = (cost + cost.T) / 2
    ad, bd = transition[:states, :states], transition[:states, states:]
    qd, nd, rd = cost[:states, :states], cost[:states, states:], cost[states:, states:]
    p = linalg.solve_discrete_are(ad, bd, qd, rd, s=nd)
    return np.linalg.solve(rd + bd.T @ p @ bd, bd.T @ p @ ad + nd.T)


def _input_column(plant) -> np.ndarray:
    """d(acceleration)/d(force) of body and wheel at static ride height (central difference, exact: linear)."""
    model = plant.model
    data = mujoco.MjData(model)
    column = []
    for force in (1.0, -1.0):
        mujoco.mj_setState(model, data, plant.sim.static.state, mujoco.mjtState.mjSTATE_FULLPHYSICS)
        data.ctrl[plant.action_ctrl] = force
        mujoco.mj_forward(model, data)
        column.append(data.qacc[plant.sim.rig.free_dofs].copy())
    return (column[0] - column[1]) / 2.0
