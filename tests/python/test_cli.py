"""The CLI contract (design.md): profile and run, JSON keys, errors with file:line:col."""
import pathlib
import json
import subprocess

from repo import CORPUS


def run(cli: str, *args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([cli, *args], capture_output=True, text=True)


def test_trapezoid_profile_matches_closed_form(cli: str) -> None:
    # Rest to rest, L = 6 mm, v = 100 mm/s, A = 2000 mm/s²: ramps of v/A = 0.05 s and a cruise
    # of (L − v²/A)/v = 0.01 s (seed 001, Table 1, linear column: 0.1100 s).
    res = run(cli, "profile", "--length", "6", "--v-max", "100", "--a-max", "2000", "--j-max", "60000",
              "--kind", "trapezoid", "--json")
    assert res.returncode == 0, res.stderr
    out = json.loads(res.stdout)
    assert abs(out["duration_s"] - 0.11) < 1e-12
    assert abs(out["v_peak_mm_s"] - 100.0) < 1e-9
    assert out["a_peak_mm_s2"] <= 2000.0 * (1 + 1e-12)


def test_run_pessoles_summary(cli: str) -> None:
    res = run(cli, "run", str(CORPUS / "pessoles_linear.ngc"),
              "--machine", str(CORPUS / "dmu50_840d.toml"), "--json")
    assert res.returncode == 0, res.stderr
    out = json.loads(res.stdout)
    for key in ["total_time_s", "path_length_mm", "motion_blocks", "end_position_mm",
                "max_axis_velocity_mm_s", "max_axis_acceleration_mm_s2", "max_axis_jerk_mm_s3"]:
        assert key in out
    # The last programmed point of the corpus file, to 1e-9 mm.
    last = [l for l in (CORPUS / "pessoles_linear.ngc").read_text().splitlines()
            if l.startswith("G1")][-1]
    want = {w[0]: float(w[1:]) for w in last.split() if w[0] in "XYZ"}
    for i, axis in enumerate("XYZ"):
        assert abs(out["end_position_mm"][i] - want[axis]) < 1e-9
    for i in range(3):
        assert out["max_axis_acceleration_mm_s2"][i] <= 9800 * (1 + 1e-9)


def test_bad_program_exit_2_with_location(cli: str, tmp_path: pathlib.Path) -> None:
    prog = tmp_path / "bad.ngc"
    prog.write_text("G21 G90\nG1 X1 F100\nG33 Z-1 K1\n")
    res = run(cli, "run", str(prog))
    assert res.returncode == 2
    assert res.stderr.strip() == (
        f"{prog}:3:1: unsupported G33 (spindle-synchronised motion: this model has no spindle position to follow)"
    )
