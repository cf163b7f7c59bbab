"""Cycle time of generated program families against an independent acceleration-limited optimum on
the same emitted path: toppra (PyPI `toppra`, time-optimal path parameterization by reachability
analysis), and the chord circles against Ruckig's 1-D bound.

Machine: every axis 250 mm/s, 2000 mm/s², jerk 1e9 mm/s³ (the jerk limit lifted: toppra has none)
or 5e4 mm/s³, 1 ms, G64 P0.01, the default `smooth` corner mode.

The bound: `cnc-motion run --csv` emits every tick's position. Through those points (repeated ones
dropped) a cubic spline is laid, parameterized by the chord length s (within O(h⁴) of the path the
ticks trace, h ≤ 0.25 mm), with s itself as a fourth coordinate so that the programmed feed is a
velocity limit on it (ds/dt ≤ F). toppra finds the fastest motion along that curve within each
axis's velocity and acceleration limits, checking the constraints only at its grid points (every
0.02 mm): a relaxation of what our motion keeps everywhere (and with a jerk limit on top), so its
time is a lower bound for any motion along this path within these limits. Ours must be within 5 %
of it at jerk 1e9.
"""
from __future__ import annotations

import json
import math
import pathlib
import subprocess
from typing import Any

import numpy as np
import pytest
import toppra
import toppra.algorithm
import toppra.constraint
from repo import families
from ruckig import InputParameter, Result, Ruckig, Trajectory

V_AXIS = 250.0  # mm/s
A_AXIS = 2000.0  # mm/s²
GRID_MM = 0.02


def machine(tmp_path: pathlib.Path, jerk: float) -> str:
    path = tmp_path / f"machine_{jerk:g}.toml"
    axes = "".join(
        f"[axis.{a}]\nmax_velocity_mm_min = {V_AXIS * 60}\nmax_acceleration_mm_s2 = {A_AXIS}\n"
        f"max_jerk_mm_s3 = {jerk}\n" for a in "xyz")
    path.write_text(f"max_feed_mm_min = {V_AXIS * 60}\npath_tolerance_mm = 0.01\n{axes}")
    return str(path)


# --- the families: tools/linuxcnc_compare/families.py (mm, mm/min; from rest where G92 puts them)

def chord_length(chord: float = 0.2, r: float = 20.0) -> float:
    n = round(2 * math.pi * r / chord)
    pts = [(round(r * math.cos(2 * math.pi * k / n), 4), round(r * math.sin(2 * math.pi * k / n), 4))
           for k in range(n + 1)]
    pts[0] = (r, 0.0)
    return sum(math.dist(p, q) for p, q in zip(pts, pts[1:]))


# --- running and bounding -----------------------------------------------------------------------

def run(cli: str, tmp_path: pathlib.Path, text: str, jerk: float) -> tuple[float, np.ndarray, dict[str, Any]]:
    prog = tmp_path / "family.ngc"
    prog.write_text(text)
    csv = tmp_path / "ticks.csv"
    res = subprocess.run([cli, "run", str(prog), "--machine", machine(tmp_path, jerk), "--csv", str(csv),
                          "--json"], capture_output=True, text=True)
    assert res.returncode == 0, res.stderr
    summary = json.loads(res.stdout)
    ticks = np.loadtxt(csv, delimiter=",", skiprows=1, usecols=(0, 2, 3, 4), ndmin=2)
    return float(summary["total_time_s"]), ticks, summary


