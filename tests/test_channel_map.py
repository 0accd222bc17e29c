"""Channel maps (contract: docs/contracts.md): DAQ names onto the contract, units from the file unless the map says,
unmapped channels listed, every refusal one line that names the channels; CSV and RPC III files too."""

import numpy as np
import pytest

from rig.cli.main import main
from rig.io.channel_map import ChannelMap, MapEntry, load_channel_map, map_from_option
from rig.io.files import read_record
from rig.io.record import RecordError
from rig.io.units import STANDARD_GRAVITY

BELGIAN_BLOCK = "belgian_block_20kph_wheel_acc.rsp"

MAP = """
[channels]
"PostDisp_LF" = "FL/actuator_disp"                                  # unit from the file's metadata
"ACC_LF_BODY" = { name = "FL/sprung_acc", unit = "g", scale = -1.0 }  # explicit unit / sign
"""


def daq_csv(path, header="time [s],PostDisp_LF [mm],ACC_LF_BODY [G],Oil_Temp [degC]"):
    """A DAQ export: its own names, a unit the units table does not know (G), a channel nobody maps."""
    time = np.arange(512) / 512.0
    table = np.column_stack([time, 10 * np.sin(2 * np.pi * 3 * time), 0.5 * np.cos(2 * np.pi * 7 * time),
                             np.full(time.size, 80.0)])
    np.savetxt(path, table, delimiter=",", fmt="%.17g", header=header, comments="")
    return path, table


def write_map(tmp_path, text=MAP):
    path = tmp_path / "map.toml"
    path.write_text(text)
    return path


def test_map_renames_converts_and_lists_the_unmapped_channel(tmp_path):
    path, table = daq_csv(tmp_path / "daq.csv")
    record = read_record(path, channel_map=load_channel_map(write_map(tmp_path)))
    assert record.names == ["FL/actuator_disp", "FL/sprung_acc"]
    assert record.units == {"FL/actuator_disp": "m", "FL/sprung_acc": "m/s^2"}
    np.testing.assert_allclose(record["FL/actuator_disp"], table[:, 1] * 1e-3, rtol=1e-15)
    np.testing.assert_allclose(record["FL/sprung_acc"], -table[:, 2] * STANDARD_GRAVITY, rtol=1e-15)
    assert record.metadata["unmapped"] == f"1 channel(s) not in {tmp_path / 'map.toml'} ignored: Oil_Temp"


def test_inline_pairs_accept_a_unique_part_of_a_name():
    channel_map = map_from_option(["LF_=FL/unsprung_acc", "RF_=FR/unsprung_acc"])
    assert channel_map == ChannelMap((MapEntry("LF_", "FL/unsprung_acc"), MapEntry("RF_", "FR/unsprung_acc")),
                                     "--map")
    assert map_from_option(None) is None


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ('[channels]\n"Missing_CH" = "FL/sprung_acc"\n',
         (r"map.toml: channel 'Missing_CH' \(for 'FL/sprung_acc'\) is not in .*daq.csv "
          r"\(it has: PostDisp_LF, ACC_LF_BODY, Oil_Temp\)$")),
        ('[channels]\n"PostDisp_LF" = "FL/actuator_disp"\n"ACC_LF_BODY" = { name = "FL/actuator_disp", unit = "g" }\n',
         r"map.toml: channels 'PostDisp_LF' and 'ACC_LF_BODY' of .*daq.csv are both mapped to 'FL/actuator_disp'$"),
        ('[channels]\n"ACC_LF_BODY" = "FL/sprung_acc"\n',
         r"daq.csv: channel 'ACC_LF_BODY' \(header column 3\): unknown unit 'G' \(known: .*\)$"),
        ('[channels]\n"ACC_LF_BODY" = { name = "FL/sprung_acc", unit = "furlong" }\n',
         r"daq.csv: channel 'ACC_LF_BODY' \(unit from .*map.toml\): unknown unit 'furlong' \(known: .*\)$"),
        ('[channels]\n"PostDisp_LF" = "FL/sprung_acc"\n',
         r"daq.csv: channel 'PostDisp_LF' \(header column 2\) in 'mm' cannot be 'FL/sprung_acc', which is in m/s\^2$"),
    ],
    ids=["missing", "two-sources", "unknown-file-unit", "unknown-map-unit", "wrong-kind"],
)
def test_bad_maps_are_refused_naming_the_channels(tmp_path, text, message):
    path, _ = daq_csv(tmp_path / "daq.csv")
    with pytest.raises(RecordError, match=message):
        read_record(path, channel_map=load_channel_map(write_map(tmp_path, text)))


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ('"PostDisp_LF" = "FL/actuator_disp"\n', r"needs a \[channels\] table"),
        ("[channels]\nPostDisp_LF = \n", r"not valid TOML"),
        ('[channels]\n"PostDisp_LF" = 3\n', r"entry 'PostDisp_LF' must be"),
        ('[channels]\n"PostDisp_LF" = { unit = "mm" }\n', r"entry 'PostDisp_LF' must be"),
        ('[channels]\n"PostDisp_LF" = { name = "FL/actuator_disp", gain = 2 }\n', r"entry 'PostDisp_LF' must be"),
        ('[channels]\n"PostDisp_LF" = { name = "FL/actuator_disp", scale = 0 }\n',
         r"entry 'PostDisp_LF': scale must be a non-zero number, got 0"),
        ('[channels]\n"PostDisp_LF" = { name = "FL/actuator_disp", scale = "-1" }\n',
         r"entry 'PostDisp_LF': scale must be a non-zero"),
        ('[channels]\n"PostDisp_LF" = { name = "FL/actuator_disp", unit = 1 }\n',
         r"entry 'PostDisp_LF': name and unit must be strings"),
    ],
)
def test_malformed_map_files_are_refused_naming_the_entry(tmp_path, text, message):
    with pytest.raises(RecordError, match=rf"^channel map .*map.toml: {message}"):
        load_channel_map(write_map(tmp_path, text))


