"""Run the cnc-motion FMUs from Python: a named-variable wrapper around fmpy's FMU2Slave
(`fmu`), the SSP of the two-FMU system (`ssp`), three co-simulation masters (`cosim`) and a
Dask parameter sweep (`sweep`)."""
from .fmu import AXES, Slave, Unpacked, cnc_outputs, enumeration_items, profiles, run_cnc
from .paths import CNC_FMU, DEFAULT_PROGRAM, ROOT, CORPUS, SSP, STRUCTURE_FMU

__all__ = ["AXES", "CNC_FMU", "DEFAULT_PROGRAM", "ROOT", "CORPUS", "SSP", "STRUCTURE_FMU", "Slave", "Unpacked",
           "cnc_outputs", "enumeration_items", "profiles", "run_cnc"]
