"""A named-variable wrapper around fmpy's FMU2Slave, and a stand-alone run of CncMotion.fmu until
`status.finished`.

Nothing here knows value references: every variable is looked up by name in modelDescription.xml,
so the scripts follow the FMU when variables are added or renumbered.
"""
from __future__ import annotations

import ctypes
import pathlib
import shutil
import tempfile
import weakref
from collections.abc import Callable, Mapping, Sequence
from typing import Any

import numpy as np
from fmpy import extract, read_model_description
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import (
    FMU2Slave,
    fmi2CallbackAllocateMemoryTYPE,
    fmi2CallbackFreeMemoryTYPE,
    fmi2CallbackFunctions,
    fmi2CallbackLoggerTYPE,
)

from .paths import CNC_FMU

AXES = "xyz"
Values = Mapping[str, Any]

_libc = ctypes.CDLL(None)
_libc.calloc.restype = ctypes.c_void_p
_libc.calloc.argtypes = [ctypes.c_size_t, ctypes.c_size_t]
_libc.free.argtypes = [ctypes.c_void_p]


class FmuError(RuntimeError):
    """An fmi2 call returned fmi2Error or fmi2Fatal (`status`); the message is what the FMU logged
    (for a bad program `file:line:col: what is wrong`)."""

    def __init__(self, message: str, status: int) -> None:
        super().__init__(message)
        self.status = status


class Unpacked:
    """An FMU extracted once; many instances (threads too) share the directory."""

    def __init__(self, fmu_path: str | pathlib.Path) -> None:
        self.path = pathlib.Path(fmu_path)
        self.md = read_model_description(str(self.path))
        self.dir = extract(str(self.path), unzipdir=tempfile.mkdtemp(prefix=self.path.stem + "_"))
        self.vars = {v.name: v for v in self.md.modelVariables}
        # Removed when this is collected or the interpreter exits, if `cleanup` was not called
        # (a Dask worker's cache, a caller that forgets): no extracted FMU is left in the temp folder.
        self._remove = weakref.finalize(self, shutil.rmtree, self.dir, ignore_errors=True)

    def cleanup(self) -> None:
        self._remove()

    def names(self, causality: str) -> list[str]:
        return [v.name for v in self.md.modelVariables if v.causality == causality]

    def items(self, name: str) -> dict[str, int]:
        """The items of an Enumeration variable, name → integer, in declared order."""
        v = self.vars[name]
        items = v.declaredType.items if v.declaredType is not None else []
        return {it.name: int(it.value) for it in items}

    def enum_value(self, name: str, item: str) -> int:
        """The integer of an Enumeration item (`machine.profile` = "trapezoid" → its index)."""
        items = self.items(name)
        if item not in items:
            raise KeyError(f"{name}: no item {item!r} in {list(items)}")
        return items[item]


def enumeration_items(fmu_path: str | pathlib.Path, name: str) -> list[str]:
    """Item names of an Enumeration variable, read from the FMU's modelDescription.xml."""
    md = read_model_description(str(fmu_path))
    v = next(v for v in md.modelVariables if v.name == name)
    return [it.name for it in (v.declaredType.items if v.declaredType is not None else [])]


def profiles(fmu_path: str | pathlib.Path = CNC_FMU) -> list[str]:
    """The feed laws CncMotion offers: the items of its `machine.profile` Enumeration."""
    return enumeration_items(fmu_path, "machine.profile")


