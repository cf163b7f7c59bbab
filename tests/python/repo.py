"""Where the repository's files are, for the Python suite (the package itself knows none of them):
the FMUs `make fmu` writes, the CLI, the corpus and the examples."""
from __future__ import annotations

import importlib.util
import os
import pathlib
import sys
from types import ModuleType

ROOT = pathlib.Path(__file__).resolve().parents[2]
FMU_DIR = ROOT / "target" / "fmu"
CNC_FMU = FMU_DIR / "CncMotion.fmu"
STRUCTURE_FMU = FMU_DIR / "MachineStructure.fmu"
BIN = ROOT / os.environ.get("CARGO_TARGET_DIR", "target") / "release"
CLI = BIN / "cnc-motion"
CORPUS = ROOT / "corpus"
EXAMPLES = ROOT / "examples"
DEFAULT_PROGRAM = ROOT / "resources" / "default.ngc"


def _load(name: str, path: pathlib.Path) -> ModuleType:
    """The Python file `path` as module `name` (registered first: its dataclasses look it up)."""
    spec = importlib.util.spec_from_file_location(name, path)
    assert spec is not None and spec.loader is not None, path
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    spec.loader.exec_module(module)
    return module


# Issue 19's program families, one text for this suite and the LinuxCNC side-by-side (which runs
# with a plain python3, hence a file of the tool's own rather than a module of the package).
families = _load("linuxcnc_compare_families", ROOT / "tools" / "linuxcnc_compare" / "families.py")


def corpus_programs() -> list[pathlib.Path]:
    """The G-code programs of the corpus (corpus/README.md says where each comes from)."""
    return sorted(CORPUS.glob("*.ngc"))
