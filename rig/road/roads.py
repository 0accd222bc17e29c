"""Road profiles for virtual test-track runs: elevation of the left and right wheel tracks along the road.

Each builder returns a ``RoadProfile`` in SI with its provenance:
- ``iso8608_road``: random road of an ISO 8608 class (A-H), reproducible by seed, optional coherence
  between the tracks;
- ``bar_obstacle``: the 200 x 50 mm rectangular bar of Forsén (1999, "Obstacle", fig. 3) across one or both wheel paths;
- ``plywood_road``: an artificial road of wooden beams on plywood as in the neuro-model paper
  (fig. 7; the paper gives no dimensions, so the defaults are assumptions);
- ``sine_sweep`` and ``step``: deterministic inputs;
- ``measured_profile``: a measured longitudinal profile from a two-column text file (x, elevation);
- ``crg_road``: the wheel tracks of an ASAM OpenCRG surface at chosen lateral offsets.
``road_from_spec`` parses the command line's ``--road`` strings.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from rig.errors import RigError

SIDES = ("left", "right")

#: ISO 8608 displacement PSD Gd(n0) in m^3 at n0 = 0.1 cycle/m: geometric mean of each class (waviness 2).
ISO_8608_CLASSES = {c: 16e-6 * 4**i for i, c in enumerate("ABCDEFGH")}
ISO_8608_N0 = 0.1  # cycle/m


class RoadError(RigError):
    """A road that cannot be built or read; the message names the problem."""


@dataclass(frozen=True)
class RoadProfile:
    """Elevation (m) of the left and right wheel tracks, sampled every ``spacing`` m from distance 0."""

    spacing: float
    left: np.ndarray
    right: np.ndarray
    provenance: str

    def __post_init__(self) -> None:
        if not self.spacing > 0:
            raise RoadError(f"road sample spacing must be positive, got {self.spacing}")
        if self.left.shape != self.right.shape or self.left.ndim != 1 or self.left.size < 2:
            raise RoadError("left and right tracks must be 1-D arrays of the same length (at least 2 samples)")
        for side in SIDES:
            bad = np.flatnonzero(~np.isfinite(self.track(side)))
            if bad.size:
                raise RoadError(f"{side} track has a non-finite elevation at {bad[0] * self.spacing:.3f} m")

    @property
    def length(self) -> float:
        """Length covered by the samples in m."""
        return (self.left.size - 1) * self.spacing

    @property
    def distance(self) -> np.ndarray:
        return np.arange(self.left.size) * self.spacing

    def track(self, side: str) -> np.ndarray:
        if side not in SIDES:
            raise RoadError(f"side must be 'left' or 'right', got {side!r}")
        return self.left if side == "left" else self.right


def iso8608_road(road_class: str, length: float = 200.0, spacing: float = 0.05, seed: int = 0,
                 coherence: float = 0.0, band: tuple[float, float] = (0.01, 10.0)) -> RoadProfile:
    """Random road with the ISO 8608 displacement PSD Gd(n) = Gd(n0) (n / n0)^-2 of class ``road_class``.

    Harmonic superposition with deterministic amplitudes sqrt(2 Gd(n) dn) and random phases (seeded),
    over spatial frequencies ``band`` cycle/m. ``coherence`` in [0, 1] is the (constant, magnitude-squared)
    coherence between left and right tracks; each track has the class PSD whatever its value.
    """
    key = road_class.upper()
    if key not in ISO_8608_CLASSES:
        raise RoadError(f"ISO 8608 class must be one of {', '.join(ISO_8608_CLASSES)}, got {road_class!r}")
    if not 0.0 <= coherence <= 1.0:
        raise RoadError(f"coherence must lie in [0, 1], got {coherence}")
    if not length >= 2 * spacing:
        raise RoadError(f"road length must be at least two samples ({2 * spacing:g} m), got {length:g} m")
    if band[1] > 0.5 / spacing:
        raise RoadError(f"band up to {band[1]} cycle/m needs a spacing of at most {0.5 / band[1]} m")
    n = int(round(length / spacing)) + 1
    frequency = np.fft.rfftfreq(n, spacing)
    resolution = frequency[1]
    inside = (frequency >= band[0]) & (frequency <= band[1])
    psd = np.zeros_like(frequency)
    psd[inside] = ISO_8608_CLASSES[key] * (frequency[inside] / ISO_8608_N0) ** -2
    amplitude = np.sqrt(2 * psd * resolution)
    rng = np.random.default_rng(seed)
    phase_common, phase_left, phase_right = rng.uniform(0, 2 * np.pi, (3, frequency.size))
    shared = coherence**0.25  # amplitude share of the common part: coherence = shared^4
    own = np.sqrt(1 - shared**2)

    def track(phase_own: np.ndarray) -> np.ndarray:
        spectrum = amplitude * (shared * np.exp(1j * phase_common) + own * np.exp(1j * phase_own))
        # rfft convention: a cosine of amplitude A at line k has coefficient A n / 2
        return np.fft.irfft(spectrum * n / 2, n)

    return RoadProfile(spacing, track(phase_left), track(phase_right),
                       f"ISO 8608 class {key} (Gd(0.1) = {ISO_8608_CLASSES[key]:.4g} m^3), {length:g} m, "
                       f"seed {seed}, coherence {coherence:g}")


def bar_obstacle(sides: str = "both", position: float = 10.0, width: float = 0.2, height: float = 0.05,
                 length: float = 30.0, spacing: float = 0.005) -> RoadProfile:
    """Rectangular bar across ``sides`` ('both', 'left', 'right') at ``position`` m: Forsén's 200 x 50 mm."""
    distance = np.arange(int(round(length / spacing)) + 1) * spacing
    bar = np.where((distance >= position) & (distance < position + width), height, 0.0)
    return RoadProfile(spacing, bar if sides in ("both", "left") else np.zeros_like(bar),
                       bar if sides in ("both", "right") else np.zeros_like(bar),
                       f"rectangular bar {width * 1e3:g} x {height * 1e3:g} mm at {position:g} m, {sides} side(s) "
                       f"(Forsén's obstacle)")


