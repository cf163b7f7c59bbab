#!/usr/bin/env python3
"""Side-by-side cycle times of cnc-motion and LinuxCNC 2.9 on the same programs and machine
(issue 19). Not part of CI or `make test`: it needs Debian's `linuxcnc-uspace` and an unprivileged
user account (README.md beside this file says how; the script checks both and says what is missing).

    python3 tools/linuxcnc_compare/compare.py [--out target/linuxcnc_compare]

The machine, for both: each axis 250 mm/s, 2000 mm/s², period 1 ms, G64 P0.01 at the program
head, feed cap 250 mm/s; ours at jerk 1e9 and 5e4 mm/s³ (LinuxCNC 2.9's planner has no jerk limit).
The programs: issue 19's families (families.py), the repository's corpus/ and examples/ programs,
and the sample programs Debian's package ships (/usr/share/linuxcnc/ncfiles) that our CLI accepts
and that run without an operator (no M0/M1/M60, no probing, no user M-codes).

LinuxCNC runs headless: the `linuxcnc` launcher with an INI of this script's making whose DISPLAY
is lcnc_display.py, as the unprivileged user (rtapi_app refuses root). Its `sampler` records the
joint position commands, the planner's path speed and the program line every servo period; a
program's time is the span from its first to its last moving sample (1 ms resolution, positions
to 1e-6 mm), the same span measured on our CSV. Writes results.csv and results.md (times, ratios
ours / LinuxCNC per program and per family, end points, worst cases with their speed profiles),
profiles/*.csv (speed over time of both) and LinuxCNC's raw samples under --out.
"""
from __future__ import annotations

import argparse
import csv
import json
import math
import os
import pathlib
import pwd
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass, field

HERE = pathlib.Path(__file__).resolve().parent
ROOT = HERE.parents[1]
sys.path.insert(0, str(HERE))
from families import Program, families  # noqa: E402

V_AXIS = 250.0  # mm/s
A_AXIS = 2000.0  # mm/s²
PERIOD_S = 0.001
JERKS = (1e9, 5e4)
NCFILES = pathlib.Path("/usr/share/linuxcnc/ncfiles")
RATIO_GOAL = 1.10
MOVE_EPS_MM = 5e-7  # LinuxCNC's samples are printed to 1e-6 mm
END_TOL_MM = 1e-3
# The same tool table for both (number: diameter, length in mm), for the sample programs that
# load a tool, offset its length (G43) or compensate its radius (G41/G42).
TOOLS = {1: (3.175, 12.9794), 2: (1.5875, 2.54), 3: (5.1054, 32.3342), 4: (6.35, 0.0)}

SETUP = """\
LinuxCNC is not set up for the comparison ({what}). As root, once:

    apt-get update && apt-get install -y --no-install-recommends linuxcnc-uspace
    useradd -m -s /bin/bash lcnc     # rtapi_app refuses root: LinuxCNC runs as this user

then run this script again (as root it runs LinuxCNC through `runuser -u lcnc`; --user names
another account). See tools/linuxcnc_compare/README.md."""


# --- the machine ------------------------------------------------------------------------------

def our_machine(path: pathlib.Path, jerk: float) -> pathlib.Path:
    axes = "".join(f"[axis.{a}]\nmax_velocity_mm_min = {V_AXIS * 60}\nmax_acceleration_mm_s2 = {A_AXIS}\n"
                   f"max_jerk_mm_s3 = {jerk}\n" for a in "xyz")
    tools = "".join(f"[tool.{n}]\nradius_mm = {d / 2:g}\nlength_mm = {z:g}\n" for n, (d, z) in TOOLS.items())
    path.write_text(f"interpolation_period_s = {PERIOD_S}\nmax_feed_mm_min = {V_AXIS * 60}\n"
                    f"path_tolerance_mm = 0.01\n{axes}{tools}")
    return path


def lcnc_tool_table() -> str:
    return "".join(f"T{n} P{n} D{d:g} Z{z:g}\n" for n, (d, z) in TOOLS.items())


