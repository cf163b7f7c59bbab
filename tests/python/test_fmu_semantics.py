"""The Reference-FMU semantics on both FMUs, through fmpy's FMU2Slave: after fmi2Error only get,
status, reset, free and FMU-state calls are allowed; non-finite times are refused; a master's
float drift is accepted; the status inquiries answer; the declared ModelStructure dependencies are
exactly the direct feed-through seen by a set-and-get probe; FMU states are compact."""
import math
import pathlib
from collections.abc import Callable
from typing import Any

import pytest
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import fmi2Discard, fmi2Error, fmi2OK

import cnc_motion_sim as sim

H = 1e-3
DO_STEP_STATUS, LAST_SUCCESSFUL_TIME, TERMINATED = 0, 2, 3


@pytest.fixture(params=["cnc", "structure"])
def fmu(request: pytest.FixtureRequest, cnc: sim.Unpacked, structure: sim.Unpacked) -> sim.Unpacked:
    return {"cnc": cnc, "structure": structure}[request.param]


def status_of(call: Callable[..., Any], *args: Any) -> int:
    """fmi2Status of a call (fmpy raises on anything above Warning)."""
    try:
        call(*args)
        return fmi2OK
    except FMICallException as e:
        return int(e.status)


def started(u: sim.Unpacked, name: str, steps: int = 20, stop_time: float | None = None) -> sim.Slave:
    s = sim.Slave(u, name)
    s.fmu.setupExperiment(startTime=0.0, stopTime=stop_time)
    s.fmu.enterInitializationMode()
    s.fmu.exitInitializationMode()
    s.t0 = 0.0
    for _ in range(steps):
        s.step(H)
    return s


def an_input(u: sim.Unpacked) -> Any:
    return next(v for v in u.md.modelVariables if v.causality == "input" and v.type == "Real")


def outputs(u: sim.Unpacked) -> list[str]:
    return [v.name for v in u.md.modelVariables if v.causality == "output"]


def assert_terminal_error(s: sim.Slave, u: sim.Unpacked, want_log: str) -> None:
    """The instance answered fmi2Error: it now refuses everything but get/status/reset/free."""
    assert any(want_log in m for _, _, m in s.log), s.log[-3:]
    f = s.fmu
    vr_out = [u.vars[outputs(u)[0]].valueReference]
    vr_in = [an_input(u).valueReference]
    assert len(f.getReal(vr_out)) == 1                      # get is allowed
    assert f.getBooleanStatus(TERMINATED)
    assert status_of(f.doStep, s.time, H) == fmi2Error
    assert "not allowed in state Error" in s.log[-1][2]
    assert status_of(f.setReal, vr_in, [0.0]) == fmi2Error
    assert status_of(f.terminate) == fmi2Error
    assert status_of(f.enterInitializationMode) == fmi2Error
    # Reset brings the instance back to Instantiated: it runs again from t = 0.
    f.reset()
    s.fmu.setupExperiment(startTime=0.0)
    f.enterInitializationMode()
    f.exitInitializationMode()
    f.doStep(0.0, H)
    s.free()


def test_bad_value_reference_is_terminal(fmu: sim.Unpacked) -> None:
    s = started(fmu, "badvr")
    assert status_of(s.fmu.getReal, [999_999]) == fmi2Error
    assert_terminal_error(s, fmu, "unknown value reference 999999")


def test_wrong_communication_point_is_terminal(fmu: sim.Unpacked) -> None:
    s = started(fmu, "badt")
    assert status_of(s.fmu.doStep, s.time + 0.5, H) == fmi2Error
    assert_terminal_error(s, fmu, "is not the slave's time")


def test_step_past_stop_time_is_terminal(fmu: sim.Unpacked) -> None:
    s = started(fmu, "stop", steps=0, stop_time=10 * H)
    for _ in range(10):
        s.step(H)
    assert status_of(s.fmu.doStep, s.time, H) == fmi2Error
    assert_terminal_error(s, fmu, "goes past the stop time")


@pytest.mark.parametrize("t", [math.nan, math.inf, -math.inf])
def test_non_finite_time_is_refused(fmu: sim.Unpacked, t: float) -> None:
    s = started(fmu, "nan")
    before = s.fmu.getRealStatus(LAST_SUCCESSFUL_TIME)
    assert status_of(s.fmu.doStep, t, H) == fmi2Error
    assert s.fmu.getRealStatus(LAST_SUCCESSFUL_TIME) == before == pytest.approx(20 * H, abs=1e-15)
    assert_terminal_error(s, fmu, "currentCommunicationPoint must be finite")


