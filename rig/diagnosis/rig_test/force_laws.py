"""Force laws measured from the data, without a model form: the evidence a suspension engineer looks at first.

Per corner, the force the suspension puts on the body follows from the wheel's equilibrium,
``F_susp = F_tyre - m_u (g + a_u)`` (tyre load and wheel acceleration measured, unsprung mass from the
data sheet). Against compression x and its rate v it is the restoring-force surface of Masri and Caughey
(J. Appl. Mech. 46, 1979), fitted here shape-free as

    F = F0 + f_k(x) + f_c(v) + F_f tanh(v / v_s) + m_x x'' + k_x (x - x_other),

f_k and f_c piecewise-linear with their own slopes in compression and rebound (knots at quarters of each
side's range), a friction step F_f, a force-lag term (a damper whose force lags the rate, e.g. through
hydraulic or top-mount compliance, shows as a negative m_x: time constant tau = -m_x / c), and the
stiffness coupling the axle's two sides (an anti-roll bar). The slopes' standard errors come with them, so a
shape is named only when the data resolve it. The tyre's force-deflection (deflection = post displacement
minus the twice-integrated wheel acceleration, in the analysis band) gives its rate and damping; the
body's equilibrium ``M q'' = sum_i j_i F_i`` (rigid-body accelerations from the four body accelerometers)
gives its mass matrix: heave mass, pitch and roll inertia about the CG and the CG's offset, which is how
a payload (a point mass at (x, y): coupled mass matrix and static moment) shows.

A rig without load cells under its wheel pans records no tyre force. The wheel's equilibrium then takes the tyre's
force from its data-sheet rate and damping on the measured deflection (post displacement minus the twice-integrated
wheel acceleration, in the analysis band): ``F_tyre = k_t d + c_t d'``, dynamic only, which is all the surface and
the body's equilibrium use (the surface fits its own constant). What that assumes is stated (``ForceLaws.assumed``):
a tyre rate off by e scales the tyre's part of every force by 1 + e, so the body's mass comes out scaled alike
while its CG (a ratio of moments) and the laws' shapes (ratios of slopes) do not.

Written by hand: the regressions are ordinary linear least squares (NumPy); no library fits a
restoring-force surface.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy import signal

from rig.causes import CAUSES, Shape, axles_of
from rig.causes.measured_law import MeasuredLaw
from rig.constants import ANALYSIS_BAND
from rig.io.channels import channel
from rig.io.record import Record
from rig.signal.filters import band_pass, integrate
from rig.vehicle.suspensions import suspension_of
from rig.vehicle.vehicle_file import Vehicle

G = 9.80665
KNOT_FRACTIONS = (0.25, 0.5, 0.75)  # knots at these fractions of each side's range (99.5th percentile)
RESOLVED = 4.0                      # a shape is named when it is this many standard errors from linear...
RELATIVE = 0.15                     # ...and this large relative to the centre slope
MIN_SECONDS = 5.0                   # shorter records do not hold enough cycles for a surface

@dataclass
class Slope:
    """A measured slope (N/m or N s/m) over an interval of travel or rate, with its standard error."""

    low: float
    high: float
    value: float
    error: float


@dataclass
class CornerLaw:
    """The suspension force law measured at one corner (N, m, m/s)."""

    corner: str
    stiffness: list[Slope]              # segments of f_k, rebound to compression
    damping: list[Slope]                # segments of f_c, rebound to compression
    friction: tuple[float, float]       # step F_f and its standard error, N
    lag_s: tuple[float, float]          # force lag time constant and its standard error, s
    coupling: tuple[float, float]       # stiffness to the other side of the axle and its error, N/m
    unexplained_share: float            # RMS of what the surface leaves over the RMS of the dynamic force
    shapes: list[Shape]                 # named shapes (the causes they point to list them as evidence)
    travel_points: tuple[np.ndarray, np.ndarray] = field(repr=False)  # binned (x, F - the rate terms)
    rate_points: tuple[np.ndarray, np.ndarray] = field(repr=False)    # binned (v, F - the travel terms)

    def law_at(self, segments: list[Slope], points: np.ndarray) -> np.ndarray:
        """The piecewise-linear law through zero with ``segments``' slopes, at ``points``."""
        edges = [s.low for s in segments] + [segments[-1].high]
        anchor = np.concatenate([[0.0], np.cumsum([s.value * (s.high - s.low) for s in segments])])
        at_zero = np.interp(0.0, edges, anchor)
        slopes = np.array([s.value for s in segments])
        inner = np.interp(points, edges, anchor)
        below = anchor[0] + slopes[0] * np.minimum(points - edges[0], 0.0)
        above = anchor[-1] + slopes[-1] * np.maximum(points - edges[-1], 0.0)
        return np.where(points < edges[0], below, np.where(points > edges[-1], above, inner)) - at_zero

    def to_json(self) -> dict:
        return {"stiffness_n_per_m": [vars(s) for s in self.stiffness],
                "damping_n_s_per_m": [vars(s) for s in self.damping],
                "friction_n": list(self.friction), "lag_s": list(self.lag_s), "coupling_n_per_m": list(self.coupling),
                "unexplained_share": self.unexplained_share, "shapes": self.shapes,
                "suggests": sorted({c for s in self.shapes for c in pointing_to(s)})}


