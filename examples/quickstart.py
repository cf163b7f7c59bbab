"""Quickstart: a short G-code program through CncMotion.fmu with fmpy (run `make fmu` first)."""
import pathlib

from fmpy import simulate_fmu

FMU = pathlib.Path(__file__).resolve().parents[1] / "target" / "fmu" / "CncMotion.fmu"
PROGRAM = "G21 G90 G17\nG1 X40 Y10 F3000\nG2 X60 Y30 R20\nG1 Y50\nM30\n"  # line, quarter circle, line

res = simulate_fmu(str(FMU), stop_time=4.0, output_interval=1e-3, start_values={"program": PROGRAM},
                   output=["x.command.position", "y.command.position", "path.feed", "path.distance",
                           "status.finished"])
done = res["time"][res["status.finished"].argmax()]  # variables are SI: m, m/s
print(f"finished at t = {done:.3f} s, path {res['path.distance'][-1] * 1e3:.3f} mm, "
      f"peak feed {res['path.feed'].max() * 6e4:.1f} mm/min, "
      f"end X {res['x.command.position'][-1] * 1e3:.3f} Y {res['y.command.position'][-1] * 1e3:.3f} mm")
