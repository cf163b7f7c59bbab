"""`machineFile` through fmpy: seed 003's pocket (`T1 D1 M06`, `G54`, `G41`) needs the tool table of its
machine file; with `run_cnc(..., machine_file=...)` it runs in the FMU and ends where the command line
(`cnc-motion run corpus/seed003_pocket.txt --machine examples/machines/seed003_pocket.toml`) ends: the
same end point and the same finishing tick. Without the file the FMU refuses the program, located."""
import json
import subprocess

import pytest

import cnc_motion_sim as sim
from repo import CORPUS, ROOT

POCKET = CORPUS / "seed003_pocket.txt"
MACHINE = ROOT / "examples" / "machines" / "seed003_pocket.toml"


def test_seed003_pocket_with_its_machine_file_ends_where_the_cli_ends(cli: str, cnc: sim.Unpacked) -> None:
    res = subprocess.run([cli, "run", str(POCKET), "--machine", str(MACHINE), "--servo", "--json"],
                         capture_output=True, text=True)
    assert res.returncode == 0, res.stderr
    want = json.loads(res.stdout)
    r = sim.run_cnc(cnc, {"programFile": str(POCKET)}, machine_file=MACHINE,
                    names=["x.command.position", "y.command.position", "z.command.position", "status.finished"])
    end_mm = [r[f"{a}.command.position"][-1] * 1e3 for a in "xyz"]
    assert end_mm == pytest.approx(want["end_position_mm"], abs=1e-9)
    # The CLI's total time is the time of its first tick with all motion done, as the FMU's.
    assert r["t_finished"] == pytest.approx(want["total_time_s"], abs=1e-9)


def test_without_its_machine_file_the_pocket_is_refused_with_its_place(cnc: sim.Unpacked) -> None:
    s = sim.Slave(cnc, "no-file")
    try:
        with pytest.raises(sim.FmuError, match=r":5:5: D1: tool 1 is not in the machine's tool table"):
            s.initialize({"programFile": str(POCKET)})
    finally:
        s.fmu.freeInstance()
