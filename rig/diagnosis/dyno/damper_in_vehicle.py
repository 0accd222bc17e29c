"""A damper law measured on a dynamometer, written into a vehicle file's axle, and the check that the file's damper
reproduces it (simulated on the dyno in MuJoCo, rig/sim/dyno.py).

The dyno measures the damper; the vehicle file holds it at the wheel. With the motion ratio MR (damper travel over
wheel travel) a damper speed u is u / MR at the wheel and a force F is F MR: slopes scale by MR^2, a quadratic
coefficient by MR^3, knee speeds by 1 / MR, a series stiffness by MR^2. Each form goes where the file can hold it:

- ``linear``: the axle's ``damping``;
- ``asymmetric``: ``[damper_asymmetry.<axle>]`` (``damping`` set to the mean of the two);
- ``quadratic`` (the paper's C0 v + Cn v|v|): ``damping`` = C0 and ``[progressive_damper.<axle>]`` = Cn, exactly
  (a negative Cn, which that section cannot hold, goes the way of the next form);
- ``quadratic_asymmetric``: ``[damper_asymmetry]`` for the slopes from zero, and the damping ramps of
  ``[measured_law.<axle>]`` for the rest: the chords of each side's Cn u^2 at ``CHORDS`` knots spaced as the
  square up to 1.25 times the fastest speed tested (exact at the knots; between them off by at most 1 / CHORDS^2
  of the quadratic term's force there, and the largest departure in N is reported);
- ``digressive``: ``[damper_asymmetry]`` for the low-speed slopes and one measured-law ramp per knee, exactly;
- ``neuro`` (the neuro-model paper's damper network): ``[damper_asymmetry]`` for the slopes from zero and measured-law
  damping ramps for the chords of its curve at ``CHORDS`` knots per side, spaced as the square (the largest departure
  between knots is reported);
- ``+series``: ``[top_mount_compliance.<axle>]`` (in series with a top mount the axle already has);
- ``+lag``: a series stiffness too, the law's slope from zero over the lag time (a Maxwell element lags by c / k);
- ``+hysteresis``: ``[strut_friction.<axle>]``, Coulomb friction of the seals' friction force (Dahl's reach, the
  travel over which it turns, is not held);
- ``+temperature``: the coefficients at one temperature (the fit's reference unless asked otherwise);
- ``+preload``: ``[damper_preload.<axle>]`` = preload x MR at the wheel, a constant force between body and wheel
  that the model carries statically: it settles higher by that force over the axle's spring + parasitic rate (a
  vertical corner; its tyre loads as they were), and the damper on the dyno shows the preload at zero speed.

Earlier damper sections of the axle are replaced (a measured law keeps its travel part).
"""

from __future__ import annotations

import dataclasses
import tomllib
from dataclasses import dataclass

import numpy as np

from rig.causes import CAUSES, Cause, damper_line_causes
from rig.diagnosis.dyno.damper_law import DamperLaw
from rig.diagnosis.dyno.dyno_test import DynoTest
from rig.sim.dyno import damper_alone, simulate_dyno
from rig.elements.top_mount import mount_mass
from rig.signal.differentiate import rate_of
from rig.vehicle.vehicle_file import Vehicle, VehicleError, vehicle_from_dict, vehicle_to_toml

CHORDS = 16              # knots per side for a quadratic the file cannot hold exactly
SPEED_MARGIN = 1.25      # the chords reach this far past the fastest speed tested


@dataclass(frozen=True)
class WrittenDamper:
    """The vehicle with the damper written into ``axle``; ``sections`` says where it went, ``notes`` what could
    not be written or was approximated."""

    vehicle: Vehicle
    axle: str
    motion_ratio: float
    temperature: float | None
    sections: tuple[str, ...]
    notes: tuple[str, ...]


@dataclass(frozen=True)
class Reproduction:
    """How the written file's damper, simulated on the dyno, reproduces the law and the measured loops: RMS
    differences in percent of the RMS force, over the test and per run (``law``: against the law at the written
    temperature; ``loop``: against the measured force), its preload included."""

    law_rms_pct: float
    loop_rms_pct: float
    runs: dict[str, tuple[float, float]]  # run name -> (law, loop) RMS %
    simulated: tuple = ()                 # one DynoSimulation per run


