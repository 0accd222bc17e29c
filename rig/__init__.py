"""Virtual four-poster test rig: MuJoCo rig and car models, replay, track runs, validation and diagnosis.

The public surface, what a notebook imports (``from rig import load_vehicle, replay``); the stages behind
it are sub-packages (ARCHITECTURE.md): ``rig.io`` records, ``rig.signal`` analysis, ``rig.elements`` force
elements, ``rig.vehicle`` vehicle files and the MJCF model, ``rig.causes`` the cause registry, ``rig.road`` road
profiles, ``rig.sim`` simulation, ``rig.diagnosis`` validation and diagnosis, ``rig.report`` plots, reports and Rerun,
``rig.cli`` the command line, ``rig.envs`` the gymnasium environments, ``rig.sweep`` design sweeps. Names are
imported when first used, so ``import rig`` stays light: it imports gymnasium only, to register the environment
ids by name (about 0.2 s).
"""

from __future__ import annotations

import importlib

__version__ = "0.1.0"

#: public name -> module that defines it
_PUBLIC = {
    # records
    "Record": "rig.io.record", "RecordError": "rig.io.record", "read_record": "rig.io.files",
    "write_record": "rig.io.files", "CORNERS": "rig.io.channels", "channel": "rig.io.channels",
    "load_channel_map": "rig.io.channel_map",
    # vehicles and models
    "Vehicle": "rig.vehicle.vehicle_file", "VehicleError": "rig.vehicle.vehicle_file",
    "load_vehicle": "rig.vehicle.vehicle_file", "vehicle_to_toml": "rig.vehicle.vehicle_file",
    "build_model": "rig.vehicle.mjcf", "settled_mjcf": "rig.vehicle.statics",
    # causes
    "CAUSES": "rig.causes", "get_cause": "rig.causes",
    # roads and simulation
    "road_from_spec": "rig.road.roads", "iso8608_road": "rig.road.roads", "RoadProfile": "rig.road.roads",
    "replay": "rig.sim.replay", "replay_batch": "rig.sim.replay", "Replayer": "rig.sim.replay",
    "ReplayResult": "rig.sim.replay", "track_run": "rig.sim.track", "VirtualRig": "rig.sim.virtual_rig",
    "iri": "rig.sim.roughness",
    # sweeps
    "make_design": "rig.sweep.design", "SweepCase": "rig.sweep.evaluate", "run_sweep": "rig.sweep.run",
    # analysis
    "ANALYSIS_BAND": "rig.constants", "tddi": "rig.signal.metrics", "rms_error_pct": "rig.signal.metrics",
    "damage_ratio": "rig.signal.metrics", "weighted_rms": "rig.signal.comfort",
    "estimate_frf": "rig.signal.frf", "spectral_matrices": "rig.signal.frf",
    # validation and diagnosis
    "validate": "rig.diagnosis.core.validation", "ValidationReport": "rig.diagnosis.core.validation",
    "diagnose": "rig.diagnosis.rig_test.diagnose", "Diagnosis": "rig.diagnosis.rig_test.diagnose",
    "hidden_cause_records": "rig.diagnosis.rig_test.synthetic",
    "diagnose_track": "rig.diagnosis.track.track_diagnosis", "TrackDiagnosis": "rig.diagnosis.track.track_diagnosis",
    "identify_unbalance": "rig.diagnosis.track.unbalance",
    # presentation
    "write_validation": "rig.report.validation_report", "write_diagnosis": "rig.report.diagnosis_report",
    "write_track_diagnosis": "rig.report.track_report",
}

__all__ = sorted(_PUBLIC)


def __getattr__(name: str):
    if name not in _PUBLIC:
        raise AttributeError(f"module 'rig' has no attribute '{name}'")
    value = getattr(importlib.import_module(_PUBLIC[name]), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_PUBLIC))


def _register_environments() -> None:
    """Gymnasium ids of the contract (docs/contracts.md, rig/envs/): registered by name, the environments load
    when made."""
    from rig.envs import register_environments

    register_environments()


def _provide_causes() -> None:
    """The causes extend vehicles (rig/vehicle/extensions.py): the vehicle layer imports them when it first reads its
    extensions, named from here, the one place above every layer."""
    from rig.vehicle.extensions import provided_by

    provided_by("rig.causes")


_register_environments()
_provide_causes()