@dataclass
class TyreLaw:
    """The tyre's dynamic force against its deflection at one corner: rate N/m, damping N s/m, with errors."""

    corner: str
    rate: tuple[float, float]
    damping: tuple[float, float]
    points: tuple[np.ndarray, np.ndarray] = field(repr=False)  # binned (deflection m, dynamic force N)

    def to_json(self) -> dict:
        return {"rate_n_per_m": list(self.rate), "damping_n_s_per_m": list(self.damping)}


@dataclass
class MassProperties:
    """The body's mass properties identified from the data: kg, m from the nominal CG, kg m^2 about the CG."""

    mass: tuple[float, float]
    cg_x: tuple[float, float]
    cg_y: tuple[float, float]
    pitch_inertia: tuple[float, float]
    roll_inertia: tuple[float, float]

    def to_json(self) -> dict:
        return {"mass_kg": list(self.mass), "cg_x_m": list(self.cg_x), "cg_y_m": list(self.cg_y),
                "pitch_inertia_kg_m2": list(self.pitch_inertia), "roll_inertia_kg_m2": list(self.roll_inertia)}


@dataclass(frozen=True)
class Departure:
    """A measured law departing from the data sheet (SI): what, the measured value and its standard error, the
    data sheet's value and the causes it points to."""

    what: str
    measured: float
    error: float
    data_sheet: float
    shape: Shape

    @property
    def suggests(self) -> list[str]:
        return pointing_to(self.shape)

    def to_json(self) -> dict:
        return {"what": self.what, "measured": self.measured, "error": self.error, "data_sheet": self.data_sheet,
                "suggests": self.suggests}