def test_inline_refusals():
    with pytest.raises(RecordError, match=r"--map item 'FL/sprung_acc' is not FROM=TO"):
        map_from_option(["ACC=FL/sprung_acc", "FL/sprung_acc"])
    with pytest.raises(RecordError, match=r"channel map nothing.toml: cannot read it"):
        map_from_option(["nothing.toml"])


def test_ambiguous_part_of_a_name_is_refused(tmp_path):
    path, _ = daq_csv(tmp_path / "daq.csv")
    with pytest.raises(RecordError, match=r"--map: 'LF' \(for 'FL/actuator_disp'\) matches 2 channels of .*daq.csv "
                                          r"\(PostDisp_LF, ACC_LF_BODY\)$"):
        read_record(path, channel_map=map_from_option(["LF=FL/actuator_disp"]))


def test_a_contract_channel_without_a_unit_asks_for_one_in_a_map(tmp_path):
    path, _ = daq_csv(tmp_path / "daq.csv", header="time [s],FL/actuator_disp [],ACC [g],T [degC]")
    with pytest.raises(RecordError, match=r"channel 'FL/actuator_disp' \(header column 2\) without a unit cannot be "
                                          r"'FL/actuator_disp', which is in m; give its unit in a channel map$"):
        read_record(path, channel_map=map_from_option(["FL/actuator_disp=FL/actuator_disp"]))
    record = read_record(path, channel_map=load_channel_map(write_map(
        tmp_path, '[channels]\n"FL/actuator_disp" = { name = "FL/actuator_disp", unit = "mm" }\n')))
    assert record["FL/actuator_disp"].max() == pytest.approx(10e-3, rel=1e-3)


def test_belgian_block_rpc3_through_a_map(real_data, tmp_path):
    """The real file: six wheel accelerometers, two of them (LM, RM) on a middle axle the rig lacks."""
    direct = read_record(real_data / BELGIAN_BLOCK)
    text = "[channels]\n" + "".join(
        f'"WFT{1 if daq in ("LF", "RF") else 2}@{daq}_Z_Acceler.RN_1" = "{corner}/unsprung_acc"\n'
        for daq, corner in (("LF", "FL"), ("RF", "FR"), ("LR", "RL"), ("RR", "RR")))
    text += '"WFT2@LM_Z_Acceler.RN_1" = { name = "FL/sprung_acc", unit = "m/s^2", scale = 0.5 }\n'
    record = read_record(real_data / BELGIAN_BLOCK, channel_map=load_channel_map(write_map(tmp_path, text)))
    assert record.rate == 256.0 and record.n_samples == 76688
    assert record.names == ["FL/unsprung_acc", "FR/unsprung_acc", "RL/unsprung_acc", "RR/unsprung_acc",
                            "FL/sprung_acc"]
    np.testing.assert_array_equal(record["FL/unsprung_acc"], direct["WFT1@LF_Z_Acceler.RN_1"])
    np.testing.assert_array_equal(record["RR/unsprung_acc"], direct["WFT2@RR_Z_Acceler.RN_1"])
    # the map's unit overrides the header's g: raw values in g read as m/s^2, halved
    np.testing.assert_allclose(record["FL/sprung_acc"],
                               0.5 * direct["WFT2@LM_Z_Acceler.RN_1"] / STANDARD_GRAVITY, rtol=1e-15)
    assert record["FL/unsprung_acc"].max() / STANDARD_GRAVITY == pytest.approx(13.811293, abs=1e-3)  # header stats
    assert record.metadata["unmapped"].endswith("ignored: WFT2@RM_Z_Acceler.RN_1")


def test_cli_says_what_it_left_out_once_and_refuses_in_one_line(tmp_path, capsys):
    path, _ = daq_csv(tmp_path / "daq.csv")
    bad = write_map(tmp_path, '[channels]\n"PostDisp_LF" = "FL/actuator_disp"\n"Oil_Temp" = "FL/sprung_acc"\n')
    assert main(["replay", "--vehicle", "proton_x", "--drive", str(path), "--out", str(tmp_path / "r.csv"),
                 "--map", str(bad)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1
    assert "rig replay: error: " in err
    assert "channel 'Oil_Temp' (header column 4) in 'degC' cannot be 'FL/sprung_acc'" in err
