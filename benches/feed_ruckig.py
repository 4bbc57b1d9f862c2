"""Compare Talas's rest-to-rest 1-DoF jerk-limited durations with ruckig (PyPI `ruckig`).

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

worst, failures, sum_rel = 0.0, 0, 0.0
for (s, v, a, j), line in zip(cases, out):
    inp = InputParameter(1)
    inp.current_position = [0.0]
    inp.target_position = [s]
    inp.max_velocity = [v]
    inp.max_acceleration = [a]
    inp.max_jerk = [j]
    traj = Trajectory(1)
    res = Ruckig(1).calculate(inp, traj)
    if res not in (Result.Working, Result.Finished):
        failures += 1
        continue
    ours = float(line)
    rel = abs(ours - traj.duration) / traj.duration
    sum_rel += rel
    worst = max(worst, rel)
print(f"cases {N}, ruckig failures {failures}, mean rel diff {sum_rel / N:.3e}, worst rel diff {worst:.3e}")
sys.exit(0 if worst <= 1e-3 and failures == 0 else 1)