def plywood_road(beam_height: float = 0.025, beam_width: float = 0.10, beam_spacing: float = 1.5, beams: int = 8,
                 start: float = 10.0, lead_out: float = 20.0, spacing: float = 0.005) -> RoadProfile:
    """Artificial road of ``beams`` wooden beams across both tracks (the neuro-model paper's fig. 7; dimensions
    ASSUMED)."""
    length = start + beams * beam_spacing + lead_out
    distance = np.arange(int(round(length / spacing)) + 1) * spacing
    offset = distance - start
    on_beam = (offset >= 0) & (offset < beams * beam_spacing) & (np.mod(offset, beam_spacing) < beam_width)
    profile = np.where(on_beam, beam_height, 0.0)
    return RoadProfile(spacing, profile, profile.copy(),
                       f"plywood road: {beams} beams {beam_width * 1e3:g} mm wide, {beam_height * 1e3:g} mm high, "
                       f"every {beam_spacing:g} m (the neuro-model paper's artificial road, dimensions assumed)")


def sine_sweep(start_wavelength: float = 20.0, end_wavelength: float = 0.5, amplitude: float = 0.005,
               length: float = 200.0, spacing: float = 0.01, sides: str = "both") -> RoadProfile:
    """Sine of constant ``amplitude`` whose wavelength sweeps logarithmically from start to end over ``length``."""
    distance = np.arange(int(round(length / spacing)) + 1) * spacing
    n0, n1 = 1 / start_wavelength, 1 / end_wavelength
    rate = np.log(n1 / n0) / length
    phase = 2 * np.pi * n0 * (np.exp(rate * distance) - 1) / rate
    wave = amplitude * np.sin(phase)
    return RoadProfile(spacing, wave if sides in ("both", "left") else np.zeros_like(wave),
                       wave if sides in ("both", "right") else np.zeros_like(wave),
                       f"log sine sweep {start_wavelength:g} m -> {end_wavelength:g} m wavelength, "
                       f"amplitude {amplitude * 1e3:g} mm, {sides} side(s)")


def step(height: float = 0.02, position: float = 10.0, rise: float = 0.0, length: float = 30.0,
         spacing: float = 0.005, sides: str = "both") -> RoadProfile:
    """Step of ``height`` m at ``position`` m, rising linearly over ``rise`` m (0: sharp edge)."""
    distance = np.arange(int(round(length / spacing)) + 1) * spacing
    profile = (height * np.clip((distance - position) / rise, 0, 1) if rise > 0
               else np.where(distance >= position, height, 0.0))
    return RoadProfile(spacing, profile if sides in ("both", "left") else np.zeros_like(profile),
                       profile if sides in ("both", "right") else np.zeros_like(profile),
                       f"step {height * 1e3:g} mm at {position:g} m over {rise:g} m, {sides} side(s)")


