"""Two-way coupling of CncMotion.fmu with MachineStructure.fmu: the largest table mass
(`couplingMass`, all three axes) for which the loop stays stable, per coupling scheme, on the FMU's
default program (1.5 s, the moves that excite the frame), and why (issue 23).

Each scheme feeds CncMotion a load held over the step, uL = a0·L(t) + a1·L(t+h), and the frame the
drive force held, uF = b0·F(t) + b1·F(t+h), or ramped from F(t) to F(t+h) (first-order hold: the
frame's fmi2SetRealInputDerivatives, canInterpolateInputs). Where a value at t+h is needed both
FMUs are rolled back (fmi2GetFMUstate/SetFMUstate) and stepped again: Newton on L(t+h) with the
interface Jacobian of both sides, CncMotion's step sensitivity G = ∂F(t+h)/∂uL measured by a
perturbed step at the start (then secant updates) and the frame's S = ∂L(t+h)/∂F(t+h) from its
directional derivatives (A, B, C: C·∫e^{As}ds·B, or C·∫e^{As}(h−s)/h ds·B for the ramp).

  jacobi        a = (1, 0), b = (1, 0): both from the previous communication point
  extrapolated  as jacobi, the load taken at mid-step from dL/dt = C·ẋ (directional derivatives)
  implicit-end  a = (0, 1), b = (0, 1): inputs held at their end-of-step values
  gauss-seidel  a = (1, 0), b = (0, 1): CncMotion first, the frame with its new force
  trapezoidal   a = (½, ½), frame ramped: the step averages, both sensitivities, input derivatives
  trap-held     a = (½, ½), b = (½, ½): the same with the frame's force held at the average

A run is unstable when a drive force passes 5 kN (the stable runs peak near 200 N) or an FMU refuses
a step. The linear analysis beside it: CncMotion linearised while z feeds (t = 0.3 s; its response
F(t+nh) to a load pulse over one step, measured by rollback) and the frame's exact step map give
the coupled step map of each scheme; its spectral radius against couplingMass says where the loop
goes unstable, and the coupled model itself has a limit: the frame's quasi-static answer to the
drive force, L = −M·Σ F/m_k, reverses the screw's force on the table at M = 1/Σ(1/m_k). Prints the
tables and writes out/coupling_aids.png:

    .venv-full/bin/python examples/coupling_aids.py [--out out] [--quick]
"""
from __future__ import annotations

import argparse
import pathlib
from dataclasses import dataclass
from typing import Any

import numpy as np

from cnc_motion_sim.fmu import Slave, Unpacked
from cnc_motion_sim.paths import CNC_FMU, STRUCTURE_FMU

AXES = "xyz"
STOP = 1.5
LIMIT_N = 5e3
Vec = np.ndarray


@dataclass(frozen=True)
class Scheme:
    a: tuple[float, float]          # load to CncMotion: a0·L(t) + a1·L(t+h)
    b: tuple[float, float] | None   # force to the frame: b0·F(t) + b1·F(t+h); None: ramped
    extrapolate: bool = False       # + (h/2)·dL/dt(t)


SCHEMES = {
    "jacobi": Scheme((1, 0), (1, 0)),
    "extrapolated": Scheme((1, 0), (1, 0), extrapolate=True),
    "implicit-end": Scheme((0, 1), (0, 1)),
    "gauss-seidel": Scheme((1, 0), (0, 1)),
    "trapezoidal": Scheme((0.5, 0.5), None),
    "trap-held": Scheme((0.5, 0.5), (0.5, 0.5)),
}


def expm(m: Vec) -> Vec:
    """e^M by scaling and squaring of the Taylor series (the small matrices here)."""
    s = max(0, int(np.ceil(np.log2(max(np.abs(m).sum(axis=1).max(), 1e-300)))) + 1)
    a, e, term = m / 2.0**s, np.eye(len(m)), np.eye(len(m))
    for k in range(1, 20):
        term = term @ a / k
        e = e + term
    for _ in range(s):
        e = e @ e
    return e


