"""CncMotion.fmu in fmpy: programs run to the end, command within the machine's limits for every
profile kind (the items of the FMU's `machine.profile`), smooth (continuous acceleration, bounded
jerk), feed hold and override, bad programs."""
import pathlib
import re
import subprocess
from collections.abc import Callable
from typing import Any

import numpy as np
import pytest

import cnc_motion_sim as sim
from repo import DEFAULT_PROGRAM, EXAMPLES, corpus_programs

REL = 1e-9
# Issue 14: seed 003's pocket with cutter compensation (G41.1 D10, G54, T/D/M6) through `program`.
CORPUS_PROGRAMS = corpus_programs()
PROGRAMS = [DEFAULT_PROGRAM] + CORPUS_PROGRAMS + [EXAMPLES / "seed003_pocket_g41.ngc"]


def limits(cnc: sim.Unpacked) -> dict[str, dict[str, float]]:
    """Axis limits (SI) from the start values of the parameters."""
    out = {}
    for a in sim.AXES:
        out[a] = {q: float(cnc.vars[f"{a}.max{Q}"].start) for q, Q in
                  [("velocity", "Velocity"), ("acceleration", "Acceleration"), ("jerk", "Jerk")]}
    return out


def test_corpus_is_there() -> None:
    assert len(CORPUS_PROGRAMS) >= 2, "corpus/*.ngc missing"


_cache: dict[tuple[str, str], dict[str, Any]] = {}


def run(cnc: sim.Unpacked, program: pathlib.Path, kind: str) -> dict[str, Any]:
    key = (str(program), kind)
    if key not in _cache:
        params = {"program": program.read_text(), "machine.profile": kind}
        _cache[key] = sim.run_cnc(cnc, params, names=[
            *(f"{a}.command.{q}" for a in sim.AXES for q in ("position", "velocity", "acceleration", "jerk")),
            "path.feed", "path.distance", "status.line", "status.finished"])
    return _cache[key]


def last_point(program: pathlib.Path) -> list[float]:
    """The last programmed X Y Z (mm) of a program made of absolute G0/G1/G2/G3 moves."""
    pos = {"X": 0.0, "Y": 0.0, "Z": 0.0}
    for line in program.read_text().splitlines():
        line = re.sub(r"\(.*?\)", "", line).split(";")[0].upper()
        for w, val in re.findall(r"([XYZ])\s*(-?[0-9.]+)", line):
            pos[w] = float(val)
    return [pos[a] for a in "XYZ"]


@pytest.mark.parametrize("program", PROGRAMS, ids=lambda p: p.stem)
def test_program_runs_to_finished(cnc: sim.Unpacked, program: pathlib.Path) -> None:
    res = run(cnc, program, "scurve7")
    assert res["status.finished"][-1] == 1.0
    end = [res[f"{a}.command.position"][-1] * 1e3 for a in sim.AXES]
    np.testing.assert_allclose(end, last_point(program), atol=1e-9)
    # At the end the command is at rest.
    for a in sim.AXES:
        assert res[f"{a}.command.velocity"][-1] == 0.0


@pytest.mark.parametrize("program", PROGRAMS, ids=lambda p: p.stem)
def test_command_within_axis_limits(cnc: sim.Unpacked, program: pathlib.Path, profile: str) -> None:
    res = run(cnc, program, profile)
    lim = limits(cnc)
    for a in sim.AXES:
        for q in ("velocity", "acceleration", "jerk"):
            if q == "jerk" and profile == "trapezoid":
                continue  # the trapezoid has no jerk limit
            peak = np.max(np.abs(res[f"{a}.command.{q}"]))
            assert peak <= lim[a][q] * (1 + REL), f"{a} {q}: {peak} > {lim[a][q]}"


