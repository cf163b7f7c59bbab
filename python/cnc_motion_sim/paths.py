"""The FMUs this package was built with, shipped inside it as package data (`cnc_motion_sim/fmu/`).

`make fmu` packages both FMUs into `target/fmu/` and copies them here; building the wheel
(`pip install ./python`) runs `make fmu` first when the copies are missing or older than the
sources (python/build_support/backend.py). The package knows nothing else of the repository:
programs and machine files are the caller's."""
from __future__ import annotations

import os
import pathlib
import zipfile

FMU_DIR = pathlib.Path(__file__).resolve().parent / "fmu"
CNC_FMU = FMU_DIR / "CncMotion.fmu"
STRUCTURE_FMU = FMU_DIR / "MachineStructure.fmu"

PathLike = str | os.PathLike[str]


def fmu_file(path: PathLike | None = None, default: pathlib.Path = CNC_FMU) -> pathlib.Path:
    """`path`, or the shipped FMU; a clear error when the file is not there."""
    p = pathlib.Path(path) if path is not None else default
    if not p.is_file():
        hint = ("this installation of cnc_motion_sim has no FMU: build it from the repository with "
                "`make fmu`, then `pip install ./python`" if path is None else "no such file")
        raise FileNotFoundError(f"{p}: {hint}")
    return p


def default_program(fmu: PathLike | None = None) -> str:
    """The G-code program the FMU runs when neither `program` nor `programFile` is set (its
    resources/default.ngc)."""
    with zipfile.ZipFile(fmu_file(fmu)) as z:
        return z.read("resources/default.ngc").decode()