def lcnc_ini(display: str) -> str:
    """LinuxCNC's INI: trivkins XYZ in mm, 1 ms servo period (the planner runs in the servo
    thread), each joint and axis 250 mm/s and 2000 mm/s², the path speed capped at 250 mm/s as
    ours (max_feed), the path acceleration left to the axes (2000·√3 is what three axes at their
    limit give), no homing needed."""
    joint = (f"TYPE = LINEAR\nHOME = 0\nMIN_LIMIT = -10000\nMAX_LIMIT = 10000\nMAX_VELOCITY = {V_AXIS:g}\n"
             f"MAX_ACCELERATION = {A_AXIS:g}\nFERROR = 100\nMIN_FERROR = 100\nHOME_SEQUENCE = 0\n")
    axis = f"MIN_LIMIT = -10000\nMAX_LIMIT = 10000\nMAX_VELOCITY = {V_AXIS:g}\nMAX_ACCELERATION = {A_AXIS:g}\n"
    a_path = A_AXIS * math.sqrt(3)
    return f"""\
[EMC]
VERSION = 1.1
MACHINE = cnc-motion-compare
DEBUG = 0

[DISPLAY]
DISPLAY = {display}

[TASK]
TASK = milltask
CYCLE_TIME = 0.001

[RS274NGC]
PARAMETER_FILE = sim.var

[EMCIO]
EMCIO = io
CYCLE_TIME = 0.100
TOOL_TABLE = tool.tbl

[EMCMOT]
EMCMOT = motmod
COMM_TIMEOUT = 1.0
SERVO_PERIOD = {round(PERIOD_S * 1e9)}

[HAL]
HALFILE = machine.hal

[KINS]
JOINTS = 3
KINEMATICS = trivkins coordinates=XYZ

[TRAJ]
COORDINATES = X Y Z
LINEAR_UNITS = mm
ANGULAR_UNITS = degree
DEFAULT_LINEAR_VELOCITY = {V_AXIS:g}
MAX_LINEAR_VELOCITY = {V_AXIS:g}
DEFAULT_LINEAR_ACCELERATION = {a_path:.1f}
MAX_LINEAR_ACCELERATION = {a_path:.1f}
NO_FORCE_HOMING = 1

[AXIS_X]
{axis}
[AXIS_Y]
{axis}
[AXIS_Z]
{axis}
[JOINT_0]
{joint}
[JOINT_1]
{joint}
[JOINT_2]
{joint}"""


# --- the programs -----------------------------------------------------------------------------

@dataclass
class Case:
    id: int
    family: str
    name: str
    path: pathlib.Path
    skip: str = ""
    pinned: bool = False
    ours: dict[float, Run] = field(default_factory=dict)
    lcnc: Run | None = None
    lcnc_error: str = ""


@dataclass
class Run:
    """One motion sampled every period: positions (mm), line, path speed (mm/s)."""
    t0: int  # index of the last sample at rest before the motion
    t1: int  # index of the last moving sample
    pos: list[tuple[float, float, float]]
    line: list[int]
    speed: list[float]
    total_time_s: float = math.nan  # ours: total_time_s from --json

    @property
    def time_s(self) -> float:
        return (self.t1 - self.t0) * PERIOD_S

    @property
    def end(self) -> tuple[float, float, float]:
        return self.pos[-1]

    def axis_max(self) -> tuple[float, float]:
        """Largest axis velocity and acceleration by finite differences (mm/s, mm/s²)."""
        v = a = 0.0
        p = self.pos
        for i in range(1, len(p)):
            for k in range(3):
                v = max(v, abs(p[i][k] - p[i - 1][k]) / PERIOD_S)
                if i >= 2:
                    a = max(a, abs(p[i][k] - 2 * p[i - 1][k] + p[i - 2][k]) / PERIOD_S ** 2)
        return v, a


def span(pos: list[tuple[float, float, float]]) -> tuple[int, int]:
    moving = [i for i in range(1, len(pos)) if math.dist(pos[i], pos[i - 1]) > MOVE_EPS_MM]
    if not moving:
        return 0, 0
    return moving[0] - 1, moving[-1]


UNATTENDED = re.compile(r"\b(M0*[01]|M60|G38(\.\d)?|M1\d\d)\b(?![.\d])", re.IGNORECASE)


def code_part(line: str) -> str:
    """The line with its comments blanked (same length): ( … ) and from ; on."""
    out: list[str] = []
    depth = 0
    for ch in line:
        if depth == 0 and ch == ";":
            return "".join(out) + " " * (len(line) - len(out))
        if ch == "(":
            depth += 1
        out.append(" " if depth else ch)
        if ch == ")" and depth:
            depth -= 1
    return "".join(out)


