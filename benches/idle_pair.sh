#!/bin/bash
# Two builds' release bench binaries back to back on an idle machine, pinned to two cores for
# the stock simulation and to one core for the feed planner (to stand in for the 2-core
# development machine): `benches/idle_pair.sh BEFORE_DIR AFTER_DIR`, each directory holding
# the `simulation` and `feed` bench executables (copied from target/release/deps/ after
# `cargo bench --no-default-features --bench simulation --bench feed --no-run`). Run it from
# the source tree the binaries were built in (they read their parts from there).
# On a machine of two cores (the development machine itself, idle) the feed planner runs on
# core 1; set SIM_CORES / FEED_CORE to choose others, SIM_ROUNDS / FEED_ROUNDS for more rounds.
set -u
before=$1 after=$2
sim_cores=${SIM_CORES:-0,1}
feed_core=${FEED_CORE:-$(($(nproc) > 2 ? 2 : 1))}
sim_rounds=${SIM_ROUNDS:-2} feed_rounds=${FEED_ROUNDS:-4}
lscpu | grep -E "Model name|^CPU\(s\)"
uptime
for round in $(seq "$sim_rounds"); do
  for b in "$before" "$after"; do
    echo "=== $b: 5-axis workstation case, 2 cores, round $round"
    TALAS_SIM_BENCH_FIVE=ws TALAS_SIM_BENCH_MOVES=100000 taskset -c "$sim_cores" "$b/simulation" --bench nomatch 2>&1 | grep -E "moves|digest"
  done
done
for round in $(seq "$feed_rounds"); do
  for b in "$before" "$after"; do
    echo "=== $b: feed, 1 core, round $round"
    FEED_ONLY=curve taskset -c "$feed_core" "$b/feed" --bench nomatch 2>&1 | grep -E "blocks per CPU"
  done
done
for b in "$before" "$after"; do
  echo "=== $b: raster simulation, 2 cores"
  TALAS_SIM_BENCH_FIVE=0 TALAS_SIM_BENCH_MOVES=100000 taskset -c "$sim_cores" "$b/simulation" --bench nomatch 2>&1 | grep -E "moves"
  echo "=== $b: feed digests"
  FEED_DIGEST=1 "$b/feed" --bench nomatch 2>&1 | tail -4
done
