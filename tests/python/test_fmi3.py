"""The FMI 3.0 archives beside the FMI 2.0 ones (issue 23; `make fmu` writes CncMotion-fmi3.fmu and
MachineStructure-fmi3.fmu): fmpy validates them, they ship the very binaries of the FMI 2 archives,
and through fmpy's FMI 3 and FMI 2 slaves their outputs are equal bit for bit on the default program
and on a two-way co-simulation of both models (one table, one engine). Early return stops at the
tick where the program finishes; output and directional derivatives equal the FMI 2 ones."""
from __future__ import annotations

import ctypes
import pathlib
import shutil
import zipfile

import pytest
from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave
from fmpy.fmi3 import FMU3Slave
from fmpy.validation import validate_fmu

from repo import FMU_DIR

FMUS = ["CncMotion", "MachineStructure"]
AXES = "xyz"


def fmi3_path(name: str) -> pathlib.Path:
    return FMU_DIR / f"{name}-fmi3.fmu"


@pytest.mark.parametrize("name", FMUS)
def test_fmpy_validates_the_fmi3_archive(fmus: tuple[pathlib.Path, pathlib.Path], name: str) -> None:
    problems = validate_fmu(str(fmi3_path(name)))
    assert problems == [], "\n".join(problems)
    assert read_model_description(str(fmi3_path(name))).fmiVersion == "3.0"


@pytest.mark.parametrize("name,ident", [("CncMotion", "CncMotion"), ("MachineStructure", "MachineStructure")])
def test_the_fmi3_archive_ships_the_fmi2_binaries(fmus: tuple[pathlib.Path, pathlib.Path], name: str,
                                                  ident: str) -> None:
    with zipfile.ZipFile(FMU_DIR / f"{name}.fmu") as z2, zipfile.ZipFile(fmi3_path(name)) as z3:
        for old, new in [("linux64", "x86_64-linux"), ("win64", "x86_64-windows")]:
            ext = "so" if old == "linux64" else "dll"
            assert z2.read(f"binaries/{old}/{ident}.{ext}") == z3.read(f"binaries/{new}/{ident}.{ext}")
        assert "terminalsAndIcons/terminalsAndIcons.xml" in z3.namelist()
        # aarch64-linux in the FMI 3 archive only (FMI 2.0 names no such platform): an ELF for ARM64.
        arm = z3.read(f"binaries/aarch64-linux/{ident}.so")
        assert arm[:4] == b"\x7fELF" and int.from_bytes(arm[18:20], "little") == 183  # EM_AARCH64
        assert not any("aarch64" in n for n in z2.namelist())


def test_arrays_types_and_capabilities(fmus: tuple[pathlib.Path, pathlib.Path]) -> None:
    md = read_model_description(str(fmi3_path("CncMotion")))
    cs = md.coSimulation
    assert float(cs.fixedInternalStepSize) == 0.001 and cs.mightReturnEarlyFromDoStep
    assert int(cs.maxOutputDerivativeOrder) == 3 and cs.hasEventMode  # the clock `tick`
    by_name = {v.name: v for v in md.modelVariables}
    position = by_name["command.position"]
    assert position.type == "Float64" and [int(d.start) for d in position.dimensions] == [3]
    assert by_name["machine.lookaheadBlocks"].type in ("UInt64", "Int32")
    assert by_name["status.line"].type in ("Int32", "UInt64")
    # Every FMI 2 variable is a scalar or one element of an FMI 3 array of the same type family.
    md2 = read_model_description(str(FMU_DIR / "CncMotion.fmu"))
    for v in md2.modelVariables:
        head, _, rest = v.name.partition(".")
        assert v.name in by_name or (head in AXES and rest in by_name), v.name


