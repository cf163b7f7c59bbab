#!/usr/bin/python3
"""The "display" of the LinuxCNC comparison session (tools/linuxcnc_compare/compare.py): the
`linuxcnc` launcher starts it as `[DISPLAY]DISPLAY` once the machine is up (task, io, motion,
HAL) and shuts LinuxCNC down when it exits. It uses LinuxCNC's Python modules only (`linuxcnc`,
`hal`: Debian's python3, not a venv), so it runs with /usr/bin/python3.

For each program of the job (a JSON file, the last argument): bring the machine back to rest at
the origin with every offset cleared (MDI), number the program on the sampler's program pin,
enable the sampler, run the program in AUTO, wait until the interpreter is idle, the queue empty
and the joints in position, disable the sampler. `halsampler` writes every enabled servo period
(x y z, path speed, program line, program number) to the job's samples file; the result of each
run (error, final joint positions) goes to the job's results file.
"""
from __future__ import annotations

import json
import subprocess
import sys
import time
from typing import Any

import hal  # type: ignore[import-not-found,unused-ignore]
import linuxcnc  # type: ignore[import-not-found,unused-ignore]

RESET_MDI = [
    "G92.1",
    "M61 Q0",
    "G10 L2 P1 X0 Y0 Z0 R0",
    "G54 G17 G21 G40 G49 G80 G90 G94 G64 P0.01",
    "G53 G0 X0 Y0 Z0",
]


class Session:
    def __init__(self, log: Any) -> None:
        self.stat = linuxcnc.stat()
        self.cmd = linuxcnc.command()
        self.err = linuxcnc.error_channel()
        self.log = log

    def say(self, text: str) -> None:
        self.log.write(text + "\n")
        self.log.flush()

    def errors(self) -> list[str]:
        out: list[str] = []
        while True:
            e = self.err.poll()
            if not e:
                return out
            kind, text = e
            if kind in (linuxcnc.NML_ERROR, linuxcnc.OPERATOR_ERROR):
                out.append(str(text))
            else:
                self.say(f"  message: {text}")

    def idle(self) -> bool:
        s = self.stat
        s.poll()
        return bool(s.interp_state == linuxcnc.INTERP_IDLE and s.queue == 0 and s.inpos
                    and s.exec_state == linuxcnc.EXEC_DONE)

    def wait_idle(self, timeout_s: float, started: float | None = None) -> list[str]:
        """Wait until idle; `started`: first wait (at most 2 s) for the program to leave idle."""
        t0 = time.monotonic()
        if started is not None:
            while time.monotonic() - t0 < 2.0:
                self.stat.poll()
                if self.stat.interp_state != linuxcnc.INTERP_IDLE:
                    break
                time.sleep(0.002)
        while True:
            errs = self.errors()
            if errs:
                self.cmd.abort()
                self.cmd.wait_complete()
                return errs
            if self.idle():
                return []
            if time.monotonic() - t0 > timeout_s:
                self.cmd.abort()
                self.cmd.wait_complete()
                return [f"timeout after {timeout_s:.0f} s"]
            time.sleep(0.005)

    def mode(self, m: int) -> None:
        self.stat.poll()
        if self.stat.task_mode != m:
            self.cmd.mode(m)
            self.cmd.wait_complete()

    def start(self) -> None:
        self.cmd.state(linuxcnc.STATE_ESTOP_RESET)
        self.cmd.wait_complete()
        self.cmd.state(linuxcnc.STATE_ON)
        self.cmd.wait_complete()
        self.cmd.feedrate(1.0)
        self.cmd.rapidrate(1.0)
        self.cmd.set_optional_stop(False)
        self.cmd.set_block_delete(True)

    def reset(self) -> list[str]:
        self.mode(linuxcnc.MODE_MDI)
        for line in RESET_MDI:
            self.cmd.mdi(line)
            self.cmd.wait_complete()
            errs = self.wait_idle(30.0)
            if errs:
                return errs
        return []


def main(argv: list[str]) -> int:
    job = json.loads(open(argv[-1]).read())
    with open(job["log"], "w") as log:
        ses = Session(log)
        ses.start()
        comp = hal.component("lcmp")
        comp.newpin("prog", hal.HAL_S32, hal.HAL_OUT)
        comp.newpin("enable", hal.HAL_BIT, hal.HAL_OUT)
        comp.ready()
        hal.new_sig("lcmp-prog", hal.HAL_S32)
        hal.connect("lcmp.prog", "lcmp-prog")
        hal.connect("sampler.0.pin.5", "lcmp-prog")
        hal.new_sig("lcmp-enable", hal.HAL_BIT)
        hal.connect("lcmp.enable", "lcmp-enable")
        hal.connect("sampler.0.enable", "lcmp-enable")
        time.sleep(0.05)
        sampler = subprocess.Popen(["halsampler", "-t", job["samples"]])
        results = []
        for prog in job["programs"]:
            ses.say(f"{prog['id']} {prog['name']}")
            errs = ses.reset()
            if errs:
                ses.say(f"  reset failed: {errs}")
            comp["prog"] = int(prog["id"])
            time.sleep(0.01)
            comp["enable"] = True
            t0 = time.monotonic()
            ses.mode(linuxcnc.MODE_AUTO)
            ses.cmd.program_open(prog["path"])
            ses.cmd.wait_complete()
            ses.cmd.auto(linuxcnc.AUTO_RUN, 0)
            errs = errs or ses.wait_idle(float(prog["timeout_s"]), started=t0)
            time.sleep(0.05)
            comp["enable"] = False
            wall = time.monotonic() - t0
            ses.stat.poll()
            results.append({"id": prog["id"], "name": prog["name"], "errors": errs, "wall_s": wall,
                            "final_joints_mm": list(ses.stat.joint_actual_position[:3])})
            ses.say(f"  {wall:.2f} s wall, errors {errs}")
            with open(job["results"], "w") as f:  # after each program: a partial run is read as well
                json.dump(results, f, indent=1)
            time.sleep(0.02)
        time.sleep(0.5)
        sampler.terminate()
        sampler.wait()
        ses.mode(linuxcnc.MODE_MANUAL)
        ses.cmd.state(linuxcnc.STATE_OFF)
        ses.cmd.wait_complete()
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
