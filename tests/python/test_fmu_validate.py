"""Both FMUs pass fmpy's validation and fmu-manipulation-toolbox's checker without findings."""
import pathlib
import subprocess
import sys

import pytest
from fmpy.validation import validate_fmu

from repo import FMU_DIR

FMUS = ["CncMotion", "MachineStructure"]


@pytest.mark.parametrize("name", FMUS)
def test_fmpy_validate_clean(fmus: tuple[pathlib.Path, pathlib.Path], name: str) -> None:
    path = FMU_DIR / f"{name}.fmu"
    problems = validate_fmu(str(path))
    assert problems == [], "\n".join(problems)
    # The command-line tool says the same (exit 0).
    res = subprocess.run([sys.executable, "-m", "fmpy", "validate", str(path)], capture_output=True, text=True)
    assert res.returncode == 0 and "No problems found." in res.stdout, res.stdout + res.stderr


@pytest.mark.parametrize("name", FMUS)
def test_fmutool_check_clean(fmus: tuple[pathlib.Path, pathlib.Path], name: str) -> None:
    path = FMU_DIR / f"{name}.fmu"
    fmutool = pathlib.Path(sys.executable).parent / "fmutool"
    cmd = [str(fmutool)] if fmutool.exists() else [sys.executable, "-m", "fmu_manipulation_toolbox.cli.fmutool"]
    res = subprocess.run(cmd + ["-input", str(path), "-check"], capture_output=True, text=True)
    text = res.stdout + res.stderr
    assert res.returncode == 0, text
    bad = [l for l in text.splitlines() if l.split("|")[0].strip() in ("WARNING", "ERROR", "FATAL")]
    assert bad == [], text
    assert "No semantic error" in text, text
