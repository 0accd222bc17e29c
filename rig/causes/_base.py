"""What a cause of the vocabulary in docs/contracts.md is: one object per cause module, read by everything that lists
or dispatches causes (vehicle files, the MJCF builder, static ride height, the measurement chain, the
diagnosis, the synthetic tests and the reports).

A cause says, in one place:
- its name, subsystem (``car``, ``rig`` or ``sensor``), meaning and signature (report text);
- its parameters with units and bounds, and where it lives in a vehicle file: a section of its own per
  axle (``[bump_stop.front]``), per car (``[mass_error]``), per channel (``[sensor_gain]``), or keys of a
  baseline section (``tyre_damping`` in ``[front]``/``[rear]``, ``actuator_lag`` in ``[rig]``);
- its MuJoCo realisation, inside ``mj_step`` (hooks on the car's MjSpec, on the sprung body's inertia and
  on the settled model), or, for sensors, its measurement-chain law;
- its fit: parameters with an initial guess, bounds and how a value changes a vehicle;
- a random instance of itself, for synthetic tests with a hidden cause.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from dataclasses import dataclass, fields
from enum import StrEnum
from typing import TYPE_CHECKING, Any, ClassVar, NamedTuple

import numpy as np

from rig.elements.parameters import parse_values
from rig.io.channels import corner_axle

if TYPE_CHECKING:
    import mujoco

    from rig.elements.frame import Frame
    from rig.vehicle.suspensions.hardpoints import Kinematics
    from rig.vehicle.vehicle_file import Vehicle

AXLES = ("front", "rear")


class Shape(StrEnum):
    """What the force laws measured from the data can show (rig/diagnosis/rig_test/force_laws.py emits them; a cause's
    ``evidence`` lists those it explains): shapes of a corner's law, then departures from the data sheet."""

    STIFFENS_IN_COMPRESSION = "stiffens in compression"
    STIFFENS_IN_REBOUND = "stiffens in rebound"
    STIFFENS_BOTH_WAYS = "stiffens both ways"
    SOFTENS_IN_COMPRESSION = "softens in compression"
    SOFTENS_IN_REBOUND = "softens in rebound"
    ASYMMETRIC_DAMPING = "asymmetric damping"
    PROGRESSIVE_DAMPING = "progressive damping"
    DIGRESSIVE_DAMPING = "digressive damping"
    FRICTION_STEP = "friction step"
    FORCE_LAGS = "force lags the rate"
    COUPLED = "coupled to the other side"
    SUSPENSION_RATE = "suspension rate"
    DAMPING = "damping"
    TYRE_RATE = "tyre rate"
    TYRE_DAMPING = "tyre damping"
    SPRUNG_MASS = "sprung mass"
    CG_X = "CG x"
    CG_Y = "CG y"
    PITCH_INERTIA = "pitch inertia"
    ROLL_INERTIA = "roll inertia"


#: the departures of the sprung body: the recalibration's factors can take them up elsewhere (module docstring of
#: rig/diagnosis/rig_test/selection.py)
BODY_SHAPES = frozenset({Shape.SPRUNG_MASS, Shape.CG_X, Shape.CG_Y, Shape.PITCH_INERTIA, Shape.ROLL_INERTIA})


class ParameterSpec(NamedTuple):
    """A vehicle-file key of a cause: the one schema of cause parameters (``rig causes`` lists them)."""

    key: str
    unit: str      # SI
    low: float     # plausible range (nan for a choice)
    high: float
    meaning: str


@dataclass(frozen=True)
class FitParameter:
    """A parameter the diagnosis fits: its initial guess, bounds, and ``apply(vehicle, value) -> vehicle``;
    ``unit`` (SI, '-' for a factor or share); ``typical`` (its size, for the optimiser's scaling, and the car
    fit's finite-difference step is 1 % of it; default: the bounds' span) and ``relative_step`` (of the post
    fit's finite differences, relative to the value; default: 1 %)."""

    name: str
    initial: float
    low: float
    high: float
    apply: Callable[[Vehicle, float], Vehicle]
    typical: float | None = None
    relative_step: float | None = None
    unit: str = "-"


CAR_SPRUNG_MASS = 300.0  # kg: the car causes' fit bounds in kg, N and N/m are a car's, and shrink below this


def car_scale(vehicle: Vehicle) -> float:
    """1 for a car or a truck; for a lighter vehicle (a lab bench of a few kg) its sprung mass over CAR_SPRUNG_MASS,
    the factor by which a cause's fit bounds in kg, N and N/m shrink so that its model stays one the vehicle can
    carry (a payload or a secondary mass no heavier than the body, a mount mode as fast as a car's)."""
    return min(1.0, vehicle.sprung_mass / CAR_SPRUNG_MASS)


