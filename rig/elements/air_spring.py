"""Air springs: F = p A(x) with a polytropic gas, p V^n constant, no level valve during a test.

With x the spring's compression from design height (m), the effective area A(x) = A0 + A' x and the volume
V(x) = V0 - A0 x - A' x^2 / 2 (dV = -A dx), the gauge force is

    F(x) = ((p0 + p_atm) (V0 / V(x))^n - p_atm) A(x)                      (``AirSpring.force``)

with p0 the gauge pressure at design height and n between 1 (isothermal) and 1.4 (adiabatic). MuJoCo has no
native element for this law; it is realised as a cubic in x: a constant force (a ``general`` actuator with a
constant bias) plus MuJoCo's polynomial tendon stiffness f(y) = a y + b y^2 + c y^3 about the design length. The
cubic is the least-squares fit of the law on Chebyshev nodes over +-``FIT_SPAN``; over +-60 mm its error is 0.17 %
of the force for tractor_4x2's springs and 0.05 % for truck_6x4's (``AirSpring.cubic_error`` says it for any spring;
tests/test_truck_elements.py checks the realised force against the law). Beyond the span the cubic departs from it.

A force element (rig/elements/): the ``beam_air`` suspension type builds from it and the ``air_spring_law`` cause
changes it.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property
from typing import ClassVar

import numpy as np

from rig.elements.parameters import param
from rig.elements.tendons import FORCE_CAP

ATMOSPHERE = 101325.0  # Pa
FIT_SPAN = 0.1  # m: the cubic is fitted over +-this compression
_NODES = 64


@dataclass(frozen=True)
class AirSpring:
    """One air spring at design height (gauge pressure, effective area and volume there)."""

    fit_span: ClassVar[float] = FIT_SPAN  # m: the realised cubic is fitted over +-this compression

    area: float = field(metadata=param("m^2", 1e-3, 0.5, "effective area at design height"))
    volume: float = field(metadata=param("m^3", 1e-4, 1.0, "gas volume at design height (bellows and reservoir)"))
    pressure: float = field(metadata=param("Pa", 1e4, 2e6, "gauge pressure at design height"))
    polytropic_index: float = field(default=1.4, metadata=param("-", 1.0, 1.4, "n of p V^n = const (1 isothermal, "
                                                                                 "1.4 adiabatic)"))
    area_slope: float = field(default=0.0, metadata=param("m^2/m", -2.0, 2.0, "change of the effective area "
                                                                             "per m of compression"))

    def volume_at(self, x: np.ndarray) -> np.ndarray:
        """Gas volume (m^3) at compression ``x`` (m)."""
        return self.volume - self.area * x - 0.5 * self.area_slope * np.square(x)

    def force(self, x: np.ndarray) -> np.ndarray:
        """The law's force (N, pushing) at compression ``x`` (m); NaN where the gas would have no volume left."""
        x = np.asarray(x, float)
        volume = self.volume_at(x)
        ratio = np.where(volume > 0, self.volume / np.where(volume > 0, volume, 1.0), np.nan)
        absolute = (self.pressure + ATMOSPHERE) * ratio ** self.polytropic_index
        return (absolute - ATMOSPHERE) * (self.area + self.area_slope * x)

    @property
    def rate(self) -> float:
        """dF/dx at design height (N/m): n (p0 + p_atm) A0^2 / V0 + p0 A'."""
        return (self.polytropic_index * (self.pressure + ATMOSPHERE) * self.area**2 / self.volume
                + self.pressure * self.area_slope)

    @cached_property
    def cubic(self) -> np.ndarray:
        """[F0, k1, k2, k3]: F ~ F0 + k1 x + k2 x^2 + k3 x^3, least squares on Chebyshev nodes over +-``fit_span``."""
        x = self.fit_span * np.cos(np.pi * (np.arange(_NODES) + 0.5) / _NODES)
        return np.polynomial.polynomial.polyfit(x, self.force(x), 3)

    def cubic_force(self, x: np.ndarray) -> np.ndarray:
        """The realised (cubic) force (N) at compression ``x`` (m)."""
        return np.polynomial.polynomial.polyval(np.asarray(x, float), self.cubic)

    def cubic_error(self, span: float = 0.06) -> float:
        """Largest |cubic - law| over +-``span`` m, relative to the law's force there."""
        x = np.linspace(-span, span, 601)
        return float(np.max(np.abs(self.cubic_force(x) - self.force(x)) / np.abs(self.force(x))))


@dataclass(frozen=True)
class MountAirSpring(AirSpring):
    """An air spring of a body on mounts (a cab): its travel is tens of mm, so its cubic is fitted over +-40 mm."""

    fit_span: ClassVar[float] = 0.04


def add_air_spring(spec, name: str, tendon, spring: AirSpring, design_length: float, lengthens: bool = False) -> None:
    """Realise ``spring`` on ``tendon`` (an MjsTendon, its length ``design_length`` m at design height): the
    tendon's polynomial stiffness about the design length and a constant-force actuator ``name``. The tendon
    shortens as the spring is compressed (a spatial tendon from frame to axle) or, with ``lengthens``, grows (a mount's
    fixed tendon, frame rise less body rise: rig/elements/mounted_body.py)."""
    import mujoco

    f0, k1, k2, k3 = spring.cubic
    # pushing force F0 + k1 x + k2 x^2 + k3 x^3 with x = -(L - L_design) (or +(L - L_design) where the tendon lengthens
    # in compression, its force then pulling); MuJoCo applies -(a y + b y^2 + c y^3) with y = L - L_design
    tendon.stiffness = [k1, k2, k3] if lengthens else [k1, -k2, k3]
    tendon.springlength = [design_length, design_length]
    actuator = spec.add_actuator(name=name, target=tendon.name)
    actuator.trntype = mujoco.mjtTrn.mjTRN_TENDON
    actuator.gainprm[0] = 0.0
    actuator.biastype = mujoco.mjtBias.mjBIAS_AFFINE
    actuator.biasprm[:3] = [-f0 if lengthens else f0, 0.0, 0.0]
    actuator.forcelimited = mujoco.mjtLimited.mjLIMITED_TRUE
    actuator.forcerange = [-FORCE_CAP, FORCE_CAP]
