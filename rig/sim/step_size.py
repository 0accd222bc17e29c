"""The longest physics step a car on measured posts may take where the default's margin is not needed: a diagnosis's
fits, which simulate the same test a thousand times.

MAX_TIMESTEP (rig/vehicle/mjcf.py, 1 ms) resolves the post servo's 150 Hz loop and the elements sized to it. A car on
measured (ideal) posts has no such loop: its fastest mode is wheel hop, about 75 rad/s. RK4's error on a mode lambda
over one step is (|lambda| h)^5 / 120 of its state; where the car's modes (the eigenvalues of its linearised state
matrix at static ride height, rig/sim/linearize.py) that the analysis band can see (|lambda| up to REACH times its top,
in rad/s) keep |lambda| h within MODE_STEP, and every faster mode stays damped by RK4 (its amplification per step
|1 + z + z^2/2 + z^3/6 + z^4/24| below 1 at z = HEADROOM lambda h, room for a fit's stiffer variants), the car steps
at the longest of COARSE_TIMESTEP and INTERMEDIATE_TIMESTEP that allows it (one step per sample at 512 Hz instead of
two: |lambda| h = 0.15 on proton_x; three per sample at 256 Hz instead of four on a truck's segmented frame, whose
zig-zag chain modes, 590-1085 rad/s and damped, lie far above the band: truck_6x4's and tractor_4x2's car channels at
1.30 ms miss those at 0.98 ms by a mean TDDI of 7e-7); else, as a linkage car's bushings (2000 rad/s), at
MAX_TIMESTEP. A cause whose element is sized to
MAX_TIMESTEP or may be stiffer than a longer step resolves (``Cause.fine_step``: a top mount, a friction law's slope, a
stop in contact) keeps its model at MAX_TIMESTEP whatever is asked: a stop of 4e7 N/m at 2 ms misses the same stop at
1 ms by a held-out TDDI of 3.6e-3, ninety times a 2 % noise floor; the car without it, by 3.9e-9.
"""

from __future__ import annotations

import numpy as np

from rig.constants import ANALYSIS_BAND
from rig.sim.linearize import car_state_matrix
from rig.sim.simulate import Simulator
from rig.vehicle.mjcf import MAX_TIMESTEP, build_model, timestep_for
from rig.vehicle.vehicle_file import Vehicle

COARSE_TIMESTEP = 2e-3        # s
INTERMEDIATE_TIMESTEP = 1.5e-3  # s: tried next (three steps per sample at 256 Hz)
MODE_STEP = 0.5         # |lambda| h of a mode the band sees at most: RK4's error (|lambda| h)^5 / 120 = 2.6e-4 a step
REACH = 1.2             # modes up to this multiple of the band's top (rad/s) are resolved, faster ones only damped:
#                         the compared channels' band-pass (8th order, forward and back) takes one there down 19-fold
HEADROOM = 1.25         # faster modes stay damped at this multiple of their |lambda|: the recalibration's stiffest
#                         variant (rates x 1.25 over masses x 0.8)


def fit_timestep(vehicle: Vehicle, rate: float, band_top: float = ANALYSIS_BAND[1]) -> float:
    """The longest physics step (s) ``vehicle`` on measured posts may take for records at ``rate`` Hz compared up to
    ``band_top`` Hz (module docstring)."""
    sim = Simulator.create(build_model(vehicle, rate, "ideal", longest=COARSE_TIMESTEP))
    modes = np.linalg.eigvals(car_state_matrix(sim))
    seen = np.abs(modes) <= REACH * 2 * np.pi * band_top
    for longest in (COARSE_TIMESTEP, INTERMEDIATE_TIMESTEP):
        step, _ = timestep_for(rate, longest)
        z = HEADROOM * modes[~seen] * step
        damped = np.abs(1 + z + z**2 / 2 + z**3 / 6 + z**4 / 24) < 1
        if step > MAX_TIMESTEP and np.all(np.abs(modes[seen]) * step <= MODE_STEP) and np.all(damped):
            return longest
    return MAX_TIMESTEP
