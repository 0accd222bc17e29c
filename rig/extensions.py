"""Model extensions beyond the baseline ride model: one vehicle-file section per cause (DESIGN.md vocabulary).

Per-axle car causes take one sub-table per axle; car-level, rig and sensor causes one table::

    [bump_stop.front]            # contact gap m of compression from static ride height, rate N/m
    gap = 0.030
    rate = 150000.0
    [damper_asymmetry.rear]      # N s/m, replace [rear] damping in compression / rebound
    compression = 1800.0
    rebound = 3200.0
    [strut_friction.front]       # Coulomb friction force in the strut, N
    force = 120.0
    [progressive_spring.front]   # seed 003: F = K0 x + quadratic x^2 + cubic x^3, x compression from static
    quadratic = 40000.0          # N/m^2
    cubic = 0.0                  # N/m^3
    [anti_roll_bar.front]        # N/m of wheel force per m of left-right travel difference
    rate = 15000.0
    [top_mount_compliance.front] # N/m, bushing in series with the damper
    rate = 400000.0
    [mass_error]                 # payload: kg at (x forward, y left) m from the sprung CG
    mass = 80.0
    x = -0.9
    y = 0.2
    [sensor_gain]                # calibration factor per channel (measured = factor x true)
    "FL/sprung_acc" = 1.06
    [sensor_delay]               # time shift per channel, s (measured lags the truth)
    "RR/unsprung_acc" = 0.004

``tyre_damping`` is the ``tyre_damping`` key of [front]/[rear] and ``actuator_lag`` the [rig] keys
``servo_bandwidth`` and ``servo_delay`` (rig/rig_config.py). rig/model.py realises the car causes inside
mj_step (tendons, friction loss, sign-clamped actuators, an extra top-mount body, the sprung body's
inertia); rig/sensors.py applies the sensor causes to simulated channels, as a measurement chain does.
"""

from __future__ import annotations

from dataclasses import MISSING, dataclass, fields

AXLES = ("front", "rear")


@dataclass(frozen=True)
class BumpStop:
    gap: float   # m, compression from static ride height to contact
    rate: float  # N/m in contact
    LIMITS = {"gap": (0.0, 0.3), "rate": (1e3, 1e8)}


@dataclass(frozen=True)
class DamperAsymmetry:
    compression: float  # N s/m
    rebound: float      # N s/m
    LIMITS = {"compression": (0.0, 1e5), "rebound": (0.0, 1e5)}


@dataclass(frozen=True)
class StrutFriction:
    force: float  # N, Coulomb friction of the strut
    LIMITS = {"force": (0.0, 5e3)}


@dataclass(frozen=True)
class ProgressiveSpring:
    quadratic: float = 0.0  # N/m^2
    cubic: float = 0.0      # N/m^3
    LIMITS = {"quadratic": (-1e7, 1e7), "cubic": (-1e9, 1e9)}


@dataclass(frozen=True)
class AntiRollBar:
    rate: float  # N/m per m of left-right travel difference
    LIMITS = {"rate": (0.0, 5e5)}


@dataclass(frozen=True)
class TopMountCompliance:
    rate: float  # N/m of the bushing in series with the damper
    LIMITS = {"rate": (1e4, 2e6)}


@dataclass(frozen=True)
class MassError:
    mass: float     # kg added to the sprung mass (negative: lighter than the data sheet)
    x: float = 0.0  # m forward of the sprung CG
    y: float = 0.0  # m left of the sprung CG
    LIMITS = {"mass": (-500.0, 2000.0), "x": (-3.0, 3.0), "y": (-1.5, 1.5)}


#: cause name -> parameter class of its per-axle sub-tables
AXLE_EXTENSIONS = {"bump_stop": BumpStop, "damper_asymmetry": DamperAsymmetry, "strut_friction": StrutFriction,
                   "progressive_spring": ProgressiveSpring, "anti_roll_bar": AntiRollBar,
                   "top_mount_compliance": TopMountCompliance}
#: cause name -> parameter class of a single table
CAR_EXTENSIONS = {"mass_error": MassError}
#: cause name -> range of its per-channel values
CHANNEL_EXTENSIONS = {"sensor_gain": (0.2, 5.0), "sensor_delay": (-0.5, 0.5)}


def parse_extensions(data: dict, where: str, axles: tuple[str, ...]) -> dict[str, object]:
    """Read the extension sections of a parsed vehicle file: cause -> axle -> parameters, cause -> parameters
    (car-level) or cause -> channel -> value (sensors)."""
    result: dict[str, object] = {}
    for cause, kind in AXLE_EXTENSIONS.items():
        if cause not in data:
            continue
        section = data[cause]
        unknown_axles = sorted(set(section) - set(axles))
        if unknown_axles:
            raise ValueError(f"{where}: [{cause}] has sub-table(s) {', '.join(unknown_axles)}; "
                             f"expected {' or '.join(f'[{cause}.{a}]' for a in axles)}")
        if cause == "anti_roll_bar" and axles == ("front",):
            raise ValueError(f"{where}: [anti_roll_bar] needs a left and a right wheel; a quarter car has one")
        result[cause] = {axle: _parameters(kind, table, f"{where}: [{cause}.{axle}]") for axle, table in section.items()}
    for cause, kind in CAR_EXTENSIONS.items():
        if cause in data:
            result[cause] = _parameters(kind, data[cause], f"{where}: [{cause}]")
    for cause, (low, high) in CHANNEL_EXTENSIONS.items():
        if cause in data:
            values = {}
            for name, value in data[cause].items():
                if isinstance(value, bool) or not isinstance(value, (int, float)) or not low <= value <= high:
                    raise ValueError(f"{where}: [{cause}] '{name}' = {value!r} is outside {low:g}..{high:g}")
                values[name] = float(value)
            result[cause] = values
    return result


def _parameters(kind: type, table: dict, where: str) -> object:
    names = [f.name for f in fields(kind)]
    required = [f.name for f in fields(kind) if f.default is MISSING]
    unknown = sorted(set(table) - set(names))
    missing = [n for n in required if n not in table]
    if unknown or missing:
        raise ValueError(f"{where}: " + "; ".join(
            ([f"unknown key(s) {', '.join(unknown)}"] if unknown else []) + ([f"missing {', '.join(missing)}"] if missing else [])
        ) + f" (keys: {', '.join(names)})")
    for name, value in table.items():
        low, high = kind.LIMITS[name]
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not low <= value <= high:
            raise ValueError(f"{where}: {name} = {value!r} is outside the plausible range {low:g}..{high:g} (SI units)")
    return kind(**{n: float(v) for n, v in table.items()})


def to_tables(extensions: dict[str, object]) -> dict:
    """The extension sections as TOML-ready tables (inverse of parse_extensions)."""
    tables: dict = {}
    for cause, value in extensions.items():
        if cause in AXLE_EXTENSIONS:
            tables[cause] = {axle: {f.name: getattr(p, f.name) for f in fields(p)} for axle, p in value.items()}
        elif cause in CAR_EXTENSIONS:
            tables[cause] = {f.name: getattr(value, f.name) for f in fields(value)}
        else:
            tables[cause] = dict(value)
    return tables
