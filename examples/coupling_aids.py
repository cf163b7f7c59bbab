"""Two-way coupling of CncMotion.fmu with MachineStructure.fmu at h = 1 ms: the largest table mass
(`couplingMass`, all three axes) for which the loop stays stable, with and without the coupling aids
the FMUs declare (issue 23), on the FMU's default program (1.5 s, the moves that excite the frame):

  * jacobi       — both FMUs step from the values of the previous communication point (the
                   masters of examples/cosim.py);
  * extrapolated — as jacobi, but CncMotion's loadForce input is the frame's loadForce extrapolated
                   to the middle of the step, L + (h/2)·dL/dt, with dL/dt = (∂L/∂x)·ẋ from
                   MachineStructure's fmi2GetDirectionalDerivative (its states x = modal q, v);
  * implicit     — both FMUs rolled back (fmi2GetFMUstate/SetFMUstate) and stepped again until the
                   interface is consistent: Newton on the load force, with the frame's step
                   sensitivity ∂L(t+h)/∂F = C·∫₀ʰe^{As}ds·B from its directional derivatives (A, B, C)
                   and CncMotion's ∂F/∂L by secant (CncMotion declares no directional derivatives).

A run is unstable when a drive force passes 5 kN (the stable runs peak below 200 N) or an FMU refuses
a step. Prints the table and writes out/coupling_aids.png:

    .venv-full/bin/python examples/coupling_aids.py [--out out]
"""
from __future__ import annotations

import argparse
import pathlib

import numpy as np

from cnc_motion_sim.fmu import Slave, Unpacked
from cnc_motion_sim.paths import CNC_FMU, STRUCTURE_FMU

AXES = "xyz"
H = 1e-3
STOP = 1.5
LIMIT_N = 5e3


def step_sensitivity(st: Slave, a: str, h: float) -> float:
    """∂loadForce(t+h)/∂driveForce held over the step, from MachineStructure's Jacobian [C D; A B]."""
    vr = lambda n: st.u.vars[f"{a}.{n}"].valueReference  # noqa: E731
    knowns = [vr(n) for n in ("driveForce", "mode1.q", "mode1.v", "mode2.q", "mode2.v")]
    unknowns = [vr(n) for n in ("loadForce", "mode1.v", "mode1.a", "mode2.v", "mode2.a")]
    j = np.array([st.fmu.getDirectionalDerivative(unknowns, knowns, list(np.eye(5)[k])) for k in range(5)]).T
    c, a_, b = j[0, 1:], j[1:, 1:], j[1:, 0]
    term = phi = np.eye(4) * h        # ∫₀ʰ e^{As} ds = Σ Aⁿ hⁿ⁺¹/(n+1)!
    for n in range(1, 30):
        term = term @ a_ * h / (n + 1)
        phi = phi + term
    return float(c @ phi @ b)


def load_rate(st: Slave, a: str) -> float:
    """dL/dt = (∂L/∂x)·ẋ (L has no direct feed-through of the drive force)."""
    vr = lambda n: st.u.vars[f"{a}.{n}"].valueReference  # noqa: E731
    states = [vr(f"mode{k}.{q}") for k in (1, 2) for q in "qv"]
    rates = st.fmu.getReal([vr(f"mode{k}.{q}") for k in (1, 2) for q in "va"])
    return st.fmu.getDirectionalDerivative([vr("loadForce")], states, rates)[0]


