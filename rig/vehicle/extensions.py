"""What extends a vehicle beyond its baseline file: sections of their own in a vehicle file, parts of the MJCF model,
references set at static ride height. The causes (rig/causes/) are such extensions; they sit above the vehicle and
register here, so that the vehicle layer reads their sections and builds them without knowing them.

``Extension`` says what the vehicle asks of one (rig/causes/_base.py ``Cause`` provides it all). Providers are the
modules that register extensions when imported; the package root (rig/__init__.py), the one place that knows every
layer, names them (``provided_by``), and they are imported the first time the registry is read.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any, Protocol

if TYPE_CHECKING:
    import mujoco
    import numpy as np

    from rig.elements.frame import Frame
    from rig.vehicle.parts import Vehicle
    from rig.vehicle.suspensions.hardpoints import Kinematics


class Extension(Protocol):
    """What the vehicle layer asks of an extension of a vehicle (a cause)."""

    name: str
    order: int       # realisation order: lower first
    fine_step: bool  # its element needs the model's finest physics step (rig/vehicle/mjcf.py MAX_TIMESTEP)

    def has_section(self) -> bool: ...
    def parse(self, section: Any, where: str, axles: tuple[str, ...]) -> object: ...
    def to_table(self, value: object) -> dict: ...
    def present(self, vehicle: Vehicle) -> bool: ...
    def check(self, vehicle: Vehicle) -> None: ...
    def implausible(self, vehicle: Vehicle) -> str | None: ...
    def adjust_sprung(self, vehicle: Vehicle, mass: float, com: np.ndarray, inertia: np.ndarray
                      ) -> tuple[float, np.ndarray, np.ndarray]: ...
    def adjust_kinematics(self, vehicle: Vehicle, corner: str, kinematics: Kinematics) -> Kinematics: ...
    def adjust_frame(self, vehicle: Vehicle, frame: Frame | dict | None) -> Frame | dict | None: ...
    def build(self, car: mujoco.MjSpec, vehicle: Vehicle) -> None: ...
    def at_static_ride_height(self, model: mujoco.MjModel, data: mujoco.MjData, vehicle: Vehicle) -> None: ...


_REGISTERED: dict[str, Extension] = {}
_PROVIDERS: list[str] = []


def provided_by(module: str) -> None:
    """Name a module that registers extensions when imported (imported when the registry is first read)."""
    if module not in _PROVIDERS:
        _PROVIDERS.append(module)


def register(extension: Extension) -> None:
    """Add ``extension`` under its name (a later one of the same name replaces it)."""
    _REGISTERED[extension.name] = extension


def unregister(name: str) -> None:
    """Remove the extension called ``name`` (a test's throwaway cause)."""
    _REGISTERED.pop(name, None)


def extensions() -> dict[str, Extension]:
    """Name -> extension, alphabetical, once every provider is imported."""
    while _PROVIDERS:
        importlib.import_module(_PROVIDERS.pop(0))
    return dict(sorted(_REGISTERED.items()))


def in_build_order() -> list[Extension]:
    """Extensions in the order their realisations are applied to a model."""
    return sorted(extensions().values(), key=lambda e: (e.order, e.name))
