"""What a record must be before anything is computed from it: values a vehicle test can produce (a unit or
scaling slip is caught here, naming the channel and sample), channels that carry something, and the analysis
band its rate and length support (rig.constants.analysis_band); each refusal is one line naming the need."""

from __future__ import annotations

import numpy as np

from rig.constants import ANALYSIS_BAND, LOWEST_PERIODS, MIN_BAND_RATIO, TOP_SHARE_OF_RATE, analysis_band
from rig.io.channels import split_channel
from rig.io.record import Record, RecordError

#: the largest magnitude (SI) a quantity reaches in any vehicle test: beyond it a channel's unit or scale is
#: wrong (a displacement in mm read as m, a force in N read as kN) or the file is garbage
PLAUSIBLE_LIMIT = {
    "drive": 1.0, "actuator_disp": 1.0, "susp_travel": 1.0, "sprung_disp": 1.0, "unsprung_disp": 1.0,  # m
    "sprung_acc": 1e4, "unsprung_acc": 1e4,                                                          # m/s^2
    "susp_velocity": 100.0,                                                                          # m/s
    "tyre_force": 1e7, "actuator_force": 1e7, "control_force": 1e7, "active_force": 1e7,            # N
    "road": 1e4,                                                                                     # m
}


def check_plausible(record: Record, source: str) -> None:
    """Refuse a contract channel with a value no vehicle test produces, naming channel, value and sample."""
    for name, values in record.channels.items():
        limit = PLAUSIBLE_LIMIT.get(split_channel(name)[1])
        if limit is None or values.size == 0:
            continue
        worst = int(np.argmax(np.abs(values)))
        if abs(values[worst]) > limit:
            raise RecordError(f"{source}: {name} reaches {values[worst]:.3g} {record.units[name]} at sample "
                              f"{worst + 1}, beyond any vehicle test (±{limit:g} {record.units[name]}): a unit or "
                              f"scale error?")


def require_band(record: Record, source: str, command: str) -> tuple[float, float]:
    """The analysis band (Hz) ``record`` supports, or a refusal saying how long a record ``command`` needs."""
    band = analysis_band(record.rate, record.duration)
    if band is not None:
        return band
    top = min(ANALYSIS_BAND[1], TOP_SHARE_OF_RATE * record.rate)
    if top < MIN_BAND_RATIO * ANALYSIS_BAND[0]:
        need = f"a sample rate of at least {MIN_BAND_RATIO * ANALYSIS_BAND[0] / TOP_SHARE_OF_RATE:g} Hz"
    else:
        need = f"at least {LOWEST_PERIODS * MIN_BAND_RATIO / top:.3g} s at this rate"
    raise RecordError(f"{source}: the record is {record.duration:.3g} s at {record.rate:g} Hz; {command} needs {need} "
                      f"(two octaves of {ANALYSIS_BAND[0]:g}-{ANALYSIS_BAND[1]:g} Hz)")


def require_signal(record: Record, names: list[str], source: str) -> None:
    """Refuse channels that stay constant: nothing was measured (a disconnected sensor, an empty column)."""
    flat = [n for n in names if np.ptp(record[n]) == 0]
    if flat:
        listed = ", ".join(flat[:4]) + (f" and {len(flat) - 4} more" if len(flat) > 4 else "")
        raise RecordError(f"{source}: {listed} never change{'s' if len(flat) == 1 else ''} (constant "
                          f"{record[flat[0]][0]:g} {record.units[flat[0]]}): nothing was measured there")
