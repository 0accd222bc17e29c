"""The longest physics step a car on measured posts may take where the default's margin is not needed: a diagnosis's
fits, which simulate the same test a thousand times.

MAX_TIMESTEP (rig/vehicle/mjcf.py, 1 ms) resolves the post servo's 150 Hz loop and the elements sized to it. A car on
measured (ideal) posts has no such loop: its fastest mode is wheel hop, about 75 rad/s. RK4's error on a mode lambda
over one step is (|lambda| h)^5 / 120 of its state; where the car's fastest mode (the largest eigenvalue of its
linearised state matrix at static ride height, rig/sim/linearize.py) keeps |lambda| h within MODE_STEP at
COARSE_TIMESTEP, the car steps at that (one step per sample at 512 Hz instead of two: |lambda| h = 0.15 on
proton_x); else, as a linkage car's bushings (2000 rad/s), at MAX_TIMESTEP. A cause whose element is sized to
MAX_TIMESTEP or may be stiffer than a longer step resolves (``Cause.fine_step``: a top mount, a friction law's slope, a
stop in contact) keeps its model at MAX_TIMESTEP whatever is asked: a stop of 4e7 N/m at 2 ms misses the same stop at
1 ms by a held-out TDDI of 3.6e-3, ninety times a 2 % noise floor; the car without it, by 3.9e-9.
"""

from __future__ import annotations

import numpy as np

from rig.sim.linearize import car_state_matrix
from rig.sim.simulate import Simulator
from rig.vehicle.mjcf import MAX_TIMESTEP, build_model
from rig.vehicle.vehicle_file import Vehicle

COARSE_TIMESTEP = 2e-3  # s
MODE_STEP = 0.5         # |lambda| h of the fastest mode at most: RK4's error (|lambda| h)^5 / 120 = 2.6e-4 a step


def fit_timestep(vehicle: Vehicle, rate: float) -> float:
    """The longest physics step (s) ``vehicle`` on measured posts may take for records at ``rate`` Hz (module
    docstring)."""
    sim = Simulator.create(build_model(vehicle, rate, "ideal", longest=COARSE_TIMESTEP))
    fastest = float(np.max(np.abs(np.linalg.eigvals(car_state_matrix(sim)))))
    return COARSE_TIMESTEP if fastest * sim.rig.timestep <= MODE_STEP else MAX_TIMESTEP
