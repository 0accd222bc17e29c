"""RPC III through rpc3-file: scaling of the real Belgian-block file, round trips within resolution."""

import numpy as np
import pytest

from rig.io.files import read_record, write_record
from rig.io.record import Record
from rig.io.units import STANDARD_GRAVITY

BELGIAN_BLOCK = "belgian_block_20kph_wheel_acc.rsp"


def test_belgian_block_scaling_matches_the_header_statistics(real_data):
    record = read_record(real_data / BELGIAN_BLOCK)
    assert record.rate == 256.0
    assert len(record.names) == 6
    assert record.n_samples == 76688
    rms_g = np.array([np.sqrt(np.mean(record[n] ** 2)) for n in record.names]) / STANDARD_GRAVITY
    assert np.all((rms_g > 1.9) & (rms_g < 2.6)), rms_g
    # nCode statistics in the header of channel 1 (LF): max 13.811293 g, min -12.297795 g, RMS 2.4940565 g
    lf = record["WFT1@LF_Z_Acceler.RN_1"] / STANDARD_GRAVITY
    assert lf.max() == pytest.approx(13.811293, abs=1e-3)
    assert lf.min() == pytest.approx(-12.297795, abs=1e-3)
    assert np.sqrt(np.mean(lf**2)) == pytest.approx(2.4940565, rel=2e-3)


@pytest.mark.parametrize("suffix", [".rsp", ".drv"])
def test_round_trip_within_the_16_bit_resolution(tmp_path, suffix):
    rng = np.random.default_rng(1)
    original = Record(512.0, {"FL/drive": 0.01 * rng.standard_normal(5000),
                              "FR/drive": 0.02 * rng.standard_normal(5000)},
                      metadata={"vehicle": "proton_x"})
    path = tmp_path / f"drive{suffix}"
    write_record(path, original)
    again = read_record(path)
    assert again.rate == 512.0
    assert again.names == original.names
    assert again.metadata["vehicle"] == "proton_x"
    for name in original.names:
        resolution = np.abs(original[name]).max() / 32752  # int16 full scale used by rpc3-file
        assert np.abs(again[name] - original[name]).max() <= resolution  # half a step plus float32 rounding


def test_real_file_round_trips_through_our_writer(tmp_path, real_data):
    record = read_record(real_data / BELGIAN_BLOCK)
    write_record(tmp_path / "copy.rsp", record)
    again = read_record(tmp_path / "copy.rsp")
    for name in record.names:
        resolution = np.abs(record[name]).max() / 32752
        assert np.abs(again[name] - record[name]).max() <= resolution