def test_non_finite_step_size_is_refused(fmu: sim.Unpacked) -> None:
    s = started(fmu, "nanh")
    assert status_of(s.fmu.doStep, s.time, math.nan) == fmi2Error
    assert_terminal_error(s, fmu, "communicationStepSize must be > 0")


def test_float_drift_of_the_master_is_accepted(fmu: sim.Unpacked) -> None:
    """An Ecos-like master: t accumulated by t += h, ending one ulp-drift away from k·h, and a
    master that is off by 0.5 µs (below the 1 µs tolerance) still steps."""
    s = started(fmu, "drift", steps=0)
    t = 0.0
    for _ in range(5000):
        s.fmu.doStep(t, 0.1 * H)
        t += 0.1 * H
    s.fmu.doStep(t + 0.5e-6, H)
    assert s.fmu.getRealStatus(LAST_SUCCESSFUL_TIME) == pytest.approx(t + 0.5e-6 + H, abs=1e-15)
    # 2 µs off is a real jump in time: refused.
    assert status_of(s.fmu.doStep, t + H + 2.5e-6, H) == fmi2Error
    s.fmu.freeInstance()


def test_status_inquiries(fmu: sim.Unpacked) -> None:
    s = started(fmu, "status", steps=30)
    f = s.fmu
    assert f.getRealStatus(LAST_SUCCESSFUL_TIME) == pytest.approx(30 * H, abs=1e-15)
    assert f.getStatus(DO_STEP_STATUS) == fmi2OK
    assert not f.getBooleanStatus(TERMINATED)
    # Kinds with nothing to tell answer fmi2Discard and leave the instance usable.
    assert status_of(f.getRealStatus, DO_STEP_STATUS) == fmi2Discard
    assert status_of(f.getIntegerStatus, DO_STEP_STATUS) == fmi2Discard
    s.step(H)
    f.terminate()
    assert f.getBooleanStatus(TERMINATED)
    assert f.getRealStatus(LAST_SUCCESSFUL_TIME) == pytest.approx(31 * H, abs=1e-15)
    f.freeInstance()


def test_saved_state_recovers_from_error(fmu: sim.Unpacked) -> None:
    s = started(fmu, "recover", steps=10)
    state = s.fmu.getFMUstate()
    assert status_of(s.fmu.doStep, 99.0, H) == fmi2Error
    s.fmu.setFMUstate(state)            # allowed in Error, restores StepComplete at t = 10 h
    s.fmu.doStep(10 * H, H)
    assert s.fmu.getRealStatus(LAST_SUCCESSFUL_TIME) == pytest.approx(11 * H, abs=1e-15)
    s.fmu.freeFMUstate(state)
    s.free()


def declared_dependencies(u: sim.Unpacked) -> dict[str, set[str]]:
    """{output name: set of input names} from <ModelStructure><Outputs> (the continuous states
    the list also holds left out)."""
    deps = {}
    for unknown in u.md.outputs:
        assert unknown.dependencies is not None, f"{unknown.variable.name}: no dependencies declared"
        deps[unknown.variable.name] = {d.name for d in unknown.dependencies if d.causality == "input"}
    return deps


def test_declared_dependencies(cnc: sim.Unpacked, structure: sim.Unpacked) -> None:
    assert all(d == set() for d in declared_dependencies(cnc).values())
    want = {f"{a}.acceleration": {f"{a}.driveForce"} for a in "xyz"}
    got = {k: v for k, v in declared_dependencies(structure).items() if v}
    assert got == want


def test_feedthrough_probe_matches_the_declaration(fmu: sim.Unpacked) -> None:
    """Change one input at a time at a communication point and read every output without a step:
    exactly the declared dependents move."""
    s = started(fmu, "probe", steps=300)
    deps = declared_dependencies(fmu)
    names = outputs(fmu)
    read = s.reader(names)
    for v in fmu.md.modelVariables:
        if v.causality != "input":
            continue
        before = read()
        old = s.get(v.name)
        new = (not old) if v.type == "Boolean" else (0.5 if v.name == "feedOverride" else old + 1000.0)
        s.set(v.name, new)
        after = read()
        moved = {n for n, a, b in zip(names, before, after) if a != b}
        assert moved == {n for n in names if v.name in deps[n]}, (v.name, moved)
        s.set(v.name, old)
    s.free()