def vrs(u: Unpacked, name: str) -> list[int]:
    return [u.vars[f"{a}.{name}"].valueReference for a in AXES]


def frame_matrices(st: Slave, a: str) -> tuple[Vec, Vec, Vec]:
    """A, B, C of one axis (states mode1.q, mode1.v, mode2.q, mode2.v; input the drive force;
    output the load force), from MachineStructure's directional derivatives."""
    vr = lambda n: st.u.vars[f"{a}.{n}"].valueReference  # noqa: E731
    knowns = [vr(n) for n in ("driveForce", "mode1.q", "mode1.v", "mode2.q", "mode2.v")]
    unknowns = [vr(n) for n in ("loadForce", "mode1.v", "mode1.a", "mode2.v", "mode2.a")]
    j = np.array([st.fmu.getDirectionalDerivative(unknowns, knowns, list(np.eye(5)[k])) for k in range(5)]).T
    return j[1:, 1:], j[1:, 0], j[0, 1:]


def frame_step(a_: Vec, b: Vec, h: float) -> tuple[Vec, Vec, Vec]:
    """Φ = e^{Ah}, Γ0 = ∫₀ʰe^{As}ds·B (held force), Γ1 = ∫₀ʰe^{A(h−s)}s ds·B (the ramp's part)."""
    z = np.zeros((6, 6))
    z[:4, :4], z[:4, 4], z[4, 5] = a_, b, 1.0
    e = expm(z * h)
    return e[:4, :4], e[:4, 4], e[:4, 5]


def input_weights(s: Scheme, gamma0: Vec, gamma1: Vec, h: float) -> tuple[Vec, Vec]:
    """The frame's step x⁺ = Φx + Γa·F(t) + Γb·F(t+h) under the scheme's force."""
    if s.b is None:
        return gamma0 - gamma1 / h, gamma1 / h
    return s.b[0] * gamma0, s.b[1] * gamma0


