"""Where the project's files are: the clone (this package is installed editable from its
`python/` folder), the FMUs `make fmu` writes, the SSP, the default program and the corpus."""
from __future__ import annotations

import os
import pathlib

ROOT = pathlib.Path(os.environ.get("CNC_MOTION_ROOT", pathlib.Path(__file__).resolve().parents[2]))
FMU_DIR = ROOT / "target" / "fmu"
CNC_FMU = FMU_DIR / "CncMotion.fmu"
STRUCTURE_FMU = FMU_DIR / "MachineStructure.fmu"
SSP = ROOT / "examples" / "cosim.ssp"
DEFAULT_PROGRAM = ROOT / "resources" / "default.ngc"
CORPUS = ROOT / "corpus"
CLI = ROOT / os.environ.get("CARGO_TARGET_DIR", "target") / "release" / "cnc-motion"


def corpus_programs() -> list[pathlib.Path]:
    """The G-code programs of the corpus (corpus/README.md says where each comes from)."""
    return sorted(CORPUS.glob("*.ngc"))
