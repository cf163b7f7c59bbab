"""Tick digest: a fingerprint of every tick the CLI emits on a fixed corpus, to show that a change
leaves the motion as it was (issue 22: "the ticks of the test corpus unchanged") or to list the
runs it changes.

    python3 tools/tick_digest.py --cli OLD_BINARY --out old.txt
    python3 tools/tick_digest.py --cli target/release/cnc-motion --out new.txt
    python3 tools/tick_digest.py --compare old.txt new.txt      # exit status 1 where they differ

The corpus: the programs of the LinuxCNC comparison as tools/linuxcnc_compare/compare.py writes
them (issue 19's families, corpus/ and examples/, `G64 P0.01` first; with `--ncfiles`, LinuxCNC's
sample programs from Debian's linuxcnc-uspace; with `--extra DIR`, every *.ngc under DIR, e.g.
LinuxCNC's tests/trajectory-planner/circular-arcs/nc_files from its source), a CAM-like program
(`--cam-lines`, 30 000 by default, from examples/cam_program.rs) and benches/data/one_hour.ngc,
each on the comparison's machine at jerk 5e4 and 1e9 mm/s³. Each run's line holds its total time
and the SHA-256 of its CSV (every tick, as written), or the error it stops with. Python 3.11, the
standard library only; two runs at a time. A few minutes on two cores.
"""
from __future__ import annotations

import argparse
import concurrent.futures
import hashlib
import json
import pathlib
import subprocess
import sys
import tempfile

HERE = pathlib.Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path.insert(0, str(HERE / "linuxcnc_compare"))

import compare  # noqa: E402  (its collect() and our_machine(): the same programs and machines)

JERKS = (5e4, 1e9)
MAX_TIME_S = 7200.0


def programs(work: pathlib.Path, ncfiles: bool, extra: list[pathlib.Path], cam_lines: int,
             cam_bin: pathlib.Path) -> list[pathlib.Path]:
    cases = compare.collect(work, ncfiles, [d.resolve() for d in extra], None, True)
    paths = [c.path for c in cases]
    if cam_lines > 0:
        cam = work / "programs" / f"cam_like_{cam_lines}.ngc"
        subprocess.run([str(cam_bin), str(cam_lines), str(cam)], check=True)
        paths.append(cam)
    paths.append(ROOT / "benches" / "data" / "one_hour.ngc")
    return paths


def run(cli: pathlib.Path, program: pathlib.Path, machine: pathlib.Path, scratch: pathlib.Path) -> str:
    csv_path = scratch / f"{program.stem}_{machine.stem}.csv"
    res = subprocess.run([str(cli), "run", str(program), "--machine", str(machine), "--json",
                          "--csv", str(csv_path), "--max-time", str(MAX_TIME_S)],
                         capture_output=True, text=True)
    if res.returncode != 0:
        last = (res.stderr.strip().splitlines() or [f"exit status {res.returncode}"])[-1]
        csv_path.unlink(missing_ok=True)
        # Without the (temporary) directory the programs were written to.
        return "error " + last.replace(str(program.parent) + "/", "").replace(str(program.parent), ".")
    digest = hashlib.sha256(csv_path.read_bytes()).hexdigest()[:32]
    csv_path.unlink()
    return f"{json.loads(res.stdout)['total_time_s']!r} s {digest}"


def digest(args: argparse.Namespace) -> int:
    cli = args.cli.resolve()
    if not cli.exists():
        print(f"{cli} is missing: cargo build --release --bin cnc-motion", file=sys.stderr)
        return 2
    cam_bin = ROOT / "target" / "release" / "examples" / "cam_program"
    if args.cam_lines > 0 and not cam_bin.exists():
        print(f"{cam_bin} is missing: cargo build --release --example cam_program", file=sys.stderr)
        return 2
    with tempfile.TemporaryDirectory() as tmp:
        work = pathlib.Path(tmp)
        paths = programs(work, args.ncfiles, args.extra, args.cam_lines, cam_bin)
        machines = [compare.our_machine(work / f"machine_j{j:g}.toml", j) for j in JERKS]
        jobs = [(p, m) for m in machines for p in paths]
        with concurrent.futures.ThreadPoolExecutor(max_workers=args.jobs) as pool:
            results = list(pool.map(lambda job: run(cli, job[0], job[1], work), jobs))
    lines = sorted(f"{p.name} {m.stem} {r}" for (p, m), r in zip(jobs, results))
    args.out.write_text("\n".join(lines) + "\n")
    moved = sum(" s " in line for line in lines)
    print(f"{len(lines)} runs ({moved} move, {len(lines) - moved} stop with an error) -> {args.out}")
    return 0


def compare_digests(a: pathlib.Path, b: pathlib.Path) -> int:
    def read(p: pathlib.Path) -> dict[str, str]:
        rows = (line.split(" ", 2) for line in p.read_text().splitlines() if line.strip())
        return {f"{name} {machine}": rest for name, machine, rest in rows}
    old, new = read(a), read(b)
    changed = sorted(k for k in old.keys() & new.keys() if old[k] != new[k])
    only = sorted(old.keys() ^ new.keys())
    for k in changed:
        print(f"changed {k}: {old[k]} -> {new[k]}")
    for k in only:
        print(f"in one only {k}")
    print(f"{len(old.keys() & new.keys())} runs in both, {len(changed)} changed, {len(only)} in one only")
    return 1 if changed or only else 0


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--cli", type=pathlib.Path, default=ROOT / "target" / "release" / "cnc-motion")
    ap.add_argument("--out", type=pathlib.Path, help="the digest to write")
    ap.add_argument("--compare", type=pathlib.Path, nargs=2, metavar=("OLD", "NEW"),
                    help="compare two digests (exit status 1 where they differ)")
    ap.add_argument("--ncfiles", action="store_true",
                    help="add LinuxCNC's sample programs (/usr/share/linuxcnc/ncfiles)")
    ap.add_argument("--extra", type=pathlib.Path, action="append", default=[],
                    help="a directory of more programs (*.ngc, recursively)")
    ap.add_argument("--cam-lines", type=int, default=30_000, help="lines of the CAM-like program (0: none)")
    ap.add_argument("--jobs", type=int, default=2, help="runs at a time")
    args = ap.parse_args()
    if args.compare:
        return compare_digests(*args.compare)
    if not args.out:
        ap.error("--out or --compare")
    return digest(args)


if __name__ == "__main__":
    sys.exit(main())