def with_extension(vehicle: Vehicle, cause: str, value: object) -> Vehicle:
    """``vehicle`` with the extension ``cause`` set to ``value``."""
    return dataclasses.replace(vehicle, extensions={**vehicle.extensions, cause: value})


def axles_of(vehicle: Vehicle) -> tuple[str, ...]:
    """The vehicle's axle names: ``front``, ``rear`` on a car, ``front`` on a quarter car; a truck's (contracts.md)."""
    return vehicle.axle_names


def scale_axle(vehicle: Vehicle, axle: str, **factors: float) -> Vehicle:
    """``vehicle`` with keys of its axle ``axle`` (``[front]``, ``[rear]``, a truck's ``[[axles]]``) multiplied."""
    current = vehicle.axle_named(axle)
    return vehicle.with_axle(axle, dataclasses.replace(current, **{k: getattr(current, k) * f
                                                                   for k, f in factors.items()}))


def set_axle(vehicle: Vehicle, axle: str, **values: float) -> Vehicle:
    """``vehicle`` with keys of its axle ``axle`` set."""
    return vehicle.with_axle(axle, dataclasses.replace(vehicle.axle_named(axle), **values))


class Cause:
    """Base of every cause; a cause module holds one instance, ``CAUSE``. Hooks default to doing nothing."""

    name: ClassVar[str]
    subsystem: ClassVar[str]
    meaning: ClassVar[str]    # one line: what is physically different
    signature: ClassVar[str]  # one line: how it shows in the evidence
    order: ClassVar[int] = 100  # realisation order: lower first (a top mount re-routes the damper first)
    generic: ClassVar[bool] = False  # a generic element extends a model the vocabulary cannot explain; not a name
    learned: ClassVar[bool] = False  # fitted on the corner laws learned from the record (hints["neuro_laws"])
    damper_line: ClassVar[str] = ""  # on a damper's line: 'law' (its own force law) or 'mount' (friction, top mount)
    damper_part: ClassVar[str] = ""  # what of a dynamometer's damper law its section holds in a vehicle file
    #                                  (rig/diagnosis/dyno/damper_in_vehicle.py): 'quadratic', 'slopes', 'rate_ramps',
    #                                  'series', 'friction' or 'preload'
    evidence: ClassVar[tuple[Shape, ...]] = ()  # force-law shapes and departures it explains
    seen_on: ClassVar[str] = "rig"  # the test that shows it: 'rig', 'track' (a rolling wheel's unbalance), 'kc'
    layouts: ClassVar[tuple[str, ...]] = ("full", "quarter", "truck")  # vehicle layouts the cause applies to
    needs: ClassVar[tuple[str, ...]] = ()  # input quantities a record must carry to show it (``active_force``)
    owns: ClassVar[tuple[str, ...]] = ()  # linear parameters (fitting.linear_parameters) it takes over where named
    fine_step: ClassVar[bool] = False  # its element is sized to MAX_TIMESTEP (rig/vehicle/mjcf.py) or may be stiffer
    #                                  than a longer step resolves: a model with it steps at no more than that
    linear: ClassVar[bool] = False  # it keeps a linear car linear: fitted on the car's frequency response
    #                               (rig/diagnosis/rig_test/frequency_fit.py) where the car stays linear on the record
    keyed_by_channel: ClassVar[bool] = False  # its section maps channel names to values, which ``measure`` and
    #                                         ``inputs`` apply (a sensor's fault, an input channel's)
    separated_by: ClassVar[str] = ""  # the test that tells it from what else the records allow (report text)
    input_quantities: ClassVar[tuple[str, ...]] = ()  # input channels whose calibration it holds (a post's
    #                                                   displacement, an actuator's force): the input chain's faults
    measured_start: ClassVar[bool] = False  # its fit starts where the data put it (rig_test/modes.py), a departure
    #                                       the recalibration bends the linear factors to absorb: fitted jointly from
    #                                       the data sheet's linear values, as a body the force laws measured

    def shows_in(self, layout: str, quantities: set[str]) -> bool:
        """Whether a test of a vehicle of ``layout`` whose record carries ``quantities`` (``actuator_disp``,
        ``active_force``...) can show this cause."""
        return layout in self.layouts and set(self.needs) <= quantities

    # ---- vehicle file -------------------------------------------------------------------------------
    def has_section(self) -> bool:
        """Whether the cause has a vehicle-file section of its own, named after it."""
        return True

    def parse(self, section: Any, where: str, axles: tuple[str, ...]) -> object:
        """The extension's value from its vehicle-file section; ValueError names what is wrong."""
        raise NotImplementedError

    def to_table(self, value: object) -> dict:
        """The section as a TOML-ready table (inverse of ``parse``)."""
        raise NotImplementedError

    def present(self, vehicle: Vehicle) -> bool:
        return self.name in vehicle.extensions

    def check(self, vehicle: Vehicle) -> None:
        """Refuse (ValueError) a vehicle the cause's section cannot apply to: another layout, a part it lacks."""
        if vehicle.layout not in self.layouts:
            raise ValueError(f"{vehicle.source}: [{self.name}] applies to layout {' or '.join(self.layouts)}, not "
                             f"{vehicle.layout!r}")

    def implausible(self, vehicle: Vehicle) -> str | None:
        """Why the cause's values in ``vehicle`` lie outside their plausible ranges (a fit's trial beyond its bounds:
        a negative bandwidth, a delay longer than the model keeps), or None; the model is then not built."""
        return None

    def parameters(self) -> list[ParameterSpec]:
        """Each vehicle-file key of the cause."""
        return [ParameterSpec(f.name, f.metadata["unit"], f.metadata["low"], f.metadata["high"], f.metadata["meaning"])
                for f in fields(self.values)]

    def copy(self, source: Vehicle, target: Vehicle) -> Vehicle:
        """``target`` with this cause as ``source`` has it (to combine two fitted causes)."""
        return with_extension(target, self.name, source.extensions[self.name])

    # ---- MuJoCo realisation (car) and measurement chain (sensors) -----------------------------------
    def adjust_sprung(self, vehicle: Vehicle, mass: float, com: np.ndarray, inertia: np.ndarray
                      ) -> tuple[float, np.ndarray, np.ndarray]:
        """The sprung body's mass (kg), CG offset (m) and principal inertia (kg m^2) with this cause."""
        return mass, com, inertia

    def adjust_kinematics(self, vehicle: Vehicle, corner: str, kinematics: Kinematics) -> Kinematics:
        """A corner's linkage (its axle's table: hardpoints, bushings) as this cause changes it
        (rig/vehicle/suspensions/)."""
        return kinematics

    def adjust_frame(self, vehicle: Vehicle, frame: Frame | dict | None) -> Frame | dict | None:
        """A truck's frame (rig/elements/frame.py; None: rigid) as this cause changes it (a table of ``[frame]``'s
        keys is read as one)."""
        return frame

    def build(self, car: mujoco.MjSpec, vehicle: Vehicle) -> None:
        """Add or change elements of the car's MjSpec (the baseline car is built; called when present)."""

    def at_static_ride_height(self, model: mujoco.MjModel, data: mujoco.MjData, vehicle: Vehicle) -> None:
        """Set references that are defined from static ride height (``data`` holds the equilibrium)."""

    def measure(self, channels: dict[str, np.ndarray], value: object, rate: float) -> dict[str, np.ndarray]:
        """Channels as the measurement chain reports them with this cause (sensor causes)."""
        return channels

    def inputs(self, channels: dict[str, np.ndarray], value: object) -> dict[str, np.ndarray]:
        """A record's input channels as the posts and actuators really moved, given what the record says (a fault of
        an input channel's calibration: ``input_gain``)."""
        return channels

    # ---- diagnosis and synthetic tests --------------------------------------------------------------
    def fit_parameters(self, vehicle: Vehicle, hints: dict | None = None) -> list[FitParameter]:
        """Parameters the diagnosis fits for this cause (car and rig causes). ``hints``, for initial guesses
        (bounds never depend on them): where the fit data's residual lives (``locate_residual``: ``peak_hz``,
        ``band_hz``, ``channels``), and what the data show without a model form (rig/diagnosis/rig_test/force_laws.py):
        ``measured_laws`` (per axle) and ``body`` (mass properties, or None); where the body's modes lie, measured
        and modelled (``pattern_peaks``, rig/diagnosis/rig_test/modes.py)."""
        return []

    def refined_parameters(self, vehicle: Vehicle, hints: dict | None = None) -> list[FitParameter]:
        """A richer form of the cause, fitted when its plain form explains too little of what it names (for
        example a smooth friction law, a payload's own inertia); empty when the cause has none. The
        parameters of ``fit_parameters`` come first, in their order."""
        return []

    def indistinct(self, params: dict[str, float]) -> str | None:
        """Why fitted values ``params`` cannot be told from no effect by any record (the diagnosis then does not name
        the cause), or None."""
        return None

    def estimate(self, measured: np.ndarray, simulated: np.ndarray, names: list[str], rate: float) -> dict[str, float]:
        """Per-channel values of a sensor cause, from measured and simulated channels (samples x channels);
        only channels whose value matters are returned."""
        return {}

    def hidden(self, truth: Vehicle, rng: np.random.Generator) -> Vehicle:
        """``truth`` with a random instance of this cause, for synthetic tests of the diagnosis."""
        raise NotImplementedError


