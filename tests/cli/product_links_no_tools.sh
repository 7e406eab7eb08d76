#!/usr/bin/env bash
# The shipped binary must not carry the tools (issue 17): no symbol of the accuracy sweep
# (nph::accuracy), the Monte Carlo path tracer (nph::reference::...PathTracer / traceGroundTruth)
# or the sample-data generator (nph::datagen) is defined in `nephele`; all three are in
# `nephele-bench`, so the pattern is known to match what it looks for.
# usage: product_links_no_tools.sh NEPHELE NEPHELE_BENCH
set -euo pipefail
product=$1 tool=$2
pattern='nph::accuracy::|nph::datagen::|nph::reference::.*[Pp]ath[Tt]rac'
count() { nm -C --defined-only "$1" | grep -cE "$pattern" || true; }
in_product=$(count "$product")
in_tool=$(count "$tool")
echo "symbols of the tools: nephele $in_product, nephele-bench $in_tool"
[ "$in_tool" -gt 0 ] || { echo "nephele-bench has none: the pattern no longer finds the tools"; exit 1; }
[ "$in_product" -eq 0 ] || { nm -C --defined-only "$product" | grep -E "$pattern" | head; exit 1; }
