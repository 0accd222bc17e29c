"""Gymnasium environments of the rig and the car (ids in docs/contracts.md), registered by ``import rig``.

Registration names the classes by string, so nothing here is imported until an environment is made.
"""

from __future__ import annotations

#: id -> (module, single env class, vector env class)
ENVIRONMENTS = {
    "FourPoster/ActiveSuspension-v0": ("rig.envs.suspension", "ActiveSuspensionEnv", "ActiveSuspensionVectorEnv"),
    "FourPoster/SemiActiveSuspension-v0": ("rig.envs.suspension", "SemiActiveSuspensionEnv",
                                           "SemiActiveSuspensionVectorEnv"),
    "FourPoster/DriveTracking-v0": ("rig.envs.drive_tracking", "DriveTrackingEnv", "DriveTrackingVectorEnv"),
}


def register_environments() -> None:
    """Register every id with gymnasium (entry points as strings: cheap; a second call changes nothing)."""
    from gymnasium.envs.registration import register, registry

    for env_id, (module, single, vector) in ENVIRONMENTS.items():
        if env_id not in registry:
            register(id=env_id, entry_point=f"{module}:{single}", vector_entry_point=f"{module}:{vector}")
