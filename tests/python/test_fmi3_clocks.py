"""CncMotion's interpolation tick as an FMI 3 clock (issue 23), through fmpy 0.3.32: `tick` is a
periodic input clock of constant interval (the default 1 ms) with Scheduled Execution beside
Co-Simulation, and Co-Simulation has Event Mode. fmpy's FMU3ScheduledExecution activating the
tick's model partition at every tick gives every output of FMU3Slave bit for bit over the whole
default program; fmpy's simulate_fmu with use_event_mode (Event Mode at an input event of
feedHold) gives the plain Co-Simulation result. fmpy has no Scheduled Execution loop of its own
(simulate_fmu instantiates one and then has no branch for it): the loop here is the scheduler."""
from __future__ import annotations

import pathlib
import zipfile
from typing import Any
from xml.etree import ElementTree

import numpy as np
import pytest
from fmpy import extract, read_model_description, simulate_fmu
from fmpy.fmi3 import FMU3ScheduledExecution, FMU3Slave

from repo import FMU_DIR

T = 1e-3


def fmi3_path(name: str) -> pathlib.Path:
    return FMU_DIR / f"{name}-fmi3.fmu"


def test_the_tick_clock_and_the_interfaces(fmus: tuple[pathlib.Path, pathlib.Path]) -> None:
    md = read_model_description(str(fmi3_path("CncMotion")))
    tick = next(v for v in md.modelVariables if v.type == "Clock")
    assert (tick.name, tick.causality, tick.variability) == ("tick", "input", "discrete")
    assert tick.intervalVariability == "constant"
    # fmpy reads no interval or priority: the XML itself.
    with zipfile.ZipFile(fmi3_path("CncMotion")) as z:
        clock = ElementTree.fromstring(z.read("modelDescription.xml")).find("ModelVariables/Clock")
    assert clock is not None and (float(clock.get("intervalDecimal", "")), clock.get("priority")) == (T, "0")
    assert md.coSimulation.hasEventMode and md.scheduledExecution is not None
    # Outputs stay unclocked (readable in Step Mode) and list the clock among their dependencies.
    assert all(not v.clocks for v in md.modelVariables)
    assert all(tick in o.dependencies for o in md.outputs)
    frame = read_model_description(str(fmi3_path("MachineStructure")))
    assert not frame.coSimulation.hasEventMode and frame.scheduledExecution is None


class Outputs:
    """Every output of an FMI 3 instance, read by type (Float64, Int32/UInt64, Boolean)."""

    def __init__(self, md: Any) -> None:
        outs = [v for v in md.modelVariables if v.causality == "output"]
        self.groups: dict[str, tuple[list[int], int]] = {}
        for kind in ("Float64", "Int32", "UInt64", "Boolean"):
            vs = [v for v in outs if v.type == kind]
            n = sum(int(v.dimensions[0].start) if v.dimensions else 1 for v in vs)
            self.groups[kind] = ([v.valueReference for v in vs], n)
        self.finished = next(v.valueReference for v in outs if v.name == "status.finished")

    def read(self, fmu: Any) -> list[Any]:
        values: list[Any] = []
        for kind, (vrs, n) in self.groups.items():
            if vrs:
                values += list(getattr(fmu, f"get{kind}")(vrs, nValues=n))
        return values


def test_scheduled_execution_gives_the_co_simulation_outputs_bit_for_bit(
        fmus: tuple[pathlib.Path, pathlib.Path], tmp_path: pathlib.Path) -> None:
    path = fmi3_path("CncMotion")
    md = read_model_description(str(path))
    unzipped = extract(str(path), str(tmp_path / "cnc"))
    ident = md.coSimulation.modelIdentifier
    se = FMU3ScheduledExecution(guid=md.guid, unzipDirectory=unzipped, modelIdentifier=ident, instanceName="se")
    cs = FMU3Slave(guid=md.guid, unzipDirectory=unzipped, modelIdentifier=ident, instanceName="cs")
    se.instantiate()
    cs.instantiate()
    for fmu in (se, cs):
        fmu.enterInitializationMode(startTime=0.0)
        fmu.exitInitializationMode()
    tick = next(v.valueReference for v in md.modelVariables if v.name == "tick")
    outputs = Outputs(md)
    k = 0
    se.activateModelPartition(tick, 0.0)
    assert outputs.read(se) == outputs.read(cs)
    while not cs.getBoolean([outputs.finished])[0]:
        cs.doStep(k * T, T)
        k += 1
        se.activateModelPartition(tick, k * T)
        assert outputs.read(se) == outputs.read(cs), f"tick {k}"
        assert se.getFloat64([0])[0] == k * T
    assert se.getBoolean([outputs.finished])[0] and k > 1000
    for fmu in (se, cs):
        fmu.terminate()
        fmu.freeInstance()


def test_event_mode_gives_the_co_simulation_result(fmus: tuple[pathlib.Path, pathlib.Path]) -> None:
    """simulate_fmu with and without Event Mode, feedHold set at 0.5 s and released at 0.9 s: with
    Event Mode fmpy sets it in Event Mode at those instants and records the instant twice (before
    and after the event: the same values); otherwise every sample is the same."""
    hold = np.array([(0.0, False), (0.5, True), (0.9, False)], dtype=[("time", float), ("feedHold", bool)])
    path = str(fmi3_path("CncMotion"))
    plain = simulate_fmu(path, stop_time=1.5, output_interval=T, input=hold)
    events = simulate_fmu(path, stop_time=1.5, output_interval=T, input=hold, use_event_mode=True)
    repeated = np.r_[np.diff(events["time"]) == 0, False]
    assert list(events["time"][repeated]) == [0.5, 0.9]
    for name in plain.dtype.names:
        assert np.array_equal(events[name][repeated], events[name][np.roll(repeated, 1)]), name
        assert np.array_equal(plain[name], events[name][~repeated]), name
    # The hold acted: the path stops within the run and resumes.
    feed = plain["path.feed"]
    assert feed[np.searchsorted(plain["time"], 0.85)] == 0.0 and feed[-1] > 0.0


def test_machine_structure_has_no_scheduled_execution(fmus: tuple[pathlib.Path, pathlib.Path],
                                                      tmp_path: pathlib.Path) -> None:
    path = fmi3_path("MachineStructure")
    md = read_model_description(str(path))
    unzipped = extract(str(path), str(tmp_path / "frame"))
    se = FMU3ScheduledExecution(guid=md.guid, unzipDirectory=unzipped,
                                modelIdentifier=md.coSimulation.modelIdentifier, instanceName="se")
    messages: list[str] = []
    with pytest.raises(Exception, match="Failed to instantiate"):
        se.instantiate(logMessage=lambda env, status, category, message: messages.append(message.decode()))
    assert messages == ["fmi3InstantiateScheduledExecution: this FMU has no clocks: Co-Simulation only"]
