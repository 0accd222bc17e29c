"""``leaf_friction``: a leaf spring's inter-leaf friction is missing from the model, or other than it says.

    [leaf_friction.front]    # Fancher's exponential envelopes k x +- friction (rig/elements/leaf_spring.py)
    friction = 2500.0        # N, half-width of the hysteresis band
    decay_length = 0.004     # m, travel over which the force closes on its envelope by 1/e

Realised on the axle's spring tendons (``<corner>/suspension``) as the LuGre/Dahl actuator ``<corner>/leaf_friction``
inside ``mj_step``, replacing the one a ``beam_leaf`` axle's ``[axles.leaf_spring]`` gives. Trucks only.

The diagnosis fits both: the friction with the decay length held at the model's (4 mm where the truth's was 3.2 mm)
came out 9-12 % high, the band widened to make up for a softer stick (the stick stiffness is friction over decay
length).
"""

from __future__ import annotations

import dataclasses

from rig.causes._base import AxleCause, FitParameter, Shape
from rig.elements.leaf_spring import LeafFriction, add_leaf_friction
from rig.vehicle.suspensions import suspensions

ACTUATOR = "{corner}/leaf_friction"


def leaf_axles(vehicle) -> tuple[str, ...]:
    """The vehicle's axles on leaf springs (their suspension type's springs have a LeafFriction law)."""
    return tuple(n for n, a in zip(vehicle.axle_names, vehicle.axles)
                 if a.suspension and (suspensions()[a.suspension].law or (None, None))[1] is LeafFriction)


class _LeafFriction(AxleCause):
    name = "leaf_friction"
    subsystem = "car"
    layouts = ("truck",)
    values = LeafFriction
    meaning = "a leaf spring's inter-leaf friction is missing or other than modelled (Fancher's envelopes)"
    signature = "a hysteresis loop about the spring line: stiff at each reversal, the envelopes +-F_c apart"
    evidence = (Shape.FRICTION_STEP,)

    def check(self, vehicle):
        super().check(vehicle)
        wrong = sorted(set(vehicle.extensions[self.name]) - set(leaf_axles(vehicle)))
        if wrong:
            raise ValueError(f"{vehicle.source}: [leaf_friction] {', '.join(wrong)}: not on leaf springs "
                             f"(the leaf-spring axles: {', '.join(leaf_axles(vehicle)) or 'none'})")

    def build_corner(self, car, corner, law):
        existing = car.actuator(ACTUATOR.format(corner=corner))
        if existing is not None:
            car.delete(existing)
        if law.friction > 0:
            add_leaf_friction(car, ACTUATOR.format(corner=corner), f"{corner}/suspension", law)

    def fit_parameters(self, vehicle, hints=None):
        def current(axle):
            return vehicle.extensions.get(self.name, {}).get(axle) or vehicle.axle_named(axle).law or \
                LeafFriction(1000.0, 0.004)

        def setter(axle, key):  # on the law as the vehicle being built has it (a fit sets its parameters in turn)
            def apply(v, x):
                law = v.extensions.get(self.name, {}).get(axle) or v.axle_named(axle).law or current(axle)
                return self.on_axle(v, axle, dataclasses.replace(law, **{key: x}))
            return apply

        return [p for a in leaf_axles(vehicle) for p in (
            FitParameter(f"{a}_friction", current(a).friction, 0.0, 2e4, setter(a, "friction"), typical=2000.0,
                         unit="N"),
            FitParameter(f"{a}_decay_length", current(a).decay_length, 1e-3, 0.02, setter(a, "decay_length"),
                         typical=1e-3, unit="m"))]

    def hidden(self, truth, rng):
        axles = leaf_axles(truth)
        if not axles:
            raise ValueError(f"{truth.name} has no leaf-spring axle to hide inter-leaf friction in")
        return self.on_every_axle(truth, lambda a: LeafFriction(rng.uniform(2000.0, 4000.0),
                                                                rng.uniform(0.002, 0.006)), axles)


CAUSE = _LeafFriction()
