"""``cab_mounts``: a truck cab's mounts are softer or stiffer, or damped otherwise, than modelled.

    [cab_mounts]             # each of the four mounts (rig/elements/mounted_body.py)
    stiffness = 2.0e4        # N/m
    damping = 1200.0         # N s/m

Realised on the cab's mount tendons (``cab/<mount>_mount``), in place of ``[cab]``'s stiffness and damping (a cab on
air springs: linear about their force at design height; ``cab_air_spring`` changes their law). Trucks with a cab only.
"""

from __future__ import annotations

from rig.causes._mounts import MountsCause


class _CabMounts(MountsCause):
    name = "cab_mounts"
    body = "cab"
    meaning = "the cab's mounts are softer, stiffer or damped otherwise than modelled"
    signature = "the seat and cab accelerations resonate at another cab bounce, pitch and roll than the model's"


CAUSE = _CabMounts()
