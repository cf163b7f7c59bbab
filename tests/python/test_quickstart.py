"""examples/quickstart.py runs as the README shows it, and its summary is the program's geometry."""
import math
import pathlib
import re
import subprocess
import sys

from repo import EXAMPLES


def check_quickstart_output(out: str) -> None:
    m = re.fullmatch(r"finished at t = ([0-9.]+) s, path ([0-9.]+) mm, peak feed ([0-9.]+) mm/min, "
                     r"end X ([0-9.-]+) Y ([0-9.-]+) mm\n", out)
    assert m, out
    t, path, feed, x, y = map(float, m.groups())
    # G1 to (40, 10), G2 R20 to (60, 30) (a quarter circle about (60, 10)), G1 to Y50; the corners
    # are blended within the 0.01 mm path tolerance, which shortens the path by far less than that.
    length = math.hypot(40, 10) + 0.5 * math.pi * 20 + 20
    assert abs(path - length) < 0.01, (path, length)
    assert (x, y) == (60.0, 50.0)
    assert 2999.9 < feed <= 3000.0 + 1e-6
    assert t > length / 50.0  # never faster than F3000 = 50 mm/s


def test_quickstart_summary(fmus: tuple[pathlib.Path, pathlib.Path]) -> None:
    out = subprocess.run([sys.executable, str(EXAMPLES / "quickstart.py")], cwd="/",
                         capture_output=True, text=True, check=True).stdout
    check_quickstart_output(out)