G64 = re.compile(r"g\s*0*64(?![.\d])", re.IGNORECASE)
P_WORD = re.compile(r"p\s*([-+.\d]+)?(?=\s*[^-+.\d\s]|\s*$)", re.IGNORECASE)
UNITS = re.compile(r"g\s*0*2([01])(?![.\d])", re.IGNORECASE)


def pin_g64(lines: list[str]) -> list[str]:
    """Every G64 without P, or with P0, given P for 0.01 mm in the units in force (G20/G21 on the
    same line first, as both execute them). LinuxCNC reads a zero or missing P as no tolerance
    (its planner then blends up to a quarter of the shorter segment: "the best speed possible,
    no matter how far from the programmed point"); ours takes the machine's path_tolerance_mm
    (0.01 here) for both. So this leaves ours as it was and gives both the same bound."""
    out: list[str] = []
    inch = False
    for line in lines:
        code = code_part(line)
        for u in UNITS.finditer(code):
            inch = u.group(1) == "0"
        m = G64.search(code)
        if m is not None:
            pin = "P0.00039370" if inch else "P0.01"
            p = P_WORD.search(code)
            if p is None:
                line = line[:m.end()] + " " + pin + line[m.end():]
            elif p.group(1) is not None and float(p.group(1)) == 0.0:
                line = line[:p.start()] + pin + line[p.end():]
        out.append(line)
    return out


def head(text: str, pin: bool = True) -> str:
    """The program with `G64 P0.01` as its first block (after a leading `%` line) and, with
    `pin`, every G64 without P given 0.01 mm (pin_g64)."""
    lines = text.splitlines()
    if pin:
        lines = pin_g64(lines)
    at = 0
    for i, line in enumerate(lines):
        if line.strip():
            at = i + 1 if line.strip() == "%" else i
            break
    return "\n".join(lines[:at] + ["G64 P0.01"] + lines[at:]) + "\n"


def collect(out: pathlib.Path, with_ncfiles: bool, extra: list[pathlib.Path], only: str | None,
            pin: bool) -> list[Case]:
    progs = out / "programs"
    progs.mkdir(parents=True, exist_ok=True)
    cases: list[Case] = []

    def add(family: str, name: str, text: str, skip: str = "", source: str = "") -> None:
        path = progs / f"{name}.ngc"
        path.write_text(text)
        cases.append(Case(len(cases) + 1, family, name, path, skip, bool(source) and text != head(source, False)))

    for p in families():
        add(p.family, p.name, p.text)
    repo = sorted((ROOT / "corpus").glob("*.ngc")) + sorted((ROOT / "examples").glob("*.ngc"))
    for f in repo:
        add("repository programs", f"{f.parent.name}_{f.stem}", head(f.read_text(), pin), source=f.read_text())
    if with_ncfiles and NCFILES.is_dir():
        for f in sorted(NCFILES.glob("*.ngc")):
            text = f.read_text(errors="replace")
            m = UNATTENDED.search(re.sub(r"\([^)]*\)|;.*", "", text))
            add("LinuxCNC ncfiles", f"ncfiles_{f.stem}", head(text, pin),
                f"needs an operator or a user M-code ({m.group(0)})" if m else "", text)
    for d in extra:
        found = sorted(pathlib.Path(top, n) for top, _, names in os.walk(d) for n in names if n.endswith(".ngc"))
        for f in found:  # os.walk does not follow links to directories (auto-test/ links to the others)
            rel = f.relative_to(d)
            text = f.read_text(errors="replace")
            m = UNATTENDED.search(re.sub(r"\([^)]*\)|;.*", "", text))
            group = rel.parts[0] if len(rel.parts) > 1 else "."
            add(f"{d.name}/{group}", f"{d.name}_{'_'.join(rel.with_suffix('').parts)}", head(text, pin),
                f"needs an operator or a user M-code ({m.group(0)})" if m else "", text)
    if only:
        cases = [c for c in cases if re.search(only, c.name)]
    return cases


# --- ours --------------------------------------------------------------------------------------