@pytest.mark.parametrize("program", PROGRAMS, ids=lambda p: p.stem)
def test_acceleration_continuous_jerk_bounded(cnc: sim.Unpacked, program: pathlib.Path,
                                              jerk_limited_profile: str) -> None:
    """Between two ticks a changes by at most ∫|j| ≤ J·T: no acceleration steps anywhere."""
    res = run(cnc, program, jerk_limited_profile)
    lim = limits(cnc)
    period = float(cnc.vars["machine.interpolationPeriod"].start)
    assert abs(np.diff(res["time"])[0] - period) < 1e-12
    for a in sim.AXES:
        acc = res[f"{a}.command.acceleration"]
        step = np.max(np.abs(np.diff(acc)))
        bound = lim[a]["jerk"] * period * (1 + 1e-9) + 1e-9 * lim[a]["acceleration"]
        assert step <= bound, f"{a}: |Δa| {step} per tick > J·T {bound}"
        assert np.all(np.isfinite(res[f"{a}.command.jerk"]))
        assert acc[0] == 0.0 and acc[-1] == 0.0


def test_trapezoid_has_acceleration_steps(cnc: sim.Unpacked) -> None:
    """The baseline really is a trapezoid: acceleration jumps (what the smoothness test guards against)."""
    res = run(cnc, DEFAULT_PROGRAM, "trapezoid")
    lim = limits(cnc)
    period = float(cnc.vars["machine.interpolationPeriod"].start)
    jumps = max(np.max(np.abs(np.diff(res[f"{a}.command.acceleration"]))) for a in "xy")
    assert jumps > 2 * lim["x"]["jerk"] * period


LINE = "G21 G90 G17\nG1 X100 F3000\nM30\n"  # 100 mm at 50 mm/s


def _line_run(cnc: sim.Unpacked, inputs: Callable[[float, sim.Slave], None] | None = None,
              override: float | None = None) -> dict[str, Any]:
    params: dict[str, Any] = {"program": LINE}
    if override is not None:
        params["feedOverride"] = override
    return sim.run_cnc(cnc, params, inputs=inputs, names=[
        "x.command.position", "x.command.velocity", "x.command.acceleration", "x.command.jerk",
        "path.feed", "status.finished"])


def test_feed_override_halves_cruise_feed(cnc: sim.Unpacked) -> None:
    full = _line_run(cnc)
    half = _line_run(cnc, override=0.5)
    lim = limits(cnc)
    period = float(cnc.vars["machine.interpolationPeriod"].start)

    def cruise(r: dict[str, Any]) -> float:  # the feed in the middle of the move
        t = r["time"]
        return np.median(r["path.feed"][(t > 0.3 * r["t_finished"]) & (t < 0.7 * r["t_finished"])])

    assert abs(cruise(full) - 0.05) < 1e-9
    assert abs(cruise(half) - 0.025) < 1e-9
    assert abs(half["x.command.position"][-1] - 0.1) < 1e-12
    assert half["t_finished"] > 1.9 * full["t_finished"] - 0.2
    # Override changes stay within the machine's limits.
    acc = half["x.command.acceleration"]
    assert np.max(np.abs(half["x.command.jerk"])) <= lim["x"]["jerk"] * (1 + REL)
    assert np.max(np.abs(np.diff(acc))) <= lim["x"]["jerk"] * period * (1 + 1e-9) + 1e-9
    # An override given before the start applies from the first tick: no overshoot above 50 %.
    assert np.max(half["path.feed"]) <= 0.025 * (1 + 1e-9), np.max(half["path.feed"])


