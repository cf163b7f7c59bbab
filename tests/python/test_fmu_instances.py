"""FMU instances: state get/set/serialize round trips, repeated reset cycles, parallel instances."""
import math
from collections.abc import Callable
from typing import Any
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest

import cnc_motion_sim as sim

H = 1e-3


Inputs = Callable[[float, sim.Slave], None]


def drive_inputs(u: sim.Unpacked) -> Inputs:
    """Deterministic inputs for either FMU: loads/forces as sines, override 1, no hold."""
    reals = [v.name for v in u.md.modelVariables if v.causality == "input" and v.type == "Real"]

    def apply(t: float, s: sim.Slave) -> None:
        for k, n in enumerate(reals):
            if n == "feedOverride":
                s.set(n, 1.0)
            else:
                s.set(n, 50.0 * math.sin(2 * math.pi * 7.0 * t + k))
    return apply


def outputs(u: sim.Unpacked) -> list[str]:
    return [v.name for v in u.md.modelVariables
            if v.causality == "output" and v.type in ("Real", "Integer", "Boolean")]


def advance(s: sim.Slave, u: sim.Unpacked, n: int, inputs: Inputs) -> Any:
    read = s.reader(outputs(u))
    rows = []
    for _ in range(n):
        inputs(s.time, s)
        s.step(H)
        rows.append(read())
    return np.array(rows)


@pytest.fixture(params=["cnc", "structure"])
def fmu(request: pytest.FixtureRequest, cnc: sim.Unpacked, structure: sim.Unpacked) -> sim.Unpacked:
    return {"cnc": cnc, "structure": structure}[request.param]


def test_fmu_state_round_trip(fmu: sim.Unpacked) -> None:
    u = fmu
    assert u.md.coSimulation.canGetAndSetFMUstate and u.md.coSimulation.canSerializeFMUstate
    inputs = drive_inputs(u)
    s = sim.Slave(u, "a")
    s.initialize()
    advance(s, u, 700, inputs)
    state = s.fmu.getFMUstate()
    blob = s.fmu.serializeFMUstate(state)
    t0, n0 = s.time, s.steps
    first = advance(s, u, 600, inputs)
    # Back to the saved state in the same instance.
    s.fmu.setFMUstate(state)
    s.steps = n0
    s.time = t0
    again = advance(s, u, 600, inputs)
    s.fmu.freeFMUstate(state)
    s.free()
    assert np.array_equal(first, again)
    # Serialized bytes into a fresh instance.
    s2 = sim.Slave(u, "b")
    s2.initialize()
    st2 = s2.fmu.deSerializeFMUstate(blob)
    s2.fmu.setFMUstate(st2)
    s2.steps, s2.time = n0, t0
    other = advance(s2, u, 600, inputs)
    s2.fmu.freeFMUstate(st2)
    s2.free()
    assert np.array_equal(first, other)


def test_reset_cycles_identical(fmu: sim.Unpacked) -> None:
    u = fmu
    inputs = drive_inputs(u)
    s = sim.Slave(u, "r")
    runs = []
    for cycle in range(4):
        if cycle:
            s.fmu.reset()
        s.initialize()
        runs.append(advance(s, u, 800, inputs))
    s.free()
    for r in runs[1:]:
        assert np.array_equal(runs[0], r)


def _run_default(cnc: sim.Unpacked, kind: str) -> Any:
    r = sim.run_cnc(cnc, {"machine.profile": kind})
    return np.column_stack([r[n] for n in sim.cnc_outputs(cnc)])


def test_parallel_instances_in_threads(cnc: sim.Unpacked) -> None:
    kinds = ["scurve7", "trapezoid", "scurve7", "quintic"]
    serial = {k: _run_default(cnc, k) for k in set(kinds)}
    with ThreadPoolExecutor(max_workers=4) as pool:
        parallel = list(pool.map(lambda k: _run_default(cnc, k), kinds))
    for k, r in zip(kinds, parallel):
        assert np.array_equal(serial[k], r), k
