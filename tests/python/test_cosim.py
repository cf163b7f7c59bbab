"""Co-simulation CncMotion ⇄ MachineStructure: the three masters agree, and jerk-limited profiles
leave less residual vibration in the frame than the trapezoid."""
import json

import numpy as np
import pytest

import cosim
import fmusim
from conftest import ROOT

T = 1.5  # s of the default program: plunge, first edges and corners


@pytest.fixture(scope="module")
def own(cnc, structure):
    return cosim.cosim_slaves(cnc, structure, stop_time=T)


def _compare(ref, other, label):
    n = min(len(ref["time"]), len(other["time"]))
    assert n >= int(T / cosim.H) - 1, f"{label}: only {n} steps"
    np.testing.assert_allclose(other["time"][:n], ref["time"][:n], rtol=0, atol=1e-9)
    compared = 0
    worst = 0.0
    for k, v in other.items():
        if k == "time" or k not in ref or k.endswith("loadForce") and k.startswith("cnc."):
            continue
        a, b = ref[k][:n], np.asarray(v[:n], dtype=float)
        scale = max(np.max(np.abs(a)), 1e-300)
        worst = max(worst, float(np.max(np.abs(a - b)) / scale))
        np.testing.assert_allclose(b, a, rtol=1e-9, atol=1e-12 * scale, err_msg=f"{label}: {k}")
        compared += 1
    print(f"{label}: {compared} signals over {n} steps, worst relative difference {worst:.3g}")
    assert compared >= 10
    return worst


def test_coupling_is_live(own, cnc, structure):
    """Drive forces reach the frame; with the tables' mass on it (two-way coupling, opt-in) the frame
    pushes back on the axes and the loop stays bounded."""
    f = np.max(np.abs(own["cnc.x.driveForce"]))
    d = np.max(np.abs(own["structure.x.deflection"]))
    assert f > 0 and d > 0, (f, d)
    assert np.max(np.abs(own["structure.x.loadForce"])) == 0.0  # coupling mass 0 by default
    two_way = cosim.cosim_slaves(cnc, structure, structure_params={"x.couplingMass": 50.0, "y.couplingMass": 50.0},
                                 stop_time=T)
    load = np.max(np.abs(two_way["structure.x.loadForce"]))
    assert 0 < load < 1e3, load
    assert np.max(np.abs(two_way["cnc.x.driveForce"])) < 10 * f


def test_fmpy_ssp_equals_own_master(own, ssp):
    _compare(own, cosim.cosim_fmpy_ssp(ssp, stop_time=T), "fmpy.ssp")


def test_libcosim_equals_own_master(own, ssp):
    _compare(own, cosim.cosim_libcosim(ssp, stop_time=T), "libcosim")


def test_residual_vibration_lower_than_trapezoid(cnc, structure):
    rms = {}
    stops = {}
    for kind in ["trapezoid", "scurve7", "quintic", "jerk15", "mixed57"]:
        res = cosim.cosim_slaves(cnc, structure, {"machine.profile": kind}, after=0.3)
        rms[kind], stops[kind] = cosim.residual_vibration(res, window=0.2)
    ratios = {k: rms[k] / rms["trapezoid"] for k in rms}
    print("residual vibration RMS (µm) and ratio to trapezoid:")
    for k in rms:
        print(f"  {k:10} {rms[k] * 1e6:10.5f} µm  ratio {ratios[k]:.4f}  ({stops[k]} stops)")
    out = ROOT / "out"
    out.mkdir(exist_ok=True)
    (out / "residual_vibration.json").write_text(json.dumps(
        {"rms_m": rms, "ratio_to_trapezoid": ratios, "stops": stops}, indent=1))
    assert all(s >= 1 for s in stops.values()), stops
    assert len(set(stops.values())) == 1, f"profiles stop a different number of times: {stops}"
    for k in ["scurve7", "quintic", "jerk15"]:
        assert ratios[k] < 1.0, ratios
