"""cnc-motion demo: simulate a G-code program with CncMotion.fmu (cnc_motion_sim, fmpy), print a
summary with the machine's limits beside the maxima, write report plots to out/.

Usage: python examples/demo.py [PROGRAM.ngc] [--machine FILE.toml] [--profile KIND] [--fmu FILE.fmu]
                               [--out out]

Without PROGRAM it runs the FMU's default program. Plots: feed_acc_jerk.png (path feed, axis
acceleration and jerk over time, the limits as lines), path.png (the XY path, equal aspect, and a
zoom on the sharpest programmed corner with the path tolerance band).
"""
from __future__ import annotations

import argparse
import math
import pathlib
import re
from collections.abc import Sequence
from typing import Any

import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.axes import Axes  # noqa: E402
from matplotlib.patches import Circle, Polygon  # noqa: E402

import cnc_motion_sim as cms  # noqa: E402

MM = 1e3  # m → mm
AXES = "xyz"
Point = tuple[float, float, float]


def title(program: str, res: cms.Result, machine: str) -> str:
    p = res.parameters
    return f"{program} · {p['machine.profile']} feed law, {p['machine.corner']} corners · {machine}"


def limits(res: cms.Result, quantity: str) -> list[float]:
    """Axis limits in mm units (the parameters in force)."""
    return [float(res.parameters[f"{a}.max{quantity}"]) * MM for a in AXES]


def summary(res: cms.Result) -> list[tuple[str, str]]:
    """(label, text) rows: values rounded to what a report shows, limits beside the maxima."""
    t = res.time
    rows = [("total time", f"{res.finished_at:.3f} s ({len(t) - 1} steps of {(t[1] - t[0]) * 1e3:g} ms)"),
            ("path length", f"{res['path.distance'][-1] * MM:.3f} mm"),
            ("end position", "  ".join(f"{a.upper()} {res[f'{a}.command.position'][-1] * MM:.3f}" for a in AXES)
             + " mm"),
            ("max feed", f"{np.max(res['path.feed']) * MM:.2f} mm/s (limit "
                         f"{float(res.parameters['machine.maxFeed']) * MM:.2f} mm/s)")]
    for q, unit in (("Velocity", "mm/s"), ("Acceleration", "mm/s²"), ("Jerk", "mm/s³")):
        peak = [float(np.max(np.abs(res[f"{a}.command.{q.lower()}"]))) * MM for a in AXES]
        rows.append((f"max axis {q.lower()}", _against(peak, limits(res, q), unit)))
    rows.append(("max following error", "  ".join(
        f"{a.upper()} {np.max(np.abs(res[f'{a}.followingError'])) * 1e6:.1f}" for a in AXES) + " µm"))
    rows.append(("max contour error", f"{np.max(np.abs(res['path.contourError'])) * 1e6:.2f} µm"))
    return rows


def _against(peak: Sequence[float], limit: Sequence[float], unit: str) -> str:
    """`X 2000.0 / 2000  Y …` (peak / limit); a peak above its limit by more than rounding is flagged."""
    digits = max(0, 3 - int(math.floor(math.log10(max(max(limit), 1e-12)))))  # 4 significant digits
    parts = []
    for a, v, lim in zip(AXES, peak, limit):
        flag = "  OVER THE LIMIT" if v > lim * (1 + 1e-9) else ""
        parts.append(f"{a.upper()} {v:.{digits}f} / {lim:.{digits}f}{flag}")
    return "  ".join(parts) + f" {unit} (peak / limit)"


def programmed_points(text: str) -> list[Point] | None:
    """The programmed points of a program made of absolute G0/G1 moves (mm), None for anything
    else (arcs, incremental moves, subroutines): the corner zoom then shows no programmed path."""
    pos = [0.0, 0.0, 0.0]
    points: list[Point] = [(0.0, 0.0, 0.0)]
    for raw in text.splitlines():
        line = re.sub(r"\(.*?\)", "", raw).split(";")[0].upper()
        if re.search(r"G0*[23]\b|G91\b|G20\b|O\d|O<|G4[12]|G5[4-9]|G92|G28|G30|G53|G8\d", line):
            return None
        words = dict(re.findall(r"([XYZ])\s*(-?[0-9.]+)", line))
        if words:
            pos = [float(words.get(a, pos[i])) for i, a in enumerate("XYZ")]
            points.append((pos[0], pos[1], pos[2]))
    return points