@dataclass
class ForceLaws:
    """All force-law evidence of one record; ``missing`` says which could not be formed and why, ``assumed`` what
    was taken from the data sheet where a channel is missing (a tyre's rate where no load cell measured its force),
    ``saturated`` the channels left out; ``learned``: the laws learned per axle as networks, where a diagnosis asked
    for them (rig/diagnosis/rig_test/neuro_corner_law.py)."""

    corners: dict[str, CornerLaw]
    tyres: dict[str, TyreLaw]
    body: MassProperties | None
    missing: list[str]
    assumed: list[str] = field(default_factory=list)
    saturated: tuple[str, ...] = ()
    learned: dict = field(default_factory=dict)

    def departures(self, vehicle: Vehicle) -> list[Departure]:
        """Where the measured laws depart from ``vehicle``'s data sheet by more than a tolerance (beyond the
        few percent a real car differs from its data sheet) and RESOLVED standard errors."""
        found = []

        def check(what: str, value: tuple[float, float], sheet: float, kind: Shape, tolerance: float) -> None:
            difference = value[0] - sheet
            if abs(difference) > tolerance and abs(difference) > RESOLVED * value[1]:
                found.append(Departure(what, float(value[0]), float(value[1]), float(sheet), kind))

        for corner, law in ((c, law) for c, law in self.corners.items() if described(vehicle, c)):
            axle = vehicle.axle(corner)
            n = len(law.stiffness) // 2
            check(f"{corner} suspension rate at ride height", (law.stiffness[n].value, law.stiffness[n].error),
                  axle.suspension_rate, Shape.SUSPENSION_RATE, RELATIVE * axle.suspension_rate)
            check(f"{corner} damping at low speed", (law.damping[n].value, law.damping[n].error), axle.damping,
                  Shape.DAMPING, RELATIVE * axle.damping)
        for corner, tyre in ((c, tyre) for c, tyre in self.tyres.items() if described(vehicle, c)):
            axle = vehicle.axle(corner)
            check(f"{corner} tyre rate", tyre.rate, axle.tyre_rate, Shape.TYRE_RATE, RELATIVE * axle.tyre_rate)
            check(f"{corner} tyre damping", tyre.damping, axle.tyre_damping, Shape.TYRE_DAMPING, 0.02 * axle.damping)
        if self.body is not None:
            check("sprung mass", self.body.mass, vehicle.sprung_mass, Shape.SPRUNG_MASS, 0.05 * vehicle.sprung_mass)
            check("CG x", self.body.cg_x, 0.0, Shape.CG_X, 0.01 * vehicle.wheelbase)
            check("CG y", self.body.cg_y, 0.0, Shape.CG_Y, 0.01 * vehicle.track_front)
            check("pitch inertia", self.body.pitch_inertia, vehicle.pitch_inertia, Shape.PITCH_INERTIA,
                  0.1 * vehicle.pitch_inertia)
            check("roll inertia", self.body.roll_inertia, vehicle.roll_inertia, Shape.ROLL_INERTIA,
                  0.1 * vehicle.roll_inertia)
        return found

    def measured_laws(self, vehicle: Vehicle) -> dict[str, MeasuredLaw]:
        """The measured corner laws as the generic extension ``measured_law`` (rig/causes/measured_law.py) per
        axle: the slope changes at the knots, averaged over the axle's corners (knots sit at the same fractions
        of each corner's range); axles with no measured corner are left out."""
        laws = {}
        for axle in axles_of(vehicle):
            measured = [law for corner, law in self.corners.items() if corner[0] == axle[0].upper()]
            if not measured:
                continue
            parts = []
            for kind in ("stiffness", "damping"):
                slopes = np.mean([[s.value for s in getattr(law, kind)] for law in measured], axis=0)
                knots = np.mean([[s.high for s in getattr(law, kind)[:-1]] for law in measured], axis=0)
                changes = [slopes[j] - slopes[j + 1] if knot < 0 else slopes[j + 1] - slopes[j]
                           for j, knot in enumerate(knots)]
                parts += [tuple(map(float, knots)), tuple(map(float, changes))]
            laws[axle] = MeasuredLaw(*parts)
        return laws

    def axle_coupling(self, vehicle: Vehicle) -> dict[str, float]:
        """Stiffness coupling each axle's two sides (N/m, an anti-roll bar's rate at the wheel), averaged over
        the axle's measured corners; axles with no measured corner are left out."""
        coupling = {}
        for axle in axles_of(vehicle):
            measured = [law.coupling[0] for corner, law in self.corners.items() if corner[0] == axle[0].upper()]
            if measured:
                coupling[axle] = float(np.mean(measured))
        return coupling

    def axle_lags(self) -> dict[str, float]:
        """Per axle, the time constant (s) by which the suspension force lags the rate (a damper through a
        compliance: c / k), averaged over the axle's corners where the data resolve it; others left out."""
        lags: dict[str, list[float]] = {}
        for corner, law in self.corners.items():
            if Shape.FORCE_LAGS in law.shapes:
                lags.setdefault("front" if corner[0] == "F" else "rear", []).append(law.lag_s[0])
        return {axle: float(np.mean(values)) for axle, values in lags.items()}

    def to_json(self, vehicle: Vehicle) -> dict:
        return {"corners": {c: law.to_json() for c, law in self.corners.items()},
                "tyres": {c: law.to_json() for c, law in self.tyres.items()},
                "body": self.body.to_json() if self.body else None,
                "departures": [d.to_json() for d in self.departures(vehicle)], "missing": self.missing,
                "assumed": self.assumed} | (
                    {"learned": {a: law.to_json() for a, law in self.learned.items()}} if self.learned else {})

    def shown(self, vehicle: Vehicle) -> set[Shape]:
        """Every shape the corner laws show and every departure from ``vehicle``'s data sheet, where a corner's law
        describes its suspension (not a beam axle's: ``Suspension.corner_law``)."""
        return {shape for corner, law in self.corners.items() for shape in law.shapes if described(vehicle, corner)} \
            | {d.shape for d in self.departures(vehicle)}

    def widely_shown(self, vehicle: Vehicle) -> set[Shape]:
        """The shapes the corner laws show at every measured corner but one at most (and at one corner at least), of
        the corners whose law describes ``vehicle``'s suspension: evidence a noise-driven shape at a corner or two
        does not give."""
        laws = [law for corner, law in self.corners.items() if described(vehicle, corner)]
        counts: dict[Shape, int] = {}
        for law in laws:
            for shape in law.shapes:
                counts[shape] = counts.get(shape, 0) + 1
        return {shape for shape, n in counts.items() if n >= max(1, len(laws) - 1)}