def test_feed_hold_stops_smoothly_stays_and_resumes(cnc: sim.Unpacked) -> None:
    t_hold, t_release = 0.8, 1.6

    def inputs(t: float, s: sim.Slave) -> None:
        s.set("feedHold", t_hold - 1e-9 <= t < t_release - 1e-9)

    free = _line_run(cnc)
    res = _line_run(cnc, inputs=inputs)
    t, feed, pos = res["time"], res["path.feed"], res["x.command.position"]
    lim = limits(cnc)
    period = float(cnc.vars["machine.interpolationPeriod"].start)
    assert abs(feed[np.searchsorted(t, t_hold) - 1] - 0.05) < 1e-9  # cruising when the hold comes
    held = (t > t_hold + 0.3) & (t < t_release)  # stopped well inside the hold
    assert np.all(feed[held] == 0.0)
    assert np.ptp(pos[held]) == 0.0
    stop = (t >= t_hold) & (t < t_release)
    assert np.all(np.diff(feed[stop]) <= 1e-12), "feed rises during the hold"
    # Smooth: no acceleration step when stopping and restarting, limits kept.
    acc = res["x.command.acceleration"]
    assert np.max(np.abs(np.diff(acc))) <= lim["x"]["jerk"] * period * (1 + 1e-9) + 1e-9
    assert np.max(np.abs(acc)) <= lim["x"]["acceleration"] * (1 + REL)
    assert np.max(np.abs(res["x.command.jerk"])) <= lim["x"]["jerk"] * (1 + REL)
    # Resumes to the programmed feed and ends where programmed, later than without the hold.
    after = t > t_release + 0.3
    assert abs(np.max(feed[after]) - 0.05) < 1e-9
    assert abs(pos[-1] - 0.1) < 1e-12
    assert res["t_finished"] > free["t_finished"] + 0.5


BAD = {
    "syntax": "G21 G90\nG1 X1 F100\nG1 X2 Y\n",
    "g33": "G21 G90\nG1 X1 F100\nG33 Z-1 K1\n",
    "arc": "G21 G90 G17\nG1 X0 Y0 F100\nG2 X10 Y0 I1 J0\n",
}


@pytest.mark.parametrize("case", BAD)
def test_bad_program_error_at_initialization(cnc: sim.Unpacked, cli: str, tmp_path: pathlib.Path, case: str) -> None:
    from fmpy.fmi1 import FMICallException
    text = BAD[case]
    prog = tmp_path / f"{case}.ngc"
    prog.write_text(text)
    ref = subprocess.run([cli, "run", str(prog)], capture_output=True, text=True)
    assert ref.returncode == 2, ref.stderr
    m = re.match(re.escape(str(prog)) + r":(\d+):(\d+): (.*)", ref.stderr.strip())
    assert m, ref.stderr
    where, what = f"{m.group(1)}:{m.group(2)}", m.group(3)
    if case == "g33":
        assert where == "3:1"
    s = sim.Slave(cnc, "bad")
    try:
        s.fmu.setupExperiment(startTime=0.0)
        s.set("program", text)
        s.fmu.enterInitializationMode()
        with pytest.raises(FMICallException) as err:
            s.fmu.exitInitializationMode()
        assert err.value.status == 3  # fmi2Error
        msgs = [m_ for _, _, m_ in s.log]
        assert any(where in m_ and what in m_ for m_ in msgs), msgs
    finally:
        s.fmu.freeInstance()


def test_simulate_fmu_defaults_equal_cli_run(fmus: tuple[pathlib.Path, pathlib.Path], cli: str,
                                             tmp_path: pathlib.Path) -> None:
    """fmpy's simulate_fmu with the FMU's defaults runs the shipped default program to
    status.finished, and every tick's command equals the CLI's `run` of the same program and
    machine to 1e-12 m."""
    from fmpy import simulate_fmu
    names = [f"{a}.command.position" for a in sim.AXES] + ["status.finished"]
    res = simulate_fmu(str(fmus[0]), output_interval=1e-3, output=names)
    assert res["status.finished"][-1], "default stop time covers the default program"
    csv = tmp_path / "ticks.csv"
    out = subprocess.run([cli, "run", str(DEFAULT_PROGRAM), "--csv", str(csv)],
                         capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    ticks = np.genfromtxt(csv, delimiter=",", names=True)
    n = len(ticks)
    # Row k of the FMU result is at t = k·1 ms; CSV row k−1 is the tick at k·1 ms.
    t = res["time"][1:n + 1]
    assert np.allclose(t, ticks["time_s"], rtol=0, atol=1e-9)
    for a in sim.AXES:
        fmu = res[f"{a}.command.position"][1:n + 1]
        np.testing.assert_allclose(fmu, ticks[f"{a}_mm"] * 1e-3, rtol=0, atol=1e-12, err_msg=a)
    i_done = int(np.argmax(res["status.finished"]))
    assert i_done == n, f"FMU finished at row {i_done}, CLI after {n} ticks"
