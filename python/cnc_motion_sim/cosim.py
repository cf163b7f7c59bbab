"""Co-simulation of CncMotion.fmu with MachineStructure.fmu at 1 ms, four ways that must agree:

  * `cosim_slaves`   — this file's own master over fmpy's FMU2Slave,
  * `cosim_fmpy_ssp` — fmpy.ssp.simulate_ssp on examples/cosim.ssp,
  * `cosim_libcosim` — libcosim (libcosimpy) on the same SSP,
  * `cosim_ecos`     — Ecos (ecospy) on the same SSP.

All four use the same scheme (fixed step, Jacobi: every FMU steps with the values the others had at
the start of the step, then the connections are applied; the own master also runs Gauss-Seidel,
`scheme="gauss-seidel"`: CncMotion steps first and the frame steps with its new drive force, which
holds the two-way loop to 122.7 kg of couplingMass at 1 ms where Jacobi diverges above 38.3 kg —
README, co-simulation), the two-way force coupling
    cnc.{x,y,z}.driveForce → structure.{x,y,z}.driveForce,
    structure.{x,y,z}.loadForce → cnc.{x,y,z}.loadForce,
and connector values that start at 0 (the frame is at rest, the drives hold still).

    python -m cnc_motion_sim.cosim (or examples/cosim.py) [--master slaves|fmpy-ssp|libcosim|ecos] [--stop-time S]
                             [--scheme jacobi|gauss-seidel] [--program FILE.ngc] [--profile scurve7]
                             [--ssp FILE.ssp] [--out out/]

The FMUs are those shipped in this package; the SSP masters run an SSP of them made on the fly (or
--ssp). libcosim and Ecos come with the `cosim` extra, the plot with the `plot` extra.

Results: dict name → numpy array, names as "cnc.x.command.position", "structure.x.deflection",
and "time" = the communication point at the END of each step.
"""
from __future__ import annotations

import argparse
import pathlib
import sys
from collections.abc import Callable, Mapping, Sequence
from typing import Any

import numpy as np

from .fmu import AXES, Slave, Unpacked
from .paths import CNC_FMU, STRUCTURE_FMU, PathLike
from .ssp import CNC_RECORDED, STRUCTURE_RECORDED, Connection, connections, default_ssp

Result = dict[str, Any]

H = 1e-3
SCHEMES = ("jacobi", "gauss-seidel")


def coupling() -> list[Connection]:
    return connections()


def cosim_slaves(cnc_u: Unpacked, structure_u: Unpacked, cnc_params: Mapping[str, Any] | None = None,
                 structure_params: Mapping[str, Any] | None = None, h: float = H, stop_time: float | None = None,
                 after: float = 0.3, t_max: float = 120.0, record: Sequence[str] | None = None,
                 inputs: Callable[[float, Slave], None] | None = None, grid: str = "exact",
                 two_way: bool = True, scheme: str = "jacobi") -> Result:
    """Own master. Runs until stop_time, or (stop_time None) until status.finished + `after` s.

    `inputs(t, cnc_slave)` may drive CncMotion's free inputs (feedHold, feedOverride) each step.
    `grid`: "exact" communication points k·h, or "ns" as libcosim computes them (see fmu.Slave).
    `two_way=False` leaves loadForce out (the frame does not push back on the axes).
    `scheme`: "jacobi" (every FMU steps with the values of the step's start, as the SSP masters) or
    "gauss-seidel" (CncMotion steps first; the frame steps with the drive force CncMotion just
    reached, its loadForce goes back at the next step: no net delay in the loop)."""
    if scheme not in SCHEMES:
        raise ValueError(f"scheme {scheme!r}: one of {', '.join(SCHEMES)}")
    cnc = Slave(cnc_u, "cnc")
    st = Slave(structure_u, "structure")
    cnc.grid = st.grid = grid
    slaves = {"cnc": cnc, "structure": st}
    try:
        cnc.initialize(cnc_params)
        st.initialize(structure_params)
        conns = coupling()
        value = {(fc, fv): 0.0 for fc, fv, _, _ in conns}
        record = record or (["cnc." + n for n in CNC_RECORDED] + ["structure." + n for n in STRUCTURE_RECORDED]
                            + [f"cnc.{fv}" for fc, fv, _, _ in conns if fc == "cnc"]
                            + [f"structure.{fv}" for fc, fv, _, _ in conns if fc == "structure"])
        record = list(dict.fromkeys(record))
        readers = {}
        for comp in slaves:
            names = [r.split(".", 1)[1] for r in record if r.startswith(comp + ".")]
            readers[comp] = (names, slaves[comp].reader(names))
        i_fin = record.index("cnc.status.finished")
        rows = []
        t_end = None
        while True:
            t = cnc.time
            if stop_time is not None and t >= stop_time - 1e-9:
                break
            if stop_time is None and (t >= t_max or (t_end is not None and t >= t_end + after - 1e-9)):
                break
            # Jacobi: inputs from the previous communication point, then every FMU steps.
            # Gauss-Seidel: CncMotion steps, then the frame with CncMotion's new outputs.
            order = [["cnc", "structure"]] if scheme == "jacobi" else [["cnc"], ["structure"]]
            if inputs is not None:
                inputs(t, cnc)
            for group in order:
                try:
                    for fc, fv, tc, tv in conns:
                        if tc in group and (two_way or tc != "cnc"):
                            slaves[tc].set(tv, value[(fc, fv)])
                except Exception as e:  # an FMU refusing a non-finite coupling value
                    slaves[tc].failed = True  # in fmi2's Error state now: freed without fmi2Terminate
                    raise RuntimeError(f"co-simulation diverged at t = {t:.3f} s "
                                       f"({ {k: v for k, v in value.items()} }): {e}") from e
                for comp in group:
                    slaves[comp].step(h)
                for fc, fv, _, _ in conns:
                    if fc in group:
                        value[(fc, fv)] = slaves[fc].get(fv)
            row = []
            for comp in slaves:
                row += readers[comp][1]()
            # reorder to `record`
            rows.append([cnc.time] + row)
            if t_end is None and row[_flat_index(readers, record, i_fin)]:
                t_end = cnc.time
        if stop_time is None and t_end is None:
            raise RuntimeError(f"program not finished after {t_max} s")
    finally:
        for s in slaves.values():
            s.free()
    a = np.array(rows)
    res: dict[str, Any] = {"time": a[:, 0]}
    col = 1
    for comp in slaves:
        for n in readers[comp][0]:
            res[f"{comp}.{n}"] = a[:, col]
            col += 1
    res["t_finished"] = t_end
    return res


