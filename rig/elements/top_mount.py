"""A top mount: the bushing a damper acts through, on a small body of its own between damper and sprung body. The body's
mass is the least that keeps the damper's pole on the mount, c / m, RK4-stable at the largest physics step with room
for a rebound coefficient 1.6 times the axle's (rig/causes/top_mount_compliance.py realises the mount and says why)."""

from rig.elements.tendons import PHYSICS_STEP

MOUNT_STEPS = 0.6     # the mount's mass is this many damper coefficients times the physics step (c h / m = 1.67)
MIN_MOUNT_MASS = 0.2  # kg


def mount_mass(damping: float) -> float:
    """The top mount's mass (kg) behind a damper of ``damping`` N s/m."""
    return max(MIN_MOUNT_MASS, MOUNT_STEPS * damping * PHYSICS_STEP)
