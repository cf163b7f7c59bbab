"""cnc_motion_sim.simulate, the package's three-line API, against the CLI's `run` of the same
program on the same machine (the engine without the FMU in between)."""
import json
import pathlib
import subprocess

import numpy as np
import pytest

import cnc_motion_sim as cms
from repo import CNC_FMU, CORPUS, DEFAULT_PROGRAM

AXES = "xyz"


def cli_run(cli: str, program: pathlib.Path, machine: pathlib.Path | None = None) -> dict:
    args = [cli, "run", str(program), "--json"] + (["--machine", str(machine)] if machine else [])
    res = subprocess.run(args, capture_output=True, text=True)
    assert res.returncode == 0, res.stderr
    return json.loads(res.stdout)


def assert_same_run(res: cms.Result, ref: dict) -> None:
    """Same finishing tick, end point and path length as the CLI (mm there, m here)."""
    assert res.finished_at == pytest.approx(ref["total_time_s"], abs=1e-9)
    end = [res[f"{a}.command.position"][-1] * 1e3 for a in AXES]
    np.testing.assert_allclose(end, ref["end_position_mm"], atol=1e-9)
    assert res["path.distance"][-1] * 1e3 == pytest.approx(ref["path_length_mm"], rel=1e-9)


def test_program_file_equals_cli(fmus: tuple[pathlib.Path, pathlib.Path], cli: str) -> None:
    res = cms.simulate(DEFAULT_PROGRAM, fmu=CNC_FMU)
    assert_same_run(res, cli_run(cli, DEFAULT_PROGRAM))
    assert np.all(np.diff(res.time) > 0) and res.time[0] == 0.0
    assert set(cms.cnc_outputs(cms.Unpacked(CNC_FMU))) <= set(res)


def test_profile_equals_cli_machine_profile(fmus: tuple[pathlib.Path, pathlib.Path], cli: str,
                                            tmp_path: pathlib.Path) -> None:
    machine = tmp_path / "trapezoid.toml"
    machine.write_text('profile = "trapezoid"\n')
    ref = cli_run(cli, DEFAULT_PROGRAM, machine)
    res = cms.simulate(gcode=DEFAULT_PROGRAM.read_text(), profile="trapezoid", fmu=CNC_FMU,
                       outputs=["x.command.position", "y.command.position", "z.command.position", "path.distance"])
    assert_same_run(res, ref)
    assert ref["total_time_s"] != cli_run(cli, DEFAULT_PROGRAM)["total_time_s"], "the profile matters"


def test_machine_file_equals_cli(fmus: tuple[pathlib.Path, pathlib.Path], cli: str) -> None:
    """The machine file as the FMU's `machineFile` parameter (known FMU issue until it has one)."""
    program, machine = CORPUS / "pessoles_linear.ngc", CORPUS / "dmu50_840d.toml"
    assert_same_run(cms.simulate(program, machine, fmu=CNC_FMU), cli_run(cli, program, machine))


def test_bad_program_raises_with_its_place(fmus: tuple[pathlib.Path, pathlib.Path], tmp_path: pathlib.Path) -> None:
    program = tmp_path / "bad.ngc"
    program.write_text("G21 G90\nG1 X1 F100\nG33 Z-1 K1\n")
    with pytest.raises(cms.FmuError, match=r"bad\.ngc:3:1: unsupported G33") as err:
        cms.simulate(program, fmu=CNC_FMU)
    assert err.value.status == 3  # fmi2Error
    with pytest.raises(FileNotFoundError, match="missing.ngc"):
        cms.simulate(tmp_path / "missing.ngc", fmu=CNC_FMU)


def test_default_program_is_the_fmus(fmus: tuple[pathlib.Path, pathlib.Path]) -> None:
    assert cms.default_program(CNC_FMU) == DEFAULT_PROGRAM.read_text()
