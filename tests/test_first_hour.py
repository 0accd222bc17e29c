"""What a new user meets first: bad output folders and inputs refused in one line before any work, degenerate inputs
named, a validation that says whether it passed and what to do next, a command line that imports no library before it
looks at its arguments."""

import os
import subprocess
import sys

import pytest

from rig.cli.main import main
from rig.diagnosis.rig_test.synthetic import hidden_cause_records
from rig.io.files import write_record
from rig.io.record import Record
from rig.vehicle.vehicle_file import load_vehicle


@pytest.fixture(scope="module")
def rig_test(tmp_path_factory):
    vehicle = load_vehicle("proton_x")
    measured, _, _ = hidden_cause_records(vehicle, "none", 3, duration=10.0, holdout_duration=2.0)
    path = tmp_path_factory.mktemp("records") / "measured.csv"
    write_record(path, measured)
    return path, measured


def refused(capsys, argv: list[str]) -> str:
    """The one line a refused command prints (exit status 2)."""
    with pytest.raises(SystemExit) as stopped:
        main(argv)
    assert stopped.value.code == 2
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1
    return lines[0]


def test_an_output_folder_under_a_file_is_refused_before_any_work(rig_test, tmp_path, capsys):
    path, _ = rig_test
    (tmp_path / "afile").write_text("x")
    line = refused(capsys, ["validate", "--vehicle", "proton_x", "--measured", str(path),
                            "--out", str(tmp_path / "afile" / "out")])
    assert f"{tmp_path / 'afile'} is a file, not a folder" in line


@pytest.mark.skipif(os.geteuid() == 0, reason="root may write in any folder: a read-only one cannot be made here")
def test_a_read_only_output_folder_is_refused_by_its_name(rig_test, tmp_path, capsys):
    path, _ = rig_test
    locked = tmp_path / "locked"
    locked.mkdir()
    locked.chmod(0o555)
    line = refused(capsys, ["validate", "--vehicle", "proton_x", "--measured", str(path), "--out", str(locked / "v")])
    assert f"cannot write in {locked} (permission denied)" in line


def test_missing_inputs_and_unknown_vehicles_are_refused_as_options_are_read(rig_test, tmp_path, capsys):
    path, _ = rig_test
    assert "no such file: nothing.csv" in refused(capsys, ["validate", "--vehicle", "proton_x", "--measured",
                                                           "nothing.csv"])
    line = refused(capsys, ["validate", "--vehicle", "proton_z", "--measured", str(path)])
    assert "'proton_z' is neither a vehicle file nor a built-in vehicle (" in line and "lab_quarter" in line


def test_iterating_into_an_earlier_runs_folder_is_refused_and_leaves_it_as_it_was(rig_test, tmp_path, capsys):
    path, _ = rig_test
    out = tmp_path / "iteration"
    out.mkdir()
    (out / "state.npz").write_bytes(b"an earlier run")
    assert main(["iterate", "--vehicle", "proton_x", "--target", str(path), "--out", str(out)]) == 2
    assert "holds an earlier drive iteration (state.npz): continue it with --resume" in capsys.readouterr().err
    assert (out / "state.npz").read_bytes() == b"an earlier run" and sorted(os.listdir(out)) == ["state.npz"]


def test_a_map_to_a_quantity_the_contract_lacks_is_named(rig_test, capsys):
    path, _ = rig_test
    assert main(["validate", "--vehicle", "proton_x", "--measured", str(path), "--map", "FL/sprung_acc=FL/bogus_qty",
                 "FL/actuator_disp=FL/actuator_disp"]) == 2
    err = capsys.readouterr().err
    assert "'FL/bogus_qty'" in err and "'bogus_qty' is not one of drive, actuator_disp" in err


def test_a_short_record_is_validated_in_the_band_it_supports_and_says_so(rig_test, tmp_path, capsys):
    _, measured = rig_test
    short = Record(measured.rate, {n: v[:256] for n, v in measured.channels.items()})  # 0.5 s at 512 Hz
    path = tmp_path / "short.csv"
    write_record(path, short)
    assert main(["validate", "--vehicle", "proton_x", "--measured", str(path), "--out", str(tmp_path / "v")]) == 0
    out = capsys.readouterr().out
    assert "note: analysis band narrowed to 8.00-50.0 Hz: a part of 0.5 s at 512 Hz" in out
    assert "analysis band narrowed to 8.00-50.0 Hz" in (tmp_path / "v" / "report.md").read_text()


def test_a_validation_says_what_ran_whether_it_passed_and_what_next(rig_test, tmp_path, capsys):
    path, _ = rig_test
    out = tmp_path / "v"
    assert main(["validate", "--vehicle", "proton_x", "--measured", str(path), "--out", str(out)]) == 0
    printed = capsys.readouterr().out
    report = (out / "report.md").read_text()
    assert f"Run: `rig validate --vehicle proton_x --measured {path} --out {out}`" in report
    verdict = next(line for line in printed.splitlines() if line.startswith(("passed:", "failed:")))
    assert f"**{verdict}**" in report
    # the data sheet misses the truth car by up to 3 %: beyond the noise of a 10 s record
    assert verdict.startswith("failed: mean TDDI") and "times this record's noise floor" in verdict
    assert f"`rig diagnose --vehicle proton_x --measured {path} --out diagnosis`" in report
    assert "next: name what the model gets wrong" in printed


def test_the_command_line_imports_no_library_before_it_reads_its_arguments():
    code = ("import sys, rig.cli.main; print(sorted(m for m in ('scipy', 'asammdf', 'pandas', 'mujoco', 'matplotlib') "
            "if m in sys.modules))")
    loaded = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout.strip()
    assert loaded == "[]"


def test_kc_on_a_car_without_linkages_says_its_zero_curves_are_zero_by_construction(tmp_path, capsys):
    assert main(["kc", "--vehicle", "proton_x", "--test", "travel", "--steps", "3", "--out", str(tmp_path)]) == 0
    note = capsys.readouterr().out.splitlines()[-1]
    assert note.startswith("note: proton_x's front and rear axle(s) have no linkage") and "zero by construction" in note
