"""A monotube damper on a dynamometer, simulated from its hydraulics for the tests: a stand-in for a real damper's
record, written from the equations and not from the laws rig dyno fits.

The dyno's actuator moves the lower eye by x_a(t) (the displacement it records, extension positive); the damper's rod
end x_d follows through the rubber bushings of both eyes in series (k_b, c_b); the load cell reads the bushings'
force. Inside: a piston of area A_p on a rod of area A_r; the rebound chamber (annulus A_a = A_p - A_r, oil of
volume V_r, bulk modulus beta lowered by entrained air) is squeezed on extension; the compression chamber's oil is
backed by a floating piston on a gas charge (polytropic, n = 1.1) that takes the rod's volume. The piston valve
passes Q = G_bleed dp + G_blow max(|dp| - p_crack, 0) sgn(dp), each direction with its own bleed, blow-off
conductance and crack pressure (rebound stiffer), dp = p_r - p_c. The rod seal rubs: F_s tanh(v_d / v_s). With a rod
of mass m:

    m v_d' = k_b (x_a - x_d) + c_b (v_a - v_d) - F_d,   F_d = p_r A_a - p_c A_p + F_s tanh(v_d / v_s)
    p_r' = beta / (V_r0 - A_a x_d) (A_a v_d - Q)
    O_c' = Q,   p_c = p_g0 (V_g0 / (V_g0 + A_p x_d - (O_c - O_c0)))^n

(F_d positive resisting extension; the compression chamber holds O_c of oil in a volume that grows A_p x_d, the gas
takes the rest). SciPy's LSODA integrates it on a fine grid; the records are sampled at ``RATE`` with 0.5 % noise on
the displacement and 1 % on the force. The programme: sine tests at five speeds and triangle tests at three, 25 mm,
three cycles each (tests/dyno_cases.py ``motions``). Its lag: the bushings in series with the valve's low-speed
slope c_low give c_low / k_b = 22 ms in rebound, the aerated oil a few ms more.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from dyno_cases import FINE, motions
from scipy.integrate import solve_ivp

from rig.io.record import Record

RATE = 300.0  # Hz, as the real record the stand-in stands for
UNITS = {"damper/displacement": "m", "damper/force": "N"}


@dataclass(frozen=True)
class Monotube:
    """The damper and its mounting (SI)."""

    piston_area: float = 1.018e-3        # m^2: 36 mm bore
    rod_area: float = 1.54e-4            # m^2: 14 mm rod
    rebound_volume: float = 8.6e-5       # m^3 of oil in the rebound chamber at mid stroke
    bulk_modulus: float = 3.0e8          # Pa: oil with entrained air
    gas_pressure: float = 2.5e6          # Pa at mid stroke
    gas_volume: float = 1.2e-4           # m^3 at mid stroke
    polytropic: float = 1.1
    bleed_rebound: float = 1.25e-10      # m^3/(s Pa)
    bleed_compression: float = 2.5e-10
    blow_rebound: float = 4.0e-10
    blow_compression: float = 8.0e-10
    crack_rebound: float = 1.7e6         # Pa
    crack_compression: float = 0.9e6
    seal_friction: float = 60.0          # N
    seal_velocity: float = 0.005         # m/s
    bushing_rate: float = 2.7e5          # N/m: both eyes' rubber in series
    bushing_damping: float = 300.0       # N s/m
    rod_mass: float = 1.0                # kg

    @property
    def annulus(self) -> float:
        return self.piston_area - self.rod_area

    def flow(self, dp: float) -> float:
        """Oil through the piston valve (m^3/s), rebound chamber to compression chamber, at pressure drop ``dp``."""
        rebound = dp >= 0
        bleed = self.bleed_rebound if rebound else self.bleed_compression
        blow = self.blow_rebound if rebound else self.blow_compression
        crack = self.crack_rebound if rebound else self.crack_compression
        return bleed * dp + blow * max(abs(dp) - crack, 0.0) * np.sign(dp)

    def gas(self, x_d: float, oil: float) -> float:
        """The compression chamber's pressure (Pa) at rod extension ``x_d`` with ``oil`` m^3 more oil than at rest."""
        volume = self.gas_volume + self.piston_area * x_d - oil
        return self.gas_pressure * (self.gas_volume / max(volume, 1e-3 * self.gas_volume)) ** self.polytropic

    def derivative(self, t: float, s: np.ndarray, x_a, v_a) -> list[float]:
        x_d, v_d, p_r, oil = s
        p_c = self.gas(x_d, oil)
        q = self.flow(p_r - p_c)
        damper = p_r * self.annulus - p_c * self.piston_area + self.seal_friction * np.tanh(v_d / self.seal_velocity)
        bushing = self.bushing_rate * (x_a(t) - x_d) + self.bushing_damping * (v_a(t) - v_d)
        volume = self.rebound_volume - self.annulus * x_d
        return [v_d, (bushing - damper) / self.rod_mass, self.bulk_modulus / volume * (self.annulus * v_d - q), q]

    def start(self, x0: float) -> list[float]:
        """At rest at extension ``x0``: no flow, the chambers at the gas pressure, the bushings carrying it."""
        p = self.gas(x0, 0.0)
        force = p * self.annulus - p * self.piston_area
        return [x0 - force / self.bushing_rate, 0.0, p, 0.0]

    def load_cell(self, t: np.ndarray, x_a: np.ndarray, v_a: np.ndarray) -> np.ndarray:
        """The force the load cell reads (N, positive resisting extension) along the actuator's motion."""
        def position(s):
            return np.interp(s, t, x_a)

        def speed(s):
            return np.interp(s, t, v_a)

        solution = solve_ivp(self.derivative, (t[0], t[-1]), self.start(x_a[0]), method="LSODA", t_eval=t,
                             args=(position, speed), rtol=1e-7, atol=[1e-9, 1e-6, 1.0, 1e-12], max_step=5e-4)
        x_d, v_d = solution.y[0], solution.y[1]
        return self.bushing_rate * (x_a - x_d) + self.bushing_damping * (v_a - v_d)


def damper_records(damper: Monotube = Monotube(), seed: int = 0, rate: float = RATE) -> list[tuple[str, Record]]:
    """The programme's records (name, Record): the actuator's displacement with 0.5 % noise, the load cell's force
    with 1 %."""
    rng = np.random.default_rng(seed)
    out = []
    for name, t, x, v in motions(rate):
        if name.startswith("sine_0.05"):
            continue  # the slowest sine holds 19 s at 300 Hz and adds nothing the 0.1 m/s one does not
        force = damper.load_cell(t, x, v)[::FINE]
        x = x[::FINE]
        channels = {"damper/displacement": x + 0.005 * np.std(x) * rng.standard_normal(x.size),
                    "damper/force": force + 0.01 * np.std(force) * rng.standard_normal(x.size)}
        out.append((name, Record(rate, channels, dict(UNITS), {"test": "dyno", "motion": name})))
    return out