class Loop:
    """CncMotion and MachineStructure (FMI 2.0 CS) coupled by one scheme at step h."""

    def __init__(self, cu: Unpacked, su: Unpacked, mass: float, scheme: Scheme, h: float) -> None:
        self.cnc, self.st, self.s, self.h = Slave(cu, "cnc"), Slave(su, "structure"), scheme, h
        self.cnc.initialize({})
        self.st.initialize({f"{a}.couplingMass": mass for a in AXES})
        self.load_in, self.force_out = vrs(cu, "loadForce"), vrs(cu, "driveForce")
        self.force_in, self.load_out = vrs(su, "driveForce"), vrs(su, "loadForce")
        self.F, self.L = np.zeros(3), np.zeros(3)
        self.t, self.fmu_steps, self.steps = 0.0, 0, 0
        # Per axis C, C·A, C·B (for dL/dt) and S = ∂L(t+h)/∂F(t+h) under the scheme's force.
        self.c: list[tuple[Vec, Vec, float]] = []
        sens = []
        for a in AXES:
            a_, b, c = frame_matrices(self.st, a)
            _, g0, g1 = frame_step(a_, b, h)
            self.c.append((c, c @ a_, float(c @ b)))
            sens.append(float(c @ input_weights(scheme, g0, g1, h)[1]))
        self.S = np.array(sens)
        self.G = self.drive_gain() if scheme.a[1] else np.zeros(3)

    def drive_gain(self, delta: float = 10.0) -> Vec:
        """∂F(t+h)/∂uL of CncMotion's first step: one step with the load and one without."""
        saved = self.cnc.fmu.getFMUstate()
        out = []
        for load in (0.0, delta):
            self.cnc.fmu.setFMUstate(saved)
            self.cnc.fmu.setReal(self.load_in, [load] * 3)
            self.cnc.fmu.doStep(0.0, self.h)
            out.append(np.array(self.cnc.fmu.getReal(self.force_out)))
        self.cnc.fmu.setFMUstate(saved)
        self.cnc.fmu.freeFMUstate(saved)
        return (out[1] - out[0]) / delta

    def load_rate(self) -> Vec:
        """dL/dt = C·(Ax + B·F) of each axis at the communication point."""
        names = [f"{a}.mode{k}.{q}" for a in AXES for k in (1, 2) for q in "qv"]
        x = np.array(self.st.fmu.getReal([self.st.u.vars[n].valueReference for n in names])).reshape(3, 4)
        return np.array([ca @ xi + cb * f for (_, ca, cb), xi, f in zip(self.c, x, self.F)])

    def attempt(self, guess: Vec) -> tuple[Vec, Vec, Vec]:
        """Both FMUs one step with L(t+h) = guess: (uL, F(t+h), L(t+h))."""
        s, h = self.s, self.h
        u_load = s.a[0] * self.L + s.a[1] * guess
        if s.extrapolate:
            u_load = u_load + h / 2 * self.load_rate()
        self.cnc.fmu.setReal(self.load_in, list(u_load))
        self.cnc.fmu.doStep(self.t, h)
        f_new = np.array(self.cnc.fmu.getReal(self.force_out))
        if s.b is None:
            self.st.fmu.setReal(self.force_in, list(self.F))
            self.st.fmu.setRealInputDerivatives(self.force_in, [1] * 3, list((f_new - self.F) / h))
        else:
            self.st.fmu.setReal(self.force_in, list(s.b[0] * self.F + s.b[1] * f_new))
        self.st.fmu.doStep(self.t, h)
        self.fmu_steps += 1
        return u_load, f_new, np.array(self.st.fmu.getReal(self.load_out))

    def step(self) -> None:
        """One communication step; Newton on L(t+h) where the scheme needs it (a1 ≠ 0)."""
        if not self.s.a[1]:
            _, self.F, self.L = self.attempt(self.L)
        else:
            saved = self.cnc.fmu.getFMUstate(), self.st.fmu.getFMUstate()
            guess, previous = self.L.copy(), None
            for it in range(12):
                if it:
                    self.cnc.fmu.setFMUstate(saved[0])
                    self.st.fmu.setFMUstate(saved[1])
                u_load, f_new, l_new = self.attempt(guess)
                residual = l_new - guess
                if np.abs(residual).max() <= 1e-6:
                    break
                if previous is not None:  # secant update of CncMotion's sensitivity
                    d = u_load - previous[0]
                    ok = np.abs(d) > 1e-9
                    self.G = np.where(ok, (f_new - previous[1]) / np.where(ok, d, 1.0), self.G)
                previous = u_load, f_new
                guess = guess + residual / (1.0 - self.s.a[1] * self.G * self.S)
            for fmu, state in zip((self.cnc.fmu, self.st.fmu), saved):
                fmu.freeFMUstate(state)
            self.F, self.L = f_new, l_new
        self.t = (self.steps + 1) * self.h
        self.steps += 1

    def free(self) -> None:
        self.cnc.fmu.freeInstance()
        self.st.fmu.freeInstance()


def run(cu: Unpacked, su: Unpacked, mass: float, scheme: str, h: float = 1e-3) -> tuple[bool, float, float]:
    """(stable, peak |drive force|, FMU steps of each model per communication step)."""
    loop = None
    try:
        loop = Loop(cu, su, mass, SCHEMES[scheme], h)
        peak = 0.0
        for _ in range(round(STOP / h)):
            loop.step()
            peak = max(peak, float(np.abs(loop.F).max()))
            if not np.isfinite(peak) or peak > LIMIT_N:
                return False, peak, loop.fmu_steps / loop.steps
        return True, peak, loop.fmu_steps / loop.steps
    except Exception:  # an FMU refusing an overflowed value: unstable
        return False, float("nan"), float("nan")
    finally:
        if loop is not None:
            loop.free()


def largest_stable_mass(cu: Unpacked, su: Unpacked, scheme: str, h: float = 1e-3, hi: float = 400.0) -> float:
    """Bisection to 0.5 kg between 0 (stable: no coupling) and `hi`."""
    lo = 0.0
    if run(cu, su, hi, scheme, h)[0]:
        return hi
    while hi - lo > 0.5:
        mid = (lo + hi) / 2
        lo, hi = (mid, hi) if run(cu, su, mid, scheme, h)[0] else (lo, mid)
    return lo


