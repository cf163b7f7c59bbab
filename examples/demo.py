"""cnc-motion demo: simulate CncMotion.fmu with fmpy on the default program (or another one), print a
summary, write plots to out/.

Usage: python examples/demo.py [PROGRAM.ngc] [--profile KIND (an item of the FMU's machine.profile)]
                               [--fmu target/fmu/CncMotion.fmu] [--out out]
"""
import argparse
import pathlib
import sys

import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from fmpy import read_model_description, simulate_fmu  # noqa: E402

from cnc_motion_sim import AXES, CNC_FMU, ROOT, profiles  # noqa: E402

H = 1e-3
MM = 1e3


def simulate(fmu, program=None, profile=None, t_max=300.0):
    """fmpy.simulate_fmu at the 1 ms interpolation period, stopped one step after status.finished."""
    md = read_model_description(str(fmu))
    names = [v.name for v in md.modelVariables
             if v.causality == "output" and v.type in ("Real", "Integer", "Boolean")]
    start = {}
    if program is not None:
        start["program"] = pathlib.Path(program).read_text()
    if profile is not None:  # fmpy sets Enumerations by their integer
        var = next(v for v in md.modelVariables if v.name == "machine.profile")
        start["machine.profile"] = next(int(i.value) for i in var.declaredType.items if i.name == profile)
    fin = [next(v.valueReference for v in md.modelVariables if v.name == "status.finished")]

    def step_finished(time, recorder):  # keep going while the program runs
        return not recorder.fmu.getBoolean(fin)[0]

    res = simulate_fmu(str(fmu), fmi_type="CoSimulation", start_time=0.0, stop_time=t_max,
                       output_interval=H, output=names, start_values=start, step_finished=step_finished)
    return res


def summary(res):
    t = res["time"]
    out = {"total_time_s": float(t[-1]), "ticks": len(t) - 1,
           "path_length_mm": float(res["path.distance"][-1] * MM)}
    out["end_position_mm"] = [float(res[f"{a}.command.position"][-1] * MM) for a in AXES]
    for q, unit in [("velocity", "mm_s"), ("acceleration", "mm_s2"), ("jerk", "mm_s3")]:
        out[f"max_axis_{q}_{unit}"] = [float(np.max(np.abs(res[f"{a}.command.{q}"])) * MM) for a in AXES]
    out["max_feed_mm_s"] = float(np.max(res["path.feed"]) * MM)
    if "x.followingError" in res.dtype.names:
        out["max_following_error_um"] = [float(np.max(np.abs(res[f"{a}.followingError"])) * 1e6) for a in AXES]
    if "path.contourError" in res.dtype.names:
        out["max_contour_error_um"] = float(np.max(np.abs(res["path.contourError"])) * 1e6)
    return out


def plots(res, out, corner=(40.0, 0.0), zoom=0.1):
    t = res["time"]
    fig, ax = plt.subplots(3, 1, sharex=True, figsize=(9, 8))
    ax[0].plot(t, res["path.feed"] * MM, label="path")
    ax[0].set_ylabel("feed (mm/s)")
    for a in AXES:
        ax[1].plot(t, res[f"{a}.command.acceleration"] * MM, label=a)
        ax[2].plot(t, res[f"{a}.command.jerk"] * MM, label=a)
    ax[1].set_ylabel("acceleration (mm/s²)")
    ax[2].set_ylabel("jerk (mm/s³)")
    ax[2].set_xlabel("time (s)")
    ax[1].legend()
    fig.tight_layout()
    fig.savefig(out / "feed_acc_jerk.png", dpi=110)
    plt.close(fig)

    fig, ax = plt.subplots(1, 2, figsize=(11, 5))
    x, y = res["x.command.position"] * MM, res["y.command.position"] * MM
    ax[0].plot(x, y, lw=0.8, label="command")
    if "x.position" in res.dtype.names:
        ax[0].plot(res["x.position"] * MM, res["y.position"] * MM, lw=0.6, label="axis (servo)")
    ax[0].set_aspect("equal")
    ax[0].set_title("path (XY)")
    ax[0].legend()
    cx, cy = corner
    ax[1].plot(x, y, ".-", ms=2, lw=0.6, label="command (ticks)")
    if "x.position" in res.dtype.names:
        ax[1].plot(res["x.position"] * MM, res["y.position"] * MM, lw=0.6, label="axis (servo)")
    ax[1].plot([cx - 2, cx, cx], [cy, cy, cy + 2], "k:", lw=0.8, label="programmed")
    ax[1].set_xlim(cx - zoom, cx + 0.25 * zoom)  # mm: the blend lies within the path tolerance
    ax[1].set_ylim(cy - 0.25 * zoom, cy + zoom)
    ax[1].set_aspect("equal")
    ax[1].set_title(f"corner zoom at X{cx:g} Y{cy:g} (mm)")
    ax[1].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out / "path.png", dpi=110)
    plt.close(fig)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("program", nargs="?", help="G-code file (default: the FMU's shipped default.ngc)")
    ap.add_argument("--profile", help="feed law: an item of the FMU's machine.profile Enumeration")
    ap.add_argument("--fmu", default=str(CNC_FMU))
    ap.add_argument("--out", default=str(ROOT / "out"))
    args = ap.parse_args()
    if not pathlib.Path(args.fmu).exists():
        sys.exit(f"{args.fmu} missing: run `make fmu` first")
    if args.profile is not None and args.profile not in profiles(args.fmu):
        ap.error(f"--profile: {args.profile!r} is not one of {profiles(args.fmu)}")
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    res = simulate(args.fmu, args.program, args.profile)
    if not res["status.finished"][-1]:
        sys.exit("program did not finish")
    for k, v in summary(res).items():
        if isinstance(v, list):
            v = "[" + ", ".join(f"{x:.6g}" for x in v) + "]"
        elif isinstance(v, float):
            v = f"{v:.6g}"
        print(f"{k:32} {v}")
    plots(res, out)
    print(f"plots: {out / 'feed_acc_jerk.png'}, {out / 'path.png'}")


if __name__ == "__main__":
    main()
