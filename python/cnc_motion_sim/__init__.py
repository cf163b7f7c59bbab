"""Run the cnc-motion FMUs from Python.

    import cnc_motion_sim as cms
    res = cms.simulate("part.ngc", machine_file="machine.toml")   # numpy arrays by output name
    print(res.finished_at, res["x.command.position"][-1])

`simulate` runs CncMotion.fmu alone (core dependencies: fmpy, numpy). Beside it: a named-variable
wrapper around fmpy's FMU2Slave (`fmu`), the SSP of the two-FMU system (`ssp`), co-simulation
masters (`cosim`; libcosim and Ecos with the `cosim` extra) and a Dask parameter sweep (`sweep`,
with the `sweep` extra). Both FMUs ship inside the package (`CNC_FMU`, `STRUCTURE_FMU`)."""
from .fmu import AXES, FmuError, Slave, Unpacked, cnc_outputs, enumeration_items, profiles, run_cnc
from .paths import CNC_FMU, STRUCTURE_FMU, default_program, fmu_file
from .simulate import Result, simulate

__all__ = ["AXES", "CNC_FMU", "FmuError", "STRUCTURE_FMU", "Result", "Slave", "Unpacked", "cnc_outputs",
           "default_program", "enumeration_items", "fmu_file", "profiles", "run_cnc", "simulate"]