def test_serialized_state_is_compact_and_checked(fmu: sim.Unpacked) -> None:
    s = started(fmu, "size", steps=500)
    state = s.fmu.getFMUstate()
    blob = s.fmu.serializeFMUstate(state)
    # Measured: CncMotion 10.7–13.5 kB on the default program (was 112 kB of JSON), MachineStructure 355 B.
    limit = {"CncMotion": 32_000, "MachineStructure": 400}[fmu.md.modelName]
    assert len(blob) < limit, len(blob)
    assert bytes(blob[:6]) == b"FMI2RS"
    # A truncated or altered blob is refused (the instance then needs a reset or a good state).
    assert status_of(s.fmu.deSerializeFMUstate, blob[:-1]) == fmi2Error
    s.fmu.setFMUstate(state)
    bad = bytearray(blob)
    bad[7] ^= 0xFF                      # format version
    assert status_of(s.fmu.deSerializeFMUstate, bytes(bad)) == fmi2Error
    s.fmu.freeFMUstate(state)
    s.fmu.freeInstance()


def test_declared_ranges_are_enforced(fmu: sim.Unpacked) -> None:
    """Every declared min/max is checked on set (outside → fmi2Error naming the range), NaN never
    passes, and the bounds themselves are accepted by the layer (the model may refuse 0 where it
    needs a positive number)."""
    ranged = [v for v in fmu.md.modelVariables
              if v.causality in ("parameter", "input") and (v.min is not None or v.max is not None)]
    assert ranged, "no declared ranges"
    if fmu.md.modelName == "CncMotion":
        assert {"feedOverride", "machine.lookaheadBlocks", "machine.profileIndex"} <= {v.name for v in ranged}
    for v in ranged:
        for bound, step in ((v.min, -1), (v.max, +1)):
            if bound is None:
                continue
            s = sim.Slave(fmu, "range")
            value = float(bound) + step
            assert status_of(s.set, v.name, value) == fmi2Error, (v.name, value)
            assert "out of range" in s.log[-1][2], s.log[-1]
            s.fmu.freeInstance()
    s = sim.Slave(fmu, "nan")
    assert status_of(s.set, an_input(fmu).name, math.nan) == fmi2Error
    assert "is not finite" in s.log[-1][2]
    s.fmu.freeInstance()


def _rss_kb() -> int:
    with open("/proc/self/statm") as f:
        import os
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE") // 1024


def test_instantiate_free_cycles_do_not_leak(fmu: sim.Unpacked) -> None:
    """1000 cycles of instantiate, initialize, 5 steps, an FMU state left unfreed, an fmi2Error,
    fmi2FreeInstance on one loaded library: no crash, and the process does not grow
    (FreeInstance frees the states it handed out)."""
    s = sim.Slave(fmu, "cycles")
    f = s.fmu

    def cycle() -> None:
        f.fmi2FreeInstance(f.component)
        f.instantiate(callbacks=s._callbacks, loggingOn=False)
        f.setupExperiment(startTime=0.0)
        f.enterInitializationMode()
        f.exitInitializationMode()
        for k in range(5):
            f.doStep(k * H, H)
        f.getFMUstate()
        assert status_of(f.doStep, 1.0, H) == fmi2Error
    for _ in range(100):
        cycle()
    before = _rss_kb()
    for _ in range(1000):
        cycle()
    grown = _rss_kb() - before
    f.freeInstance()
    assert grown < 1024, f"resident set grew by {grown} kB over 1000 cycles"


def test_resources_in_a_folder_with_spaces_percent_and_unicode(cnc: sim.Unpacked, tmp_path: pathlib.Path) -> None:
    """fmpy passes fmuResourceLocation as pathlib's as_uri(): percent-encoded spaces, '%', '#' and
    UTF-8. CncMotion finds its default programFile there (the resources folder decoded exactly once)
    and runs the shipped program's first move."""
    import shutil
    from fmpy.fmi2 import FMU2Slave
    where = tmp_path / "50% done" / "Überlauf #2"
    shutil.copytree(cnc.dir, where)
    uri = (where / "resources").as_uri()
    assert "%25" in uri and "%20" in uri and "%C3%9C" in uri and "%23" in uri, uri
    f = FMU2Slave(guid=cnc.md.guid, unzipDirectory=str(where), modelIdentifier=cnc.md.coSimulation.modelIdentifier,
                  instanceName="percent")
    f.instantiate()
    try:
        f.setupExperiment(startTime=0.0)
        f.enterInitializationMode()
        f.exitInitializationMode()
        feed = cnc.vars["path.feed"].valueReference
        for k in range(300):
            f.doStep(k * H, H)
        assert f.getReal([feed])[0] > 0, "the default program moves"
        f.terminate()
    finally:
        f.freeInstance()
