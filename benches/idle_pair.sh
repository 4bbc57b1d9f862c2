#!/bin/bash
# Two builds' release bench binaries back to back on an idle machine, pinned to two cores for
# the stock simulation and to one core for the feed planner (to stand in for the 2-core
# development machine): `benches/idle_pair.sh BEFORE_DIR AFTER_DIR`, each directory holding
# the `simulation` and `feed` bench executables (copied from target/release/deps/ after
# `cargo bench --no-default-features --bench simulation --bench feed --no-run`). Run it from
# the source tree the binaries were built in (they read their parts from there).
set -u
before=$1 after=$2
lscpu | grep -E "Model name|^CPU\(s\)"
uptime
for round in 1 2; do
  for b in "$before" "$after"; do
    echo "=== $b: 5-axis workstation case, 2 cores, round $round"
    TALAS_SIM_BENCH_FIVE=ws TALAS_SIM_BENCH_MOVES=100000 taskset -c 0,1 "$b/simulation" --bench nomatch 2>&1 | grep -E "moves|digest"
  done
done
for round in 1 2 3 4; do
  for b in "$before" "$after"; do
    echo "=== $b: feed, 1 core, round $round"
    FEED_ONLY=curve taskset -c 2 "$b/feed" --bench nomatch 2>&1 | grep -E "blocks per CPU"
  done
done
for b in "$before" "$after"; do
  echo "=== $b: raster simulation, 2 cores"
  TALAS_SIM_BENCH_FIVE=0 TALAS_SIM_BENCH_MOVES=100000 taskset -c 0,1 "$b/simulation" --bench nomatch 2>&1 | grep -E "moves"
  echo "=== $b: feed digests"
  FEED_DIGEST=1 "$b/feed" --bench nomatch 2>&1 | tail -4
done
