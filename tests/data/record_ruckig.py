"""Record Ruckig's minimal single-DOF durations for the scurve7 comparison test.

Run once outside the repo's environment:
    python3 -m venv /tmp/rk && /tmp/rk/bin/pip install ruckig
    /tmp/rk/bin/python tests/data/record_ruckig.py > tests/data/ruckig_scurve7.csv

Each row: kind, inputs (SI), Ruckig's duration. kind = rest: v_in = v_out = 0 (the same problem as
a scurve7 block with V_F = v_max, so durations must agree). kind = moving: v_in, v_out != 0 with
a = 0 at both ends, both <= v_max, and the length at least the fastest ramp v_in -> v_out (else
the block cannot reach v_out and is a different problem). Ruckig also allows negative speeds and
any jerk pattern, so its time is at least a lower bound for scurve7.
"""
import random

from ruckig import InputParameter, Result, Ruckig, Trajectory


def ruckig_duration(length, v_in, v_out, v_max, a_max, j_max):
    inp = InputParameter(1)
    inp.current_position = [0.0]
    inp.current_velocity = [v_in]
    inp.current_acceleration = [0.0]
    inp.target_position = [length]
    inp.target_velocity = [v_out]
    inp.target_acceleration = [0.0]
    inp.max_velocity = [v_max]
    inp.max_acceleration = [a_max]
    inp.max_jerk = [j_max]
    traj = Trajectory(1)
    result = Ruckig(1).calculate(inp, traj)
    return traj.duration if result == Result.Working else None


def ramp_distance(v1, v2, a_max, j_max):
    """Distance of the fastest change v1 -> v2 with a = 0 at both ends (seed 004)."""
    dv = abs(v2 - v1)
    t = 2.0 * (dv / j_max) ** 0.5 if dv * j_max <= a_max * a_max else dv / a_max + a_max / j_max
    return 0.5 * (v1 + v2) * t


def log_uniform(rng, lo, hi):
    return lo * (hi / lo) ** rng.random()


def main():
    rng = random.Random(4)
    print("kind,length,v_in,v_out,v_max,a_max,j_max,duration")
    rows = 0
    while rows < 45:
        kind = "rest" if rows < 30 else "moving"
        length = log_uniform(rng, 1e-5, 0.5)
        v_max = log_uniform(rng, 0.005, 1.0)
        a_max = log_uniform(rng, 0.2, 20.0)
        j_max = log_uniform(rng, 2.0, 2000.0)
        v_in = v_out = 0.0
        if kind == "moving":
            v_in = v_max * rng.random()
            v_out = v_max * rng.random()
            if ramp_distance(v_in, v_out, a_max, j_max) > length:
                continue
        d = ruckig_duration(length, v_in, v_out, v_max, a_max, j_max)
        if d is None:
            continue
        print(f"{kind},{length!r},{v_in!r},{v_out!r},{v_max!r},{a_max!r},{j_max!r},{d!r}")
        rows += 1


if __name__ == "__main__":
    main()