def _flat_index(readers: Mapping[str, tuple[list[str], Any]], record: Sequence[str], i: int) -> int:
    """Column of record[i] in the concatenated per-component reader rows."""
    comp, name = record[i].split(".", 1)
    col = 0
    for c, (names, _) in readers.items():
        if c == comp:
            return col + names.index(name)
        col += len(names)
    raise KeyError(record[i])


def cosim_fmpy_ssp(ssp: PathLike | None = None, stop_time: float = 2.0, h: float = H,
                   parameters: Mapping[str, Any] | None = None) -> Result:
    """fmpy.ssp.simulate_ssp. Its rows are stamped with the START of each step; we restamp with the end.
    fmpy.ssp ignores the SSD's parameter bindings: give them again as `parameters`
    {"structure.x.couplingMass": 1.0, ...}."""
    from types import SimpleNamespace

    from fmpy.ssp.simulation import simulate_ssp
    ssp = ssp if ssp is not None else default_ssp()
    pset = None
    if parameters:
        pset = SimpleNamespace(parameters=[SimpleNamespace(name=k, value=v) for k, v in parameters.items()])
    r = simulate_ssp(str(ssp), stop_time=stop_time, step_size=h, parameter_set=pset)
    res = {"time": (np.arange(len(r)) + 1) * h}
    for name in r.dtype.names[1:]:
        res[name] = np.asarray(r[name], dtype=float)
    return res


def cosim_libcosim(ssp: PathLike | None = None, stop_time: float = 2.0, h: float = H) -> Result:
    """libcosim 0.x through libcosimpy: SSP loaded by libcosim, fixed-step (Jacobi) algorithm, time in ns."""
    from libcosimpy.CosimEnums import CosimVariableType
    from libcosimpy.CosimExecution import CosimExecution
    from libcosimpy.CosimLogging import CosimLogLevel, log_output_level
    from libcosimpy.CosimObserver import CosimObserver

    log_output_level(CosimLogLevel.WARNING)

    h_ns = int(round(h * 1e9))
    ex = CosimExecution.from_ssp_file(str(ssp if ssp is not None else default_ssp()), step_size=h_ns)
    obs = CosimObserver.create_last_value()
    ex.add_observer(obs)
    wanted = {"cnc": CNC_RECORDED, "structure": STRUCTURE_RECORDED + [f"{a}.loadForce" for a in AXES]}
    wanted["cnc"] = wanted["cnc"] + [f"{a}.driveForce" for a in AXES]
    plan = []  # (key, slave index, reader kind, reference)
    for comp, names in wanted.items():
        idx = ex.slave_index_from_instance_name(comp)
        desc = {v.name.decode(): v for v in ex.slave_variables(idx)}
        for n in names:
            v = desc[n]
            plan.append((f"{comp}.{n}", idx, CosimVariableType(v.type), v.reference))
    n_steps = int(round(stop_time / h))
    rows = []
    for _ in range(n_steps):
        if not ex.step():
            raise RuntimeError("libcosim step failed")
        row = []
        for key, idx, ty, ref in plan:
            if ty == CosimVariableType.REAL:
                row.append(obs.last_real_values(idx, [ref])[0])
            elif ty == CosimVariableType.BOOLEAN:
                row.append(float(obs.last_boolean_values(idx, [ref])[0]))
            else:
                row.append(float(obs.last_integer_values(idx, [ref])[0]))
        rows.append(row)
    a = np.array(rows)
    res = {"time": (np.arange(n_steps) + 1) * h}
    for i, (key, *_rest) in enumerate(plan):
        res[key] = a[:, i]
    return res


