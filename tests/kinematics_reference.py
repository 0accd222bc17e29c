"""An independent kinematics solver for the tests: loop closure of double-wishbone and MacPherson corners from
their hardpoints with SciPy's root finder, written from the contract (docs/contracts.md) without the project's code.

Unlike the project's solvers (MuJoCo statics in ``rig kc``, the upright-pose Newton of the builder), it works in
joint angles: a double wishbone by its two arm angles and the upright's turn about the ball joints' axis, a
MacPherson strut by the arm angle and the knuckle's turn about the lower ball joint - top mount axis, the knuckle's
strut axis placed through the top mount in closed form. Alignment follows the contract's definitions.
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import root


def _unit(v):
    return v / np.linalg.norm(v)


def _rotation(axis, angle):
    """Rotation matrix about unit ``axis`` by ``angle`` (rad), Rodrigues."""
    k = _unit(np.asarray(axis, float))
    cross = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + np.sin(angle) * cross + (1 - np.cos(angle)) * cross @ cross


def _aligning(a, b):
    """The smallest rotation taking direction ``a`` to direction ``b``."""
    a, b = _unit(a), _unit(b)
    axis = np.cross(a, b)
    if np.linalg.norm(axis) < 1e-15:
        return np.eye(3)
    return _rotation(axis, np.arctan2(np.linalg.norm(axis), a @ b))


class ReferenceCorner:
    """One corner (``side`` +1 left, -1 right) from a kinematics table as in the vehicle file (left hardpoints)."""

    def __init__(self, table: dict, side: int = 1, steered: bool = True):
        self.kind = table["type"]
        self.side = side
        self.steered = steered
        self.p = {k: np.array([v[0], side * v[1], v[2]], float) for k, v in table.items() if isinstance(v, list)}
        camber, toe = np.radians(table.get("static_camber", 0.0)), np.radians(table.get("static_toe", 0.0))
        # outboard wheel normal: top inboard for negative camber, front inboard for toe-in
        self.normal0 = np.array([np.sin(toe) * np.cos(camber), side * np.cos(toe) * np.cos(camber), -np.sin(camber)])
        self.tie_rod = np.linalg.norm(self.p["tie_rod_outer"] - self.p["tie_rod_inner"])
        self.x = np.zeros(3 if self.kind == "double_wishbone" else 2)

    def _arm(self, front, rear, outer, angle):
        axis = self.p[rear] - self.p[front]
        return self.p[front] + _rotation(axis, angle) @ (self.p[outer] - self.p[front])

    def _upright(self, x):
        """(rotation, reference point, its position) of the upright for unknowns ``x``."""
        if self.kind == "double_wishbone":
            lower = self._arm("lower_front", "lower_rear", "lower_outer", x[0])
            upper = self._arm("upper_front", "upper_rear", "upper_outer", x[1])
            kingpin0 = self.p["upper_outer"] - self.p["lower_outer"]
            turn = _rotation(upper - lower, x[2]) @ _aligning(kingpin0, upper - lower)
            return turn, self.p["lower_outer"], lower
        lower = self._arm("lower_front", "lower_rear", "lower_outer", x[0])
        top = self.p["strut_top"]
        axis0 = _unit(self.p["strut_top"] - self.p["strut_lower"])
        base = self.p["strut_lower"] - self.p["lower_outer"]  # the strut axis in the knuckle, from the ball joint
        reach = np.linalg.norm(top - lower)
        # the point of the knuckle's strut axis that sits at the top mount: |base + s axis0| = reach, near design
        b = base @ axis0
        s = -b + np.sqrt(b * b - (base @ base - reach**2))
        point = base + s * axis0
        turn = _rotation(top - lower, x[1]) @ _aligning(point, top - lower)
        return turn, self.p["lower_outer"], lower

    def moved(self, name, x):
        turn, reference, position = self._upright(x)
        return position + turn @ (self.p[name] - reference)

    def _equations(self, x, travel, rack):
        centre = self.moved("wheel_centre", x)
        inner = self.p["tie_rod_inner"] + (np.array([0.0, rack, 0.0]) if self.steered else 0.0)
        tie = np.linalg.norm(self.moved("tie_rod_outer", x) - inner) - self.tie_rod
        out = [centre[2] - self.p["wheel_centre"][2] - travel, tie]
        if self.kind == "double_wishbone":
            lower = self._arm("lower_front", "lower_rear", "lower_outer", x[0])
            upper = self._arm("upper_front", "upper_rear", "upper_outer", x[1])
            out.append(np.linalg.norm(upper - lower) - np.linalg.norm(self.p["upper_outer"] - self.p["lower_outer"]))
        return out

    def _jacobian(self, x, travel, rack, step=1e-7):
        """Central differences with a fixed step (hybr's own steps scale with x, which starts at zero)."""
        columns = []
        for j in range(len(x)):
            dx = np.zeros(len(x))
            dx[j] = step
            columns.append((np.array(self._equations(x + dx, travel, rack))
                            - np.array(self._equations(x - dx, travel, rack))) / (2 * step))
        return np.column_stack(columns)

    def solve(self, travel, rack=0.0, substeps=4):
        """Solve at ``travel`` (m, bump +) and ``rack`` (m, to the left), walking out from the last solution."""
        start = (self.last if hasattr(self, "last") else (0.0, 0.0))
        for f in np.linspace(0, 1, substeps + 1)[1:]:
            t, r = start[0] + f * (travel - start[0]), start[1] + f * (rack - start[1])
            # unknowns shifted by 1: MINPACK's first trust region scales with |x|, tiny near design
            solution = root(lambda z, t=t, r=r: self._equations(z - 1.0, t, r), self.x + 1.0,
                            jac=lambda z, t=t, r=r: self._jacobian(z - 1.0, t, r), method="hybr", tol=1e-15)
            if np.max(np.abs(self._equations(solution.x - 1.0, t, r))) > 1e-12:
                raise RuntimeError(f"no closure at travel {t}, rack {r}: {solution.message}")
            self.x = solution.x - 1.0
        self.last = (travel, rack)
        return self.alignment()

    def alignment(self):
        """camber, toe (deg), track change (m), caster, kingpin (deg) as the contract defines them."""
        turn = self._upright(self.x)[0]
        normal = turn @ self.normal0
        centre = self.moved("wheel_centre", self.x)
        top_name = "upper_outer" if self.kind == "double_wishbone" else None
        bottom = self.moved("lower_outer", self.x)
        top = self.moved(top_name, self.x) if top_name else self.p["strut_top"]
        axis = top - bottom
        return {
            "camber": -np.degrees(np.arcsin(normal[2])),
            "toe": np.degrees(np.arctan2(normal[0], self.side * normal[1])),
            "track_change": self.side * (centre[1] - self.p["wheel_centre"][1]),
            "caster": np.degrees(np.arctan2(-axis[0], axis[2])),
            "kingpin": np.degrees(np.arctan2(-self.side * axis[1], axis[2])),
        }


def sweep(table: dict, side: int, travels=(), racks=(), steered=True) -> dict[str, np.ndarray]:
    """Alignment along a travel sweep (rack 0) or a rack sweep (travel 0), solved outward from design."""
    corner = ReferenceCorner(table, side, steered)
    values = list(travels) if len(travels) else list(racks)
    results = [None] * len(values)
    order = np.argsort(np.abs(values))
    for k in order:  # nearest to design first; each solve walks from the previous one
        results[k] = corner.solve(values[k], 0.0) if len(travels) else corner.solve(0.0, values[k])
    return {q: np.array([r[q] for r in results]) for q in results[0]}


def rocker_spring_lengths(table: dict, side: int, travels) -> np.ndarray:
    """The spring's length at each wheel travel on a double wishbone with a pushrod and rocker: the lower arm's angle
    from the loop closure above, the rocker's from the pushrod's length (SciPy's brentq within +-1 rad of design),
    the spring from the body (spring_upper) to the rocker (spring_lower)."""
    from scipy.optimize import brentq

    corner = ReferenceCorner(table, side)
    p = corner.p
    pushrod = np.linalg.norm(p["pushrod_outer"] - p["pushrod_inner"])
    axis = p["rocker_axis"] - p["rocker_pivot"]

    def turned(name, angle):
        return p["rocker_pivot"] + _rotation(axis, angle) @ (p[name] - p["rocker_pivot"])

    lengths = []
    for travel in travels:
        corner.solve(travel)
        outer = corner._arm("lower_front", "lower_rear", "pushrod_outer", corner.x[0])
        angle = brentq(lambda a, outer=outer: np.linalg.norm(turned("pushrod_inner", a) - outer) - pushrod, -1.0,
                       1.0, xtol=1e-15, rtol=1e-15)
        lengths.append(np.linalg.norm(turned("spring_lower", angle) - p["spring_upper"]))
    return np.array(lengths)