def sharpest_corner(points: Sequence[Point]) -> tuple[Point, Point, Point] | None:
    """(previous, corner, next) of the largest direction change between two XY moves at one Z, at
    a point the program passes once (the zoom shows that corner alone); the first of equals."""
    visits: dict[tuple[float, float], int] = {}
    for p in points:
        visits[p[:2]] = visits.get(p[:2], 0) + 1
    best, corner = 0.0, None
    for p0, p1, p2 in zip(points, points[1:], points[2:]):
        if not (p0[2] == p1[2] == p2[2]) or visits[p1[:2]] > 1:
            continue
        u, v = np.subtract(p1, p0)[:2], np.subtract(p2, p1)[:2]
        nu, nv = np.linalg.norm(u), np.linalg.norm(v)
        if nu == 0 or nv == 0:
            continue
        turn = math.acos(float(np.clip(np.dot(u, v) / (nu * nv), -1.0, 1.0)))
        if turn > best + 1e-9:
            best, corner = turn, (p0, p1, p2)
    return corner


def tolerance_band(ax: Axes, corner: tuple[Point, Point, Point], tol: float, label: str) -> None:
    """The points within `tol` of the two programmed segments (rectangles and a disc at the corner)."""
    style: dict[str, Any] = {"facecolor": "#cfe8cf", "edgecolor": "none", "zorder": 0}
    for a, b in (corner[:2], corner[1:]):
        d = np.subtract(b, a)[:2]
        n = np.array([-d[1], d[0]]) / np.linalg.norm(d) * tol
        pa, pb = np.array(a[:2]), np.array(b[:2])
        ax.add_patch(Polygon(np.array([pa + n, pb + n, pb - n, pa - n]), **style))
    ax.add_patch(Circle(corner[1][:2], tol, **style, label=label))


