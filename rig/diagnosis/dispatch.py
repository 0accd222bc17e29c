"""Which diagnosis a test's records get: a rig test (one record) the rig diagnosis, track tests (records driven on
the road, one per constant speed) the track diagnosis; rig and track records are not mixed."""

from __future__ import annotations

from collections.abc import Callable, Sequence

from rig.diagnosis.rig_test.diagnose import Diagnosis, diagnose
from rig.diagnosis.track.track_diagnosis import TrackDiagnosis, diagnose_track
from rig.diagnosis.track.unbalance import is_track_record
from rig.io.record import Record, RecordError
from rig.vehicle.vehicle_file import Vehicle


def diagnose_records(vehicle: Vehicle, records: Sequence[Record], holdout: Record | None = None,
                     names: Sequence[str] = (), progress: Callable[[str], None] | None = None
                     ) -> Diagnosis | TrackDiagnosis:
    """Diagnose ``records`` (``holdout``: the record to score on) by the kind of test they hold; ``names`` (file
    names, the hold-out's last) only word the errors."""
    everything = [*records, *([holdout] if holdout is not None else [])]
    names = list(names) or [f"record {i + 1}" for i in range(len(everything))]
    if any(is_track_record(r) for r in records):
        mixed = [name for name, r in zip(names, everything) if not is_track_record(r)]
        if mixed:
            raise RecordError(f"{', '.join(mixed)}: not a track record ('# test: track'); rig and track tests are "
                              f"diagnosed apart")
        return diagnose_track(vehicle, list(records), holdout, progress=progress)
    if len(records) > 1:
        raise RecordError("a rig test is one measured record (several are taken only as track tests at several speeds)")
    try:
        return diagnose(vehicle, records[0], holdout, progress=progress)
    except RecordError as err:
        raise RecordError(f"{names[0]}: {err}") from None
