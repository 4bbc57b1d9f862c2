#!/usr/bin/env bash
# STEP import: Talas (criterion, benches/kernel.rs) against Open CASCADE (cadquery-ocp-novtk),
# measured back to back on the same machine. Prints both medians and their ratio.
#   bash benches/compare_import.sh [FILE.stp]
set -euo pipefail
cd "$(dirname "$0")/.."
file=${1:-tests/data/pocket-fillets.stp}
[ -x .venv/bin/python ] || { python3 -m venv .venv && .venv/bin/pip install -q cadquery-ocp-novtk; }
occt=$(.venv/bin/python benches/occt_import.py "$file" 20)
echo "$occt"
TALAS_BENCH_STEP="$file" cargo bench --no-default-features --bench kernel -- --warm-up-time 1 --measurement-time 3 step_import 2>/dev/null \
  | tee /tmp/talas_bench.txt | grep -A1 "^step_import" | grep -E "step_import|time:"
talas_ms=$(grep -A1 "read_step$" /tmp/talas_bench.txt | awk '/time:/ {v=$5; u=$6; if (u ~ /µs/) v=v/1000; print v}')
occt_ms=$(echo "$occt" | awk '/read_step median/ {print $4}')
echo "ratio OCCT/Talas (read_step): $(python3 -c "print(round($occt_ms/$talas_ms, 1))")x"