def run(cu: Unpacked, su: Unpacked, mass: float, scheme: str) -> tuple[bool, float, int]:
    """(stable, peak |drive force|, FMU steps per model)."""
    cnc, st = Slave(cu, "cnc"), Slave(su, "structure")
    steps, peak = 0, 0.0
    try:
        cnc.initialize({})
        st.initialize({f"{a}.couplingMass": mass for a in AXES})
        force = {a: 0.0 for a in AXES}
        load = {a: 0.0 for a in AXES}
        rate = {a: 0.0 for a in AXES}
        sens = {a: step_sensitivity(st, a, H) for a in AXES}
        gain = {a: -1.0 for a in AXES}
        for _ in range(round(STOP / H)):
            if scheme != "implicit":
                tau = H / 2 if scheme == "extrapolated" else 0.0
                for a in AXES:
                    st.set(f"{a}.driveForce", force[a])
                    cnc.set(f"{a}.loadForce", load[a] + tau * rate[a])
                cnc.step(H)
                st.step(H)
                steps += 1
                for a in AXES:
                    force[a], load[a] = cnc.get(f"{a}.driveForce"), st.get(f"{a}.loadForce")
                    rate[a] = load_rate(st, a) if tau else 0.0
            else:
                saved = cnc.fmu.getFMUstate(), st.fmu.getFMUstate()
                guess, previous = dict(load), None
                for it in range(6):
                    if it:
                        for s, state in zip((cnc, st), saved):
                            s.fmu.setFMUstate(state)
                            s.steps -= 1
                            s.time = s.t0 + s.steps * H
                    for a in AXES:
                        cnc.set(f"{a}.loadForce", float(np.clip(guess[a], -2e4, 2e4)))
                    cnc.step(H)
                    force = {a: cnc.get(f"{a}.driveForce") for a in AXES}
                    for a in AXES:
                        st.set(f"{a}.driveForce", float(np.clip(force[a], -2e4, 2e4)))
                    st.step(H)
                    steps += 1
                    load = {a: st.get(f"{a}.loadForce") for a in AXES}
                    residual = {a: guess[a] - load[a] for a in AXES}
                    if max(abs(r) for r in residual.values()) < 1e-6:
                        break
                    if previous is not None:
                        for a in AXES:
                            d = guess[a] - previous[0][a]
                            if abs(d) > 1e-12:
                                gain[a] = (force[a] - previous[1][a]) / d
                    previous = dict(guess), force
                    guess = {a: guess[a] - residual[a] / (1.0 - sens[a] * gain[a]) for a in AXES}
                for s, state in zip((cnc, st), saved):
                    s.fmu.freeFMUstate(state)
            peak = max(peak, *(abs(f) for f in force.values()))
            if not np.isfinite(peak) or peak > LIMIT_N:
                return False, peak, steps
        return True, peak, steps
    except Exception:  # an FMU refusing an overflowed value: unstable
        return False, float("nan"), steps
    finally:
        cnc.fmu.freeInstance()
        st.fmu.freeInstance()


def largest_stable_mass(cu: Unpacked, su: Unpacked, scheme: str, hi: float = 400.0) -> float:
    """Bisection to 0.5 kg between 0 (stable: no coupling) and `hi`."""
    lo = 0.0
    if run(cu, su, hi, scheme)[0]:
        return hi
    while hi - lo > 0.5:
        mid = (lo + hi) / 2
        lo, hi = (mid, hi) if run(cu, su, mid, scheme)[0] else (lo, mid)
    return lo


def main() -> None:
    ap = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    ap.add_argument("--out", default="out")
    args = ap.parse_args()
    cu, su = Unpacked(CNC_FMU), Unpacked(STRUCTURE_FMU)
    try:
        result = {}
        for scheme in ("jacobi", "extrapolated", "implicit"):
            m = largest_stable_mass(cu, su, scheme)
            _, _, steps = run(cu, su, m, scheme)
            result[scheme] = m
            print(f"{scheme:13s} largest stable couplingMass {m:6.1f} kg "
                  f"({steps / round(STOP / H):.2f} FMU steps per communication step)")
    finally:
        cu.cleanup()
        su.cleanup()
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(7, 3.2), layout="constrained")
    ax.barh(list(result), list(result.values()), color=["0.5", "tab:blue", "tab:orange"])
    for k, (name, m) in enumerate(result.items()):
        ax.text(m + 0.5, k, f"{m:.1f} kg", va="center")
    ax.set_xlabel("largest stable couplingMass (kg, all axes), h = 1 ms")
    ax.set_title("CncMotion ↔ MachineStructure: two-way coupling with and without the aids", fontsize=10)
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    fig.savefig(out / "coupling_aids.png", dpi=110)
    print(f"plot: {out / 'coupling_aids.png'}")


if __name__ == "__main__":
    main()
