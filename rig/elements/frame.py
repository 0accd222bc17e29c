"""A truck's flexible frame: rigid segments joined by bending and torsion springs (Forsén's first method).

``[frame]`` (layout ``truck``; without it the frame is rigid, the sprung body of the car model) gives the frame's
``length`` (m), its ``front_overhang`` ahead of the front axle (m), the number of ``segments``, and its vertical
bending and torsional stiffness: ``bending_stiffness`` EI (N m^2) and ``torsion_stiffness`` GJ (N m^2/rad), or
target frequencies ``bending_frequency`` and ``torsion_frequency`` (Hz: the first free-free modes of the frame with
the sprung mass and roll inertia spread evenly over its length, from which EI and GJ follow by the Euler-Bernoulli
beam and the torsion rod). ``damping_ratio`` damps each joint in proportion to its stiffness, the ratio being the
first mode's of its kind.

The sprung mass is spread along the frame with a linearly varying mass per length that keeps its mass and CG, the
roll inertia in proportion to the mass; whatever pitch inertia the file gives beyond that spread's own goes to the
segment that holds the CG (a file whose pitch inertia is below the spread's is refused, as is a CG outside the middle
third of the frame, where the spread would need negative mass). Each segment is a body; the one holding the CG is
the sprung body ``body`` (heave, pitch, roll), the others hang off it forward and rearward, each on a hinge about y
(bending, EI / l) and one about x (torsion, GJ / l) at its joint with the next, l the segment length. The joints'
springs and dampers are MuJoCo joint stiffness and damping: inside ``mj_step``.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass, field, fields

import numpy as np

from rig.elements.parameters import param

BEAM_ROOT = 4.730040744862704      # beta L of the first free-free bending mode (Euler-Bernoulli)
ROOT_BODY = "body"
SEGMENT_COLOR = [0.80, 0.15, 0.12, 0.55]
_RAIL_SIZE = (0.15, 0.12)          # m: half width and half height drawn per segment (geometry only)


@dataclass(frozen=True)
class Frame:
    """A flexible frame (SI). Stiffnesses are the whole frame's (both rails)."""

    length: float = field(metadata=param("m", 1.0, 25.0, "frame length"))
    front_overhang: float = field(metadata=param("m", 0.0, 5.0, "frame front end ahead of the front axle"))
    bending_stiffness: float = field(metadata=param("N m^2", 1e4, 1e10, "vertical bending stiffness EI"))
    torsion_stiffness: float = field(metadata=param("N m^2/rad", 1e3, 1e9, "torsional stiffness GJ"))
    segments: int = field(default=12, metadata=param("-", 2, 60, "number of rigid segments"))
    damping_ratio: float = field(default=0.03, metadata=param("-", 0.0, 0.5, "of each kind's first mode"))

    def to_table(self) -> dict:
        return {f.name: getattr(self, f.name) for f in fields(self)}

    def bending_frequency(self, mass: float) -> float:
        """Hz: the first free-free bending mode with ``mass`` kg spread evenly (Euler-Bernoulli)."""
        omega = BEAM_ROOT**2 * math.sqrt(self.bending_stiffness / (mass / self.length)) / self.length**2
        return omega / (2 * math.pi)

    def torsion_frequency(self, roll_inertia: float) -> float:
        """Hz: the first free-free torsion mode with ``roll_inertia`` kg m^2 spread evenly (torsion rod)."""
        return math.sqrt(self.torsion_stiffness / (roll_inertia / self.length)) / (2 * self.length)


def bending_stiffness_for(frequency: float, mass: float, length: float) -> float:
    """EI (N m^2) of a uniform free-free beam of ``mass`` kg over ``length`` m whose first bending mode is at
    ``frequency`` Hz: omega = (beta L)^2 sqrt(EI / (m' L^4))."""
    return (2 * math.pi * frequency / BEAM_ROOT**2) ** 2 * (mass / length) * length**4


def torsion_stiffness_for(frequency: float, roll_inertia: float, length: float) -> float:
    """GJ (N m^2/rad) of a uniform free-free rod of ``roll_inertia`` kg m^2 over ``length`` m whose first torsion mode
    is at ``frequency`` Hz: omega = (pi / L) sqrt(GJ / (I' ))."""
    return (2 * math.pi * frequency * length / math.pi) ** 2 * (roll_inertia / length)


