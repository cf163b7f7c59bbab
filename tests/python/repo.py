"""Where the repository's files are, for the Python suite (the package itself knows none of them):
the FMUs `make fmu` writes, the CLI, the corpus and the examples."""
from __future__ import annotations

import os
import pathlib

ROOT = pathlib.Path(__file__).resolve().parents[2]
FMU_DIR = ROOT / "target" / "fmu"
CNC_FMU = FMU_DIR / "CncMotion.fmu"
STRUCTURE_FMU = FMU_DIR / "MachineStructure.fmu"
BIN = ROOT / os.environ.get("CARGO_TARGET_DIR", "target") / "release"
CLI = BIN / "cnc-motion"
CORPUS = ROOT / "corpus"
EXAMPLES = ROOT / "examples"
DEFAULT_PROGRAM = ROOT / "resources" / "default.ngc"


def corpus_programs() -> list[pathlib.Path]:
    """The G-code programs of the corpus (corpus/README.md says where each comes from)."""
    return sorted(CORPUS.glob("*.ngc"))