def damper_in_vehicle(vehicle: Vehicle, axle: str, law: DamperLaw, motion_ratio: float = 1.0,
                      temperature: float | None = None, speeds: tuple[float, float] = (1.0, 1.0)) -> WrittenDamper:
    """``vehicle`` with ``law`` (damper level) as ``axle``'s damper (see the module notes). ``temperature`` (degC)
    picks the coefficients of a drifting law (default: its reference); ``speeds`` (m/s, damper): the fastest
    rebound and compression speeds tested, which the chords of an asymmetric quadratic cover."""
    damper_alone(vehicle, axle)  # refuses an axle the vehicle lacks
    if not motion_ratio > 0:
        raise VehicleError(f"motion ratio must be positive, got {motion_ratio}")
    temperature = law.reference_temperature if temperature is None else temperature
    c = _at_temperature(law, temperature)
    sections, notes = [], []
    target = _without_damper(vehicle, axle)
    ratio2 = motion_ratio ** 2
    form = law.form if not (law.form == "quadratic" and c["cn"] < 0) else "quadratic_asymmetric"
    if form == "quadratic_asymmetric" and law.form == "quadratic":
        c = {"c0_rebound": c["c0"], "cn_rebound": c["cn"], "c0_compression": c["c0"], "cn_compression": c["cn"]}
        notes.append("a negative quadratic coefficient, which [progressive_damper] cannot hold, written as ramps")
    if form == "linear":
        target = _set_damping(target, axle, c["c"] * ratio2)
        sections.append(f"[{axle}] damping")
    elif form == "quadratic":
        target = _set_damping(target, axle, c["c0"] * ratio2)
        target, section = _written(target, "quadratic", axle, c["cn"] * motion_ratio ** 3)
        sections += [f"[{axle}] damping", section]
    else:
        slopes, knots, changes, note = _piecewise(form, c, speeds)
        notes += note
        rebound, compression = slopes[0] * ratio2, slopes[1] * ratio2
        target = _set_damping(target, axle, 0.5 * (rebound + compression))
        target, section = _written(target, "slopes", axle, compression, rebound)
        sections.append(section)
        if knots:
            target, section = _written(target, "rate_ramps", axle, [k / motion_ratio for k in knots],
                                       [d * ratio2 for d in changes])
            sections.append(f"{section} rate_knots, damping_changes")
    target = _dynamics(vehicle, target, axle, law, motion_ratio, sections, notes)
    if law.preload:
        preload = law.coefficients["preload"] * motion_ratio
        target, section = _written(target, "preload", axle, preload)
        sections.append(section)
        notes.append(f"preload {law.coefficients['preload']:.1f} N (a gas force pushing the rod out) written as "
                     f"{preload:.1f} N at the wheel: the model settles "
                     f"{preload / target.axle_named(axle).suspension_rate * 1e3:.2f} mm higher on the axle's springs "
                     f"(spring + parasitic rate), its motions measured from there")
    if law.temperature:
        notes.append(f"coefficients at {temperature:.1f} degC (drift {law.coefficients['temperature_drift']:+.5f} "
                     f"per degC): a vehicle file holds one temperature")
    friction = vehicle.extensions.get(_holding("friction").name, {}).get(axle)
    if friction is not None and not law.hysteresis:
        notes.append(f"the axle's strut friction ({friction.force:g} N) is kept; the dyno's law has none of its own "
                     f"(remove [{_holding('friction').name}.{axle}] if it stood for the damper's)")
    checked = _checked(target)
    return WrittenDamper(checked, axle, motion_ratio, temperature if law.temperature else None, tuple(sections),
                         tuple(notes))


def _dynamics(vehicle: Vehicle, target: Vehicle, axle: str, law: DamperLaw, motion_ratio: float,
              sections: list[str], notes: list[str]) -> Vehicle:
    """``target`` with the law's series stiffness (or its lag as one) and its seals' friction, ``sections`` and
    ``notes`` told where they went."""
    if law.series or law.lag:
        rate = law.coefficients["series_rate"] if law.series else _slope_from_zero(law) / law.coefficients["lag_time"]
        target, written, note = _series(vehicle, target, axle, rate * motion_ratio**2)
        sections += [f"[{_holding('series').name}.{axle}]"] if written else []
        notes.append(note if law.series else f"the lag of {law.coefficients['lag_time'] * 1e3:.1f} ms as a series "
                                               f"stiffness (the slope from zero over the lag): {note}")
    if law.hysteresis:
        friction = law.coefficients["friction"] * motion_ratio
        target, section = _written(target, "friction", axle, friction)
        sections.append(section)
        notes.append(f"the seals' friction {law.coefficients['friction']:.1f} N as Coulomb friction of "
                     f"{friction:.1f} N at the wheel (its reach of {law.coefficients['friction_reach'] * 1e3:.2f} mm "
                     f"is not held)")
    return target


