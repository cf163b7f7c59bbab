"""Parameter sweep: axis jerk limit × feed profile × program, each case a co-simulation of
CncMotion.fmu on MachineStructure.fmu, distributed with Dask (as fmpy's parameter-variation example).

    python examples/sweep.py                          # LocalCluster (2 workers) on this machine
    python examples/sweep.py --scheduler tcp://HOST:8786   # a running dask-scheduler (workers need
                                                           # this repo and the FMUs at the same paths)
    python examples/sweep.py --jerk 10000 40000 --profile scurve7 trapezoid --program resources/default.ngc

Per case: cycle time, peak contour error, peak deflection and residual vibration of the frame.
Writes out/sweep.csv and prints the table.
"""
import argparse
import csv
import itertools
import pathlib
import sys

import numpy as np

HERE = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
import fmusim  # noqa: E402

FIELDS = ["program", "profile", "jerk_mm_s3", "cycle_time_s", "max_contour_error_um", "max_deflection_um",
          "residual_vibration_um", "stops"]
_unpacked = {}


def simulate_case(case, cnc_fmu, structure_fmu, two_way=False):
    """One case (program path, profile, jerk limit in mm/s³) → dict of FIELDS. Runs in a Dask worker
    (absolute FMU paths: a worker imports this module from its own scratch folder). One-way coupling
    by default: the frame is driven by the axes; `two_way` also feeds loadForce back (see README)."""
    sys.path.insert(0, str(HERE))
    from cosim import cosim_slaves, residual_vibration

    program, profile, jerk = case
    key = (cnc_fmu, structure_fmu)
    if key not in _unpacked:  # unpack once per worker process
        _unpacked[key] = (fmusim.Unpacked(cnc_fmu), fmusim.Unpacked(structure_fmu))
    cnc, st = _unpacked[key]
    params = {"program": pathlib.Path(program).read_text(), "machine.profile": profile}
    for a in fmusim.AXES:
        params[f"{a}.maxJerk"] = jerk * 1e-3
    res = cosim_slaves(cnc, st, params, record=[
        *(f"cnc.{a}.command.velocity" for a in fmusim.AXES), "cnc.status.finished", "cnc.path.contourError",
        *(f"structure.{a}.deflection" for a in fmusim.AXES)], after=0.2, two_way=two_way)
    rms, stops = residual_vibration(res)
    defl = np.sqrt(sum(res[f"structure.{a}.deflection"] ** 2 for a in fmusim.AXES))
    return {"program": pathlib.Path(program).name, "profile": profile, "jerk_mm_s3": jerk,
            "cycle_time_s": res["t_finished"],
            "max_contour_error_um": float(np.max(np.abs(res["cnc.path.contourError"])) * 1e6),
            "max_deflection_um": float(np.max(defl) * 1e6),
            "residual_vibration_um": rms * 1e6, "stops": stops}


def cases(programs, profiles, jerks):
    return [(str(p), k, float(j)) for p, k, j in itertools.product(programs, profiles, jerks)]


def run_serial(case_list, two_way=False):
    return [simulate_case(c, str(fmusim.CNC_FMU), str(fmusim.STRUCTURE_FMU), two_way) for c in case_list]


def run_dask(case_list, scheduler=None, n_workers=2, two_way=False):
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
            # Remote workers get the example modules shipped; LocalCluster workers inherit sys.path.
            # (Not for a LocalCluster: its scheduler lives in this process and would re-import the
            # uploaded copies here, pointing fmusim's paths at the scratch folder.)
            for name in ("fmusim.py", "make_ssp.py", "cosim.py", "sweep.py"):
                client.upload_file(str(HERE / name))
        futures = client.map(simulate_case, case_list, cnc_fmu=str(fmusim.CNC_FMU),
                             structure_fmu=str(fmusim.STRUCTURE_FMU), two_way=two_way, pure=False)
        return client.gather(futures)
    finally:
        client.close()
        if cluster is not None:
            cluster.close()


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scheduler", help="address of a running Dask scheduler (default: LocalCluster)")
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--jerk", type=float, nargs="+", default=[10000, 40000, 160000], help="mm/s³")
    ap.add_argument("--profile", nargs="+", default=["scurve7", "quintic", "jerk15", "trapezoid"])
    ap.add_argument("--program", nargs="+", default=[str(fmusim.DEFAULT_PROGRAM)])
    ap.add_argument("--two-way", action="store_true", help="feed the frame's loadForce back to the axes")
    ap.add_argument("--out", default=str(fmusim.ROOT / "out"))
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