def parse_frame(table: object, where: str, mass: float, roll_inertia: float) -> Frame:
    """``[frame]``, with frequencies turned into stiffnesses for the sprung ``mass`` and ``roll_inertia``."""
    if not isinstance(table, dict):
        raise ValueError(f"{where}: [frame] must be a table")
    table = dict(table)
    conversions = {"bending_frequency": ("bending_stiffness", lambda f, length: bending_stiffness_for(f, mass, length)),
                   "torsion_frequency": ("torsion_stiffness",
                                         lambda f, length: torsion_stiffness_for(f, roll_inertia, length))}
    length = table.get("length")
    for key, (target, convert) in conversions.items():
        if key in table:
            if target in table:
                raise ValueError(f"{where}: [frame] give {key} or {target}, not both")
            value = table.pop(key)
            if isinstance(value, bool) or not isinstance(value, (int, float)) or not 0.5 <= value <= 100.0:
                raise ValueError(f"{where}: [frame] {key} = {value!r} is outside the plausible range 0.5..100 Hz")
            if not isinstance(length, (int, float)) or isinstance(length, bool) or length <= 0:
                raise ValueError(f"{where}: [frame] {key} needs the frame's length (m)")
            table[target] = convert(float(value), float(length))
    names = [f.name for f in fields(Frame)]
    required = ["length", "front_overhang", "bending_stiffness", "torsion_stiffness"]
    unknown = sorted(set(table) - set(names))
    missing = [n for n in required if n not in table]
    if unknown or missing:
        raise ValueError(f"{where}: [frame] " + "; ".join(
            ([f"unknown key(s) {', '.join(unknown)}"] if unknown else [])
            + ([f"missing {', '.join(missing)}"] if missing else []))
            + " (keys: length, front_overhang, bending_stiffness or bending_frequency, torsion_stiffness or "
              "torsion_frequency, segments, damping_ratio)")
    values = {}
    for f in fields(Frame):
        if f.name not in table:
            continue
        value, meta = table[f.name], f.metadata
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not meta["low"] <= value <= meta["high"]:
            raise ValueError(f"{where}: [frame] {f.name} = {value!r} is outside the plausible range "
                             f"{meta['low']:g}..{meta['high']:g} {meta['unit']}")
        if f.name == "segments" and value != int(value):
            raise ValueError(f"{where}: [frame] segments must be a whole number, got {value!r}")
        values[f.name] = int(value) if f.name == "segments" else float(value)
    return Frame(**values)


@dataclass(frozen=True)
class Segment:
    """One rigid segment: its span (x front, x rear; m from the sprung CG, x forward), mass (kg), CG x (m), pitch
    inertia about its CG (kg m^2) and roll inertia (kg m^2)."""

    front: float
    rear: float
    mass: float
    cg: float
    pitch_inertia: float
    roll_inertia: float


def segments_of(frame: Frame, cg_to_front_axle: float, mass: float, roll_inertia: float,
                pitch_inertia: float | None = None, cg: float = 0.0) -> list[Segment]:
    """The segments, front to rear (x from the body's origin, the design CG), with ``mass`` spread linearly about its
    CG at x = ``cg`` and ``roll_inertia`` in proportion; the segment holding x = 0 takes ``pitch_inertia`` (kg m^2,
    about the CG) beyond the spread's own, if given. ValueError when the spread needs negative mass or the pitch
    inertia is below the spread's."""
    front = cg_to_front_axle + frame.front_overhang
    length, n = frame.length, frame.segments
    centre = front - length / 2 - cg  # the frame's middle, from the CG
    if abs(centre) > length / 6 + 1e-12:
        raise ValueError(f"the sprung CG is {abs(centre):.3g} m from the frame's middle: more than a sixth of its "
                         f"length ({length / 6:.3g} m), so its mass cannot be spread along it")
    a, b = mass / length, -12.0 * mass * centre / length**3  # mass per length a + b (u - centre), u = x - cg
    edges = front - length * np.arange(n + 1) / n
    out = []
    for hi, lo in itertools.pairwise(edges):
        def moment(k, hi=hi - cg, lo=lo - cg):  # integral of (a + b (u - centre)) u^k du over the span
            return ((a - b * centre) * (hi ** (k + 1) - lo ** (k + 1)) / (k + 1)
                    + b * (hi ** (k + 2) - lo ** (k + 2)) / (k + 2))
        m = moment(0)
        offset = moment(1) / m
        out.append(Segment(hi, lo, m, cg + offset, moment(2) - m * offset**2, roll_inertia * m / mass))
    if pitch_inertia is not None:
        spread = sum(s.mass * (s.cg - cg) ** 2 + s.pitch_inertia for s in out)
        if pitch_inertia < spread * (1 - 1e-9):
            raise ValueError(f"the sprung pitch inertia {pitch_inertia:.4g} kg m^2 is below that of its mass spread "
                             f"along the {length:g} m frame ({spread:.4g} kg m^2)")
        root = root_index(out)
        out[root] = Segment(out[root].front, out[root].rear, out[root].mass, out[root].cg,
                            out[root].pitch_inertia + pitch_inertia - spread, out[root].roll_inertia)
    return out


