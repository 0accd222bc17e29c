"""``measured_law``: the suspension's force law differs in shape from the model's; realised as measured.

The generic element of the diagnosis: when no cause of the vocabulary explains a corner law, the shape the
data show (rig/diagnosis/rig_test/force_laws.py) is added to the model as it is, piecewise-linear in travel and in
its rate, each side of ride height with its own slopes:

    [measured_law.front]          # slope changes beyond each knot, away from ride height
    travel_knots = [-0.006, -0.004, -0.002, 0.0, 0.002, 0.004, 0.006]  # m, compression positive
    stiffness_changes = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 40000.0]         # N/m
    rate_knots = [-0.3, -0.2, -0.1, 0.0, 0.1, 0.2, 0.3]                 # m/s
    damping_changes = [0.0, -2000.0, 0.0, 0.0, 0.0, -2000.0, 0.0]       # N s/m

A knot at or above zero adds its change above it (x > k), one below zero below it (x < k): the force is
``sum_j dk_j ramp_j(x) + sum_j dc_j ramp_j(v)`` on top of the model's linear spring and damper. Inside
``mj_step``: one affine actuator per knot, ``F = b0 + b1 L + b2 dL/dt`` (its control is never set), clamped to one
force sign so that it acts only beyond its knot: the travel ramps on a tendon from body to hub (they get their
reference length at static ride height), the damping ramps on the damper's own tendon, so that they are the
damper's (in series with a compliant top mount where the axle has one; body to hub otherwise, as before). No
Python callback: rollout and batch stay in C.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from rig.causes._base import AxleCause, FitParameter, ParameterSpec, with_extension
from rig.elements.tendons import FORCE_CAP, damper_of

LIMITS = {"travel_knots": 0.3, "stiffness_changes": 1e7, "rate_knots": 10.0, "damping_changes": 1e6}


@dataclass(frozen=True)
class MeasuredLaw:
    travel_knots: tuple[float, ...]
    stiffness_changes: tuple[float, ...]
    rate_knots: tuple[float, ...]
    damping_changes: tuple[float, ...]

    def scaled(self, stiffness: float, damping: float) -> MeasuredLaw:
        """The law with its stiffness and damping changes scaled."""
        return MeasuredLaw(self.travel_knots, tuple(stiffness * c for c in self.stiffness_changes), self.rate_knots,
                           tuple(damping * c for c in self.damping_changes))


def ramp_force(law: MeasuredLaw, travel: np.ndarray, rate: np.ndarray) -> np.ndarray:
    """The law's force on the body (N, up) at compression ``travel`` (m) and its ``rate`` (m/s)."""
    def ramps(values, knots, changes):
        return sum(c * (np.maximum(values - k, 0.0) if k >= 0 else np.minimum(values - k, 0.0))
                   for k, c in zip(knots, changes))
    return ramps(travel, law.travel_knots, law.stiffness_changes) + ramps(rate, law.rate_knots, law.damping_changes)


class ListedLaw(AxleCause):
    """An axle cause whose sub-tables hold numbers and lists of numbers within limits (a law given by knots or by a
    network's weights): each read by ``read(table, where)``, written back as it was read."""

    limits: dict[str, float]
    scalars: tuple[str, ...] = ()

    def parse(self, section: Any, where: str, axles: tuple[str, ...]) -> dict[str, object]:
        if not isinstance(section, dict) or set(section) - set(axles):
            return super().parse(section, where, axles)  # raises, naming what is wrong with the sub-tables
        return {axle: self.read(table, f"{where}: [{self.name}.{axle}]") for axle, table in section.items()}

    def to_table(self, value: dict) -> dict:
        return {axle: {k: getattr(law, k) if k in self.scalars else list(getattr(law, k)) for k in self.limits}
                for axle, law in value.items()}

    def read(self, table: Any, where: str) -> object:
        raise NotImplementedError

    def numbers(self, table: Any, where: str) -> dict[str, float | tuple[float, ...]]:
        """The table's values, its keys exactly ``limits``', each a number (``scalars``) or a list of numbers within
        its limit; ValueError names what is wrong."""
        if not isinstance(table, dict):
            raise ValueError(f"{where} must be a table")
        wrong = sorted(set(table) ^ set(self.limits))
        if wrong:
            raise ValueError(f"{where}: keys must be exactly {', '.join(self.limits)} (wrong or missing: "
                             f"{', '.join(wrong)})")
        values = {}
        for key, limit in self.limits.items():
            scalar = key in self.scalars
            items = [table[key]] if scalar else table[key]
            if not isinstance(items, list) or not all(isinstance(x, (int, float)) and not isinstance(x, bool)
                                                       and abs(x) <= limit for x in items):
                raise ValueError(f"{where}: {key} must be {'a number' if scalar else 'a list of numbers'} within "
                                 f"±{limit:g}")
            values[key] = float(items[0]) if scalar else tuple(float(x) for x in items)
        return values


