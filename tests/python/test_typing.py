"""The package is typed: mypy (configuration in python/pyproject.toml) finds no error."""
import subprocess
import sys


def test_package_type_checks(root):
    out = subprocess.run([sys.executable, "-m", "mypy", "--cache-dir", str(root / "target" / "mypy-cache"),
                          "cnc_motion_sim"], cwd=root / "python", capture_output=True, text=True)
    assert out.returncode == 0, out.stdout + out.stderr
    assert out.stdout.startswith("Success: no issues found"), out.stdout