class AxleCause(Cause):
    """A cause with one sub-table per axle, ``[<name>.front]``, parameters from the dataclass ``values``."""

    values: ClassVar[type]
    needs_both_sides: ClassVar[bool] = False  # e.g. an anti-roll bar: refused on a quarter car

    def parse(self, section: Any, where: str, axles: tuple[str, ...]) -> dict[str, object]:
        if not isinstance(section, dict):
            raise ValueError(f"{where}: [{self.name}] must hold sub-tables "
                             f"{', '.join(f'[{self.name}.{a}]' for a in axles)}")
        unknown = sorted(set(section) - set(axles))
        if unknown:
            raise ValueError(f"{where}: [{self.name}] has sub-table(s) {', '.join(unknown)}; "
                             f"expected {' or '.join(f'[{self.name}.{a}]' for a in axles)}")
        if self.needs_both_sides and len(axles) == 1:
            raise ValueError(f"{where}: [{self.name}] needs a left and a right wheel; a quarter car has one")
        return {axle: parse_values(self.values, table, f"{where}: [{self.name}.{axle}]")
                for axle, table in section.items()}

    def to_table(self, value: dict) -> dict:
        return {axle: dataclasses.asdict(p) for axle, p in value.items()}

    def implausible(self, vehicle: Vehicle) -> str | None:
        return refusal(lambda: self.parse(self.to_table(vehicle.extensions[self.name]), vehicle.source,
                                           axles_of(vehicle)))

    def build(self, car: mujoco.MjSpec, vehicle: Vehicle) -> None:
        for corner in vehicle.corners:
            value = self.at(vehicle, corner)
            if value is not None:
                self.build_corner(car, corner, value)

    def build_corner(self, car: mujoco.MjSpec, corner: str, value: object) -> None:
        """Realise the cause at one corner that has it (``value``: its parameters there)."""

    def at_static_ride_height(self, model: mujoco.MjModel, data: mujoco.MjData, vehicle: Vehicle) -> None:
        for corner in vehicle.corners:
            value = self.at(vehicle, corner)
            if value is not None:
                self.at_static_corner(model, data, corner, value)

    def at_static_corner(self, model: mujoco.MjModel, data: mujoco.MjData, corner: str, value: object) -> None:
        """Set one corner's references from static ride height."""

    def at(self, vehicle: Vehicle, corner: str) -> object | None:
        """The parameters at ``corner``, or None where the vehicle does not have the cause."""
        return vehicle.extensions.get(self.name, {}).get(corner_axle(corner))

    def damper_value(self, old: object | None, *numbers: object) -> object | None:
        """Its parameters at an axle holding ``numbers`` of a dynamometer's damper law (``damper_part``; in the order
        of ``values``' fields), ``old`` those the axle had (None); None where nothing is left (no ``numbers``)."""
        return self.values(*numbers) if numbers else None

    def on_damper_alone(self, value: object) -> object | None:
        """What of its parameters ``value`` at an axle acts on the damper alone, as a dynamometer holds it (the
        damper's line without springs, stops or tyre: rig/sim/dyno.py); None where nothing does."""
        return value

    def on_every_axle(self, vehicle: Vehicle, make: Callable[[str], object],
                      axles: tuple[str, ...] | None = None) -> Vehicle:
        """``vehicle`` with this cause on every axle (or those of ``axles``), ``make(axle)`` giving its parameters."""
        return with_extension(vehicle, self.name, {a: make(a) for a in (axles or axles_of(vehicle))})

    def on_axle(self, vehicle: Vehicle, axle: str, value: object) -> Vehicle:
        """``vehicle`` with this cause's parameters on one axle set (others kept)."""
        return with_extension(vehicle, self.name, {**vehicle.extensions.get(self.name, {}), axle: value})


