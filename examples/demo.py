"""cnc-motion demo: run the default program, print a summary, write plots to out/.

Usage: python examples/demo.py [PROGRAM] [--machine FILE.toml]
"""
import argparse
import csv
import json
import pathlib
import subprocess
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parent.parent
CLI = ROOT / "target" / "release" / "cnc-motion"


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("program", nargs="?", default=str(ROOT / "resources" / "default.ngc"))
    ap.add_argument("--machine")
    ap.add_argument("--out", default=str(ROOT / "out"))
    args = ap.parse_args()
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    csv_path = out / "demo.csv"
    cmd = [str(CLI), "run", args.program, "--json", "--csv", str(csv_path)]
    if args.machine:
        cmd += ["--machine", args.machine]
    res = subprocess.run(cmd, capture_output=True, text=True)
    if res.returncode != 0:
        sys.exit(res.stderr)
    summary = json.loads(res.stdout)
    for k, v in summary.items():
        print(f"{k:32} {v}")
    with open(csv_path) as f:
        rows = list(csv.DictReader(f))
    col = lambda name: [float(r[name]) for r in rows]  # noqa: E731
    t = col("time_s")
    fig, ax = plt.subplots(3, 1, sharex=True, figsize=(9, 8))
    ax[0].plot(t, col("feed_mm_s"))
    ax[0].set_ylabel("feed (mm/s)")
    for a in "xyz":
        ax[1].plot(t, col(f"a{a}_mm_s2"), label=a)
        ax[2].plot(t, col(f"j{a}_mm_s3"), label=a)
    ax[1].set_ylabel("acceleration (mm/s²)")
    ax[2].set_ylabel("jerk (mm/s³)")
    ax[2].set_xlabel("time (s)")
    ax[1].legend()
    fig.tight_layout()
    fig.savefig(out / "feed_acc_jerk.png", dpi=110)
    fig, ax = plt.subplots(1, 2, figsize=(11, 5))
    x, y = col("x_mm"), col("y_mm")
    ax[0].plot(x, y, lw=0.8)
    ax[0].set_aspect("equal")
    ax[0].set_title("path (XY)")
    ax[1].plot(x, y, ".-", ms=2, lw=0.6)
    ax[1].set_xlim(38.5, 40.5)
    ax[1].set_ylim(-0.5, 1.5)
    ax[1].set_aspect("equal")
    ax[1].set_title("corner zoom at X40 Y0 (ticks)")
    fig.tight_layout()
    fig.savefig(out / "path.png", dpi=110)
    print(f"plots: {out / 'feed_acc_jerk.png'}, {out / 'path.png'}")


if __name__ == "__main__":
    main()
