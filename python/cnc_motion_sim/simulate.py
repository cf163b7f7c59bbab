"""Simulate a G-code program on a machine with CncMotion.fmu and get the outputs as numpy arrays:

    import cnc_motion_sim as cms
    res = cms.simulate("part.ngc", machine_file="machine.toml")
    print(res.finished_at, res["x.command.position"][-1])

Values are the FMU's: SI units (m, m/s, s), sampled at every communication point (`res["time"]`).
"""
from __future__ import annotations

import pathlib
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .fmu import Unpacked, cnc_outputs, run_cnc
from .paths import CNC_FMU, PathLike, fmu_file

# The FMU parameter that takes a machine file (the CLI's TOML): tools, offsets, limits, servo.
MACHINE_FILE = "machineFile"


class Result(dict[str, NDArray[np.float64]]):
    """Output name → values over `self["time"]`; `finished_at` is the time `status.finished` was
    first true (s); `parameters` the value of every parameter in force (after initialization)."""

    def __init__(self, values: Mapping[str, NDArray[np.float64]], finished_at: float,
                 parameters: Mapping[str, Any]) -> None:
        super().__init__(values)
        self.finished_at = finished_at
        self.parameters = dict(parameters)

    @property
    def time(self) -> NDArray[np.float64]:
        return self["time"]


def simulate(program: PathLike | None = None, machine_file: PathLike | None = None, *,
             gcode: str | None = None, profile: str | None = None,
             parameters: Mapping[str, Any] | None = None, outputs: Sequence[str] | None = None,
             step: float = 1e-3, after: float = 0.0, t_max: float = 3600.0,
             fmu: PathLike | None = None) -> Result:
    """Run CncMotion.fmu until the program has finished (plus `after` seconds).

    program       G-code file (given to the FMU as `programFile`, so errors name it), or
    gcode         the program as text; neither: the FMU's default program.
    machine_file  machine file (TOML, as for `cnc-motion run --machine`), set as `machineFile`.
    profile       feed law, an item of `machine.profile` ("scurve7", "trapezoid", …).
    parameters    further start values by variable name ({"x.maxJerk": 40.0, …}), set last.
    outputs       the variables to record (default: every output).
    step          communication step (s); the interpolator ticks at its own period inside it.
    fmu           another CncMotion.fmu than the one this package ships.

    A bad program, machine file or parameter raises FmuError with the FMU's message
    (`file:line:col: what is wrong`); a program that does not finish within `t_max` simulated
    seconds raises RuntimeError."""
    if program is not None and gcode is not None:
        raise ValueError("give either `program` (a file) or `gcode` (text), not both")
    unpacked = Unpacked(fmu_file(fmu, CNC_FMU))
    try:
        start: dict[str, Any] = {}
        if machine_file is not None:
            if MACHINE_FILE not in unpacked.vars:
                raise ValueError(f"{unpacked.path}: this CncMotion.fmu has no `{MACHINE_FILE}` parameter "
                                 f"(it predates machine files in the FMU); give the machine's values as "
                                 f"`parameters` instead")
            start[MACHINE_FILE] = str(_existing(machine_file))
        if program is not None:
            start["programFile"] = str(_existing(program))
        if gcode is not None:
            start["program"] = gcode
        if profile is not None:
            start["machine.profile"] = profile
        start.update(parameters or {})
        names = list(outputs) if outputs is not None else cnc_outputs(unpacked)
        if "status.finished" not in names:
            names.append("status.finished")
        in_force: dict[str, Any] = {}
        res = run_cnc(unpacked, start, h=step, t_max=t_max, after=after, names=names, parameters_out=in_force)
    finally:
        unpacked.cleanup()
    finished_at = float(res.pop("t_finished"))
    return Result(res, finished_at, in_force)


def _existing(path: PathLike) -> pathlib.Path:
    p = pathlib.Path(path).resolve()
    if not p.is_file():
        raise FileNotFoundError(f"{path}: no such file")
    return p