def run_ours(cli: pathlib.Path, case: Case, jerk: float, out: pathlib.Path, max_s: float) -> Run | str:
    machine = our_machine(out / f"machine_j{jerk:g}.toml", jerk)
    csv_path = out / "ours" / f"{case.name}_j{jerk:g}.csv"
    csv_path.parent.mkdir(exist_ok=True)
    res = subprocess.run([str(cli), "run", str(case.path), "--machine", str(machine), "--json",
                          "--csv", str(csv_path), "--max-time", str(max_s)],
                         capture_output=True, text=True)
    if res.returncode != 0:
        return (res.stderr.strip().splitlines() or ["exit status %d" % res.returncode])[-1].replace(f"{out}/", "")
    summary = json.loads(res.stdout)
    pos: list[tuple[float, float, float]] = [(0.0, 0.0, 0.0)]
    line, speed = [0], [0.0]
    with open(csv_path) as f:
        rows = csv.reader(f)
        next(rows)
        for r in rows:
            pos.append((float(r[2]), float(r[3]), float(r[4])))
            line.append(int(r[1]))
            speed.append(float(r[5]))
    t0, t1 = span(pos)
    end = tuple(summary["end_position_mm"])
    assert math.dist(end, pos[-1]) < 1e-6, (end, pos[-1])
    return Run(t0, t1, pos, line, speed, float(summary["total_time_s"]))


# --- LinuxCNC ----------------------------------------------------------------------------------

def check_linuxcnc(user: str) -> str:
    """What is missing for a LinuxCNC run, or ''."""
    for exe in ("linuxcnc", "halsampler", "rtapi_app"):
        if shutil.which(exe) is None:
            return f"`{exe}` is not on PATH: linuxcnc-uspace is not installed"
    if not pathlib.Path("/usr/bin/python3").exists() or subprocess.run(
            ["/usr/bin/python3", "-c", "import linuxcnc, hal"], capture_output=True).returncode != 0:
        return "/usr/bin/python3 cannot import LinuxCNC's modules `linuxcnc` and `hal`"
    if os.geteuid() == 0:
        try:
            if pwd.getpwnam(user).pw_uid == 0:
                return f"the user {user} is root"
        except KeyError:
            return f"there is no user {user}"
    return ""


def lcnc_version() -> str:
    res = subprocess.run(["dpkg-query", "-W", "-f", "${Version}", "linuxcnc-uspace"],
                         capture_output=True, text=True)
    return res.stdout.strip() or "unknown"


def run_linuxcnc(cases: list[Case], user: str, out: pathlib.Path, timeouts: dict[int, float]) -> None:
    work = pathlib.Path(tempfile.mkdtemp(prefix="cnc_motion_lcnc_"))
    progs = work / "programs"
    progs.mkdir()
    shutil.copy(HERE / "machine.hal", work)
    shutil.copy(HERE / "lcnc_display.py", work)
    (work / "lcnc_display.py").chmod(0o755)
    (work / "tool.tbl").write_text(lcnc_tool_table())
    programs: list[dict[str, object]] = []
    for c in cases:
        shutil.copy(c.path, progs / c.path.name)
        programs.append({"id": c.id, "name": c.name, "path": str(progs / c.path.name), "timeout_s": timeouts[c.id]})
    job = {"samples": str(work / "samples.txt"), "results": str(work / "results.json"),
           "log": str(work / "display.log"), "programs": programs}
    (work / "job.json").write_text(json.dumps(job, indent=1))
    (work / "machine.ini").write_text(lcnc_ini(f"{work / 'lcnc_display.py'} {work / 'job.json'}"))
    cmd = ["linuxcnc", str(work / "machine.ini")]
    if os.geteuid() == 0:
        pw = pwd.getpwnam(user)
        for p in [work, *work.rglob("*")]:
            os.chown(p, pw.pw_uid, pw.pw_gid)
        cmd = ["runuser", "-u", user, "--", "env", f"HOME={pw.pw_dir}", f"USER={user}", *cmd]
    budget = sum(timeouts.values()) + 30 * len(cases) + 120
    print(f"LinuxCNC: {len(cases)} programs, real time (at most {budget:.0f} s) in {work}", flush=True)
    t = time.monotonic()
    with open(work / "linuxcnc.log", "w") as log:
        res = subprocess.run(cmd, cwd=work, stdout=log, stderr=subprocess.STDOUT, timeout=budget)
    print(f"LinuxCNC exited {res.returncode} after {time.monotonic() - t:.0f} s", flush=True)
    dest = out / "linuxcnc"
    dest.mkdir(exist_ok=True)
    for name in ("machine.ini", "machine.hal", "job.json", "samples.txt", "results.json", "display.log",
                 "linuxcnc.log"):
        if (work / name).exists():
            shutil.copy(work / name, dest / name)
    shutil.rmtree(work, ignore_errors=True)
    read_linuxcnc(cases, dest)


