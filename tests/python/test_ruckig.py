"""Rest-to-rest, the 7-phase S-curve is the time-optimal jerk-limited profile: its duration must equal
Ruckig's (an independent solver, PyPI `ruckig`) to 1e-9 relative, for random blocks."""
import json
import random
import subprocess

import pytest
from ruckig import InputParameter, Result, Ruckig, Trajectory


def ruckig_duration(length: float, v_max: float, a_max: float, j_max: float) -> float:
    otg = Ruckig(1)
    inp = InputParameter(1)
    inp.current_position = [0.0]
    inp.current_velocity = [0.0]
    inp.current_acceleration = [0.0]
    inp.target_position = [length]
    inp.target_velocity = [0.0]
    inp.target_acceleration = [0.0]
    inp.max_velocity = [v_max]
    inp.max_acceleration = [a_max]
    inp.max_jerk = [j_max]
    traj = Trajectory(1)
    assert otg.calculate(inp, traj) == Result.Working
    return float(traj.duration)


def cases() -> list[tuple[float, float, float, float]]:
    rng = random.Random(20261122)
    out = []
    for _ in range(40):
        # mm, mm/s, mm/s², mm/s³ over the ranges of real machine tools, blocks from µm to metres.
        length = 10 ** rng.uniform(-3, 3)
        v_max = 10 ** rng.uniform(0, 3)
        a_max = 10 ** rng.uniform(2, 4.5)
        j_max = 10 ** rng.uniform(3, 6)
        out.append((length, v_max, a_max, j_max))
    return out


@pytest.mark.parametrize("length,v_max,a_max,j_max", cases())
def test_scurve7_rest_to_rest_equals_ruckig(cli: str, length: float, v_max: float, a_max: float, j_max: float) -> None:
    res = subprocess.run([cli, "profile", "--length", repr(length), "--v-max", repr(v_max),
                          "--a-max", repr(a_max), "--j-max", repr(j_max), "--kind", "scurve7", "--json"],
                         capture_output=True, text=True)
    assert res.returncode == 0, res.stderr
    ours = json.loads(res.stdout)["duration_s"]
    theirs = ruckig_duration(length, v_max, a_max, j_max)
    assert abs(ours - theirs) <= 1e-9 * theirs, (ours, theirs)
