"""Co-simulation CncMotion ⇄ MachineStructure: the four masters agree, and jerk-limited profiles
leave less residual vibration in the frame than the trapezoid."""
import pathlib
from typing import Any
import json

import numpy as np
import pytest

from cnc_motion_sim import cosim
import cnc_motion_sim as sim
from repo import CNC_FMU, ROOT, STRUCTURE_FMU

T = 1.5  # s of the default program: plunge, first edges and corners


@pytest.fixture(scope="module")
def own(cnc: sim.Unpacked, structure: sim.Unpacked) -> dict[str, Any]:
    return cosim.cosim_slaves(cnc, structure, stop_time=T)


@pytest.fixture(scope="module")
def own_ns(cnc: sim.Unpacked, structure: sim.Unpacked) -> dict[str, Any]:
    return cosim.cosim_slaves(cnc, structure, stop_time=T, grid="ns")


def _compare(ref: dict[str, Any], other: dict[str, Any], label: str) -> float:
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
        assert np.array_equal(a, b), f"{label}: {k} differs by up to {np.max(np.abs(a - b)):.3g}"
        compared += 1
    print(f"{label}: {compared} signals over {n} steps, worst relative difference {worst:.3g}")
    assert compared >= 10
    return worst


def test_coupling_is_live(own: dict[str, Any], cnc: sim.Unpacked, structure: sim.Unpacked) -> None:
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


STABLE = {f"{a}.couplingMass": 1.0 for a in "xyz"}  # a two-way loop that is stable at 1 ms


@pytest.fixture(scope="module")
def stable_ssp(fmus: tuple[pathlib.Path, pathlib.Path], tmp_path_factory: pytest.TempPathFactory) -> pathlib.Path:
    from cnc_motion_sim.ssp import make_ssp
    return make_ssp(tmp_path_factory.mktemp("ssp") / "stable.ssp", *fmus, structure_params=STABLE)


@pytest.mark.parametrize("grid", ["exact", "ns"])
def test_masters_agree_on_a_stable_two_way_loop(cnc: sim.Unpacked, structure: sim.Unpacked,
                                                stable_ssp: pathlib.Path, grid: str) -> None:
    """Parameters bound in the SSP (libcosim) = parameter_set (fmpy.ssp) = set by the own master."""
    own_ = cosim.cosim_slaves(cnc, structure, structure_params=STABLE, stop_time=T, grid=grid)
    assert max(np.max(np.abs(own_[f"structure.{a}.loadForce"])) for a in "xyz") > 0
    assert max(np.max(np.abs(own_[f"cnc.{a}.driveForce"])) for a in "xyz") < 1e3
    if grid == "exact":
        _compare(own_, cosim.cosim_fmpy_ssp(stable_ssp, stop_time=T,
                                            parameters={f"structure.{k}": v for k, v in STABLE.items()}),
                 "fmpy.ssp (stable)")
        ecos = cosim.cosim_ecos(stable_ssp, stop_time=T, parameters={f"structure.{k}": v for k, v in STABLE.items()})
        _compare(own_, _without_feedthrough(ecos), "Ecos (stable)")
    else:
        _compare(own_, cosim.cosim_libcosim(stable_ssp, stop_time=T), "libcosim (stable)")


def test_libcosim_sets_the_profile_through_the_integer_index(cnc: sim.Unpacked, structure: sim.Unpacked,
                                                             tmp_path: pathlib.Path) -> None:
    """libcosim ignores Enumerations: the Integer machine.profileIndex bound in the SSP selects the
    trapezoid there, equal to the own master setting the Enumeration, and unlike the default."""
    from cnc_motion_sim.ssp import make_ssp
    ssp_ = make_ssp(tmp_path / "trapezoid.ssp", CNC_FMU, STRUCTURE_FMU, cnc_params={"machine.profileIndex": 5})
    own_ = cosim.cosim_slaves(cnc, structure, cnc_params={"machine.profile": "trapezoid"}, stop_time=T, grid="ns")
    lib = cosim.cosim_libcosim(ssp_, stop_time=T)
    _compare(own_, lib, "libcosim (profileIndex 5)")
    default = cosim.cosim_slaves(cnc, structure, stop_time=T, grid="ns")
    assert not np.array_equal(default["cnc.path.feed"], lib["cnc.path.feed"][:len(default["time"])])


def test_fmpy_ssp_equals_own_master(own: dict[str, Any], ssp: pathlib.Path) -> None:
    _compare(own, cosim.cosim_fmpy_ssp(ssp, stop_time=T), "fmpy.ssp")