def measured_profile(path: str | os.PathLike) -> RoadProfile:
    """A measured longitudinal profile: whitespace text, columns distance (m) and elevation (m).

    The same profile is used for both wheel tracks. Distance must be uniformly spaced.
    """
    path = Path(path)
    try:
        table = np.loadtxt(path, ndmin=2)
    except (OSError, ValueError) as err:
        raise RoadError(f"{path}: not a two-column profile of numbers ({err})") from None
    if table.shape[1] < 2 or table.shape[0] < 2:
        raise RoadError(f"{path}: expected two columns (distance m, elevation m), got shape {table.shape}")
    distance, elevation = table[:, 0], table[:, 1]
    steps = np.diff(distance)
    spacing = float(np.median(steps))
    bad = np.flatnonzero(np.abs(steps - spacing) > 1e-6 * max(1.0, abs(distance[-1])))
    if spacing <= 0 or bad.size:
        row = bad[0] + 2 if bad.size else 1
        raise RoadError(f"{path}: distance is not uniformly increasing at row {row}")
    return RoadProfile(spacing, elevation.copy(), elevation.copy(),
                       f"measured profile {path.name}: {distance[0]:g}-{distance[-1]:g} m every {spacing:g} m")


def crg_road(path: str | os.PathLike, left_offset: float = 0.75, right_offset: float = -0.75) -> RoadProfile:
    """Wheel tracks of an OpenCRG surface at lateral offsets (m, left positive) from its reference line."""
    from rig.road.opencrg import read_opencrg

    try:
        surface = read_opencrg(path)
    except (OSError, ValueError) as err:  # the reader's messages name the file
        raise RoadError(str(err)) from None
    try:
        left, right = surface.long_section(left_offset), surface.long_section(right_offset)
    except ValueError as err:
        raise RoadError(f"{path}: {err}") from None
    return RoadProfile(float(surface.u[1] - surface.u[0]), left, right,
                       f"OpenCRG {Path(path).name}: tracks at v = {left_offset:+g} m and {right_offset:+g} m")


def road_from_spec(spec: str) -> RoadProfile:
    """Build a road from a command-line spec ``kind[:key=value,...]`` or a file path.

    Kinds: ``iso8608`` (class, length, spacing, seed, coherence), ``bar`` (sides, position, width,
    height, length), ``plywood``, ``sweep`` (start_wavelength, end_wavelength, amplitude, length),
    ``step`` (height, position, rise, length), ``profile`` (path), ``crg`` (path, left, right).
    A bare ``*.crg`` path is an OpenCRG surface; any other existing file is a measured profile.
    Examples: ``iso8608:class=C,length=500,seed=2``, ``bar:sides=right``, ``crg:path=road.crg,left=0.8``.
    """
    if Path(spec).is_file():
        return crg_road(spec) if spec.lower().endswith(".crg") else measured_profile(spec)
    kind, _, rest = spec.partition(":")
    options: dict[str, str] = {}
    for item in filter(None, rest.split(",")):
        key, sep, value = item.partition("=")
        if not sep:
            raise RoadError(f"road spec '{spec}': '{item}' is not key=value")
        options[key.strip()] = value.strip()
    builders = {
        "iso8608": (iso8608_road, {"class": ("road_class", str), "length": ("length", float),
                                   "spacing": ("spacing", float), "seed": ("seed", int),
                                   "coherence": ("coherence", float)}),
        "bar": (bar_obstacle, {"sides": ("sides", str), "position": ("position", float), "width": ("width", float),
                               "height": ("height", float), "length": ("length", float)}),
        "plywood": (plywood_road, {"height": ("beam_height", float), "beams": ("beams", int),
                                   "beam_spacing": ("beam_spacing", float)}),
        "sweep": (sine_sweep, {"start_wavelength": ("start_wavelength", float),
                               "end_wavelength": ("end_wavelength", float), "amplitude": ("amplitude", float),
                               "length": ("length", float), "sides": ("sides", str)}),
        "step": (step, {"height": ("height", float), "position": ("position", float), "rise": ("rise", float),
                        "length": ("length", float), "sides": ("sides", str)}),
        "profile": (measured_profile, {"path": ("path", str)}),
        "crg": (crg_road, {"path": ("path", str), "left": ("left_offset", float), "right": ("right_offset", float)}),
    }
    if kind not in builders:
        raise RoadError(f"unknown road '{spec}': not a file, and kind '{kind}' is not one of {', '.join(builders)}")
    builder, known = builders[kind]
    unknown = sorted(set(options) - set(known))
    if unknown:
        raise RoadError(f"road spec '{spec}': unknown option(s) {', '.join(unknown)} for {kind} "
                        f"(known: {', '.join(known)})")
    try:
        kwargs = {known[k][0]: known[k][1](v) for k, v in options.items()}
    except ValueError as err:
        raise RoadError(f"road spec '{spec}': {err}") from None
    if kind == "iso8608" and "road_class" not in kwargs:
        raise RoadError(f"road spec '{spec}': iso8608 needs class=A..H")
    return builder(**kwargs)
