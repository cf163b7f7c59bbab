"""Every platform's binaries of both FMUs, run for real beside linux64: Debian's wine64 runs a plain C
importer (tests/c/fmi2_harness.c, built with mingw-w64: LoadLibrary/GetProcAddress, a variadic
logger) on the win64 DLLs of the FMI 2 archives; qemu-aarch64 runs the same C source built with
Debian's aarch64 gcc (dlopen) on the aarch64-linux libraries of the FMI 3 archives (FMI 2.0 names no
aarch64 platform; the library exports the fmi2 functions too, which the harness drives); and the
same source built for the host runs the linux64 libraries with the same scripts. Each writes every
call's status, every log message and every recorded output as IEEE-754 bits; each platform's file
must agree with linux64's:

- statuses, log messages, step counts, Integers and Booleans: identical;
- Reals: within 1e-12 of each variable's largest magnitude in the run (a drive's force: within its
  resolution, below). They are not all bit-identical:
  the planner's and the drives' sin, cos, atan2, tanh, … come from each platform's C library
  (glibc on Linux x86_64 and aarch64, msvcrt/mingw-w64 on Windows), which round differently in the
  last bit; the drives carry such a difference into their outputs. The largest relative differences
  seen are printed (about 1e-15 of a column's range; command positions differ by at most an ulp).
- A drive's `driveForce` is its screw's spring force k·(r·θ − x) (docs/servo.md): a difference of two
  positions of up to 0.1 m times k = 150 N/µm. A last-bit difference of either position, which the
  drives carry from a one-ulp command difference, is k·ulp(x) ≈ 150e6 N/m · 1.4e-17 m ≈ 2e-9 N:
  1.6e-11 of the pocket's 131 N peak, above 1e-12 of the column whatever the platforms do. Its bound
  is that resolution, `FORCE_ULPS` ulps of each position (seen: 2 on a pocket variant of a corner
  choice; 0 on main).

The wine prefix lives in target/wine (created once, ~15-60 s, with Mono/Gecko off).
"""
import math
import os
import shutil
import struct
import subprocess
import zipfile
from pathlib import Path
from typing import Any, Callable

import pytest

from cnc_motion_sim import Unpacked
from repo import CORPUS, FMU_DIR, ROOT

# One scripted call: an operation and its arguments (see _script).
Command = tuple[Any, ...]

HARNESS = ROOT / "target" / "harness"
PREFIX = ROOT / "target" / "wine"
BOUND = 1e-12
FORCE_ULPS = 4
# The C library of Debian's aarch64 cross toolchain (libc6-arm64-cross), for qemu-aarch64 -L.
ARM64_SYSROOT = Path("/usr/aarch64-linux-gnu")


def _bits(x: float) -> str:
    return struct.pack(">d", float(x)).hex()


def _wine() -> str:
    for name in ("wine64", "wine"):
        found = shutil.which(name)
        if found:
            return found
    if os.access("/usr/lib/wine/wine64", os.X_OK):
        return "/usr/lib/wine/wine64"
    pytest.fail("wine64 not found: run `make system-deps` (apt-get install wine64)")


def _env() -> dict[str, str]:
    env = dict(os.environ, WINEPREFIX=str(PREFIX), WINEDEBUG="-all", WINEDLLOVERRIDES="mscoree,mshtml=")
    env.pop("DISPLAY", None)
    return env


