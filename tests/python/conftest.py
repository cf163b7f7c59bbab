import pathlib
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
SHARED = ROOT.parent / "shared"
CLI = ROOT / "target" / "release" / "cnc-motion"


@pytest.fixture(scope="session")
def cli():
    if not CLI.exists():
        subprocess.run(["cargo", "build", "--release", "--bin", "cnc-motion"], cwd=ROOT, check=True)
    return str(CLI)
