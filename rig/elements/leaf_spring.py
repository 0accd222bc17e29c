"""Inter-leaf friction of a leaf spring: Fancher's exponential-envelope law, realised inside ``mj_step``.

A multi-leaf spring's force is its linear rate plus a friction force that, after every reversal, approaches the
envelope k x + F_c (loading) or k x - F_c (unloading) exponentially with travel (Fancher, Ervin, MacAdam and
Winkler, "Measurement and representation of the mechanical properties of truck leaf springs", SAE 800905, 1980):

    F = k x + F_f,   dF_f/dx = (s F_c - F_f) / beta,   s = sign(dx/dt),

so between reversals F_f = s F_c + (F_f0 - s F_c) exp(-|x - x0| / beta) exactly (``fancher_force``): the friction
``friction`` = F_c is the envelopes' half-width, ``decay_length`` = beta the travel over which the force closes on
its envelope by 1/e. The law is rate-independent.

MuJoCo realises it with a native element: the LuGre friction of a ``dcmotor`` actuator with no inputs, whose bristle
state obeys dz/dt = v - sigma0 |v| z / g(v) with F_f = -sigma0 z and g = F_c (static friction equal to Coulomb: no
Stribeck dip), which is the Dahl model: the same differential equation with sigma0 = F_c / beta. The state lives in
``mjData.act`` and is integrated with the rest of the state (RK4); nothing runs in Python.

A force element (rig/elements/): the ``beam_leaf`` suspension type builds from it and the ``leaf_friction`` cause
changes it.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from rig.elements.parameters import param

STRIBECK_VELOCITY = 1.0  # m/s: immaterial (static friction equals Coulomb friction); any positive value
NO_INPUTS = 16  # ctrlspec of a dcmotor with input="none": a passive element with no controls


@dataclass(frozen=True)
class LeafFriction:
    """Inter-leaf friction: the envelopes' half-width (N) and the decay length (m) of Fancher's law."""

    friction: float = field(metadata=param("N", 0.0, 1e5, "half-width of the hysteresis band (k x +- F_c)"))
    decay_length: float = field(metadata=param("m", 1e-4, 0.05, "travel over which the force closes on its "
                                                               "envelope by 1/e (Fancher's beta)"))


def fancher_friction(x: np.ndarray, friction: float, decay_length: float, start: float = 0.0) -> np.ndarray:
    """The friction force F_f (N) along a travel history ``x`` (m, samples), from F_f = ``start`` at x[0]: exact for
    travel that is monotone between samples (Fancher's exponential approach to k x +- F_c)."""
    x = np.asarray(x, float)
    out = np.empty_like(x)
    force = start
    out[0] = force
    for k in range(1, x.size):
        step = x[k] - x[k - 1]
        envelope = np.sign(step) * friction
        force = envelope + (force - envelope) * np.exp(-abs(step) / decay_length)
        out[k] = force
    return out


def add_leaf_friction(spec, name: str, tendon: str, law: LeafFriction) -> None:
    """A ``dcmotor`` actuator ``name`` on ``tendon`` with LuGre (Dahl) friction realising ``law``: the force opposes
    the tendon's velocity and closes on +-friction over the decay length."""
    import mujoco

    actuator = spec.add_actuator(name=name, target=tendon)
    actuator.trntype = mujoco.mjtTrn.mjTRN_TENDON
    stiffness = law.friction / law.decay_length
    actuator.set_to_dcmotor(motorconst=[0.0, 0.0], resistance=1.0,
                            lugre=[stiffness, 0.0, law.friction, law.friction, STRIBECK_VELOCITY], ctrlspec=NO_INPUTS)
