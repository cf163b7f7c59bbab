"""Fixtures of the Python suite: the CLI, both FMUs of target/fmu (built through `make fmu` when
missing; never skipped), unpacked once per session, their SSP, and the feed laws read from
CncMotion's modelDescription.

A test asking for `profile` runs once per item of the FMU's `machine.profile` Enumeration;
`jerk_limited_profile` the same without `trapezoid` (the one law without a jerk limit)."""
import pathlib
import subprocess
from collections.abc import Iterator

import pytest

from cnc_motion_sim import Unpacked, profiles as fmu_profiles
from cnc_motion_sim.ssp import make_ssp
from repo import CLI, CNC_FMU, CORPUS, ROOT, STRUCTURE_FMU


@pytest.fixture(scope="session")
def root() -> pathlib.Path:
    return ROOT


@pytest.fixture(scope="session")
def corpus() -> pathlib.Path:
    return CORPUS


@pytest.fixture(scope="session")
def cli() -> str:
    if not CLI.exists():
        subprocess.run(["cargo", "build", "--release", "--bin", "cnc-motion"], cwd=ROOT, check=True)
    return str(CLI)


def _make_fmu() -> None:
    missing = [p for p in (CNC_FMU, STRUCTURE_FMU) if not p.exists()]
    if missing:
        subprocess.run(["make", "fmu"], cwd=ROOT, check=True)
    for p in (CNC_FMU, STRUCTURE_FMU):
        assert p.exists(), f"`make fmu` did not write {p}"


@pytest.fixture(scope="session")
def fmus() -> tuple[pathlib.Path, pathlib.Path]:
    _make_fmu()
    return CNC_FMU, STRUCTURE_FMU


@pytest.fixture(scope="session")
def cnc(fmus: tuple[pathlib.Path, pathlib.Path]) -> Iterator[Unpacked]:
    u = Unpacked(fmus[0])
    yield u
    u.cleanup()


@pytest.fixture(scope="session")
def structure(fmus: tuple[pathlib.Path, pathlib.Path]) -> Iterator[Unpacked]:
    u = Unpacked(fmus[1])
    yield u
    u.cleanup()


@pytest.fixture(scope="session")
def ssp(fmus: tuple[pathlib.Path, pathlib.Path], tmp_path_factory: pytest.TempPathFactory) -> pathlib.Path:
    """The SSP of both FMUs (cnc_motion_sim.ssp), as `make ssp` writes it."""
    return make_ssp(tmp_path_factory.mktemp("ssp") / "cosim.ssp", *fmus)


@pytest.fixture(scope="session")
def profiles(fmus: tuple[pathlib.Path, pathlib.Path]) -> list[str]:
    """The feed laws, in the order of the `machine.profile` Enumeration."""
    return fmu_profiles(fmus[0])


def pytest_generate_tests(metafunc: pytest.Metafunc) -> None:
    wanted = [n for n in ("profile", "jerk_limited_profile") if n in metafunc.fixturenames]
    if not wanted:
        return
    _make_fmu()
    kinds = fmu_profiles(CNC_FMU)
    assert "trapezoid" in kinds, kinds
    for name in wanted:
        metafunc.parametrize(name, [k for k in kinds if name == "profile" or k != "trapezoid"])


# --- Known FMU defects found by this suite --------------------------------------------------------
# Each entry marks the matching tests xfail(strict=True): they still run, are reported as xfailed,
# and turn into a FAILURE as soon as the defect is fixed (then delete the entry). Keep it short.
KNOWN_FMU_ISSUES: dict[str, str] = {}


def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    for item in items:
        for key, reason in KNOWN_FMU_ISSUES.items():
            if key in item.nodeid:
                item.add_marker(pytest.mark.xfail(strict=True, reason="known FMU defect: " + reason))