# -- the linear analysis ------------------------------------------------------------------------

def drive_pulse_response(cu: Unpacked, h: float, at: float = 0.3, n: int | None = None,
                         delta: float = 10.0) -> Vec:
    """g[j] = ∂F_z(t + (j+1)h)/∂uL_z held over [t, t+h], CncMotion alone at time `at` (z feeding):
    its linearisation, by rollback and a perturbed run."""
    n = n or round(0.4 / h)
    c = Slave(cu, "pulse")
    c.initialize({})
    for k in range(round(at / 1e-3)):
        c.fmu.doStep(k * 1e-3, 1e-3)
    saved, t0 = c.fmu.getFMUstate(), round(at / 1e-3) * 1e-3
    load, force = vrs(cu, "loadForce")[2], vrs(cu, "driveForce")[2]
    runs = []
    for pulse in (0.0, delta):
        c.fmu.setFMUstate(saved)
        out = []
        for k in range(n):
            c.fmu.setReal([load], [pulse if k == 0 else 0.0])
            c.fmu.doStep(t0 + k * h, h)
            out.append(c.fmu.getReal([force])[0])
        runs.append(np.array(out))
    c.fmu.freeFMUstate(saved)
    c.fmu.freeInstance()
    return (runs[1] - runs[0]) / delta


def spectral_radius(g: Vec, frame: tuple[Vec, Vec, Vec], mass: float, s: Scheme, h: float) -> float:
    """Largest |eigenvalue| of the coupled step map z → z⁺, z = (x, uL of the last len(g) steps,
    F(t)): the frame x⁺ = Φx + Γa·F + Γb·F⁺, L = C·x (C ∝ couplingMass), the drive
    F⁺ = Σ g[j]·uL(t − jh), and the scheme's uL = a0·L + a1·L⁺ (+ (h/2)·C(Ax + B·F))."""
    a_, b, c1 = frame
    c = c1 * mass
    phi, g0, g1 = frame_step(a_, b, h)
    ga, gb = input_weights(s, g0, g1, h)
    n, m = len(g), 4 + len(g) + 1
    x, f = slice(0, 4), 4 + n
    rest = np.zeros(m)                 # F⁺ = g[0]·uL + rest·z
    rest[4:4 + n - 1] = g[1:]
    u = np.zeros(m)                    # uL = u·z + k·F⁺
    u[x] = s.a[0] * c + s.a[1] * c @ phi
    u[f] = s.a[1] * c @ ga
    if s.extrapolate:
        u[x] += h / 2 * c @ a_
        u[f] += h / 2 * c @ b
    k = s.a[1] * c @ gb
    u = (u + k * rest) / (1.0 - k * g[0])
    f_new = g[0] * u + rest
    t = np.zeros((m, m))
    t[x, x] = phi
    t[x, :] += np.outer(ga, np.eye(m)[f]) + np.outer(gb, f_new)
    t[4, :] = u
    t[5:4 + n, 4:3 + n] = np.eye(n - 1)
    t[f, :] = f_new
    return float(np.abs(np.linalg.eigvals(t)).max())


def linear_limit(g: Vec, frame: tuple[Vec, Vec, Vec], s: Scheme, h: float, hi: float = 400.0) -> float:
    """The couplingMass where the spectral radius reaches 1 (bisection to 0.1 kg)."""
    lo = 0.0
    if spectral_radius(g, frame, hi, s, h) < 1:
        return hi
    while hi - lo > 0.1:
        mid = (lo + hi) / 2
        lo, hi = (mid, hi) if spectral_radius(g, frame, mid, s, h) < 1 else (lo, mid)
    return lo