def test_libcosim_equals_own_master(own_ns: dict[str, Any], ssp: pathlib.Path) -> None:
    """libcosim counts time in integer ns and passes h = t(k+1) − t(k) in seconds, which differs from
    1e-3 by ±1 ulp at most steps; on that same time grid the own master gives identical signals."""
    _compare(own_ns, cosim.cosim_libcosim(ssp, stop_time=T), "libcosim")


def _feedthrough_outputs() -> list[str]:
    """Outputs that declare a direct dependency on an input (ModelStructure; MachineStructure's
    dependencies also list the continuous states they read), as "comp.name"."""
    from fmpy import read_model_description
    out = []
    for comp, fmu in (("cnc", CNC_FMU), ("structure", STRUCTURE_FMU)):
        md = read_model_description(str(fmu))
        out += [f"{comp}.{o.variable.name}" for o in md.outputs
                if any(d.causality == "input" for d in o.dependencies or [])]
    return out


def _without_feedthrough(res: dict[str, Any]) -> dict[str, Any]:
    return {k: v for k, v in res.items() if k not in _feedthrough_outputs()}


def test_ecos_equals_own_master(own: dict[str, Any], ssp: pathlib.Path, structure: sim.Unpacked) -> None:
    """A third importer, Ecos (ecospy): it sums its time in floating point (the communication points
    drift by ulps, which the FMUs accept) and steps by exactly 1 ms, so on the exact grid every output
    without direct feed-through equals the own master's bit for bit. Ecos samples after applying the
    connections, so x.acceleration = Σ(F/m − 2ζωq̇ − ω²q) already holds the new drive force: it
    equals the own master's value plus (F_k − F_{k−1})·Σ 1/m_i."""
    ecos = cosim.cosim_ecos(ssp, stop_time=T)
    drift = np.max(np.abs(ecos["time"] - (np.arange(len(ecos["time"])) + 1) * cosim.H))
    assert 0 < drift < 1e-12, f"Ecos' time grid drifts by {drift:.3g} s"
    feedthrough = _feedthrough_outputs()
    assert feedthrough == [f"structure.{a}.acceleration" for a in "xyz"], feedthrough
    _compare(own, _without_feedthrough(ecos), "Ecos")
    from fmpy import read_model_description
    start = {v.name: float(v.start) for v in read_model_description(str(STRUCTURE_FMU)).modelVariables
             if v.start is not None and v.type == "Real"}
    n = len(own["time"])
    moving = 0
    for a in "xyz":
        force = own[f"cnc.{a}.driveForce"]
        step = np.diff(force, prepend=0.0) * (1 / start[f"{a}.mode1.mass"] + 1 / start[f"{a}.mode2.mass"])
        want = own[f"structure.{a}.acceleration"] + step
        got = ecos[f"structure.{a}.acceleration"][:n]
        scale = np.max(np.abs(want))
        assert np.max(np.abs(got - want)) <= 1e-14 * scale, (a, np.max(np.abs(got - want)), scale)
        moving += scale > 0
    assert moving >= 2, "the frame accelerates along at least two axes in the first 1.5 s"


def test_ecos_runs_a_corpus_program_as_the_own_master(cnc: sim.Unpacked, structure: sim.Unpacked,
                                                      ssp: pathlib.Path, corpus: pathlib.Path) -> None:
    """Ecos on a real CAM program (Pessoles' linear path, its first 3 s: the rapid and five cutting
    moves) with the trapezoid law chosen
    through the Integer twin machine.profileIndex, two-way with 1 kg on the frame: every output
    without direct feed-through bit for bit as the own master setting the Enumeration."""
    program = (corpus / "pessoles_linear.ngc").read_text()
    stop = 3.0
    own_ = cosim.cosim_slaves(cnc, structure, cnc_params={"program": program, "machine.profile": "trapezoid"},
                              structure_params=STABLE, stop_time=stop)
    params = {"cnc.program": program, "cnc.machine.profileIndex": 5}
    params.update({f"structure.{k}": v for k, v in STABLE.items()})
    ecos = cosim.cosim_ecos(ssp, stop_time=stop, parameters=params)
    assert np.max(np.abs(own_["cnc.path.feed"])) > 0.01, "the program moves"
    assert np.max(own_["cnc.status.line"]) >= 8, "past the rapid, into the cutting moves"
    _compare(own_, _without_feedthrough(ecos), "Ecos (pessoles_linear, trapezoid)")


