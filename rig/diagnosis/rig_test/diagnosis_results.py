"""What a rig diagnosis found, as typed results: the verdict, the fitted candidates with their optimiser results
and parameter intervals, the remainder no cause explains, and the whole ``Diagnosis``; ``Diagnosis.to_json`` is
diagnosis.json (docs/contracts.md). Reports and Rerun take these results; the JSON is written from them.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import OptimizeResult

from rig.causes import CAUSES, Cause, FitParameter
from rig.diagnosis.rig_test.evidence import Evidence, Remainder
from rig.diagnosis.rig_test.force_laws import ForceLaws
from rig.diagnosis.core.holdout import Split
from rig.diagnosis.rig_test.input_chain import InputChain
from rig.diagnosis.core.integrity import Finding
from rig.diagnosis.core.timing import StageTime
from rig.io.record import Record
from rig.signal.residual_tests import ResidualTests
from rig.vehicle.vehicle_file import Vehicle

NOT_CAUSES = ("none", "unexplained")


class Verdict(tuple):
    """The verdict: the names of the causes found, best first, and ``unexplained`` when a remainder beyond the
    noise is left; ``none`` alone when nothing is. Prints as diagnosis.json writes it ('a+b'), and compares equal
    to that text too."""

    def __new__(cls, names: tuple[str, ...] | list[str]) -> Verdict:
        return super().__new__(cls, tuple(names) or ("none",))

    def __str__(self) -> str:
        return "+".join(self)

    def __eq__(self, other: object) -> bool:
        if isinstance(other, str):
            return str(self) == other
        return tuple.__eq__(self, other)

    def __ne__(self, other: object) -> bool:
        return not self == other

    __hash__ = tuple.__hash__

    @property
    def causes(self) -> tuple[str, ...]:
        """The names of causes of the vocabulary (without ``none`` and ``unexplained``)."""
        return tuple(n for n in self if n not in NOT_CAUSES)


@dataclass
class Candidate:
    """A fitted cause: its parameters (with units and confidence intervals from the optimiser's Jacobian), the
    extended vehicle, its held-out score and its gain on the model it was fitted on top of (``added_to``: the
    causes that model already had; none: the recalibrated model)."""

    effect: str
    params: dict[str, float]
    vehicle: Vehicle
    tddi_holdout: float
    simulated: np.ndarray = field(repr=False)  # held-out channels as compared (samples x Experiment.names)
    gain: float = 0.0
    n_params: int = 0
    parameters: list[FitParameter] = field(default_factory=list, repr=False)  # how params change a vehicle
    linear_values: np.ndarray | None = field(default=None, repr=False)  # from a joint fit with the linear ones
    fit: OptimizeResult | None = field(default=None, repr=False)       # the optimiser's result of its last fit
    intervals: dict[str, tuple[float, float]] = field(default_factory=dict)  # 95 % confidence intervals
    units: dict[str, str] = field(default_factory=dict)
    added_to: tuple[str, ...] = ()
    refined: bool = False         # fitted in the cause's richer form (``Cause.refined_parameters``)
    groups: str | None = None     # a sensor cause's channel groups, in words
    plausibility: str | None = None  # why a sensor cause's pattern is suspicious (``rig_test/sensors.py``)
    why_not: str | None = None    # why a cause past a threshold line is not named
    own_gain: float | None = None  # a named cause's share: the final model's held-out TDDI reduction over it without
    checked_first: bool = False   # an input channel's fault the records showed before any fit, corrected first
    alike: dict[str, str] = field(default_factory=dict)  # causes it gains alike with, the records cannot separate them

    @property
    def cause(self) -> Cause:
        return CAUSES[self.effect]

    def summary(self) -> dict:
        """The candidate's entry in diagnosis.json's ``causes``."""
        entry = {"effect": self.effect, "subsystem": self.cause.subsystem, "params": self.params,
                 "tddi_holdout": self.tddi_holdout, "gain": self.gain}
        extra = {"own_gain": self.own_gain, "units": self.units,
                 "intervals": {k: list(v) for k, v in self.intervals.items()},
                 "n_params": self.n_params, "added_to": list(self.added_to), "refined": self.refined,
                 "groups": self.groups, "plausibility": self.plausibility, "why_not": self.why_not,
                 "checked_first": self.checked_first, "alike": self.alike}
        return entry | {k: v for k, v in extra.items() if v not in (None, {}, [], False)}


@dataclass
class LinearFit:
    """The recalibration: scale factors of the data sheet's rates, damping and masses, with 95 % confidence
    intervals from the optimiser's Jacobian, and its result."""

    values: dict[str, float]
    intervals: dict[str, tuple[float, float]]
    result: OptimizeResult | None = field(default=None, repr=False)

    def to_json(self) -> dict:
        return {"factors": self.values, "intervals": {k: list(v) for k, v in self.intervals.items()}}


@dataclass
class Unexplained:
    """The remainder no named cause explains: where it lives, how far above the noise it is, the force-law shapes no
    named cause accounts for, and the generic element fitted to the recalibrated model in the named causes' place,
    with whether the extended model carries it."""

    where: Remainder
    tddi_holdout: float              # the held-out TDDI the model with the named causes leaves
    floor_multiple: float            # ... over the noise floor
    force_law_shapes: dict[str, list[str]] = field(default_factory=dict)  # corner -> shapes no named cause explains
    generic_extension: Candidate | None = None
    generic_carried: bool = False    # the extended model carries the generic element (else the named causes)

    def to_json(self) -> dict:
        document = self.where.to_json() | {"tddi_holdout": self.tddi_holdout, "floor_multiple": self.floor_multiple,
                                           "force_law_shapes": self.force_law_shapes}
        if self.generic_extension is not None:
            document["generic_extension"] = self.generic_extension.summary() | {"carried": self.generic_carried}
        return document


@dataclass(frozen=True)
class Shortfall:
    """A named cause that explains less than half of what it was fitted to, after its richer form was tried."""

    effect: str
    gain: float
    refined_tried: bool
    left: str  # what the remainder is, in words

    def text(self) -> str:
        return (f"{self.effect} explains {100 * self.gain:.0f} % of the discrepancy it was fitted to"
                + (" (its richer form tried)" if self.refined_tried else "") + f"; {self.left}")


@dataclass(frozen=True)
class DetectionLimit:
    """The held-out TDDI beyond which this record calls a model wrong (NONE_FACTOR times the noise floor), and
    whether the record is long enough to judge a model no cause explains (``reason`` says why not)."""

    tddi_holdout: float
    judged: bool
    reason: str = ""

    def to_json(self) -> dict:
        return {"tddi_holdout": self.tddi_holdout, "judged": self.judged} | ({"reason": self.reason} if self.reason
                                                                              else {})


@dataclass
class Step:
    """The evidence formed again after a cause is named: what the model then leaves on the held-out data."""

    named: tuple[str, ...]
    tddi_holdout: float
    where: Remainder


@dataclass(kw_only=True)
class Diagnosis:
    """What ``diagnose`` found; ``to_json`` is diagnosis.json. ``compared`` holds the held-out data as
    compared (analysis band): ``measured`` and as the ``recalibrated`` and ``extended`` models simulate it. Built by
    keyword: its three TDDIs and its vehicles stand side by side."""

    verdict: Verdict
    causes: list[Candidate]          # ranked: the named first, in the order they were named
    baseline_tddi: float
    recalibrated_tddi: float
    extended_tddi: float
    extended_vehicle: Vehicle
    recalibrated_vehicle: Vehicle
    findings: list[Finding]
    evidence: Evidence               # from the recalibrated model's held-out residual
    noise_floor: float               # TDDI that measurement noise alone would leave (rig/diagnosis/core/noise.py)
    compared: dict[str, Record]
    force_laws: ForceLaws            # measured from the data without a model form
    data_sheet: Vehicle              # the vehicle as given, before recalibration
    recalibration: LinearFit         # the linear parameters' fit (scale factors of the data sheet)
    band_hz: tuple[float, float]     # where channels were compared
    split: Split                     # the parts fitted and scored
    detection_limit: DetectionLimit
    unexplained: Unexplained | None = None
    named: list[Candidate] = field(default_factory=list)  # the causes the verdict names, in the order named
    shortfalls: list[Shortfall] = field(default_factory=list)
    steps: list[Step] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)  # what the reader must know (band narrowed, floor a bound...)
    stage_times: list[StageTime] = field(default_factory=list, repr=False)  # wall time of each step and fit (s)
    inputs: InputChain | None = None  # each input channel's gain on the responses, checked before any fit
    residual_tests: list[ResidualTests] = field(default_factory=list)  # the final model's, per held-out channel

    @property
    def verdict_text(self) -> str:
        return str(self.verdict)

    def to_json(self) -> dict:
        """The contract of diagnosis.json (docs/contracts.md)."""
        document = {"verdict": str(self.verdict), "causes": [c.summary() for c in self.causes],
                    "baseline": {"tddi_holdout": self.baseline_tddi},
                    "recalibrated": {"tddi_holdout": self.recalibrated_tddi} | self.recalibration.to_json(),
                    "extended": {"tddi_holdout": self.extended_tddi}, "noise_floor": {"tddi_holdout": self.noise_floor},
                    "detection_limit": self.detection_limit.to_json(), "band_hz": list(self.band_hz),
                    "holdout": self.split.to_json(), "integrity": [vars(f) for f in self.findings],
                    "evidence": self.evidence.to_json() | {"force_laws": self.force_laws.to_json(self.data_sheet)},
                    "shortfalls": [vars(s) | {"text": s.text()} for s in self.shortfalls],
                    "steps": [{"named": list(s.named), "tddi_holdout": s.tddi_holdout} | s.where.to_json()
                              for s in self.steps],
                    "notes": self.notes} | ({"input_chain": self.inputs.to_json()} if self.inputs else {})
        if self.unexplained is not None:
            document["unexplained"] = self.unexplained.to_json()
        if self.residual_tests:
            document["residual_tests"] = {t.model: t.to_json() for t in self.residual_tests}
        return document
