"""The Dask sweep on a 2-worker LocalCluster gives the serial results, case for case."""
import pathlib
import tempfile
import cnc_motion_sim as sim
from cnc_motion_sim import sweep


def test_sweep_local_cluster_equals_serial(fmus: tuple[pathlib.Path, pathlib.Path], tmp_path: pathlib.Path) -> None:
    prog = tmp_path / "short.ngc"
    prog.write_text("G21 G90 G17 G64\nG1 X20 F3000\nG1 Y10\nG0 X0 Y0\nM30\n")
    case_list = sweep.cases([prog], ["scurve7", "trapezoid"], [20000.0, 80000.0])
    serial = sweep.run_serial(case_list)
    unpacked = set(pathlib.Path(tempfile.gettempdir()).glob("CncMotion_*"))
    parallel = sweep.run_dask(case_list, n_workers=2)
    assert parallel == serial
    # Each worker unpacked the FMU into the temp folder; a closed cluster leaves none of it behind.
    assert set(pathlib.Path(tempfile.gettempdir()).glob("CncMotion_*")) == unpacked
    # The sweep sees the jerk limit: a lower limit takes longer.
    t = {(r["profile"], r["jerk_mm_s3"]): r["cycle_time_s"] for r in serial}
    assert t[("scurve7", 20000.0)] > t[("scurve7", 80000.0)]


def test_package_zip_for_remote_workers_imports(tmp_path: pathlib.Path) -> None:
    """What `run_dask(scheduler=...)` uploads: the package as a zip that a worker can import from."""
    import os
    import subprocess
    import sys

    z = sweep._package_zip(tmp_path)
    env = dict(os.environ, PYTHONPATH=str(z))
    out = subprocess.run([sys.executable, "-c", "import cnc_motion_sim.sweep as s; print(s.__file__)"],
                         cwd=tmp_path, env=env, capture_output=True, text=True, check=True).stdout
    assert out.strip() == str(z / "cnc_motion_sim" / "sweep.py")