def plot_feed(res: cms.Result, out: pathlib.Path, heading: str) -> pathlib.Path:
    t = res.time
    fig, ax = plt.subplots(3, 1, sharex=True, figsize=(10, 8.5), layout="constrained")
    ax[0].plot(t, res["path.feed"] * MM, color="k", lw=1.2, label="path feed")
    ax[0].axhline(float(res.parameters["machine.maxFeed"]) * MM, color="r", ls="--", lw=1, label="max feed")
    ax[0].set_ylabel("feed (mm/s)")
    colors = {"x": "C0", "y": "C1", "z": "C2"}
    for row, q, unit in ((1, "Acceleration", "mm/s²"), (2, "Jerk", "mm/s³")):
        for a, lim in zip(AXES, limits(res, q)):
            ax[row].plot(t, res[f"{a}.command.{q.lower()}"] * MM, color=colors[a], lw=1, label=f"{a.upper()} axis")
        lims = limits(res, q)
        if max(lims) - min(lims) <= 1e-9 * max(lims):  # one limit for all axes: one pair of lines
            for sign in (1, -1):
                ax[row].axhline(sign * lims[0], color="r", ls="--", lw=1,
                                label=f"limit ±{lims[0]:.0f} {unit}" if sign > 0 else None)
        else:
            for a, lim in zip(AXES, lims):
                for sign in (1, -1):
                    ax[row].axhline(sign * lim, color=colors[a], ls="--", lw=0.8,
                                    label=f"{a.upper()} limit ±{lim:.0f}" if sign > 0 else None)
        ax[row].set_ylabel(f"axis {q.lower()} ({unit})")
    ax[2].set_xlabel("time (s)")
    for a in ax:
        a.grid(True, lw=0.3, alpha=0.6)
        a.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8, frameon=False)
    fig.suptitle(heading, fontsize=11)
    path = out / "feed_acc_jerk.png"
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def plot_path(res: cms.Result, out: pathlib.Path, heading: str, program_text: str) -> pathlib.Path:
    x, y = res["x.command.position"] * MM, res["y.command.position"] * MM
    xa, ya = res["x.position"] * MM, res["y.position"] * MM
    points = programmed_points(program_text)
    corner = sharpest_corner(points) if points else None
    fig, ax = plt.subplots(1, 2 if corner else 1, figsize=(12, 5.6) if corner else (7, 5.6), layout="constrained",
                           squeeze=False)
    whole = ax[0][0]
    if points:
        whole.plot([p[0] for p in points], [p[1] for p in points], color="0.6", ls=":", lw=1, label="programmed")
    whole.plot(x, y, color="C0", lw=1, label="command")
    whole.plot(xa, ya, color="C3", lw=0.7, label="axes (servo)")
    whole.set_aspect("equal", adjustable="datalim")
    whole.set_xlabel("X (mm)")
    whole.set_ylabel("Y (mm)")
    whole.set_title("path in XY", fontsize=10)
    whole.grid(True, lw=0.3, alpha=0.6)
    whole.legend(loc="upper center", bbox_to_anchor=(0.5, -0.12), ncol=3, fontsize=8, frameon=False)
    if corner:
        tol = float(res.parameters["machine.pathTolerance"]) * MM
        cx, cy = corner[1][0], corner[1][1]
        half = max(6 * tol, 0.03)  # mm: the blend lies within the tolerance of the corner
        # The window's centre moved into the angle between the two segments (the corner off-centre).
        u, v = (np.subtract(b[:2], a[:2]) for a, b in (corner[:2], corner[1:]))
        shift = (-u / np.linalg.norm(u) + v / np.linalg.norm(v)) * 0.5 * half
        mx, my = cx + shift[0], cy + shift[1]
        whole.plot([cx], [cy], "o", ms=9, mfc="none", mec="k", mew=0.8)
        whole.annotate("corner zoom", (cx, cy), xytext=(-8, 8), textcoords="offset points", ha="right", fontsize=8)
        zoom = ax[0][1]
        tolerance_band(zoom, corner, tol, f"path tolerance ±{tol:g} mm")
        zoom.plot([p[0] for p in corner], [p[1] for p in corner], color="0.3", ls=":", lw=1, label="programmed")
        zoom.plot(x, y, ".-", color="C0", ms=3, lw=0.8, label="command (one dot per 1 ms tick)")
        zoom.plot(xa, ya, color="C3", lw=0.8, label="axes (servo)")
        zoom.set_xlim(mx - half, mx + half)
        zoom.set_ylim(my - half, my + half)
        zoom.set_aspect("equal")
        zoom.set_xlabel("X (mm)")
        zoom.set_ylabel("Y (mm)")
        zoom.set_title(f"corner at X{cx:g} Y{cy:g}", fontsize=10)
        zoom.grid(True, lw=0.3, alpha=0.6)
        zoom.legend(loc="upper center", bbox_to_anchor=(0.5, -0.12), ncol=2, fontsize=8, frameon=False)
    fig.suptitle(heading, fontsize=11)
    path = out / "path.png"
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def main() -> None:
    ap = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    ap.add_argument("program", nargs="?", help="G-code file (default: the FMU's default program)")
    ap.add_argument("--machine", help="machine file (TOML, as for `cnc-motion run --machine`)")
    ap.add_argument("--profile", help="feed law: an item of the FMU's machine.profile")
    ap.add_argument("--fmu", help="CncMotion.fmu (default: the one shipped in cnc_motion_sim)")
    ap.add_argument("--out", default="out")
    args = ap.parse_args()
    fmu = cms.fmu_file(args.fmu)
    if args.profile is not None and args.profile not in cms.profiles(fmu):
        ap.error(f"--profile: {args.profile!r} is not one of {cms.profiles(fmu)}")
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    res = cms.simulate(args.program, args.machine, profile=args.profile, fmu=fmu)
    text = pathlib.Path(args.program).read_text() if args.program else cms.default_program(fmu)
    program = pathlib.Path(args.program).name if args.program else "default.ngc (the FMU's)"
    machine = pathlib.Path(args.machine).name if args.machine else "default machine"
    heading = title(program, res, machine)
    print(heading)
    for label, value in summary(res):
        print(f"  {label:22} {value}")
    paths = [plot_feed(res, out, heading), plot_path(res, out, heading, text)]
    print("plots: " + ", ".join(str(p) for p in paths))


if __name__ == "__main__":
    main()
