"""What a bump stop and a rebound stop share: a dead-band spring per axle with a gap, a rate and a quadratic rise,
one set of values on every axle, fitted (gap and rate, the rise in the richer form) and hidden alike; each cause
says on which side of static ride height it acts."""

from __future__ import annotations

import dataclasses

from rig.causes._base import AxleCause, FitParameter


class StopCause(AxleCause):
    """An axle cause whose ``values`` dataclass is a stop: ``gap`` (m), ``rate`` (N/m), ``quadratic`` (N/m^2)."""

    subsystem = "car"
    fine_step = True  # a stop in contact (a vehicle file may give 1e8 N/m) is a wheel mode faster than a coarse step

    def fit_parameters(self, vehicle, hints=None):
        return [FitParameter("gap", 0.02, 0.003, 0.05, lambda v, g: self._with(v, gap=g), unit="m"),
                FitParameter("rate", 5e4, 1e3, 1e6, lambda v, k: self._with(v, rate=k), unit="N/m")]

    def refined_parameters(self, vehicle, hints=None):
        """A stop that stiffens as it is pressed (an elastomer's rise): its rate grows by 2 quadratic d."""
        return [*self.fit_parameters(vehicle, hints),
                FitParameter("quadratic", 1e6, 0.0, 5e7, lambda v, q: self._with(v, quadratic=q), unit="N/m^2")]

    def _with(self, vehicle, **values):
        current = next(iter(vehicle.extensions.get(self.name, {}).values()), self.values(0.02, 1e5))
        return self.on_every_axle(vehicle, lambda a: dataclasses.replace(current, **values))

    def hidden(self, truth, rng):
        gap, rate = rng.uniform(0.012, 0.018), rng.uniform(1e5, 2e5)
        return self.on_every_axle(truth, lambda a: self.values(gap, rate))