def toppra_time(points: np.ndarray, feed_mm_s: float) -> float:
    """The acceleration-limited optimum along the curve through `points` (module docstring)."""
    step = np.linalg.norm(np.diff(points, axis=0), axis=1)
    points = points[np.concatenate([[True], step > 1e-7])]
    s = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(points, axis=0), axis=1))])
    path = toppra.SplineInterpolator(s, np.hstack([points, s[:, None]]))
    grid = np.linspace(0.0, s[-1], max(200, int(s[-1] / GRID_MM)) + 1)
    v_lim = np.array([[-V_AXIS, V_AXIS]] * 3 + [[-feed_mm_s, feed_mm_s]])
    a_lim = np.array([[-A_AXIS, A_AXIS]] * 3 + [[-1e5, 1e5]])
    constraints = [toppra.constraint.JointVelocityConstraint(v_lim),
                   toppra.constraint.JointAccelerationConstraint(a_lim)]
    algo = toppra.algorithm.TOPPRA(constraints, path, gridpoints=grid, parametrizer="ParametrizeConstAccel")
    _, sd, _ = algo.compute_parameterization(0, 0)
    sd = np.maximum(sd, 0.0)
    # Constant path acceleration between grid points: Δt = 2·Δs/(ṡ_i + ṡ_i+1).
    return float(np.sum(2.0 * np.diff(grid) / np.maximum(sd[1:] + sd[:-1], 1e-12)))


def ratio_to_toppra(cli: str, tmp_path: pathlib.Path, text: str, feed_mm_min: float) -> float:
    ours, ticks, summary = run(cli, tmp_path, text, 1e9)
    for i in range(3):
        assert summary["max_axis_acceleration_mm_s2"][i] <= A_AXIS * (1 + 1e-6)
        assert summary["max_axis_velocity_mm_s"][i] <= V_AXIS * (1 + 1e-6)
    bound = toppra_time(ticks[:, 1:4], feed_mm_min / 60.0)
    ratio = ours / bound
    print(f"ours {ours:.4f} s, toppra {bound:.4f} s: {ratio:.4f}")
    return ratio


FAMILIES = {
    **{f"circle F{f}": (families.circle(f), f) for f in (6000, 9000, 12000, 15000)},
    "chord circle F3000": (families.chord_circle(3000), 3000),
    "chord circle F10000": (families.chord_circle(10000), 10000),
    "spiral of 1000 G2 R arcs": (families.arc_spiral(), 15000),
    "G1 spiral pocket": (families.g1_spiral(), 6000),
    "raster": (families.raster(), 3000),
    "alternating 8/1 µm moves": (families.micro_line(), 3000),
}


@pytest.mark.parametrize("name", list(FAMILIES))
def test_within_five_percent_of_toppra(cli: str, tmp_path: pathlib.Path, name: str) -> None:
    text, feed = FAMILIES[name]
    assert ratio_to_toppra(cli, tmp_path, text, feed) <= 1.05


@pytest.mark.parametrize("jerk", [5e4, 1e9])
def test_circle_time_does_not_grow_with_the_feed(cli: str, tmp_path: pathlib.Path, jerk: float) -> None:
    times = [run(cli, tmp_path, families.circle(f), jerk)[0] for f in (6000, 9000, 12000, 15000)]
    assert all(b <= a * (1 + 1e-3) for a, b in zip(times, times[1:])), times


def ruckig_rest_to_rest(length: float, v_max: float, a_max: float, j_max: float) -> float:
    otg = Ruckig(1)
    inp = InputParameter(1)
    inp.current_position, inp.target_position = [0.0], [length]
    inp.current_velocity = inp.current_acceleration = [0.0]
    inp.target_velocity = inp.target_acceleration = [0.0]
    inp.max_velocity, inp.max_acceleration, inp.max_jerk = [v_max], [a_max], [j_max]
    traj = Trajectory(1)
    assert otg.calculate(inp, traj) == Result.Working
    return float(traj.duration)


@pytest.mark.parametrize("feed", [3000, 10000])
def test_chord_circles_within_fifteen_percent_of_ruckig(cli: str, tmp_path: pathlib.Path, feed: float) -> None:
    # The 1-D bound: the programmed length rest to rest at the feed with an axis's a and j.
    ours = run(cli, tmp_path, families.chord_circle(feed), 5e4)[0]
    bound = ruckig_rest_to_rest(chord_length(), feed / 60.0, A_AXIS, 5e4)
    print(f"ours {ours:.4f} s, Ruckig 1-D {bound:.4f} s: {ours / bound:.4f}")
    assert ours <= 1.15 * bound
