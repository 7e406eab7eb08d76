#!/usr/bin/env bash
# Runs every benchmark binary, writing JSON (Google Benchmark's format) and CSV into
# <build>/bench/. Usage: tools/bench.sh [build-dir] [extra benchmark args...]
set -euo pipefail
build=${1:-build}
shift || true
out="$build/bench"
mkdir -p "$out"
for exe in "$build"/tests/bench/nephele_*benchmarks; do
  [ -x "$exe" ] || continue
  name=$(basename "$exe")
  echo "== $name (backend: ${NEPHELE_GL:-auto})"
  "$exe" --benchmark_out="$out/$name.json" --benchmark_out_format=json \
         --benchmark_repetitions="${NEPHELE_BENCH_REPETITIONS:-3}" --benchmark_report_aggregates_only=true "$@"
  python3 "$(dirname "$0")/bench_json_to_csv.py" "$out/$name.json" > "$out/$name.csv"
  echo "   -> $out/$name.json, $out/$name.csv"
done
