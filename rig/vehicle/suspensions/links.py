"""The moving parts of a linkage in the car's MjSpec: a part's mass properties at design (``Part``), its body, its
drawn links, a rod ball-jointed at both ends, and the stiffness of the equalities that close a loop. The linkage
types (rig/vehicle/suspensions/linkage.py) and a pushrod's rocker (rocker.py) build from them."""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np

CONSTRAINT_SOLREF = (-4e6, -4e3)  # equality reference stiffness (1/s^2) and damping (1/s): 2000 rad/s, critical
CONSTRAINT_SOLIMP = (0.9999, 0.9999, 0.001, 0.5, 2.0)
LINK_COLOR = [0.55, 0.57, 0.60, 1.0]
LINK_RADIUS = 0.012    # m, drawn


@dataclass(frozen=True)
class Part:
    """A moving part at design: mass (kg), CG (m, axle frame), inertia about the CG (3 x 3, kg m^2), and the CG's
    velocity and the angular velocity per m of wheel travel."""

    mass: float
    cg: np.ndarray
    inertia: np.ndarray
    velocity: np.ndarray
    spin: np.ndarray

    @property
    def kinetic_mass(self) -> float:
        """Twice the kinetic energy per (m/s of travel)^2: the part's share of the mass at the wheel, kg."""
        return float(self.mass * self.velocity @ self.velocity + self.spin @ self.inertia @ self.spin)


def add_link_geom(body: mujoco.MjsBody, start: np.ndarray, end: np.ndarray, radius: float = LINK_RADIUS) -> None:
    """A drawn cylinder between two points of ``body`` (its frame), massless."""
    body.add_geom(type=mujoco.mjtGeom.mjGEOM_CYLINDER, fromto=[*start, *end], size=[radius, 0.0, 0.0],
                  rgba=LINK_COLOR, contype=0, conaffinity=0, mass=0.0)


def add_part_body(parent: mujoco.MjsBody, name: str, pos: np.ndarray, part: Part, origin: np.ndarray
                  ) -> mujoco.MjsBody:
    """A link body at ``pos`` in its parent (identity orientation), with the part's mass properties; ``origin`` is
    the body's own origin in the axle frame (to place the part's CG)."""
    body = parent.add_body(name=name, pos=list(pos))
    body.mass = part.mass
    body.ipos = list(part.cg - origin)
    body.fullinertia = [*np.diag(part.inertia), part.inertia[0, 1], part.inertia[0, 2], part.inertia[1, 2]]
    body.explicitinertial = True
    return body


def equality_stiff(equality: mujoco.MjsEquality) -> None:
    """A loop-closing equality as stiff as RK4 at 1 ms integrates (CONSTRAINT_SOLREF, CONSTRAINT_SOLIMP)."""
    equality.solref = list(CONSTRAINT_SOLREF)
    equality.solimp = list(CONSTRAINT_SOLIMP)


def add_rod(car: mujoco.MjSpec, name: str, site1: str, site2: str) -> None:
    """A rod ball-jointed at both ends (a tie rod, a pushrod): a spatial tendon ``name`` between the sites, held at
    its design length by a tendon ``equality``."""
    tendon = car.add_tendon(name=name)
    tendon.wrap_site(site1)
    tendon.wrap_site(site2)
    tendon.width, tendon.rgba = LINK_RADIUS, LINK_COLOR
    equality = car.add_equality(name=name, type=mujoco.mjtEq.mjEQ_TENDON, objtype=mujoco.mjtObj.mjOBJ_TENDON,
                                name1=name)
    equality.data[:5] = [0.0, 1.0, 0.0, 0.0, 0.0]  # length - design length = 0
    equality_stiff(equality)