def test_outputs_insensitive_to_ulp_step_jitter(own: dict[str, Any], own_ns: dict[str, Any]) -> None:
    """A step of 1 ms ± 1 ulp (libcosim's grid) must not change the physics: positions to 1 nm,
    following errors to 0.1 µm, forces to 1e-6 of their peak."""
    worst = {}
    for k in own:
        if k in ("time", "t_finished") or k not in own_ns:
            continue
        a, b = own[k], own_ns[k]
        d = float(np.max(np.abs(a - b)))
        if k.endswith(("position", "deflection")):
            tol = 1e-9
        elif k.endswith("followingError"):
            tol = 1e-7
        else:
            tol = 1e-6 * max(float(np.max(np.abs(a))), 1e-12)
        if d > tol:
            worst[k] = d
    assert worst == {}, f"ulp-level step jitter moves: {worst}"


TABLES = {f"{a}.couplingMass": 50.0 for a in "xyz"}  # the default axes' table mass on the frame


def test_two_way_coupling_stable_at_1ms(cnc: sim.Unpacked, structure: sim.Unpacked) -> None:
    """With the tables' mass on the frame on all three axes the two-way loop (loadForce back to the
    axes) at 1 ms: Gauss-Seidel stays bounded (drive forces within twice the one-way ones), Jacobi
    diverges. The linearised coupled step map (examples/coupling_aids.py) puts the limits at 28 kg
    (Jacobi, spectral radius 1; 38.3 kg simulated) and 127 kg (Gauss-Seidel, the model's own limit
    1/Σ(1/m_k) = 127.3 kg on z), so 50 kg lies between them."""
    one = cosim.cosim_slaves(cnc, structure, structure_params=TABLES, stop_time=2.0, two_way=False)
    peak_one = max(np.max(np.abs(one[f"cnc.{a}.driveForce"])) for a in "xyz")
    try:
        two = cosim.cosim_slaves(cnc, structure, structure_params=TABLES, stop_time=2.0, scheme="gauss-seidel")
    except RuntimeError as e:  # an FMU refusing a non-finite coupling value
        pytest.fail(str(e)[:300])
    peak_two = max(np.max(np.abs(two[f"cnc.{a}.driveForce"])) for a in "xyz")
    print(f"peak drive force: one-way {peak_one:.4g} N, two-way Gauss-Seidel {peak_two:.4g} N")
    assert np.isfinite(peak_two) and peak_two <= 2 * peak_one, (peak_one, peak_two)
    try:
        jacobi = cosim.cosim_slaves(cnc, structure, structure_params=TABLES, stop_time=2.0)
        peak_jacobi = max(np.max(np.abs(jacobi[f"cnc.{a}.driveForce"])) for a in "xyz")
    except RuntimeError:  # diverged to non-finite values, which the FMU refuses
        peak_jacobi = np.inf
    print(f"two-way Jacobi: peak {peak_jacobi:.4g} N")
    assert not peak_jacobi <= 2 * peak_one, (peak_one, peak_jacobi)


STOPS = "G21 G90 G17 G61\nG1 X30 F4000\nG4 P0.25\nG1 Y20\nG4 P0.25\nG1 X0 Y0\nG4 P0.25\nG1 Z-5 F2000\nM30\n"
RESIDUAL: dict[str, dict[str, Any]] = {}


@pytest.mark.parametrize("program", ["default", "stops"])
def test_residual_vibration_lower_than_trapezoid(cnc: sim.Unpacked, structure: sim.Unpacked, profiles: list[str],
                                                program: str) -> None:
    """Residual vibration of the frame after each standstill of the command (RMS of |deflection| in
    0.2 s windows), driven by the axes one-way: the measure of the command profile, independent of
    the stability of the loadForce loop tested above. `stops`: exact stops and dwells."""
    rms = {}
    stops = {}
    for kind in profiles:
        params = {"machine.profile": kind}
        if program == "stops":
            params["program"] = STOPS
        res = cosim.cosim_slaves(cnc, structure, params, after=0.3, two_way=False)
        rms[kind], stops[kind] = cosim.residual_vibration(res, window=0.2)
    ratios = {k: rms[k] / rms["trapezoid"] for k in rms}
    print(f"\nresidual vibration, program {program}: RMS and ratio to trapezoid")
    for k in rms:
        print(f"  {k:10} {rms[k] * 1e6:10.5f} µm  ratio {ratios[k]:.4f}  ({stops[k]} stops)")
    RESIDUAL[program] = {"rms_m": rms, "ratio_to_trapezoid": ratios, "stops": stops}
    out = ROOT / "out"
    out.mkdir(exist_ok=True)
    (out / "residual_vibration.json").write_text(json.dumps(RESIDUAL, indent=1))
    assert all(s >= 1 for s in stops.values()), stops
    assert len(set(stops.values())) == 1, f"profiles stop a different number of times: {stops}"
    for k in ["scurve7", "quintic", "jerk15"]:
        assert ratios[k] < 1.0, ratios