class Pair:
    """One model as an FMI 2 and an FMI 3 slave, stepped alike; outputs by FMI 2 name."""

    def __init__(self, name: str, tmp: pathlib.Path, early_return: bool = False) -> None:
        self.dirs = [extract(str(FMU_DIR / f"{name}.fmu"), str(tmp / f"{name}2")),
                     extract(str(fmi3_path(name)), str(tmp / f"{name}3"))]
        self.md2 = read_model_description(self.dirs[0])
        self.md3 = read_model_description(self.dirs[1])
        ident = self.md2.coSimulation.modelIdentifier
        self.s2 = FMU2Slave(guid=self.md2.guid, unzipDirectory=self.dirs[0], modelIdentifier=ident,
                            instanceName="two")
        self.s3 = FMU3Slave(guid=self.md3.guid, unzipDirectory=self.dirs[1], modelIdentifier=ident,
                            instanceName="three")
        self.s2.instantiate()
        self.s3.instantiate(earlyReturnAllowed=early_return)
        self.v2 = {v.name: v for v in self.md2.modelVariables}
        self.v3 = {v.name: v for v in self.md3.modelVariables}
        self.by_vr3 = {v.valueReference: v for v in self.md3.modelVariables}
        self.outputs = [v.name for v in self.md2.modelVariables if v.causality == "output"]

    def start(self, parameters: dict[str, float] | None = None) -> None:
        self.s2.setupExperiment(startTime=0.0)
        self.s2.enterInitializationMode()
        self.s3.enterInitializationMode(startTime=0.0)
        for name, value in (parameters or {}).items():
            self.set(name, value)
        self.s2.exitInitializationMode()
        self.s3.exitInitializationMode()

    def element(self, name: str) -> tuple[int, int, int]:
        """FMI 3 value reference, index and length of an FMI 2 variable's value."""
        if name in self.v3:
            return self.v3[name].valueReference, 0, 1
        head, _, rest = name.partition(".")
        return self.v3[rest].valueReference, AXES.index(head), 3

    def set(self, name: str, value: float) -> None:
        self.s2.setReal([self.v2[name].valueReference], [value])
        vr, k, n = self.element(name)
        values = self.s3.getFloat64([vr], nValues=n)
        values[k] = value
        self.s3.setFloat64([vr], values)

    def get(self, name: str) -> tuple[float, float]:
        v = self.v2[name]
        vr, k, n = self.element(name)
        if v.type == "Real":
            return self.s2.getReal([v.valueReference])[0], self.s3.getFloat64([vr], nValues=n)[k]
        if v.type == "Boolean":
            return float(self.s2.getBoolean([v.valueReference])[0]), float(self.s3.getBoolean([vr], nValues=n)[k])
        get3 = self.s3.getUInt64 if self.by_vr3[vr].type == "UInt64" else self.s3.getInt32
        return float(self.s2.getInteger([v.valueReference])[0]), float(get3([vr], nValues=n)[k])

    def step(self, t: float, h: float) -> None:
        self.s2.doStep(t, h)
        self.s3.doStep(t, h)

    def compare(self, t: float) -> None:
        for name in self.outputs:
            a, b = self.get(name)
            assert a == b, f"{name} at t = {t}: FMI 2 {a!r}, FMI 3 {b!r}"

    def free(self) -> None:
        for s in (self.s2, self.s3):
            s.terminate()
            s.freeInstance()


def test_default_program_outputs_equal_fmi2_bit_for_bit(fmus: tuple[pathlib.Path, pathlib.Path],
                                                         tmp_path: pathlib.Path) -> None:
    cnc = Pair("CncMotion", tmp_path)
    cnc.start()
    stop, h = float(cnc.md2.defaultExperiment.stopTime), 1e-3
    n = round(stop / h)
    for k in range(n):
        cnc.step(k * h, h)
        if k % 7 == 0 or k == n - 1:
            cnc.compare((k + 1) * h)
    assert cnc.get("status.finished") == (1.0, 1.0)
    cnc.free()