def reproduction(written: WrittenDamper, law: DamperLaw, test: DynoTest) -> Reproduction:
    """Simulate the written damper on the dyno with each run's displacement and compare it with the law and with
    the measured force (see ``Reproduction``)."""
    sums = np.zeros(4)  # law error, law power, loop error, loop power
    runs, simulated = {}, []
    for run in test.runs:
        sim = simulate_dyno(written.vehicle, written.axle, run.displacement, run.rate, velocity=run.velocity,
                            motion_ratio=written.motion_ratio)
        simulated.append(sim)
        expected = law.along(run, rate_of(sim.force, run.rate).values, written.temperature)
        part = np.array([np.sum((sim.force - expected) ** 2), np.sum(expected ** 2),
                         np.sum((sim.force - run.force) ** 2), np.sum(run.force ** 2)])
        runs[run.name] = (float(100 * np.sqrt(part[0] / part[1])), float(100 * np.sqrt(part[2] / part[3])))
        sums += part
    return Reproduction(float(100 * np.sqrt(sums[0] / sums[1])), float(100 * np.sqrt(sums[2] / sums[3])), runs,
                        tuple(simulated))


def _at_temperature(law: DamperLaw, temperature: float | None) -> dict[str, float]:
    """The base form's coefficients at ``temperature``: slopes scaled by the drift, knee speeds as they are."""
    scale = float(law.temperature_scale(temperature))
    return {k: v if k.startswith("knee") else v * scale for k, v in law.coefficients.items()
            if k not in ("preload", "series_rate", "temperature_drift", "lag_time", "friction", "friction_reach")}


def _slope_from_zero(law: DamperLaw) -> float:
    """The base law's slope at zero speed, the mean of rebound's and compression's (N s/m)."""
    h = 1e-4
    return float((law.base_force(np.array(h)) - law.base_force(np.array(-h))) / (2 * h))


def _piecewise(form: str, c: dict[str, float], speeds: tuple[float, float]
               ) -> tuple[tuple[float, float], list[float], list[float], list[str]]:
    """Slopes from zero (rebound, compression), compression-rate knots and slope changes (damper level) of a
    per-direction law: exact for ``asymmetric`` and ``digressive``, chords for ``quadratic_asymmetric``."""
    if form == "asymmetric":
        return (c["c_rebound"], c["c_compression"]), [], [], []
    if form == "digressive":
        return ((c["c_low_rebound"], c["c_low_compression"]), [-c["knee_rebound"], c["knee_compression"]],
                [c["c_high_rebound"] - c["c_low_rebound"], c["c_high_compression"] - c["c_low_compression"]], [])
    if form == "neuro":
        return _neuro_chords(DamperLaw("neuro", c), speeds)
    knots, changes, slopes, worst = [], [], [], []
    for side, sign, speed in (("rebound", -1.0, speeds[0]), ("compression", 1.0, speeds[1])):
        at = SPEED_MARGIN * speed * (np.arange(CHORDS + 1) / CHORDS) ** 2  # denser near zero, where forces are small
        cn = c[f"cn_{side}"]
        slopes.append(c[f"c0_{side}"] + cn * at[1])
        for j in range(1, CHORDS):
            knots.append(sign * at[j])
            changes.append(cn * (at[j + 1] - at[j - 1]))
        worst.append(abs(cn) * np.max(np.diff(at)) ** 2 / 4)
    order = np.argsort(knots)
    note = [f"the quadratic terms as chords at {CHORDS} knots per side (spaced as the square, up to {SPEED_MARGIN:g} x "
            f"the fastest speed tested): at most {max(worst):.3g} N (damper) off between knots, 1/{CHORDS ** 2} of "
            f"the quadratic term's force where it is"]
    return tuple(slopes), [knots[i] for i in order], [changes[i] for i in order], note