def cosim_ecos(ssp: PathLike | None = None, stop_time: float = 2.0, h: float = H,
               parameters: Mapping[str, Any] | None = None) -> Result:
    """Ecos through ecospy: SSP loaded by Ecos, fixed step, time summed in floating point (t += h, so
    the communication points drift by ulps, e.g. 1.4999999999999456 after 1500 steps; h itself is
    exactly `h`). Ecos applies the connections right after each step and before its post-step
    listener runs, so an output with direct feed-through (MachineStructure's x.acceleration) is
    sampled with the NEW input already set; every other output is sampled as the own master does.
    Ecos ignores the SSD's inline parameter bindings (it reads parameter sets from .ssv files): give
    them as `parameters` {"structure.x.couplingMass": 1.0, "cnc.program": "G1 X1 F600", ...} (set by the
    Python type of the value: float Real, int Integer, bool Boolean, str String) before initialization."""
    from ecospy import EcosSimulation, SimulationListener

    wanted = {"cnc": CNC_RECORDED + [f"{a}.driveForce" for a in AXES],
              "structure": STRUCTURE_RECORDED + [f"{a}.loadForce" for a in AXES]}
    sim = EcosSimulation(ssp_path=str(ssp if ssp is not None else default_ssp()), step_size=h)
    getters: list[tuple[str, Callable[[], float]]] = []

    def reader(read: Callable[[str], Any], ident: str) -> Callable[[], float]:
        return lambda: float(read(ident))

    for comp, names in wanted.items():
        for n in names:
            read = sim.get_bool if n == "status.finished" else sim.get_integer if n == "status.line" else sim.get_real
            getters.append((f"{comp}.{n}", reader(read, f"{comp}::{n}")))
    rows: list[list[float]] = []
    times: list[float] = []

    class Recorder(SimulationListener):
        def post(self, info: Any) -> None:
            times.append(info.time)
            rows.append([read() for _, read in getters])

    sim.add_listener("recorder", Recorder())
    try:
        for name, value in (parameters or {}).items():
            comp, var = name.split(".", 1)
            setter = {bool: sim.set_bool, int: sim.set_integer, str: sim.set_string}.get(type(value), sim.set_real)
            setter(f"{comp}::{var}", value)
        sim.init()
        sim.step(int(round(stop_time / h)))
        sim.terminate()
    finally:
        sim.free()
    a = np.array(rows)
    res: Result = {"time": np.array(times)}
    for i, (key, _) in enumerate(getters):
        res[key] = a[:, i]
    return res


def residual_vibration(res: Mapping[str, Any], window: float = 0.2, min_standstill: float = 0.02,
                       prefix: str = "cnc.") -> tuple[float, int]:
    """RMS of the frame deflection |d| in the windows after each stop of the command.

    A stop is where the commanded axis speeds fall to zero and stay there at least `min_standstill`;
    its window runs `window` s or until the command moves again. Returns (rms, number of stops)."""
    t = res["time"]
    speed = np.sqrt(sum(res[f"{prefix}{a}.command.velocity"] ** 2 for a in AXES))
    defl = np.sqrt(sum(res[f"structure.{a}.deflection"] ** 2 for a in AXES))
    still = speed <= 1e-12
    samples = []
    stops = 0
    i = 1
    n = len(t)
    while i < n:
        if still[i] and not still[i - 1]:
            j = i
            while j < n and still[j]:
                j += 1
            if t[j - 1] - t[i] >= min_standstill - 1e-12:
                end = np.searchsorted(t, t[i] + window, side="right")
                samples.append(defl[i:min(end, j)])
                stops += 1
            i = j
        else:
            i += 1
    if not samples:
        return float("nan"), 0
    s = np.concatenate(samples)
    return float(np.sqrt(np.mean(s ** 2))), stops