class CarCause(Cause):
    """A cause with a single table ``[<name>]``, parameters from the dataclass ``values``."""

    values: ClassVar[type]

    def parse(self, section: Any, where: str, axles: tuple[str, ...]) -> object:
        return parse_values(self.values, section, f"{where}: [{self.name}]")

    def to_table(self, value: object) -> dict:
        return dataclasses.asdict(value)

    def implausible(self, vehicle: Vehicle) -> str | None:
        return refusal(lambda: self.parse(self.to_table(vehicle.extensions[self.name]), vehicle.source,
                                          axles_of(vehicle)))

    def field_setter(self, key: str, default: object) -> Callable[[Vehicle, float], Vehicle]:
        """``apply`` of a FitParameter that sets one field of the cause's parameters (``default`` where the
        vehicle does not have the cause yet)."""
        def apply(vehicle: Vehicle, value: float) -> Vehicle:
            current = vehicle.extensions.get(self.name, default)
            return with_extension(vehicle, self.name, dataclasses.replace(current, **{key: value}))
        return apply


class ChannelCause(Cause):
    """A sensor cause: one value per channel in ``[<name>]``, within ``bounds`` (``unit``); ``neutral`` is the
    value of a channel without the fault, ``min_effect`` the departure from it worth naming."""

    subsystem = "sensor"
    keyed_by_channel = True
    unit: ClassVar[str]
    bounds: ClassVar[tuple[float, float]]
    signed: ClassVar[bool] = False  # a value's size lies within ``bounds`` on either side of zero (a factor that may
    #                                 reverse a channel's polarity)
    typical: ClassVar[float]  # size of a value's error, for fitting
    neutral: ClassVar[float]
    min_effect: ClassVar[float]

    def channel_values(self, measured: np.ndarray, simulated: np.ndarray, rate: float) -> np.ndarray:
        """The value of every channel (samples x channels) that best maps the model's channel onto the measured."""
        raise NotImplementedError

    def response(self, value: float, frequency: np.ndarray) -> np.ndarray:
        """What the fault at ``value`` makes of a channel's response at ``frequency`` (Hz): measured over true."""
        raise NotImplementedError

    def estimate(self, measured, simulated, names, rate):
        values = self.channel_values(measured, simulated, rate)
        return {n: float(v) for n, v in zip(names, values) if abs(v - self.neutral) >= self.min_effect}

    def group_parameters(self, groups: dict[str, tuple[tuple[str, ...], float]]) -> list[FitParameter]:
        """Groups of channels (label -> (channels, value)) as parameters to fit (jointly with the car's): a
        group's channels share one value, as a DAQ module shares its clock or its range."""
        def apply(vehicle, value, names):
            return with_extension(vehicle, self.name, {**vehicle.extensions.get(self.name, {}),
                                                       **dict.fromkeys(names, float(value))})
        return [FitParameter(label, value, *self.fit_bounds(value), lambda v, x, n=names: apply(v, x, n),
                             typical=self.typical, unit=self.unit)
                for label, (names, value) in groups.items()]

    def fit_bounds(self, value: float) -> tuple[float, float]:
        """The bounds a value is fitted within: ``bounds``, or for a signed cause their side of zero that ``value``
        is on (a polarity found stays found)."""
        low, high = self.bounds
        return (-high, -low) if self.signed and value < 0 else (low, high)

    def parse(self, section: Any, where: str, axles: tuple[str, ...]) -> dict[str, float]:
        low, high = self.bounds
        values = {}
        for name, value in section.items():
            number = not isinstance(value, bool) and isinstance(value, (int, float))
            if not number or not low <= (abs(value) if self.signed else value) <= high:
                sides = f"±{low:g}..{high:g} (negative: polarity reversed)" if self.signed else f"{low:g}..{high:g}"
                raise ValueError(f"{where}: [{self.name}] '{name}' = {value!r} is outside {sides}")
            values[name] = float(value)
        return values

    def implausible(self, vehicle: Vehicle) -> str | None:
        return refusal(lambda: self.parse(vehicle.extensions[self.name], vehicle.source, ()))

    def to_table(self, value: dict) -> dict:
        return dict(value)

    def parameters(self) -> list[ParameterSpec]:
        low, high = self.bounds
        if self.signed:
            return [ParameterSpec('"<corner>/<quantity>"', self.unit, -high, high,
                                  f"per channel; size {low:g}..{high:g}, negative: polarity reversed")]
        return [ParameterSpec('"<corner>/<quantity>"', self.unit, low, high, "per channel")]


def refuse_factor(value: object, where: str) -> None:
    """Refuse (ValueError) a calibration factor whose size is outside 0.2..5 (negative: a polarity reversed)."""
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not 0.2 <= abs(value) <= 5.0:
        raise ValueError(f"{where} = {value!r}: a factor's size must be 0.2..5 (negative: polarity reversed)")


def refusal(parse: Callable[[], object]) -> str | None:
    """The ValueError ``parse()`` refuses with, as text, or None."""
    try:
        parse()
    except ValueError as err:
        return str(err)
    return None