def _neuro_chords(law: DamperLaw, speeds: tuple[float, float]
                  ) -> tuple[tuple[float, float], list[float], list[float], list[str]]:
    """``_piecewise`` of a neuro law: its curve's chords at CHORDS knots per side, spaced as the square."""
    knots, changes, slopes, worst = [], [], [], 0.0
    for sign, speed in ((1.0, speeds[0]), (-1.0, speeds[1])):
        at = SPEED_MARGIN * speed * (np.arange(CHORDS + 1) / CHORDS) ** 2
        force = law.base_force(sign * at)
        chord = np.diff(force) / np.diff(sign * at)  # dF/du of each chord, u the rod's extension rate
        slopes.append(float(chord[0]))
        knots += [float(-sign * a) for a in at[1:-1]]  # knots in compression rate
        changes += [float(d) for d in np.diff(chord)]
        fine = np.linspace(0.0, at[-1], 20 * CHORDS + 1)
        worst = max(worst, float(np.max(np.abs(law.base_force(sign * fine) - np.interp(fine, at, force)))))
    order = np.argsort(knots)
    note = [f"the network's curve as chords at {CHORDS} knots per side (spaced as the square, up to {SPEED_MARGIN:g} x "
            f"the fastest speed tested): at most {worst:.3g} N (damper) off between knots"]
    return tuple(slopes), [knots[i] for i in order], [changes[i] for i in order], note


def _without_damper(vehicle: Vehicle, axle: str) -> Vehicle:
    """``vehicle`` without ``axle``'s damper sections (a measured law keeps its travel part)."""
    extensions = {}
    for name, value in vehicle.extensions.items():
        if name in damper_line_causes("law") and axle in value:
            value = {a: v for a, v in value.items() if a != axle}
            kept = CAUSES[name].damper_value(vehicle.extensions[name][axle])
            if kept is not None:  # a measured law's travel part
                value[axle] = kept
        if value:
            extensions[name] = value
    return dataclasses.replace(vehicle, extensions=extensions)


def _holding(part: str) -> Cause:
    """The cause whose section holds ``part`` of a damper law (``Cause.damper_part``)."""
    return next(cause for cause in CAUSES.values() if cause.damper_part == part)


def _written(vehicle: Vehicle, part: str, axle: str, *numbers: object) -> tuple[Vehicle, str]:
    """``vehicle`` with ``part`` of a damper law (``numbers``) in its cause's section at ``axle``, and that section."""
    cause = _holding(part)
    section = vehicle.extensions.get(cause.name, {})
    value = cause.damper_value(section.get(axle), *numbers)
    return dataclasses.replace(vehicle, extensions={**vehicle.extensions, cause.name: {**section, axle: value}}), \
        f"[{cause.name}.{axle}]"


def _set_damping(vehicle: Vehicle, axle: str, damping: float) -> Vehicle:
    return dataclasses.replace(vehicle, **{axle: dataclasses.replace(getattr(vehicle, axle), damping=damping)})


def _series(original: Vehicle, target: Vehicle, axle: str, rate: float) -> tuple[Vehicle, bool, str]:
    """The damper's series stiffness (wheel level) as a top mount, in series with one the axle already has;
    whether it was written, and a note on how."""
    mount = _holding("series")
    existing = original.extensions.get(mount.name, {}).get(axle)
    combined = rate if existing is None else 1.0 / (1.0 / rate + 1.0 / existing.rate)
    low, high = next((p.low, p.high) for p in mount.parameters() if p.key == "rate")
    if not low <= combined <= high:
        return target, False, (f"series stiffness {rate:.4g} N/m at the wheel not written: [{mount.name}] "
                               f"holds {low:g}..{high:g} N/m")
    how = "" if existing is None else f", in series with the axle's top mount of {existing.rate:.4g} N/m"
    note = (f"series stiffness {rate:.4g} N/m at the wheel as a top mount of {combined:.4g} N/m{how}; the model's "
            f"top mount carries {mount_mass(target.axle_named(axle).damping):.2g} kg, which the dyno's law does not")
    return _written(target, "series", axle, combined)[0], True, note


def _checked(vehicle: Vehicle) -> Vehicle:
    """The vehicle as its file reads back (``vehicle_from_dict`` of its TOML): refused as the file would be."""
    return vehicle_from_dict(tomllib.loads(vehicle_to_toml(vehicle)), vehicle.source or vehicle.name)