def main() -> None:
    ap = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    ap.add_argument("--master", choices=["slaves", "fmpy-ssp", "libcosim", "ecos"], default="slaves")
    ap.add_argument("--stop-time", type=float)
    ap.add_argument("--program", help="G-code file (own master only; the SSP runs the FMU's default)")
    ap.add_argument("--profile", default=None, help="machine.profile (own master only)")
    ap.add_argument("--one-way", action="store_true", help="no loadForce back to the axes (own master only)")
    ap.add_argument("--scheme", choices=SCHEMES, default="jacobi",
                    help="coupling scheme of the own master (gauss-seidel holds the two-way loop with heavier tables)")
    ap.add_argument("--ssp", help="the SSP for fmpy-ssp, libcosim and ecos (default: made from the shipped FMUs)")
    ap.add_argument("--out", default="out")
    a = ap.parse_args()
    if a.master == "slaves":
        cnc, st = Unpacked(CNC_FMU), Unpacked(STRUCTURE_FMU)
        params = {}
        if a.program:
            params["program"] = pathlib.Path(a.program).read_text()
        if a.profile:
            params["machine.profile"] = a.profile
        try:
            res = cosim_slaves(cnc, st, params, stop_time=a.stop_time, two_way=not a.one_way, scheme=a.scheme)
        except RuntimeError as e:
            sys.exit(f"{e}\n(two-way coupling unstable at this step: --scheme gauss-seidel, a shorter step, "
                     "or --one-way, which drives the frame only)")
        finally:
            cnc.cleanup()
            st.cleanup()
    elif a.master == "fmpy-ssp":
        res = cosim_fmpy_ssp(a.ssp, stop_time=a.stop_time or 6.5)
    elif a.master == "ecos":
        res = cosim_ecos(a.ssp, stop_time=a.stop_time or 6.5)
    else:
        res = cosim_libcosim(a.ssp, stop_time=a.stop_time or 6.5)
    t = res["time"]
    coupling = "one-way" if a.master == "slaves" and a.one_way else "two-way"
    print(f"master {a.master} ({coupling}): {len(t)} steps of {H * 1e3:g} ms to t = {t[-1]:.3f} s")
    for a_ in AXES:
        d = res[f"structure.{a_}.deflection"]
        f = res[f"cnc.{a_}.driveForce"]
        print(f"  {a_}: max |drive force| {np.max(np.abs(f)):10.3f} N   max |deflection| "
              f"{np.max(np.abs(d)) * 1e6:9.3f} µm")
    peak = max(float(np.max(np.abs(res[f"cnc.{a_}.driveForce"]))) for a_ in AXES)
    if not np.isfinite(peak) or peak > 1e6:
        print(f"  WARNING: drive forces reach {peak:.3g} N: the two-way loop diverges at this step "
              "(see README, co-simulation)")
    rms, stops = residual_vibration(res)
    print(f"  residual vibration after {stops} stops: RMS {rms * 1e6:.4f} µm")
    out = pathlib.Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(2, 1, sharex=True, figsize=(10, 6.5), layout="constrained")
    for a_ in AXES:
        ax[0].plot(t, res[f"cnc.{a_}.driveForce"], lw=1, label=f"{a_.upper()} axis")
        ax[1].plot(t, res[f"structure.{a_}.deflection"] * 1e6, lw=1, label=f"{a_.upper()} axis")
    ax[0].set_ylabel("drive force (N)")
    ax[1].set_ylabel("frame deflection (µm)")
    ax[1].set_xlabel("time (s)")
    for axis in ax:
        axis.grid(True, lw=0.3, alpha=0.6)
        axis.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8, frameon=False)
    program = pathlib.Path(a.program).name if a.program else "the FMU's default program"
    master = {"slaves": "own master (fmpy FMU2Slave)", "fmpy-ssp": "fmpy.ssp", "libcosim": "libcosim",
              "ecos": "Ecos"}[a.master]
    fig.suptitle(f"CncMotion.fmu ({program}) on MachineStructure.fmu: {master}, {coupling} coupling, "
                 f"h = {H * 1e3:g} ms", fontsize=11)
    fig.savefig(out / f"cosim_{a.master}.png", dpi=110)
    print(f"plot: {out / f'cosim_{a.master}.png'}")


if __name__ == "__main__":
    main()
