"""The two-way coupling schemes of examples/coupling_aids.py (issue 23): with the tables' 50 kg on
the frame at h = 1 ms, Jacobi diverges and the trapezoidal scheme (both FMUs' step sensitivities,
the frame's drive force ramped through its input derivatives) stays bounded in about two FMU steps
per step, with its interface conditions met after every step; the linearised loop puts each
scheme's limit where the simulation finds it, the trapezoidal one at the coupled model's own limit
1/Σ(1/m_k). MachineStructure's input interpolation through fmpy (fmi2SetRealInputDerivatives)
follows the closed-form ramp response."""
from __future__ import annotations

import importlib.util
import pathlib
import sys
from types import ModuleType

import numpy as np
import pytest
from cnc_motion_sim.fmu import Slave, Unpacked
from repo import EXAMPLES


@pytest.fixture(scope="module")
def aids() -> ModuleType:
    spec = importlib.util.spec_from_file_location("coupling_aids", EXAMPLES / "coupling_aids.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules["coupling_aids"] = module
    spec.loader.exec_module(module)
    return module


def test_trapezoidal_coupling_holds_the_tables_mass_where_jacobi_diverges(
        aids: ModuleType, cnc: Unpacked, structure: Unpacked) -> None:
    assert not aids.run(cnc, structure, 50.0, "jacobi")[0]
    stable, peak, per_step = aids.run(cnc, structure, 50.0, "trapezoidal")
    print(f"trapezoidal at 50 kg: peak {peak:.1f} N, {per_step:.2f} FMU steps per step")
    assert stable and peak < 400.0 and per_step < 2.5


def test_the_interface_conditions_hold_after_every_step(aids: ModuleType, cnc: Unpacked,
                                                        structure: Unpacked) -> None:
    """CncMotion's load is the step's average (L(t) + L(t+h))/2, and the frame's drive force,
    ramped over the step, ends at CncMotion's new drive force."""
    loop = aids.Loop(cnc, structure, 50.0, aids.SCHEMES["trapezoidal"], 1e-3)
    try:
        for _ in range(400):
            before = loop.L.copy()
            loop.step()
            held = np.array([loop.cnc.get(f"{a}.loadForce") for a in "xyz"])
            assert np.abs(held - (before + loop.L) / 2).max() <= 1e-6
            ramped = np.array([loop.st.get(f"{a}.driveForce") for a in "xyz"])
            assert np.abs(ramped - loop.F).max() <= 1e-9 * max(1.0, float(np.abs(loop.F).max()))
        assert np.abs(loop.L).max() > 1.0, "the frame pushes back"
    finally:
        loop.free()


def test_the_linearised_loop_limits(aids: ModuleType, cnc: Unpacked, structure: Unpacked) -> None:
    """The spectral radius of the coupled step map crosses 1 where the simulation finds the limits:
    Jacobi between 25 and 32 kg (simulated 38 kg: z feeds only part of the run), the end-of-step
    implicit scheme below 10 kg, Gauss-Seidel and the trapezoidal scheme within 2 % of the model's
    own limit 1/Σ(1/m_k)."""
    limit = aids.model_limit(structure)["z"]
    assert limit == pytest.approx(1 / (1 / 350 + 1 / 200))
    st = aids.Slave(structure, "frame")
    st.initialize({"z.couplingMass": 1.0})
    frame = aids.frame_matrices(st, "z")
    st.fmu.freeInstance()
    g = aids.drive_pulse_response(cnc, 1e-3)
    brackets = {"jacobi": (25.0, 32.0), "implicit-end": (5.0, 10.0),
                "gauss-seidel": (0.98 * limit, 1.02 * limit), "trapezoidal": (0.98 * limit, 1.02 * limit)}
    for name, (below, above) in brackets.items():
        radius = [aids.spectral_radius(g, frame, m, aids.SCHEMES[name], 1e-3) for m in (below, above)]
        print(name, radius)
        assert radius[0] < 1.0 < radius[1], name


def test_the_frame_interpolates_a_ramped_drive_force_through_fmpy(structure: Unpacked) -> None:
    """x.driveForce = r·t in steps of 10 ms through fmpy's FMU2Slave: given its slope
    (setRealInputDerivatives) the deflection follows the sum of the modes' ramp responses
    (r/k)·[t − 2ζ/ω + e^{−ζωt}(2ζ/ω·cos ω_d t + (2ζ² − 1)/ω_d·sin ω_d t)]; held, it lags. (fmpy's
    simulate_fmu(set_input_derivatives=True) cannot drive it: its buffer of derivatives has room for
    exactly 9 continuous inputs.)"""
    r, h, modes = 4.0e4, 0.01, [(45.0, 0.03, 400.0), (120.0, 0.02, 250.0)]

    def exact(t: float) -> float:
        q = 0.0
        for f, zeta, m in modes:
            w = 2 * np.pi * f
            wd = w * np.sqrt(1 - zeta**2)
            free = 2 * zeta / w * np.cos(wd * t) + (2 * zeta**2 - 1) / wd * np.sin(wd * t)
            q += r / (m * w * w) * (t - 2 * zeta / w + np.exp(-zeta * w * t) * free)
        return float(q)

    for derivatives in (True, False):
        st = Slave(structure, "ramp")
        st.initialize({})
        force = [st.u.vars["x.driveForce"].valueReference]
        errors = []
        for k in range(20):
            st.fmu.setReal(force, [r * k * h])
            if derivatives:
                st.fmu.setRealInputDerivatives(force, [1], [r])
            st.step(h)
            errors.append(abs(st.get("x.deflection") - exact((k + 1) * h)) / exact(0.2))
        st.free()
        print(f"input derivatives {derivatives}: largest error {max(errors):.2e} of the last deflection")
        assert (max(errors) < 1e-9) if derivatives else (max(errors) > 1e-2)
