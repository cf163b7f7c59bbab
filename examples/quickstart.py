"""Quickstart: simulate G-code with CncMotion.fmu from Python (`pip install ./python`, see README).

    python examples/quickstart.py [PROGRAM.ngc [MACHINE.toml]]

Without arguments it runs a line, a quarter circle and a line on the default machine."""
import sys

import cnc_motion_sim as cms

PROGRAM = "G21 G90 G17\nG1 X40 Y10 F3000\nG2 X60 Y30 R20\nG1 Y50\nM30\n"

args = sys.argv[1:]
res = cms.simulate(args[0], *args[1:2]) if args else cms.simulate(gcode=PROGRAM)  # arrays by output name, SI units
print(f"finished at t = {res.finished_at:.3f} s, path {res['path.distance'][-1] * 1e3:.3f} mm, "
      f"peak feed {res['path.feed'].max() * 6e4:.1f} mm/min, "
      f"end X {res['x.command.position'][-1] * 1e3:.3f} Y {res['y.command.position'][-1] * 1e3:.3f} mm")