@pytest.fixture(scope="session")
def wine() -> str:
    """wine64 with a prefix under target/ and the harness built (`make harness`)."""
    subprocess.run(["make", "-s", "harness"], cwd=ROOT, check=True)
    wine = _wine()
    if not (PREFIX / "system.reg").exists():
        PREFIX.mkdir(parents=True, exist_ok=True)
        subprocess.run([wine, "wineboot", "-i"], env=_env(), check=True, timeout=600,
                       stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    server = Path(wine).with_name("wineserver")
    if server.exists():  # wait until wineboot's services have settled
        subprocess.run([str(server), "-w"], env=_env(), timeout=120)
    return wine


@pytest.fixture(scope="session")
def qemu() -> str:
    """qemu-aarch64 (Debian's qemu-user) and the aarch64 harness built (`make harness`)."""
    subprocess.run(["make", "-s", "harness"], cwd=ROOT, check=True)
    found = shutil.which("qemu-aarch64")
    if found is None or not (ARM64_SYSROOT / "lib").is_dir():
        pytest.fail("qemu-aarch64 or the aarch64 C library not found: run `make system-deps`")
    return found


@pytest.fixture(scope="session")
def runners(wine: str, qemu: str) -> dict[str, str]:
    """The emulator of each platform that needs one."""
    return {"win64": wine, "aarch64-linux": qemu}


def _arm64_library(model: str, tmp_path: Path) -> Path:
    """The aarch64-linux library of `model`'s FMI 3 archive (the one that ships it)."""
    member = f"binaries/aarch64-linux/{model}.so"
    with zipfile.ZipFile(FMU_DIR / f"{model}-fmi3.fmu") as z:
        z.extract(member, tmp_path / "fmi3")
    return tmp_path / "fmi3" / member


def _windows_path(p: Path) -> str:
    return "Z:" + str(p).replace("/", "\\")


def _uri(p: Path, windows: bool) -> str:
    return "file:///" + (_windows_path(p).replace("\\", "/") if windows else str(p).lstrip("/"))


def _script(md: Any, commands: list[Command]) -> str:
    vars = {v.name: v for v in md.modelVariables}

    def vr(name: str) -> int:
        return vars[name].valueReference

    lines = [f"guid {md.guid}"]
    for c in commands:
        op, *args = c
        if op == "set":
            name, value = args
            kind = vars[name].type
            if kind == "Real":
                lines.append(f"real {vr(name)} {_bits(value)}")
            elif kind in ("Integer", "Enumeration"):
                lines.append(f"integer {vr(name)} {int(value)}")
            elif kind == "Boolean":
                lines.append(f"boolean {vr(name)} {int(bool(value))}")
            else:
                lines.append(f"string {vr(name)} " + str(value).replace("\\", "\\\\").replace("\n", "\\n"))
        elif op == "record":
            outs = [v for v in md.modelVariables if v.causality == "output"]
            kinds = {"Real": "r", "Integer": "i", "Boolean": "b"}
            lines.append("record " + " ".join(f"{kinds[v.type]}:{v.valueReference}" for v in outs))
        elif op == "until":
            lines.append(f"until {vr(args[0])} {args[1]} {_bits(args[2])}")
        elif op == "steps":
            lines.append(f"steps {args[0]} {_bits(args[1])}")
        else:
            lines.append(" ".join([op] + [str(a) for a in args]))
    return "\n".join(lines) + "\n"


PLATFORMS = ("linux64", "win64", "aarch64-linux")


def _run(runners: dict[str, str], unpacked: Unpacked, commands: Callable[[bool], list[Command]],
         tmp_path: Path, name: str) -> dict[str, list[str]]:
    """The script through linux64 (native harness), win64 (wine) and aarch64-linux (qemu); every
    platform's output file, by platform."""
    md, model = unpacked.md, unpacked.md.coSimulation.modelIdentifier
    resources = Path(unpacked.dir) / "resources"
    out: dict[str, list[str]] = {}
    for platform in PLATFORMS:
        windows = platform == "win64"
        script = tmp_path / f"{name}_{platform}.txt"
        script.write_text(_script(md, commands(windows)))
        result = tmp_path / f"{name}_{platform}.out"
        env = None
        if windows:
            dll = Path(unpacked.dir) / "binaries" / "win64" / f"{model}.dll"
            cmd = [runners[platform], str(HARNESS / "win64" / "fmi2_harness.exe"), _windows_path(dll),
                   _uri(resources, True), _windows_path(script), _windows_path(result)]
            env = _env()
        elif platform == "aarch64-linux":
            so = _arm64_library(model, tmp_path)
            cmd = [runners[platform], "-L", str(ARM64_SYSROOT), str(HARNESS / "aarch64" / "fmi2_harness"),
                   str(so), _uri(resources, False), str(script), str(result)]
        else:
            so = Path(unpacked.dir) / "binaries" / "linux64" / f"{model}.so"
            cmd = [str(HARNESS / "fmi2_harness"), str(so), _uri(resources, False), str(script), str(result)]
        res = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=600)
        assert res.returncode == 0, f"{cmd}: {res.returncode}\n{res.stdout}\n{res.stderr}"
        out[platform] = result.read_text().splitlines()
    return out


def _compare_all(runs: dict[str, list[str]], floors: dict[int, float] | None = None
                 ) -> tuple[int, dict[str, float]]:
    """Every platform against linux64 (`_compare`, with `floors`): the step count and each one's
    largest relative difference."""
    steps, worst = 0, {}
    for platform in PLATFORMS[1:]:
        steps, worst[platform] = _compare(runs["linux64"], runs[platform], floors)
    return steps, worst


def _worst(worst: dict[str, float]) -> str:
    return ", ".join(f"{p} {w:.1e}" for p, w in worst.items())


def _force_floors(md: Any, linux: list[str]) -> dict[int, float]:
    """Each drive's driveForce column: its resolution FORCE_ULPS·k·ulp(x) at the axis's largest
    table position in the (linux) run, k the screw's axial stiffness (the FMU's start value)."""
    names = [v.name for v in md.modelVariables if v.causality == "output"]
    start = {v.name: v.start for v in md.modelVariables}
    steps = [line.split()[2:] for line in linux if line.startswith("step ")]
    floors = {}
    for axis in "xyz":
        force, position = f"{axis}.driveForce", f"{axis}.position"
        if force not in names or position not in names or not steps:
            continue
        col = names.index(position)
        x = max(abs(struct.unpack(">d", bytes.fromhex(s[col]))[0]) for s in steps)
        floors[names.index(force)] = FORCE_ULPS * float(start[f"{axis}.servo.axialStiffness"]) * math.ulp(x)
    return floors