def test_co_simulation_outputs_equal_fmi2_bit_for_bit(fmus: tuple[pathlib.Path, pathlib.Path],
                                                      tmp_path: pathlib.Path) -> None:
    """Two-way Gauss-Seidel coupling at h = T (drive forces to the frame, its load forces back)."""
    cnc, frame = Pair("CncMotion", tmp_path), Pair("MachineStructure", tmp_path)
    cnc.start()
    frame.start({f"{a}.couplingMass": 20.0 for a in AXES})
    h = 1e-3
    for k in range(1500):
        for a in AXES:
            forces = cnc.get(f"{a}.driveForce")
            frame.s2.setReal([frame.v2[f"{a}.driveForce"].valueReference], [forces[0]])
            vr, i, n = frame.element(f"{a}.driveForce")
            values = frame.s3.getFloat64([vr], nValues=n)
            values[i] = forces[1]
            frame.s3.setFloat64([vr], values)
        frame.step(k * h, h)
        for a in AXES:
            loads = frame.get(f"{a}.loadForce")
            cnc.s2.setReal([cnc.v2[f"{a}.loadForce"].valueReference], [loads[0]])
            vr, i, n = cnc.element(f"{a}.loadForce")
            values = cnc.s3.getFloat64([vr], nValues=n)
            values[i] = loads[1]
            cnc.s3.setFloat64([vr], values)
        cnc.step(k * h, h)
        if k % 5 == 0:
            cnc.compare((k + 1) * h)
            frame.compare((k + 1) * h)
    assert max(abs(frame.get(f"{a}.loadForce")[0]) for a in AXES) >= 0.0
    cnc.free()
    frame.free()


def test_early_return_at_the_program_end(fmus: tuple[pathlib.Path, pathlib.Path], tmp_path: pathlib.Path) -> None:
    """Steps of 100 ticks with early return allowed: the step that contains the program's end
    returns at its tick, the one FMI 2 reports status.finished first at 1 ms steps."""
    ref = Pair("CncMotion", tmp_path / "ref")
    ref.start()
    h, k = 1e-3, 0
    while ref.get("status.finished")[0] == 0.0:
        ref.step(k * h, h)
        k += 1
    finish = k * h
    ref.free()
    cnc = Pair("CncMotion", tmp_path / "early", early_return=True)
    cnc.start()
    t, H, early = 0.0, 0.1, []
    while t < finish + 2 * H:
        _, terminate, returned, last = cnc.s3.doStep(t, H)
        assert not terminate
        if returned:
            early.append(last)
            assert last < t + H
        t = last
    assert early == [pytest.approx(finish, abs=1e-9)], (early, finish)
    assert cnc.s3.getBoolean([cnc.element("status.finished")[0]])[0]
    cnc.free()


def test_derivatives_equal_the_fmi2_ones(fmus: tuple[pathlib.Path, pathlib.Path], tmp_path: pathlib.Path) -> None:
    cnc = Pair("CncMotion", tmp_path)
    cnc.start()
    for k in range(300):
        cnc.step(k * 1e-3, 1e-3)
    vr3 = cnc.v3["command.position"].valueReference
    for order in (1, 2, 3):
        d2 = cnc.s2.getRealOutputDerivatives([cnc.v2[f"{a}.command.position"].valueReference for a in AXES],
                                             [order] * 3)
        values = (ctypes.c_double * 3)()
        status = cnc.s3.fmi3GetOutputDerivatives(cnc.s3.component, (ctypes.c_uint32 * 1)(vr3), 1,
                                                 (ctypes.c_int32 * 1)(order), values, 3)
        assert status == 0 and list(values) == list(d2)
    assert list(values) == [cnc.get(f"{a}.command.jerk")[1] for a in AXES]
    cnc.free()
    frame = Pair("MachineStructure", tmp_path)
    frame.start({"x.couplingMass": 50.0})
    frame.set("x.driveForce", 800.0)
    for k in range(20):
        frame.step(k * 1e-3, 1e-3)
    unknowns = ["x.acceleration", "x.loadForce", "x.mode1.a"]
    knowns = ["x.driveForce", "x.mode1.q", "x.mode1.v"]
    for j in range(len(knowns)):
        seed = [float(i == j) for i in range(len(knowns))]
        d2 = frame.s2.getDirectionalDerivative([frame.v2[n].valueReference for n in unknowns],
                                               [frame.v2[n].valueReference for n in knowns], seed)
        # FMI 3: whole arrays; the x elements are the first of each.
        u3 = [frame.element(n)[0] for n in unknowns]
        k3 = [frame.element(n)[0] for n in knowns]
        seed3 = [0.0] * 9
        seed3[3 * j] = 1.0
        d3 = frame.s3.getDirectionalDerivative(u3, k3, seed3, nSensitivity=9)
        assert [d3[3 * i] for i in range(len(unknowns))] == list(d2)
    frame.free()


