"""Parameter sweep: axis jerk limit × feed profile × program, each case a co-simulation of
CncMotion.fmu on MachineStructure.fmu, distributed with Dask (as fmpy's parameter-variation example).

    python -m cnc_motion_sim.sweep (or examples/sweep.py)   # LocalCluster (2 workers) on this machine
    python -m cnc_motion_sim.sweep --scheduler tcp://HOST:8786   # a running dask-scheduler (its workers
                                   # get this package's code uploaded; they need the FMUs at the paths
                                   # they have here, e.g. the package installed at the same place)
    python -m cnc_motion_sim.sweep --jerk 10000 40000 --profile scurve7 trapezoid --program part.ngc

Per case: cycle time, peak contour error, peak deflection and residual vibration of the frame.
Programs default to the FMU's own default program. Writes OUT/sweep.csv and prints the table.
Needs the `sweep` extra (dask, distributed).
"""
from __future__ import annotations

import argparse
import csv
import itertools
import pathlib
import shutil
import tempfile
from collections.abc import Iterable
from typing import Any

import numpy as np

from . import paths
from .cosim import cosim_slaves, residual_vibration
from .fmu import AXES, Unpacked, profiles

Case = tuple[str, str, float]

FIELDS = ["program", "profile", "jerk_mm_s3", "cycle_time_s", "max_contour_error_um", "max_deflection_um",
          "residual_vibration_um", "stops"]
_unpacked: dict[tuple[str, str], tuple[Unpacked, Unpacked]] = {}


def simulate_case(case: Case, cnc_fmu: str, structure_fmu: str, two_way: bool = False) -> dict[str, Any]:
    """One case (program path, "" for the FMU's default program; profile; jerk limit in mm/s³) →
    dict of FIELDS. Runs in a Dask worker (absolute FMU paths: a remote worker imports this package
    from an uploaded zip). One-way coupling by default: the frame is driven by the axes; `two_way`
    also feeds loadForce back (see README)."""
    program, profile, jerk = case
    key = (cnc_fmu, structure_fmu)
    if key not in _unpacked:  # unpack once per worker process
        _unpacked[key] = (Unpacked(cnc_fmu), Unpacked(structure_fmu))
    cnc, st = _unpacked[key]
    params: dict[str, Any] = {"machine.profile": profile}
    if program:
        params["program"] = pathlib.Path(program).read_text()
    for a in AXES:
        params[f"{a}.maxJerk"] = jerk * 1e-3
    res = cosim_slaves(cnc, st, params, record=[
        *(f"cnc.{a}.command.velocity" for a in AXES), "cnc.status.finished", "cnc.path.contourError",
        *(f"structure.{a}.deflection" for a in AXES)], after=0.2, two_way=two_way)
    rms, stops = residual_vibration(res)
    defl = np.sqrt(sum(res[f"structure.{a}.deflection"] ** 2 for a in AXES))
    return {"program": pathlib.Path(program).name if program else "default.ngc", "profile": profile, "jerk_mm_s3": jerk,
            "cycle_time_s": res["t_finished"],
            "max_contour_error_um": float(np.max(np.abs(res["cnc.path.contourError"])) * 1e6),
            "max_deflection_um": float(np.max(defl) * 1e6),
            "residual_vibration_um": rms * 1e6, "stops": stops}


def cases(programs: Iterable[str | pathlib.Path], kinds: Iterable[str], jerks: Iterable[float]) -> list[Case]:
    return [(str(p), k, float(j)) for p, k, j in itertools.product(programs, kinds, jerks)]


def run_serial(case_list: list[Case], two_way: bool = False) -> list[dict[str, Any]]:
    cnc, structure = str(paths.fmu_file(None, paths.CNC_FMU)), str(paths.fmu_file(None, paths.STRUCTURE_FMU))
    return [simulate_case(c, cnc, structure, two_way) for c in case_list]


def _package_zip(folder: pathlib.Path) -> pathlib.Path:
    """This package as a zip for `Client.upload_file` (workers put it on their sys.path)."""
    here = pathlib.Path(__file__).resolve().parent
    return pathlib.Path(shutil.make_archive(str(folder / here.name), "zip", here.parent, here.name))


def run_dask(case_list: list[Case], scheduler: str | None = None, n_workers: int = 2,
             two_way: bool = False) -> list[dict[str, Any]]:
    """Map the cases over a Dask cluster; a LocalCluster of `n_workers` single-threaded processes
    unless `scheduler` names a running one."""
    from dask.distributed import Client, LocalCluster
    cluster = None
    if scheduler:
        client = Client(scheduler)
    else:
        cluster = LocalCluster(n_workers=n_workers, threads_per_worker=1, processes=True,
                               dashboard_address=":0")
        client = Client(cluster)
    try:
        if scheduler:
            # Remote workers get this package shipped; LocalCluster workers import the installed one.
            # (Not for a LocalCluster: its scheduler lives in this process and would re-import the
            # uploaded copy here, pointing the package's paths at the scratch folder.)
            with tempfile.TemporaryDirectory() as tmp:
                client.upload_file(str(_package_zip(pathlib.Path(tmp))))
        cnc, structure = str(paths.fmu_file(None, paths.CNC_FMU)), str(paths.fmu_file(None, paths.STRUCTURE_FMU))
        futures = client.map(simulate_case, case_list, cnc_fmu=cnc, structure_fmu=structure, two_way=two_way,
                             pure=False)
        return client.gather(futures)
    finally:
        client.close()
        if cluster is not None:
            cluster.close()


def main() -> None:
    ap = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    ap.add_argument("--scheduler", help="address of a running Dask scheduler (default: LocalCluster)")
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--jerk", type=float, nargs="+", default=[10000, 40000, 160000], help="mm/s³")
    kinds = profiles() if paths.CNC_FMU.exists() else None  # the items of machine.profile
    ap.add_argument("--profile", nargs="+", choices=kinds, default=["scurve7", "quintic", "jerk15", "trapezoid"])
    ap.add_argument("--program", nargs="+", default=[""], help="G-code files (default: the FMU's own)")
    ap.add_argument("--two-way", action="store_true", help="feed the frame's loadForce back to the axes")
    ap.add_argument("--out", default="out")
    a = ap.parse_args()
    cl = cases(a.program, a.profile, a.jerk)
    rows = run_dask(cl, a.scheduler, a.workers, a.two_way)
    out = pathlib.Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    with open(out / "sweep.csv", "w", newline="") as f:
        w = csv.DictWriter(f, FIELDS)
        w.writeheader()
        w.writerows(rows)
    print(f"{'program':24} {'profile':10} {'jerk mm/s3':>11} {'time s':>8} {'contour um':>11} "
          f"{'defl um':>9} {'resid um':>9}")
    for r in rows:
        print(f"{r['program']:24} {r['profile']:10} {r['jerk_mm_s3']:11.0f} {r['cycle_time_s']:8.3f} "
              f"{r['max_contour_error_um']:11.3f} {r['max_deflection_um']:9.3f} {r['residual_vibration_um']:9.4f}")
    print(f"table: {out / 'sweep.csv'}")


if __name__ == "__main__":
    main()