class Slave:
    """One FMI 2.0 CS instance of an unpacked FMU, read and written by variable name."""

    def __init__(self, unpacked: Unpacked, instance_name: str = "instance",
                 log: list[tuple[int, str, str]] | None = None) -> None:
        self.u = unpacked
        self.log = [] if log is None else log
        self.fmu = FMU2Slave(guid=unpacked.md.guid, unzipDirectory=unpacked.dir,
                             modelIdentifier=unpacked.md.coSimulation.modelIdentifier,
                             instanceName=instance_name)
        self._callbacks = self._make_callbacks()
        self.fmu.instantiate(callbacks=self._callbacks, loggingOn=True)
        self.time = 0.0
        self.steps = 0

    def _make_callbacks(self) -> Any:
        log = self.log

        def logger(env: Any, instance: Any, status: int, category: bytes, message: bytes) -> None:
            # Messages are printf formats; FMUs escape a literal '%' as '%%'. fmpy's C logger proxy is
            # not used: it keeps ONE global logger for all instances (a crash with instances in threads).
            text = message.decode(errors="replace").replace("%%", "%") if message else ""
            log.append((int(status), category.decode(errors="replace") if category else "", text))

        cb = fmi2CallbackFunctions()
        cb.logger = fmi2CallbackLoggerTYPE(logger)
        cb.allocateMemory = fmi2CallbackAllocateMemoryTYPE(_libc.calloc)
        cb.freeMemory = fmi2CallbackFreeMemoryTYPE(_libc.free)
        return cb

    # -- values by name ---------------------------------------------------------------------
    def set(self, name: str, value: Any) -> None:
        v = self.u.vars[name]
        vr = [v.valueReference]
        if v.type == "Real":
            self.fmu.setReal(vr, [float(value)])
        elif v.type == "Integer":
            self.fmu.setInteger(vr, [int(value)])
        elif v.type == "Enumeration":
            self.fmu.setInteger(vr, [self.u.enum_value(name, value) if isinstance(value, str) else int(value)])
        elif v.type == "Boolean":
            self.fmu.setBoolean(vr, [bool(value)])
        elif v.type == "String":
            self.fmu.setString(vr, [str(value)])
        else:
            raise TypeError(f"{name}: type {v.type}")

    def set_many(self, values: Values | None) -> None:
        for k, val in (values or {}).items():
            self.set(k, val)

    def get(self, name: str) -> Any:
        v = self.u.vars[name]
        vr = [v.valueReference]
        if v.type == "Real":
            return self.fmu.getReal(vr)[0]
        if v.type in ("Integer", "Enumeration"):
            return self.fmu.getInteger(vr)[0]
        if v.type == "Boolean":
            return bool(self.fmu.getBoolean(vr)[0])
        return self.fmu.getString(vr)[0]

    def parameters(self) -> dict[str, Any]:
        """Every parameter's current value (Enumerations by item name)."""
        out = {}
        for n in self.u.names("parameter"):
            value = self.get(n)
            if self.u.vars[n].type == "Enumeration":
                value = next((k for k, i in self.u.items(n).items() if i == value), value)
            out[n] = value
        return out

    def reader(self, names: Sequence[str]) -> Callable[[], list[float]]:
        """A function returning the current values of `names` (grouped by type, one call each)."""
        groups: dict[str, tuple[list[int], list[int]]] = {}
        for i, n in enumerate(names):
            v = self.u.vars[n]
            kind = "Integer" if v.type == "Enumeration" else v.type
            groups.setdefault(kind, ([], []))
            groups[kind][0].append(i)
            groups[kind][1].append(v.valueReference)
        get = {"Real": self.fmu.getReal, "Integer": self.fmu.getInteger, "Boolean": self.fmu.getBoolean}
        out = [0.0] * len(names)

        def read() -> list[float]:
            for kind, (idx, vrs) in groups.items():
                for i, val in zip(idx, get[kind](vrs)):
                    out[i] = float(val)
            return list(out)

        return read

    # -- life cycle -------------------------------------------------------------------------
    def initialize(self, parameters: Values | None = None, start_time: float = 0.0) -> None:
        """Set the parameters and initialize; a refused value or program raises FmuError."""
        try:
            self.fmu.setupExperiment(startTime=start_time)
            self.set_many(parameters)
            self.fmu.enterInitializationMode()
            self.fmu.exitInitializationMode()
        except FMICallException as e:
            self.failed = True
            errors = [text for status, _, text in self.log if status >= 3]  # fmi2Error, fmi2Fatal
            raise FmuError("; ".join(errors) or str(e), e.status) from e
        self.time = start_time
        self.steps = 0
        self.t0 = start_time

    # Time grid of the communication points: "exact" = t0 + k·h (no drift from summing h), or
    # "ns" = libcosim's integer nanoseconds, t_k = k·h_ns/1e9 and h = t_(k+1) − t_k (varies by ulps).
    grid = "exact"

    def step(self, h: float) -> None:
        if self.grid == "ns":
            h_ns = int(round(h * 1e9))
            t0, t1 = (self.steps * h_ns) / 1e9, ((self.steps + 1) * h_ns) / 1e9
            self.fmu.doStep(currentCommunicationPoint=t0, communicationStepSize=t1 - t0)
            self.steps += 1
            self.time = t1
            return
        self.fmu.doStep(currentCommunicationPoint=self.time, communicationStepSize=h)
        self.steps += 1
        self.time = self.t0 + self.steps * h

    # Set when initialization or a set failed: the instance is in the error state, where
    # fmi2Terminate is not allowed (only get, reset and free).
    failed = False

    def free(self) -> None:
        try:
            if not self.failed:
                self.fmu.terminate()
        finally:
            self.fmu.freeInstance()


def cnc_outputs(unpacked: Unpacked) -> list[str]:
    """The CncMotion outputs we record (all Real/Integer/Boolean outputs)."""
    return [v.name for v in unpacked.md.modelVariables
            if v.causality == "output" and v.type in ("Real", "Integer", "Boolean", "Enumeration")]


def run_cnc(unpacked: Unpacked, parameters: Values | None = None, h: float = 1e-3, t_max: float = 120.0,
            after: float = 0.0, inputs: Callable[[float, Slave], None] | None = None,
            names: Sequence[str] | None = None, parameters_out: dict[str, Any] | None = None,
            machine_file: str | pathlib.Path | None = None) -> dict[str, Any]:
    """Run CncMotion alone until status.finished (plus `after` seconds); returns {name: array}.

    `inputs(t, slave)` may set inputs before each step (feed hold, override). `machine_file`: the
    CLI's machine file (TOML), given to the FMU's `machineFile` as an absolute path; `parameters`
    that differ from their start values override its keys. `parameters_out` receives the value of
    every parameter after initialization (the ones in force)."""
    s = Slave(unpacked, "cnc")
    if machine_file is not None:
        parameters = {"machineFile": str(pathlib.Path(machine_file).resolve()), **(parameters or {})}
    try:
        s.initialize(parameters)
        if parameters_out is not None:
            parameters_out.update(s.parameters())
        names = names or cnc_outputs(unpacked)
        read = s.reader(names)
        i_fin = names.index("status.finished")
        rows = [[s.time] + read()]
        t_end = None
        while s.time < t_max:
            if inputs is not None:
                inputs(s.time, s)
            s.step(h)
            row = read()
            rows.append([s.time] + row)
            if t_end is None and row[i_fin]:
                t_end = s.time
            if t_end is not None and s.time >= t_end + after - 1e-12:
                break
        if t_end is None:
            raise RuntimeError(f"program not finished after {t_max} s; log: {s.log[-5:]}")
    finally:
        s.free()
    a = np.array(rows)
    res: dict[str, Any] = {"time": a[:, 0]}
    for i, n in enumerate(names):
        res[n] = a[:, i + 1]
    res["t_finished"] = t_end
    return res