def read_linuxcnc(cases: list[Case], dest: pathlib.Path) -> None:
    if not (dest / "results.json").exists():
        raise SystemExit(f"LinuxCNC wrote no results: see {dest}/linuxcnc.log and display.log")
    results = {r["id"]: r for r in json.loads((dest / "results.json").read_text())}
    samples: dict[int, list[list[str]]] = {}
    last_tag: dict[int, int] = {}
    gaps: set[int] = set()
    with open(dest / "samples.txt") as f:
        for raw in f:
            r = raw.split()
            if len(r) != 7:
                gaps.update(samples)  # an 'overrun' line: samples were lost
                continue
            pid, tag = int(r[6]), int(r[0])
            if pid == 0:
                continue
            if pid in last_tag and tag != last_tag[pid] + 1:
                gaps.add(pid)
            last_tag[pid] = tag
            samples.setdefault(pid, []).append(r)
    for c in cases:
        res = results.get(c.id)
        if res is None:
            c.lcnc_error = "LinuxCNC: not run"
            continue
        if res["errors"]:
            c.lcnc_error = "LinuxCNC: " + "; ".join(res["errors"])[:200]
            continue
        rows = samples.get(c.id, [])
        if c.id in gaps or not rows:
            c.lcnc_error = "LinuxCNC: samples lost (sampler overrun)" if rows else "LinuxCNC: no samples"
            continue
        pos = [(float(r[1]), float(r[2]), float(r[3])) for r in rows]
        t0, t1 = span(pos)
        c.lcnc = Run(t0, t1, pos, [int(r[5]) for r in rows], [float(r[4]) for r in rows])


# --- the report --------------------------------------------------------------------------------

def speeds(run: Run) -> list[float]:
    """Path speed from the positions, per sample from the start of the motion (mm/s)."""
    p = run.pos
    return [math.dist(p[i], p[i - 1]) / PERIOD_S for i in range(run.t0 + 1, run.t1 + 1)]


def write_profile(c: Case, path: pathlib.Path) -> None:
    assert c.lcnc is not None
    cols = [speeds(c.lcnc), c.lcnc.speed[c.lcnc.t0 + 1:c.lcnc.t1 + 1]] + [speeds(c.ours[j]) for j in JERKS]
    n = max(len(x) for x in cols)
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["time_s", "linuxcnc_speed_mm_s", "linuxcnc_current_vel_mm_s",
                    *[f"ours_j{j:g}_speed_mm_s" for j in JERKS]])
        for i in range(n):
            w.writerow([f"{(i + 1) * PERIOD_S:.3f}", *[f"{x[i]:.3f}" if i < len(x) else "" for x in cols]])


def windows(run: Run, n: int) -> list[tuple[float, float]]:
    """Time (s) and distance (mm) in each n-th of the path's length."""
    p = run.pos
    steps = [math.dist(p[i], p[i - 1]) for i in range(run.t0 + 1, run.t1 + 1)]
    total = sum(steps) or 1.0
    out = [(0.0, 0.0)] * n
    s = 0.0
    for d in steps:
        k = min(n - 1, int(n * (s + 0.5 * d) / total))
        out[k] = (out[k][0] + PERIOD_S, out[k][1] + d)
        s += d
    return out


def window_losses(c: Case, jerk: float, n: int = 20, top: int = 3) -> str:
    """Where along the path (in 5 % steps of its length) ours spends the most time beyond
    LinuxCNC's, with both mean speeds there."""
    assert c.lcnc is not None
    ours, theirs = windows(c.ours[jerk], n), windows(c.lcnc, n)
    diff = sorted(((ours[k][0] - theirs[k][0], k) for k in range(n)), reverse=True)
    return "; ".join(f"{100 * k // n}–{100 * (k + 1) // n} %: +{d * 1e3:.0f} ms "
                     f"({ours[k][1] / max(ours[k][0], 1e-9):.0f} vs {theirs[k][1] / max(theirs[k][0], 1e-9):.0f} mm/s)"
                     for d, k in diff[:top] if d > 0.0005) or "nowhere"


