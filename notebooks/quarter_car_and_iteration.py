# %% [markdown]
# # Worked example: the quarter car of seed 002 on the virtual rig
#
# A script in the "percent" notebook format (open it as a notebook with Jupytext or VS Code); the test
# suite runs it top to bottom (tests/test_notebooks.py). It checks the model against seed 002's transfer
# functions, then runs a short drive iteration and plots both.

# %%
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from rig.signal.filters import frf_of_periodic, periodic_multisine
from rig.sim.simulate import Simulator
from rig.vehicle import ride_model
from rig.vehicle.mjcf import build_model
from rig.vehicle.vehicle_file import load_vehicle

quarter = load_vehicle("proton_x_quarter")  # seed 002, Table 4.2, front left corner

# %% [markdown]
# ## 1. The sprung-mass transfer function, simulated and closed-form (seed 002 eq. 3.5)
# A multisine with exact periodicity gives a noise-free FRF from the last period.

# %%
rate, period = 512.0, 2048
lines = np.arange(2, 121)
frequency = lines * rate / period
sim = Simulator.create(build_model(quarter, rate, "ideal"))
road = periodic_multisine(frequency, rate, period, periods=4, rms=0.002)
out = sim.run(road[:, None])
omega = 2 * np.pi * frequency
simulated = frf_of_periodic(out["sprung_acc"][0, :, 0], road, period, lines) / -(omega**2)
closed_form, _ = ride_model.quarter_car_frf(quarter, "FL", frequency)
error = np.abs(np.abs(simulated) / np.abs(closed_form) - 1).max()
print(f"largest magnitude error 0.5-30 Hz: {100 * error:.4f} %")
assert error < 0.01

fig, ax = plt.subplots(figsize=(6, 3.5))
ax.loglog(frequency, np.abs(closed_form), "k", label="seed 002 eq. 3.5")
ax.loglog(frequency, np.abs(simulated), "C1--", label="MuJoCo rig model")
ax.set_xlabel("frequency [Hz]")
ax.set_ylabel("|X_b / X_r|")
ax.legend()
fig.savefig("quarter_car_frf.png", dpi=90)

# %% [markdown]
# ## 2. Three iterations of the drive for a track target (seed 002, section 4.1.1)

# %%
from controllers.rpc import DriveIteration, IterationSettings  # noqa: E402
from rig.road.roads import iso8608_road  # noqa: E402
from rig.sim.track import track_run  # noqa: E402

target = track_run(quarter, iso8608_road("B", 200.0, seed=1), 20.0, duration=6.0).record
job = DriveIteration(quarter, target, ["FL/sprung_acc", "FL/unsprung_acc"], "quarter_iteration",
                     IterationSettings(iterations=3, target_error_pct=0.0))
result = job.run(progress=False)
errors = [h.worst_rms_error_pct for h in result.history]
print("worst channel RMS error per iteration [%]:", [round(e, 2) for e in errors])
assert errors[-1] < errors[0]
