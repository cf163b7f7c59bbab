"""setuptools' build backend, with the FMUs put into the package first.

A wheel (or sdist) of cnc_motion_sim carries CncMotion.fmu and MachineStructure.fmu as package data
(cnc_motion_sim/fmu/). Built inside the repository, `make fmu` runs first: it rebuilds the FMUs when
the Rust sources changed and copies them into the package (a no-op when they are up to date; the
first time it compiles the crates, a few minutes). Outside the repository (an unpacked sdist) the
FMUs must already be there. Editable installs do not need them at build time."""
from __future__ import annotations

import pathlib
import shutil
import subprocess
import sys
from typing import Any

from setuptools import build_meta as _setuptools
from setuptools.build_meta import *  # noqa: F401,F403  (every other hook as setuptools has it)

PACKAGE = pathlib.Path(__file__).resolve().parents[1]
FMUS = [PACKAGE / "cnc_motion_sim" / "fmu" / name for name in ("CncMotion.fmu", "MachineStructure.fmu")]


def _put_fmus() -> None:
    root = PACKAGE.parent
    if (root / "Cargo.toml").is_file() and (root / "Makefile").is_file():
        make = shutil.which("make")
        if make is None:
            raise SystemExit("cnc-motion-sim: building the FMUs needs `make` (and Rust): run `make fmu` in "
                             f"{root} first")
        print(f"cnc-motion-sim: make -C {root} fmu (the FMUs shipped in the package)", file=sys.stderr)
        # make's output goes to stderr: pip shows it on failure (and with -v).
        subprocess.run([make, "-C", str(root), "fmu"], check=True, stdout=sys.stderr)
    missing = [str(p) for p in FMUS if not p.is_file()]
    if missing:
        raise SystemExit(f"cnc-motion-sim: {', '.join(missing)} missing: run `make fmu` in the repository")


def build_wheel(wheel_directory: str, config_settings: dict[str, Any] | None = None,
                metadata_directory: str | None = None) -> str:
    _put_fmus()
    return _setuptools.build_wheel(wheel_directory, config_settings, metadata_directory)


def build_sdist(sdist_directory: str, config_settings: dict[str, Any] | None = None) -> str:
    _put_fmus()
    return _setuptools.build_sdist(sdist_directory, config_settings)