def model_limit(su: Unpacked) -> dict[str, float]:
    """M = 1/Σ(1/m_k) per axis: where the frame's quasi-static load −M·Σ F/m_k cancels the screw's
    force on the table (the coupled model's own stability limit, whatever the scheme)."""
    st = Slave(su, "limit")
    st.initialize({})
    out = {a: 1.0 / sum(1.0 / st.get(f"{a}.mode{k}.mass") for k in (1, 2)) for a in AXES}
    st.fmu.freeInstance()
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    ap.add_argument("--out", default="out")
    ap.add_argument("--quick", action="store_true", help="1 ms only: no step sweep, a coarser linear analysis")
    args = ap.parse_args()
    cu, su = Unpacked(CNC_FMU), Unpacked(STRUCTURE_FMU)
    h = 1e-3
    try:
        limit = model_limit(su)
        print("the coupled model's own limit M = 1/Σ(1/m_k): "
              + ", ".join(f"{a} {m:.1f} kg" for a, m in limit.items()))
        st = Slave(su, "frame")
        st.initialize({"z.couplingMass": 1.0})
        frame = frame_matrices(st, "z")
        st.fmu.freeInstance()
        g = drive_pulse_response(cu, h)
        print(f"\nh = 1 ms: largest stable couplingMass (all axes), simulated / linearised (z feeding)")
        stable: dict[str, float] = {}
        linear: dict[str, float] = {}
        for name, s in SCHEMES.items():
            stable[name] = largest_stable_mass(cu, su, name, h)
            linear[name] = linear_limit(g, frame, s, h)
            _, peak, per_step = run(cu, su, stable[name], name, h)
            print(f"  {name:13s} {stable[name]:6.1f} kg / {linear[name]:6.1f} kg   "
                  f"{per_step:.2f} FMU steps per step (peak {peak:.0f} N)")
        steps = [0.25e-3, 0.5e-3, 1e-3, 2e-3, 5e-3, 10e-3] if not args.quick else []
        if steps:
            print("\ncouplingMass 50 kg (the tables'): stable steps (ms)")
            for name in SCHEMES:
                ok = [f"{x * 1e3:g}" for x in steps if run(cu, su, 50.0, name, x)[0]]
                print(f"  {name:13s} {' '.join(ok) or 'none'}")
        masses = np.linspace(1.0, 160.0, 20 if args.quick else 54)
        radius = {name: [spectral_radius(g, frame, m, s, h) for m in masses] for name, s in SCHEMES.items()}
    finally:
        cu.cleanup()
        su.cleanup()
    plot(pathlib.Path(args.out), stable, limit, masses, radius)


def plot(out: pathlib.Path, stable: dict[str, float], limit: dict[str, float], masses: Vec,
         radius: dict[str, list[float]]) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, (ax, ax2) = plt.subplots(1, 2, figsize=(11, 3.8), layout="constrained")
    colors: dict[str, Any] = {name: f"C{k}" for k, name in enumerate(SCHEMES)}
    ax.barh(list(stable), list(stable.values()), color=[colors[n] for n in stable])
    for k, (name, m) in enumerate(stable.items()):
        ax.text(m + 1.0, k, f"{m:.1f} kg", va="center", fontsize=8)
    ax.axvline(limit["z"], color="k", ls="--", lw=0.8)
    ax.invert_yaxis()
    ax.text(limit["z"], -0.6, f"the model's own limit, z: {limit['z']:.1f} kg", fontsize=8, ha="right", va="bottom")
    ax.set_xlim(0, 1.2 * limit["z"])
    ax.set_xlabel("largest stable couplingMass (kg, all axes), h = 1 ms, simulated")
    for name, r in radius.items():
        ax2.plot(masses, r, label=name, color=colors[name], lw=1.2)
    ax2.axhline(1.0, color="k", ls="--", lw=0.8)
    ax2.set_ylim(0.97, 1.06)
    ax2.set_xlabel("couplingMass (kg)")
    ax2.set_ylabel("spectral radius of the step map")
    ax2.set_title("linearised loop, z axis feeding, h = 1 ms", fontsize=9)
    ax2.legend(fontsize=7, ncol=2)
    fig.suptitle("CncMotion ↔ MachineStructure: two-way coupling schemes", fontsize=10)
    out.mkdir(parents=True, exist_ok=True)
    fig.savefig(out / "coupling_aids.png", dpi=110)
    print(f"plot: {out / 'coupling_aids.png'}")


if __name__ == "__main__":
    main()