def test_an_error_leaves_the_instance_terminated(fmus: tuple[pathlib.Path, pathlib.Path],
                                                  tmp_path: pathlib.Path) -> None:
    """As the FMI 3 Reference-FMUs: a refused call answers fmi3Error and the instance goes to
    Terminated, where values can still be read, a step is refused, and fmi3Reset brings it back."""
    cnc = Pair("CncMotion", tmp_path)
    cnc.start()
    s3 = cnc.s3
    override = cnc.v3["feedOverride"].valueReference
    with pytest.raises(Exception):
        s3.setFloat64([override], [5.0])                      # outside 0 … 2
    assert s3.getFloat64([override]) == [1.0]
    with pytest.raises(Exception):
        s3.doStep(0.0, 1e-3)
    s3.reset()
    s3.enterInitializationMode(startTime=0.0)
    s3.exitInitializationMode()
    load = cnc.v3["loadForce"].valueReference
    with pytest.raises(Exception):
        s3.setFloat64([load], [1.0])                          # an array of 3 given 1 value
    s3.reset()
    s3.enterInitializationMode(startTime=0.0)
    s3.exitInitializationMode()
    s3.doStep(0.0, 1e-3)
    assert s3.getFloat64([load], nValues=3) == [0.0, 0.0, 0.0]
    cnc.free()


def test_simulate_fmu_records_the_arrays(fmus: tuple[pathlib.Path, pathlib.Path]) -> None:
    """fmpy's simulate_fmu on the FMI 3 archive: one column per array (x, y, z), equal to the FMI 2
    archive's three columns."""
    from fmpy import simulate_fmu
    r3 = simulate_fmu(str(fmi3_path("CncMotion")), stop_time=0.5, output_interval=1e-3)
    r2 = simulate_fmu(str(FMU_DIR / "CncMotion.fmu"), stop_time=0.5, output_interval=1e-3)
    assert len(r3) == len(r2) == 501
    for name in ("command.position", "driveForce", "followingError"):
        for k, a in enumerate(AXES):
            assert list(r3[name][:, k]) == list(r2[f"{a}.{name}"]), f"{a}.{name}"


def test_fmu_states_round_trip_and_belong_to_their_version(fmus: tuple[pathlib.Path, pathlib.Path],
                                                           tmp_path: pathlib.Path) -> None:
    """fmi3GetFMUState/SerializeFMUState mid-program, 100 more steps; the state deserialized and set
    again gives the same 100 steps bit for bit. A state serialized by the FMI 2 interface is refused
    (another instantiation token)."""
    cnc = Pair("CncMotion", tmp_path)
    cnc.start()
    s3, h = cnc.s3, 1e-3
    position = cnc.v3["command.position"].valueReference
    force = cnc.v3["driveForce"].valueReference
    for k in range(400):
        s3.doStep(k * h, h)
    saved = s3.serializeFMUState(s3.getFMUState())

    def run() -> list[list[float]]:
        rows = []
        for k in range(400, 500):
            s3.doStep(k * h, h)
            rows.append(s3.getFloat64([position, force], nValues=6))
        return rows

    first = run()
    state = s3.deserializeFMUState(saved)
    s3.setFMUState(state)
    s3.freeFMUState(state)
    assert run() == first
    for k in range(400):
        cnc.s2.doStep(k * h, h)
    fmi2_bytes = cnc.s2.serializeFMUstate(cnc.s2.getFMUstate())
    with pytest.raises(Exception):
        s3.deserializeFMUState(fmi2_bytes)
    # The refusal left the FMI 3 instance Terminated (no fmi3Terminate there).
    cnc.s2.terminate()
    cnc.s2.freeInstance()
    s3.freeInstance()