def speed_summary(run: Run) -> str:
    s = speeds(run)
    if not s:
        return "-"
    return f"mean {statistics.fmean(s):.1f}, peak {max(s):.1f} mm/s"


def ratio(c: Case, jerk: float) -> float:
    assert c.lcnc is not None
    return c.ours[jerk].time_s / c.lcnc.time_s if c.lcnc.time_s > 0 else math.nan


def report(cases: list[Case], out: pathlib.Path, version: str) -> str:
    done = [c for c in cases if c.lcnc is not None and len(c.ours) == len(JERKS) and c.lcnc.time_s > 0]
    with open(out / "results.csv", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["family", "program", "linuxcnc_s", *[f"ours_j{j:g}_s" for j in JERKS],
                    *[f"ratio_j{j:g}" for j in JERKS], "ours_total_time_s", "end_point_diff_mm",
                    "linuxcnc_max_axis_v_mm_s", "linuxcnc_max_axis_a_mm_s2", "skipped"])
        for c in cases:
            if c in done:
                assert c.lcnc is not None
                v, a = c.lcnc.axis_max()
                w.writerow([c.family, c.name, f"{c.lcnc.time_s:.3f}", *[f"{c.ours[j].time_s:.3f}" for j in JERKS],
                            *[f"{ratio(c, j):.4f}" for j in JERKS], f"{c.ours[JERKS[0]].total_time_s:.4f}",
                            f"{math.dist(c.ours[JERKS[0]].end, c.lcnc.end):.2e}", f"{v:.1f}", f"{a:.0f}", ""])
            else:
                w.writerow([c.family, c.name, "", "", "", "", "", "", "", "", "", c.skip or c.lcnc_error])

    md: list[str] = []
    md.append(f"# cnc-motion against LinuxCNC {version}\n")
    md.append("Machine: each axis 250 mm/s and 2000 mm/s², 1 ms, G64 P0.01, feed cap 250 mm/s; ours at jerk "
              "1e9 and 5e4 mm/s³ (LinuxCNC 2.9's planner has no jerk limit). Time: first to last moving "
              "sample (1 ms). Ratio: ours / LinuxCNC.\n")
    md.append("## Per family\n")
    md.append("| family | programs | ratio at jerk 1e9: median (min – max) | > 1.10 | "
              "ratio at jerk 5e4: median (min – max) | > 1.10 |")
    md.append("|---|---|---|---|---|---|")
    fams: dict[str, list[Case]] = {}
    for c in done:
        fams.setdefault(c.family, []).append(c)
    for fam, cs in [*fams.items(), ("all", done)]:
        cells = []
        for j in JERKS:
            r = [ratio(c, j) for c in cs]
            cells.append(f"{statistics.median(r):.3f} ({min(r):.3f} – {max(r):.3f}) | "
                         f"{sum(x > RATIO_GOAL for x in r)}")
        name = f"**{fam}**" if fam == "all" else fam
        md.append(f"| {name} | {len(cs)} | {' | '.join(cells)} |")
    md.append("\n## Per program\n")
    md.append("| program | LinuxCNC s | ours 1e9 s | ratio | ours 5e4 s | ratio | end point Δ mm | "
              "LinuxCNC max axis v, a |")
    md.append("|---|---|---|---|---|---|---|---|")
    for c in done:
        assert c.lcnc is not None
        v, a = c.lcnc.axis_max()
        md.append(f"| {c.name} | {c.lcnc.time_s:.3f} | {c.ours[1e9].time_s:.3f} | {ratio(c, 1e9):.3f} | "
                  f"{c.ours[5e4].time_s:.3f} | {ratio(c, 5e4):.3f} | "
                  f"{math.dist(c.ours[1e9].end, c.lcnc.end):.1e} | {v:.0f}, {a:.0f} |")
    bad_end = [c.name for c in done if c.lcnc and math.dist(c.ours[1e9].end, c.lcnc.end) > END_TOL_MM]
    md.append(f"\nEnd points differing by more than {END_TOL_MM} mm: {', '.join(bad_end) or 'none'}.\n")
    md.append("## Worst cases (jerk 1e9)\n")
    prof = out / "profiles"
    prof.mkdir(exist_ok=True)
    worst = sorted(done, key=lambda c: -ratio(c, 1e9))
    for c in worst[:max(6, sum(ratio(c, 1e9) > RATIO_GOAL for c in done))]:
        assert c.lcnc is not None
        write_profile(c, prof / f"{c.name}.csv")
        md.append(f"- **{c.name}** {ratio(c, 1e9):.3f} (5e4: {ratio(c, 5e4):.3f}): ours "
                  f"{speed_summary(c.ours[1e9])}, LinuxCNC {speed_summary(c.lcnc)}; ours slower at "
                  f"{window_losses(c, 1e9)} (profiles/{c.name}.csv)")
    pinned = [c.name for c in done if c.pinned]
    md.append(f"\nPrograms whose G64 without P or with P0 was given 0.01 mm (pin_g64): {len(pinned)} of {len(done)}.")
    skipped = [c for c in cases if c not in done]
    if skipped:
        md.append("\n## Not compared\n")
        for c in skipped:
            md.append(f"- {c.name}: {c.skip or c.lcnc_error}")
    text = "\n".join(md) + "\n"
    (out / "results.md").write_text(text)
    return text


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--cli", type=pathlib.Path, default=ROOT / "target" / "release" / "cnc-motion")
    ap.add_argument("--out", type=pathlib.Path, default=ROOT / "target" / "linuxcnc_compare")
    ap.add_argument("--user", default="lcnc", help="the unprivileged account LinuxCNC runs as (when root)")
    ap.add_argument("--only", help="a regular expression: only programs whose name it matches")
    ap.add_argument("--no-ncfiles", action="store_true", help="leave out LinuxCNC's sample programs")
    ap.add_argument("--extra", type=pathlib.Path, action="append", default=[],
                    help="a directory of more programs (*.ngc, recursively; a family per subdirectory), "
                         "e.g. LinuxCNC's tests/trajectory-planner/circular-arcs/nc_files from its source")
    ap.add_argument("--max-program-s", type=float, default=120.0,
                    help="leave out programs whose motion takes longer (LinuxCNC runs in real time)")
    ap.add_argument("--as-written", action="store_true",
                    help="leave a program's G64 without P as it is (LinuxCNC: no tolerance; ours: 0.01 mm)")
    ap.add_argument("--ours-only", action="store_true", help="run ours only (which programs it accepts)")
    ap.add_argument("--reuse", action="store_true", help="read the last LinuxCNC run under --out again")
    args = ap.parse_args()
    if not args.cli.exists():
        print(f"{args.cli} is missing: cargo build --release --bin cnc-motion", file=sys.stderr)
        return 2
    missing = check_linuxcnc(args.user)
    if missing and not args.reuse:
        print(SETUP.format(what=missing), file=sys.stderr)
        return 2
    out: pathlib.Path = args.out.resolve()
    out.mkdir(parents=True, exist_ok=True)
    cases = collect(out, not args.no_ncfiles, [d.resolve() for d in args.extra], args.only, not args.as_written)
    timeouts: dict[int, float] = {}
    for c in cases:
        for j in JERKS:
            if c.skip:
                break
            r = run_ours(args.cli, c, j, out, args.max_program_s)
            if isinstance(r, str) and "not finished after --max-time" in r:
                c.skip = f"longer than --max-program-s {args.max_program_s:g} s (LinuxCNC runs in real time)"
            elif isinstance(r, str):
                c.skip = f"cnc-motion: {r}"
            elif r.t1 == r.t0:
                c.skip = "no motion"
            else:
                c.ours[j] = r
        if not c.skip:
            timeouts[c.id] = 3 * max(r.total_time_s for r in c.ours.values()) + 20
        print(f"{c.name}: {c.skip or ', '.join(f'{r.time_s:.3f} s' for r in c.ours.values())}", flush=True)
    runnable = [c for c in cases if not c.skip]
    if args.ours_only:
        return 0
    if args.reuse:
        read_linuxcnc(runnable, out / "linuxcnc")
    else:
        run_linuxcnc(runnable, args.user, out, timeouts)
    print(report(cases, out, lcnc_version()))
    return 0


if __name__ == "__main__":
    sys.exit(main())