def described(vehicle: Vehicle, corner: str) -> bool:
    """Whether a corner's force law describes ``corner`` of ``vehicle`` (``Suspension.corner_law``)."""
    return suspension_of(vehicle, corner).corner_law


def measure_force_laws(record: Record, vehicle: Vehicle, saturated: tuple[str, ...] = (),
                       band: tuple[float, float] = ANALYSIS_BAND) -> ForceLaws:
    """The force laws of ``record`` (SI channels of a rig test) for the car of ``vehicle`` (its unsprung
    masses and corner positions) in ``band`` (Hz); channels named in ``saturated`` are not used."""
    missing: list[str] = []
    if record.duration < MIN_SECONDS:
        short = f"no force laws: the record lasts {record.duration:.1f} s, shorter than the {MIN_SECONDS:g} s they need"
        return ForceLaws({}, {}, None, [short])

    def usable(corner: str, quantities: tuple[str, ...], evidence: str) -> bool:
        for quantity in quantities:
            name = channel(corner, quantity)
            if name not in record or name in saturated:
                why = "is saturated" if name in saturated else "is not in the record"
                missing.append(f"{evidence} at {corner} not formed: {name} {why}")
                return False
        return True

    rate = record.rate
    corners: dict[str, CornerLaw] = {}
    tyres: dict[str, TyreLaw] = {}
    forces: dict[str, np.ndarray] = {}
    assumed: list[str] = []
    for corner in vehicle.corners:
        loaded = channel(corner, "tyre_force") in record and channel(corner, "tyre_force") not in saturated
        if not usable(corner, ("unsprung_acc",) if loaded else ("unsprung_acc", "actuator_disp"),
                      "suspension force law"):
            continue
        if not loaded:
            assumed.append(_assumed_tyre(corner, vehicle))
        force = suspension_force(record, vehicle, corner, band, loaded)
        forces[corner] = force
        if usable(corner, ("susp_travel", "sprung_acc"), "suspension force law"):
            other = other_side(corner) if other_side(corner) in vehicle.corners else None
            other_name = channel(other, "susp_travel") if other else None
            other_travel = record[other_name] if other_name in record and other_name not in saturated else None
            corners[corner] = _corner_law(corner, record, force, other_travel, band[1])
        if not loaded:
            missing.append(f"tyre force-deflection at {corner} not formed: {channel(corner, 'tyre_force')} is not in "
                           f"the record (a wheel-pan load cell would give the tyre's own rate and damping)")
        elif usable(corner, ("actuator_disp",), "tyre force-deflection"):
            tyres[corner] = _tyre_law(corner, record, rate, band)
    body = None
    if vehicle.layout_type.pitches_and_rolls and len(forces) == 4:
        if all([usable(c, ("sprung_acc",), "body mass properties") for c in vehicle.corners]):  # names every one
            body = _mass_properties(record, vehicle, forces, band)
    elif vehicle.layout_type.pitches_and_rolls:
        missing.append("body mass properties not formed: the suspension forces of all four corners are needed")
    return ForceLaws(corners, tyres, body, missing, assumed, saturated)


def suspension_force(record: Record, vehicle: Vehicle, corner: str, band: tuple[float, float] = ANALYSIS_BAND,
                     loaded: bool | None = None) -> np.ndarray:
    """The force the suspension puts on the body at ``corner`` (N, up): F_tyre - m_u (g + a_u), the tyre's force as
    its load cell measured it, or where there is none (``loaded`` False; default: whether the record has the
    channel) from its data-sheet rate on its measured deflection, dynamic only."""
    loaded = channel(corner, "tyre_force") in record if loaded is None else loaded
    tyre = record[channel(corner, "tyre_force")] if loaded else _tyre_force_from_rate(corner, record, vehicle, band)
    return tyre - vehicle.axle(corner).unsprung_mass * (G + record[channel(corner, "unsprung_acc")])


def pointing_to(evidence: Shape | str) -> list[str]:
    """The causes of the registry whose ``evidence`` holds a named shape or departure."""
    return [name for name, cause in CAUSES.items() if evidence in cause.evidence]


