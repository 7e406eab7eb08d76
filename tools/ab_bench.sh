#!/usr/bin/env bash
# One benchmark from two builds, run alternately with the order rotated each round (the machines
# are noisy: compare medians of the rounds, and ratios inside one run where the benchmark prints
# them). For changes that cannot be switched at run time — a shader edit embedded at build time —
# build A, copy its binary, build B.
# Usage: tools/ab_bench.sh BUILD_A BUILD_B FILTER [ROUNDS] [BINARY]
#   BUILD_A/B  build directories (or copies holding tests/bench/<BINARY>)
#   FILTER     --benchmark_filter, e.g. 'BM_DetailCost/scene:1'
#   ROUNDS     3 by default; BINARY nephele_frame_benchmarks by default
# Example (docs/detail.md "Level of detail"):
#   tools/ab_bench.sh /tmp/lod/build-before /tmp/lod/build-after 'BM_DetailCost/scene:1' 3
set -euo pipefail
[ $# -ge 3 ] || { sed -n '2,12p' "$0"; exit 2; }
a=$1 b=$2 filter=$3 rounds=${4:-3} binary=${5:-nephele_frame_benchmarks}
export NEPHELE_GL=${NEPHELE_GL:-egl} NEPHELE_LOG=${NEPHELE_LOG:-warn}
for build in "$a" "$b"; do
  [ -x "$build/tests/bench/$binary" ] || { echo "ab_bench: no $build/tests/bench/$binary" >&2; exit 1; }
done
for r in $(seq 1 "$rounds"); do
  if [ $((r % 2)) = 1 ]; then order=("A:$a" "B:$b"); else order=("B:$b" "A:$a"); fi
  for entry in "${order[@]}"; do
    echo "=== round $r ${entry%%:*} (${entry#*:})"
    "${entry#*:}/tests/bench/$binary" --benchmark_filter="$filter" 2>&1 | grep -vE '^-+$|^Run|^\*\*\*|^$' || true
  done
done
