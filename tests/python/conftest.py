import os
import pathlib
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
# CI puts ../shared beside the clone; a git worktree may sit one level deeper.
SHARED = next((p / "shared" for p in (ROOT.parent, ROOT.parent.parent) if (p / "shared" / "corpus").is_dir()),
              ROOT.parent / "shared")
CLI = ROOT / os.environ.get("CARGO_TARGET_DIR", "target") / "release" / "cnc-motion"


@pytest.fixture(scope="session")
def cli():
    if not CLI.exists():
        subprocess.run(["cargo", "build", "--release", "--bin", "cnc-motion"], cwd=ROOT, check=True)
    return str(CLI)


# --- FMU fixtures (the FMUs are built through the Makefile if missing; never skipped) ------------
import sys  # noqa: E402

sys.path.insert(0, str(ROOT / "examples"))
import fmusim  # noqa: E402

CORPUS_PROGRAMS = sorted((SHARED / "corpus").glob("*.ngc"))


def _make_fmu():
    missing = [p for p in (fmusim.CNC_FMU, fmusim.STRUCTURE_FMU, fmusim.SSP) if not p.exists()]
    if missing:
        subprocess.run(["make", "fmu"], cwd=ROOT, check=True)
    for p in (fmusim.CNC_FMU, fmusim.STRUCTURE_FMU, fmusim.SSP):
        assert p.exists(), f"`make fmu` did not write {p}"


@pytest.fixture(scope="session")
def fmus():
    _make_fmu()
    return fmusim.CNC_FMU, fmusim.STRUCTURE_FMU


@pytest.fixture(scope="session")
def cnc(fmus):
    u = fmusim.Unpacked(fmus[0])
    yield u
    u.cleanup()


@pytest.fixture(scope="session")
def structure(fmus):
    u = fmusim.Unpacked(fmus[1])
    yield u
    u.cleanup()


@pytest.fixture(scope="session")
def ssp(fmus):
    return fmusim.SSP


# --- Known FMU defects found by this suite --------------------------------------------------------
# Each entry marks the matching tests xfail(strict=True): they still run, are reported as xfailed,
# and turn into a FAILURE as soon as the defect is fixed (then delete the entry). Keep it short.
KNOWN_FMU_ISSUES = {
    "test_two_way_coupling_stable_at_1ms":
        "with the tables' 50 kg on the frame (couplingMass, opt-in; 0 by default) the 1 ms Jacobi loop "
        "diverges after ~0.7 s through the 150 Hz z mode (Gauss-Seidel stays bounded, 205 N)",
}


def pytest_collection_modifyitems(config, items):
    for item in items:
        for key, reason in KNOWN_FMU_ISSUES.items():
            if key in item.nodeid:
                item.add_marker(pytest.mark.xfail(strict=True, reason="known FMU defect: " + reason))