def other_side(corner: str) -> str:
    return corner[0] + ("R" if corner[1] == "L" else "L")


def _low_pass(values: np.ndarray, rate: float, top: float) -> np.ndarray:
    sos = signal.butter(4, top, fs=rate, output="sos")
    return signal.sosfiltfilt(sos, values, axis=0)


def _ramps(values: np.ndarray) -> tuple[np.ndarray, np.ndarray, tuple[float, float]]:
    """Columns of one-sided ramps at the knots, the knots, and the range they cover: rebound side (acting
    below their knot), zero and the compression side (acting above theirs), so each side has its own slopes.
    A side of zero the data never reach (a travel channel not zeroed at ride height, a one-sided test) gets
    the other side's knots mirrored: its columns are zero, so it adds nothing, and the knots still increase."""
    low, high = np.quantile(values, [0.005, 0.995])
    reach = max(-low, high)
    low, high = min(low, -reach) if low >= 0 else low, max(high, reach) if high <= 0 else high
    knots = np.array([low * f for f in reversed(KNOT_FRACTIONS)] + [0.0] + [high * f for f in KNOT_FRACTIONS])
    columns = [np.minimum(values - k, 0.0) if k < 0 else np.maximum(values - k, 0.0) for k in knots]
    return np.column_stack(columns), knots, (float(low), float(high))


def _segments(linear: int, ramps: slice, knots: np.ndarray, coef: np.ndarray, cov: np.ndarray,
              covered: tuple[float, float], values: np.ndarray) -> list[Slope]:
    """Slopes of a ramp expansion between its knots: the linear slope plus the ramps active there. A segment
    no sample of ``values`` falls in says nothing: it takes its nearest measured neighbour's slope with a zero
    error (the convention of ``_changed`` for 'not resolved')."""
    edges = np.concatenate([[covered[0]], knots, [covered[1]]])
    ramp_index = np.arange(ramps.start, ramps.stop)
    segments = []
    for j in range(len(edges) - 1):
        weights = np.zeros(coef.size)
        weights[linear] = 1.0
        centre = 0.5 * (edges[j] + edges[j + 1])
        for k, knot in enumerate(knots):  # a rebound ramp acts below its knot, a compression ramp above
            if (knot < 0 and centre < knot) or (knot >= 0 and centre > knot):
                weights[ramp_index[k]] = 1.0
        segments.append(Slope(float(edges[j]), float(edges[j + 1]), float(weights @ coef),
                              float(np.sqrt(weights @ cov @ weights))))
    counts = np.histogram(values, edges)[0]
    measured = np.flatnonzero(counts)
    for j in np.flatnonzero(counts == 0):
        nearest = segments[measured[np.argmin(np.abs(measured - j))]] if measured.size else segments[j]
        segments[j] = Slope(segments[j].low, segments[j].high, nearest.value, 0.0)
    return segments