class _MeasuredLaw(ListedLaw):
    name = "measured_law"
    damper_line = "law"
    damper_part = "rate_ramps"
    subsystem = "car"
    values = MeasuredLaw
    generic = True
    meaning = "the suspension force law differs in shape from the model's (realised as measured)"
    signature = "the measured restoring force bends away from the model's straight law"

    def damper_value(self, old, rate_knots=(), damping_changes=()):
        """The damper's part of the law (its rate ramps) replaced; the travel part kept."""
        travel = (old.travel_knots, old.stiffness_changes) if old is not None else ((), ())
        if not travel[0] and not rate_knots:
            return None
        return MeasuredLaw(*travel, tuple(rate_knots), tuple(damping_changes))

    def on_damper_alone(self, value):
        """The law's rate ramps; its travel ramps are the spring's, which a dynamometer does not hold."""
        return MeasuredLaw((), (), value.rate_knots, value.damping_changes) if value.rate_knots else None

    limits = LIMITS

    def read(self, table: Any, where: str) -> MeasuredLaw:
        values = self.numbers(table, where)
        for knots, changes in (("travel_knots", "stiffness_changes"), ("rate_knots", "damping_changes")):
            if len(values[knots]) != len(values[changes]):
                raise ValueError(f"{where}: {knots} and {changes} must have the same length")
            if any(b <= a for a, b in zip(values[knots], values[knots][1:])):
                raise ValueError(f"{where}: {knots} must increase")
        return MeasuredLaw(**values)

    def parameters(self):
        return [ParameterSpec("travel_knots", "m", -LIMITS["travel_knots"], LIMITS["travel_knots"],
                              "knots in compression"),
                ParameterSpec("stiffness_changes", "N/m", -LIMITS["stiffness_changes"], LIMITS["stiffness_changes"],
                              "stiffness added beyond each travel knot"),
                ParameterSpec("rate_knots", "m/s", -LIMITS["rate_knots"], LIMITS["rate_knots"],
                              "knots in compression rate"),
                ParameterSpec("damping_changes", "N s/m", -LIMITS["damping_changes"], LIMITS["damping_changes"],
                              "damping added beyond each rate knot")]

    def build_corner(self, car, corner, law):
        add_ramps(car, corner, law, self.name)

    def at_static_corner(self, model, data, corner, law):
        set_ramp_references(model, data, corner, law, self.name)

    def fit_parameters(self, vehicle, hints=None):
        measured = (hints or {}).get("measured_laws")
        if not measured:
            return []

        reference = next(iter(measured))  # the law is scaled alike on every measured axle: one axle tells

        def apply(v, stiffness, damping):
            return with_extension(v, self.name, {a: law.scaled(stiffness, damping) for a, law in measured.items()})

        def current(v):
            law = v.extensions.get(self.name, {}).get(reference)
            first = measured[reference]
            if law is None:
                return 1.0, 1.0
            share = [np.dot(a, b) / max(np.dot(b, b), 1e-30) for a, b in
                     ((law.stiffness_changes, first.stiffness_changes), (law.damping_changes, first.damping_changes))]
            return share[0], share[1]

        return [FitParameter("stiffness_share", 1.0, 0.0, 2.0, lambda v, s: apply(v, s, current(v)[1])),
                FitParameter("damping_share", 1.0, 0.0, 2.0, lambda v, s: apply(v, current(v)[0], s))]


def add_ramps(car, corner: str, law: MeasuredLaw, prefix: str) -> None:
    """One clamped affine actuator per knot of ``law`` at ``corner`` (module docstring), named ``<prefix>_k<j>`` and
    ``<prefix>_c<j>``: the travel ramps on a tendon ``<corner>/<prefix>`` from body to hub, the damping ramps on the
    damper's own tendon."""
    import mujoco

    tendon = car.add_tendon(name=f"{corner}/{prefix}")
    tendon.wrap_site(f"{corner}/body")
    tendon.wrap_site(f"{corner}/hub")
    tendon.rgba = [0.2, 0.2, 0.2, 0.0]
    for kind, knots, changes, line in (("k", law.travel_knots, law.stiffness_changes, tendon.name),
                                       ("c", law.rate_knots, law.damping_changes, damper_of(car, corner).name)):
        for j, (knot, change) in enumerate(zip(knots, changes)):
            actuator = car.add_actuator(name=f"{corner}/{prefix}_{kind}{j}", target=line)
            actuator.trntype = mujoco.mjtTrn.mjTRN_TENDON
            # a unit gain on a control that stays 0: with gain = -biasprm[1] (both 0), MuJoCo would read a
            # positive biasprm[2] (a softening damping ramp) as a position actuator's damping ratio
            actuator.gainprm[0] = 1.0
            actuator.biastype = mujoco.mjtBias.mjBIAS_AFFINE
            # compression x = L0 - L and its rate v = -dL/dt: F = change (x - knot) or change (v - knot)
            actuator.biasprm[:3] = [0.0, 0.0, 0.0] if kind == "k" else [-change * knot, 0.0, -change]
            active_sign = np.sign(change) * (1 if knot >= 0 else -1)
            actuator.forcelimited = mujoco.mjtLimited.mjLIMITED_TRUE
            actuator.forcerange = [0.0, FORCE_CAP] if active_sign >= 0 else [-FORCE_CAP, 0.0]


def set_ramp_references(model, data, corner: str, law: MeasuredLaw, prefix: str) -> None:
    """The travel ramps of ``add_ramps`` referred to static ride height (``data`` holds the equilibrium)."""
    for j, (knot, change) in enumerate(zip(law.travel_knots, law.stiffness_changes)):
        actuator = model.actuator(f"car.{corner}/{prefix}_k{j}").id
        length = data.actuator_length[actuator]
        model.actuator_biasprm[actuator, :2] = [change * (length - knot), -change]


CAUSE = _MeasuredLaw()
