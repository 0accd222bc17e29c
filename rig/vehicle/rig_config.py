"""Four-poster rig parameters: the one place where their defaults live.

Defaults follow Nurhadiyanto's thesis (section 4.1.4): MTS Series 248 actuators rated
50 kN with 150 mm stroke (±75 mm), 340 l/min three-stage valves, 300 mm wheel pans. Values marked
ASSUMPTION are not in the thesis. A vehicle file may override any of them in a ``[rig]`` section.

Post model (see rig/vehicle/mjcf.py): drive -> transport delay -> first-order lag (``servo_bandwidth``) ->
position loop (natural frequency ``loop_frequency``, damping ratio ``loop_damping``) acting on the post's
moving mass, with a static-load feed-forward; the loop's finite stiffness makes the achieved displacement
depend on the tyre load, as on a real rig.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields


@dataclass(frozen=True)
class RigConfig:
    stroke: float = 0.075                 # m, half of the 150 mm total stroke (Nurhadiyanto's thesis)
    force_limit: float = 50e3             # N, actuator rating (Nurhadiyanto's thesis)
    velocity_limit: float = 2.38          # m/s, DERIVED: 340 l/min / piston area (50 kN at an ASSUMED 21 MPa)
    post_mass: float = 30.0               # kg, piston rod + wheel pan, ASSUMPTION
    pan_diameter: float = 0.30            # m, Nurhadiyanto's thesis (geometry only)
    servo_bandwidth: float = 50.0         # Hz, -3 dB of the first-order command lag, ASSUMPTION
    servo_delay: float = 0.002            # s, transport delay of valve + controller, ASSUMPTION
    loop_frequency: float = 150.0         # Hz, position-loop natural frequency on the post mass, ASSUMPTION
    loop_damping: float = 0.7             # -, position-loop damping ratio, ASSUMPTION

    @property
    def loop_stiffness(self) -> float:
        """Position-loop gain in N/m: post_mass * (2 pi loop_frequency)^2."""
        return self.post_mass * (2 * math.pi * self.loop_frequency) ** 2

    @property
    def loop_damping_coefficient(self) -> float:
        """Position-loop velocity gain in N s/m."""
        return 2 * self.loop_damping * self.post_mass * 2 * math.pi * self.loop_frequency

    @property
    def lag_time_constant(self) -> float:
        """Time constant of the command lag in s (0 for an infinite bandwidth)."""
        return 0.0 if math.isinf(self.servo_bandwidth) else 1.0 / (2 * math.pi * self.servo_bandwidth)

    @classmethod
    def from_table(cls, table: dict, where: str) -> RigConfig:
        """Build from a ``[rig]`` table, refusing unknown keys and non-positive values."""
        known = {f.name for f in fields(cls)}
        unknown = sorted(set(table) - known)
        if unknown:
            raise ValueError(f"{where}: unknown key(s) {', '.join(unknown)} in [rig] "
                             f"(known: {', '.join(sorted(known))})")
        for key, value in table.items():
            if not isinstance(value, (int, float)) or isinstance(value, bool) or not value >= 0:
                raise ValueError(f"{where}: [rig] {key} must be a non-negative number, got {value!r}")
        return cls(**{k: float(v) for k, v in table.items()})