def _compare(linux: list[str], windows: list[str], floors: dict[int, float] | None = None) -> tuple[int, float]:
    """Log lines identical; calls: the same status (the scripts differ in their paths); step lines:
    same counts, Integers/Booleans equal, Reals within BOUND of their column's largest magnitude
    (or within `floors` of a column, where given). Returns (steps, largest relative difference)."""
    assert len(linux) == len(windows), (len(linux), len(windows))
    steps = [(a.split()[2:], b.split()[2:]) for a, b in zip(linux, windows) if a.startswith("step ")]
    for a, b in zip(linux, windows):
        if a.startswith("call "):
            assert (a.split()[:2], a.split()[-1]) == (b.split()[:2], b.split()[-1]), (a, b)
        elif a.startswith("step "):
            assert a.split()[:2] == b.split()[:2]
        else:
            assert a == b
    def real(h: str) -> float:
        return float(struct.unpack(">d", bytes.fromhex(h))[0])

    worst = 0.0
    if steps:
        for col in range(len(steps[0][0])):
            ca = [s[0][col] for s in steps]
            cb = [s[1][col] for s in steps]
            if len(ca[0]) != 16:  # Integer or Boolean
                assert ca == cb, f"column {col}"
                continue
            x, y = [real(h) for h in ca], [real(h) for h in cb]
            scale = max(max(abs(v) for v in x), 1e-300)
            diff = max(abs(p - q) for p, q in zip(x, y))
            floor = (floors or {}).get(col, 0.0)
            assert diff <= max(BOUND * scale, floor), f"column {col}: {diff} of {scale}"
            if diff > BOUND * scale:
                print(f"column {col}: {diff:.2e} within its resolution {floor:.2e}")
            else:
                worst = max(worst, diff / scale)
    return len(steps), worst


POCKET = "seed003_pocket.txt"


def test_cnc_motion_on_every_platform_equals_linux64(runners: dict[str, str], cnc: Unpacked,
                                                    tmp_path: Path) -> None:
    h = 1e-3
    def default(windows: bool) -> list[Command]:
        return [("instantiate", "default"), ("init",), ("record",), ("until", "status.finished", 100000, h),
                ("terminate",), ("free",)]
    runs = _run(runners, cnc, default, tmp_path, "default")
    steps, worst = _compare_all(runs, _force_floors(cnc.md, runs["linux64"]))
    assert steps > 5000, steps
    print(f"\ndefault program, servo on: {steps} steps, largest relative difference {_worst(worst)}")

    machine = ROOT / "examples" / "machines" / "seed003_pocket.toml"
    program = CORPUS / POCKET

    def pocket(windows: bool) -> list[Command]:
        path = _windows_path(program) if windows else str(program)
        return [("instantiate", "pocket"), ("set", "machineFile", _uri(machine, windows)),
                ("set", "programFile", path), ("set", "feedOverride", 1.5), ("init",), ("record",),
                ("until", "status.finished", 200000, h), ("terminate",), ("free",)]

    runs = _run(runners, cnc, pocket, tmp_path, "pocket")
    steps, worst = _compare_all(runs, _force_floors(cnc.md, runs["linux64"]))
    assert steps > 1000, steps
    print(f"seed 003 pocket with its machine file: {steps} steps, largest relative difference {_worst(worst)}")

    def relation(windows: bool) -> list[Command]:
        return [("instantiate", "relation"), ("set", "x.servo.ratedTorque", 3.0), ("init",), ("free",)]
    runs = _run(runners, cnc, relation, tmp_path, "relation")
    _compare_all(runs)
    for platform in PLATFORMS[1:]:
        errors = [line for line in runs[platform] if line.startswith("log 3 ")]
        assert any("x.servo.peakTorque" in e and "x.servo.ratedTorque" in e for e in errors), runs[platform]


def test_machine_structure_on_every_platform_equals_linux64(runners: dict[str, str], structure: Unpacked,
                                                            tmp_path: Path) -> None:
    def commands(windows: bool) -> list[Command]:
        return [("instantiate", "frame"), ("set", "x.driveForce", 1000.0), ("set", "z.driveForce", -250.0),
                ("init",), ("record",), ("steps", 2000, 1e-3), ("terminate",), ("free",)]
    steps, worst = _compare_all(_run(runners, structure, commands, tmp_path, "structure"))
    assert steps == 2000
    print(f"\nMachineStructure step response: {steps} steps, largest relative difference {_worst(worst)}")