def root_index(segments: list[Segment]) -> int:
    """The segment that holds the sprung CG (x = 0)."""
    return next(i for i, s in enumerate(segments) if s.rear <= 0.0 <= s.front)


def segment_name(index: int, root: int) -> str:
    """The body of segment ``index`` (front to rear): ``body`` for the one holding the CG."""
    return ROOT_BODY if index == root else f"frame/segment_{index:02d}"


def segment_origin(segments: list[Segment], index: int, root: int) -> float:
    """x (m from the sprung CG) of a segment body's origin: the CG for the root, else its joint towards the root."""
    if index == root:
        return 0.0
    return segments[index].rear if index < root else segments[index].front


def segment_at(segments: list[Segment], x: float) -> int:
    """The segment whose span holds ``x`` (m from the sprung CG); the end segments hold what lies beyond the ends."""
    for i, s in enumerate(segments):
        if x >= s.rear:
            return i
    return len(segments) - 1


def add_segments(spec, body, segments: list[Segment], frame: Frame, com_yz: tuple[float, float] = (0.0, 0.0)) -> None:
    """Fill the root ``body`` (heave, pitch and roll joints of its own, origin at the sprung CG) with its segment's
    mass and hang the other segments off it on bending and torsion hinges (see the module docstring)."""
    import mujoco

    root = root_index(segments)
    length = frame.length / frame.segments
    bend, twist = frame.bending_stiffness / length, frame.torsion_stiffness / length
    mass = sum(s.mass for s in segments)
    roll = sum(s.roll_inertia for s in segments)
    # stiffness-proportional damping: c = 2 zeta k / omega_1 of each kind's first mode (uniform frame)
    bend_omega = BEAM_ROOT**2 * math.sqrt(frame.bending_stiffness / (mass / frame.length)) / frame.length**2
    twist_omega = math.pi / frame.length * math.sqrt(frame.torsion_stiffness / (roll / frame.length))
    bodies = {root: body}
    order = list(range(root - 1, -1, -1)) + list(range(root + 1, len(segments)))
    for i in [root, *order]:
        segment, origin = segments[i], segment_origin(segments, i, root)
        if i != root:
            parent = root if i in (root - 1, root + 1) else (i + 1 if i < root else i - 1)
            current = bodies[parent].add_body(name=segment_name(i, root),
                                              pos=[origin - segment_origin(segments, parent, root), 0.0, 0.0])
            for label, axis, k, omega in (("bend", [0, 1, 0], bend, bend_omega), ("twist", [1, 0, 0], twist,
                                                                                    twist_omega)):
                current.add_joint(name=f"{segment_name(i, root)}_{label}", type=mujoco.mjtJoint.mjJNT_HINGE,
                                  axis=axis, stiffness=[k, 0.0, 0.0], damping=[2 * frame.damping_ratio * k / omega,
                                                                               0.0, 0.0])
            bodies[i] = current
        current = bodies[i]
        current.mass = segment.mass
        current.ipos = [segment.cg - origin, *(com_yz if i == root else (0.0, 0.0))]
        current.inertia = [segment.roll_inertia, segment.pitch_inertia, max(segment.roll_inertia,
                                                                           segment.pitch_inertia)]
        current.explicitinertial = True
        current.add_geom(name=f"{segment_name(i, root)}_rails", type=mujoco.mjtGeom.mjGEOM_BOX,
                         size=[(segment.front - segment.rear) / 2, *_RAIL_SIZE],
                         pos=[(segment.front + segment.rear) / 2 - origin, 0.0, 0.0], rgba=SEGMENT_COLOR,
                         contype=0, conaffinity=0, mass=0.0)


def frame_spec(frame: Frame, mass: float, roll_inertia: float):
    """A free-free frame alone (no gravity): the root's heave, pitch and roll joints and the segments, the sprung
    CG at the frame's middle; for modal checks against the Euler-Bernoulli beam and the torsion rod."""
    import mujoco

    spec = mujoco.MjSpec()
    spec.option.gravity = [0.0, 0.0, 0.0]
    body = spec.worldbody.add_body(name=ROOT_BODY)
    for name, kind, axis in (("heave", mujoco.mjtJoint.mjJNT_SLIDE, [0, 0, 1]),
                             ("pitch", mujoco.mjtJoint.mjJNT_HINGE, [0, 1, 0]),
                             ("roll", mujoco.mjtJoint.mjJNT_HINGE, [1, 0, 0])):
        body.add_joint(name=name, type=kind, axis=axis)
    segments = segments_of(frame, frame.length / 2 - frame.front_overhang, mass, roll_inertia)
    add_segments(spec, body, segments, frame)
    return spec