def _corner_law(corner: str, record: Record, force: np.ndarray, other_travel: np.ndarray | None,
                top: float) -> CornerLaw:
    rate = record.rate
    x = _low_pass(record[channel(corner, "susp_travel")], rate, top)
    name_v = channel(corner, "susp_velocity")
    v = _low_pass(record[name_v], rate, top) if name_v in record else np.gradient(x) * rate
    accel = _low_pass(record[channel(corner, "unsprung_acc")] - record[channel(corner, "sprung_acc")], rate, top)
    f = _low_pass(force, rate, top)
    x_ramps, x_knots, x_range = _ramps(x)
    v_ramps, v_knots, v_range = _ramps(v)
    v_step = 0.05 * np.std(v)
    columns = [np.ones_like(x), x, x_ramps, v, v_ramps, np.tanh(v / v_step), accel]
    if other_travel is not None:
        columns.append(x - _low_pass(other_travel, rate, top))
    design = np.column_stack(columns)
    scale = np.std(design, axis=0)
    scale[scale == 0] = 1.0  # the constant, and ramps on a side the data never reach
    coef, cov, residual = _least_squares(design / scale, f)
    coef, cov = coef / scale, cov / np.outer(scale, scale)
    n = len(KNOT_FRACTIONS) * 2 + 1
    i_x, i_v = 1, 2 + n
    i_step, i_acc = i_v + 1 + n, i_v + 2 + n
    stiffness = _segments(i_x, slice(2, 2 + n), x_knots, coef, cov, x_range, x)
    damping = _segments(i_v, slice(i_v + 1, i_v + 1 + n), v_knots, coef, cov, v_range, v)
    c_centre = 0.5 * (damping[n // 2].value + damping[n // 2 + 1].value)
    lag = (-coef[i_acc] / c_centre, np.sqrt(cov[i_acc, i_acc]) / abs(c_centre))
    coupling = (float(coef[-1]), float(np.sqrt(cov[-1, -1]))) if other_travel is not None else (0.0, 0.0)
    friction = (float(coef[i_step]), float(np.sqrt(cov[i_step, i_step])))
    dynamic = f - np.mean(f)
    travel_part = design[:, 1:i_v] @ coef[1:i_v]
    rate_part = design[:, i_v:i_acc] @ coef[i_v:i_acc]
    law = CornerLaw(corner, stiffness, damping, friction, (float(lag[0]), float(lag[1])), coupling,
                    float(np.std(residual) / np.std(dynamic)), [],
                    _binned(x, residual + travel_part), _binned(v, residual + rate_part))
    law.shapes = _shapes(law, np.std(dynamic))
    return law


def _least_squares(design: np.ndarray, target: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Coefficients, their covariance (residual variance x (A^T A)^-1) and the residual."""
    coef, *_ = np.linalg.lstsq(design, target, rcond=None)
    residual = target - design @ coef
    variance = residual @ residual / max(1, design.shape[0] - design.shape[1])
    return coef, variance * np.linalg.pinv(design.T @ design), residual


def _changed(a: Slope, b: Slope) -> float:
    """How many standard errors slope ``b`` lies above ``a`` when it differs by more than RELATIVE (else 0)."""
    difference = b.value - a.value
    error = np.hypot(a.error, b.error)
    if abs(difference) < RELATIVE * abs(a.value) or error == 0:  # no data on a side: nothing resolved
        return 0.0
    return difference / error


def _shapes(law: CornerLaw, force_rms: float) -> list[Shape]:
    shapes = []
    n = len(law.stiffness) // 2
    centre_k = [law.stiffness[n - 1], law.stiffness[n]]
    rebound = _changed(centre_k[0], law.stiffness[0])
    compression = _changed(centre_k[1], law.stiffness[-1])
    if rebound > RESOLVED and compression > RESOLVED:
        shapes.append(Shape.STIFFENS_BOTH_WAYS)
    else:
        for change, stiffens, softens in ((compression, Shape.STIFFENS_IN_COMPRESSION, Shape.SOFTENS_IN_COMPRESSION),
                                          (rebound, Shape.STIFFENS_IN_REBOUND, Shape.SOFTENS_IN_REBOUND)):
            if change > RESOLVED:
                shapes.append(stiffens)
            elif change < -RESOLVED:
                shapes.append(softens)
    slow_rebound, slow_compression = law.damping[n - 1], law.damping[n]
    if abs(_changed(slow_compression, slow_rebound)) > RESOLVED:
        shapes.append(Shape.ASYMMETRIC_DAMPING)
    ends = [_changed(slow_rebound, law.damping[0]), _changed(slow_compression, law.damping[-1])]
    if all(e > RESOLVED for e in ends):
        shapes.append(Shape.PROGRESSIVE_DAMPING)
    elif all(e < -RESOLVED for e in ends):
        shapes.append(Shape.DIGRESSIVE_DAMPING)
    if law.friction[0] > RESOLVED * law.friction[1] and law.friction[0] > 0.05 * force_rms:
        shapes.append(Shape.FRICTION_STEP)
    if law.lag_s[0] > RESOLVED * law.lag_s[1] and law.lag_s[0] > 1e-3:
        shapes.append(Shape.FORCE_LAGS)
    k = 0.5 * (centre_k[0].value + centre_k[1].value)
    if abs(law.coupling[0]) > RESOLVED * law.coupling[1] and abs(law.coupling[0]) > 0.05 * abs(k):
        shapes.append(Shape.COUPLED)
    return shapes


def _binned(x: np.ndarray, y: np.ndarray, bins: int = 24) -> tuple[np.ndarray, np.ndarray]:
    edges = np.quantile(x, np.linspace(0.005, 0.995, bins + 1))
    index = np.clip(np.searchsorted(edges, x) - 1, 0, bins - 1)
    inside = (x >= edges[0]) & (x <= edges[-1])
    counts = np.bincount(index[inside], minlength=bins)
    keep = counts > 0
    centres = np.bincount(index[inside], x[inside], bins)[keep] / counts[keep]
    means = np.bincount(index[inside], y[inside], bins)[keep] / counts[keep]
    return centres, means


def _deflection(corner: str, record: Record, band: tuple[float, float]) -> np.ndarray:
    """The tyre's dynamic deflection (m, compression positive): the post's displacement less the wheel's, the wheel's
    integrated twice from its acceleration, both in the analysis band (below half its lower edge the integral would
    only amplify leakage)."""
    rate = record.rate
    wheel = band_pass(integrate(record[channel(corner, "unsprung_acc")], rate, band[0] / 2, times=2), rate, band)
    return band_pass(record[channel(corner, "actuator_disp")], rate, band) - wheel


def _tyre_force_from_rate(corner: str, record: Record, vehicle: Vehicle, band: tuple[float, float]) -> np.ndarray:
    """The tyre's dynamic force (N) from its data-sheet rate and damping on the measured deflection."""
    axle = vehicle.axle(corner)
    deflection = _deflection(corner, record, band)
    return axle.tyre_rate * deflection + axle.tyre_damping * np.gradient(deflection) * record.rate


def _assumed_tyre(corner: str, vehicle: Vehicle) -> str:
    axle = vehicle.axle(corner)
    return (f"suspension force at {corner} from the tyre's data-sheet rate ({axle.tyre_rate:.4g} N/m, damping "
            f"{axle.tyre_damping:.3g} N s/m) on its measured deflection: {corner}/tyre_force is not in the record; a "
            f"tyre rate off by 5 % scales the force's tyre part, and the body's mass with it, by 5 % (a wheel-pan load "
            f"cell would measure it)")


def _tyre_law(corner: str, record: Record, rate: float, band: tuple[float, float]) -> TyreLaw:
    deflection = _deflection(corner, record, band)
    force = band_pass(record[channel(corner, "tyre_force")], rate, band)
    design = np.column_stack([deflection, np.gradient(deflection) * rate])
    coef, cov, _ = _least_squares(design, force)
    errors = np.sqrt(np.diag(cov))
    return TyreLaw(corner, (float(coef[0]), float(errors[0])), (float(coef[1]), float(errors[1])),
                   _binned(deflection, force))


def _mass_properties(record: Record, vehicle: Vehicle, forces: dict[str, np.ndarray],
                     band: tuple[float, float]) -> MassProperties:
    """Fit the symmetric 3x3 mass matrix M of (heave, pitch, roll) to M q'' = sum_i j_i F_i, j_i = (1, x_i, y_i)."""
    rate = record.rate
    jacobian = np.array([[1.0, *vehicle.corner_position(c)] for c in vehicle.corners])
    body = band_pass(record.quantity("sprung_acc", vehicle.corners), rate, band)
    q = np.linalg.lstsq(jacobian, body.T, rcond=None)[0].T                 # samples x (z'', pitch'', roll'')
    load = band_pass(np.column_stack([forces[c] for c in vehicle.corners]), rate, band) @ jacobian
    # unknowns m, Sx, Sy, Jxx (pitch), Jyy (roll), Jxy in M = [[m, Sx, Sy], [Sx, Jxx, Jxy], [Sy, Jxy, Jyy]]
    zero = np.zeros_like(q[:, 0])
    rows = [np.column_stack([q[:, 0], q[:, 1], q[:, 2], zero, zero, zero]),
            np.column_stack([zero, q[:, 0], zero, q[:, 1], zero, q[:, 2]]),
            np.column_stack([zero, zero, q[:, 0], zero, q[:, 2], q[:, 1]])]
    design, target = np.vstack(rows), load.T.reshape(-1)
    coef, cov, _ = _least_squares(design, target)
    m, sx, sy, jxx, jyy = coef[:5]

    def spread(gradient: np.ndarray) -> float:
        return float(np.sqrt(gradient @ cov @ gradient))

    x, y = sx / m, sy / m
    e = np.eye(6)
    return MassProperties(
        (float(m), spread(e[0])), (float(x), spread(e[1] / m - e[0] * sx / m**2)),
        (float(y), spread(e[2] / m - e[0] * sy / m**2)),
        (float(jxx - m * x * x), spread(e[3] - 2 * x * e[1] + x * x * e[0])),
        (float(jyy - m * y * y), spread(e[4] - 2 * y * e[2] + y * y * e[0])))
