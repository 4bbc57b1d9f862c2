"""Compare Talas's 1-DoF jerk-limited durations with ruckig (PyPI `ruckig`): 2000 rest-to-rest
moves, and 2000 moves between boundary speeds v0 != v1 (zero acceleration at both ends) over a
distance between the shortest that changes v0 to v1 and the shortest that reaches the velocity
limit, so that every peak-velocity case of the planner (neither, one or both changes with a
constant-acceleration phase) is met.

Run from the repository root:
    python3 -m venv .venv && .venv/bin/pip install ruckig
    cargo build --no-default-features --example 02_feed_profile_durations
    .venv/bin/python benches/feed_ruckig.py
"""
import os
import random
import subprocess
import sys

from ruckig import InputParameter, Result, Ruckig, Trajectory

N = 2000
rng = random.Random(2026)
cases = []
for _ in range(N):
    s = 10 ** rng.uniform(-3, 3)
    v = 10 ** rng.uniform(0, 3)
    a = 10 ** rng.uniform(1, 4)
    j = 10 ** rng.uniform(2, 6)
    cases.append((s, v, a, j))

target = os.environ.get("CARGO_TARGET_DIR", "target")
exe = os.path.join(target, "debug", "examples", "02_feed_profile_durations")
text = "\n".join(",".join(repr(x) for x in c) for c in cases) + "\n"
out = subprocess.run([exe], input=text, capture_output=True, text=True, check=True).stdout.split("\n")



def change_distance(va, vb, a, j):
    """Distance of the change va -> vb at zero acceleration at both ends (closed form)."""
    dv = abs(vb - va)
    t = dv / a + a / j if dv * j >= a * a else 2.0 * (dv / j) ** 0.5
    return 0.5 * (va + vb) * t


rng2 = random.Random(2027)
moving = []
for _ in range(N):
    v = 10 ** rng2.uniform(0, 3)
    a = 10 ** rng2.uniform(1, 4)
    j = 10 ** rng2.uniform(2, 6)
    v0, v1 = v * rng2.random(), v * rng2.random()
    lo = change_distance(v0, v1, a, j)
    hi = change_distance(v0, v, a, j) + change_distance(v, v1, a, j)
    moving.append((lo + rng2.uniform(0.01, 0.99) * (hi - lo), v, a, j, v0, v1))

text = "\n".join(",".join(repr(x) for x in c) for c in moving) + "\n"
out_moving = subprocess.run([exe], input=text, capture_output=True, text=True, check=True).stdout.split("\n")


def compare(name, rows, lines):
    """Worst and mean relative difference of the durations against ruckig's."""
    worst, failures, sum_rel = 0.0, 0, 0.0
    for row, line in zip(rows, lines):
        s, v, a, j = row[:4]
        v0, v1 = row[4:] if len(row) == 6 else (0.0, 0.0)
        inp = InputParameter(1)
        inp.current_position = [0.0]
        inp.current_velocity = [v0]
        inp.target_position = [s]
        inp.target_velocity = [v1]
        inp.max_velocity = [v]
        inp.max_acceleration = [a]
        inp.max_jerk = [j]
        traj = Trajectory(1)
        res = Ruckig(1).calculate(inp, traj)
        if res not in (Result.Working, Result.Finished) or line.startswith("error"):
            failures += 1
            continue
        ours = float(line)
        rel = abs(ours - traj.duration) / traj.duration
        sum_rel += rel
        worst = max(worst, rel)
    print(f"{name}: cases {len(rows)}, failures {failures}, mean rel diff {sum_rel / len(rows):.3e}, worst rel diff {worst:.3e}")
    return worst <= 1e-3 and failures == 0


ok = compare("rest to rest", cases, out)
ok = compare("v0 -> v1", moving, out_moving) and ok
sys.exit(0 if ok else 1)
