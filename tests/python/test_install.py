"""The package installs anywhere: a wheel built outside the repository carries the FMUs `make fmu`
built; installed (not editable) it runs examples/quickstart.py from another folder; its core needs
only fmpy and numpy."""
import importlib.metadata
import os
import pathlib
import shutil
import subprocess
import sys

from repo import CNC_FMU, EXAMPLES, ROOT
from test_quickstart import check_quickstart_output

CORE = ("fmpy", "numpy")
EXTRAS = ("matplotlib", "libcosimpy", "ecospy", "dask", "distributed")


def test_wheel_ships_the_fmus_and_runs_the_quickstart_elsewhere(fmus: tuple[pathlib.Path, pathlib.Path],
                                                                tmp_path: pathlib.Path) -> None:
    # python/ alone (as in an sdist): the build backend finds no repository around it and takes
    # the FMUs that `make fmu` copied into the package.
    src = tmp_path / "src"
    shutil.copytree(ROOT / "python", src, ignore=shutil.ignore_patterns("build", "*.egg-info", "__pycache__"))
    site = tmp_path / "site"
    res = subprocess.run([sys.executable, "-m", "pip", "install", "--quiet", "--no-deps", "--no-build-isolation",
                          "--target", str(site), str(src)], capture_output=True, text=True)
    assert res.returncode == 0, res.stdout + res.stderr
    for fmu in fmus:
        shipped = site / "cnc_motion_sim" / "fmu" / fmu.name
        assert shipped.read_bytes() == fmu.read_bytes(), f"{shipped} is not the FMU in {fmu.parent}"
    env = dict(os.environ, PYTHONPATH=str(site))
    where = subprocess.run([sys.executable, "-c", "import cnc_motion_sim; print(cnc_motion_sim.CNC_FMU)"],
                           cwd=tmp_path, env=env, capture_output=True, text=True, check=True).stdout
    assert where.strip() == str(site / "cnc_motion_sim" / "fmu" / "CncMotion.fmu")
    out = subprocess.run([sys.executable, str(EXAMPLES / "quickstart.py")], cwd=tmp_path, env=env,
                         capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    check_quickstart_output(out.stdout)


def test_core_dependencies_are_fmpy_and_numpy() -> None:
    requires = importlib.metadata.requires("cnc-motion-sim") or []
    assert sorted(r for r in requires if "extra ==" not in r) == sorted(CORE), requires


def test_simulate_runs_without_the_extras(fmus: tuple[pathlib.Path, pathlib.Path]) -> None:
    """Every module imports, and `simulate` runs, with the extras' packages made unimportable."""
    code = (f"import sys\nfor m in {EXTRAS!r}: sys.modules[m] = None\n"
            "import cnc_motion_sim as cms, cnc_motion_sim.cosim, cnc_motion_sim.ssp, cnc_motion_sim.sweep\n"
            f"res = cms.simulate(gcode='G21 G90 G1 X5 F600\\nM30\\n', fmu={str(CNC_FMU)!r})\n"
            "print(res['x.command.position'][-1])\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    assert abs(float(out.stdout) - 5e-3) < 1e-12
