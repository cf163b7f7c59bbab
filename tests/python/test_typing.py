"""The Python code is typed: mypy (configuration in python/pyproject.toml: every function annotated)
finds no error in the package, this suite and the examples."""
import pathlib
import subprocess
import sys


def test_package_tests_and_examples_type_check(root: pathlib.Path) -> None:
    out = subprocess.run([sys.executable, "-m", "mypy", "--cache-dir", str(root / "target" / "mypy-cache"),
                          "cnc_motion_sim", str(root / "tests" / "python"), str(root / "examples")],
                         cwd=root / "python", capture_output=True, text=True)
    assert out.returncode == 0, out.stdout + out.stderr
    assert out.stdout.startswith("Success: no issues found"), out.stdout
