"""``driveline_mounts``: a truck's engine and gearbox mounts are softer or stiffer, or damped otherwise, than
modelled.

    [driveline_mounts]       # each of the four mounts (rig/elements/mounted_body.py)
    stiffness = 1.0e6        # N/m
    damping = 4000.0         # N s/m

Realised on the driveline's mount tendons (``driveline/<mount>_mount``), in place of ``[driveline]``'s stiffness and
damping. Trucks with a driveline on mounts only.
"""

from __future__ import annotations

from rig.causes._mounts import MountsCause


class _DrivelineMounts(MountsCause):
    name = "driveline_mounts"
    body = "driveline"
    meaning = "the engine and gearbox mounts are softer, stiffer or damped otherwise than modelled"
    signature = "the frame's accelerations above the front axle resonate or absorb at another driveline bounce, " \
                "pitch and roll than the model's"


CAUSE = _DrivelineMounts()
