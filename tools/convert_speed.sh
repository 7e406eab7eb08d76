#!/usr/bin/env bash
# `nephele convert` against a raw NetCDF read of the same variables (issue 19, docs/benchmarks.md
# "convert against a raw read"): the raw read (tests/bench/netcdf_raw_read.cpp, built as
# nephele_netcdf_raw_read, from the first variant's build that has it) and one `nephele convert` per variant,
# interleaved with the order rotated per round; wall and CPU (user + system) seconds and page faults
# from GNU time, medians over the rounds, ratios to the raw read; then `cmp` of every variant's .nph
# against the first's (the outputs must be byte-identical).
# RAW_ENV=VAR=VALUE adds a second raw read under that environment ("raw_env"), e.g. the raw read on
# huge pages too: RAW_ENV=GLIBC_TUNABLES=glibc.malloc.hugetlb=1.
# Usage: tools/convert_speed.sh OUT_DIR ROUNDS WRFOUT LABEL=BUILD_DIR[@ENV=VALUE] [...]
#   e.g. tools/convert_speed.sh /tmp/cs 3 wrfout.nc before=/tmp/old after=build \
#        tunable=/tmp/old@GLIBC_TUNABLES=glibc.malloc.hugetlb=1
set -euo pipefail
out=$1
rounds=$2
input=$3
shift 3
variants=("$@")
mkdir -p "$out"
raw=
for v in "${variants[@]}"; do  # the first variant's build that has the raw reader
  b=${v#*=}
  b=${b%%@*}
  if [ -x "$b/tests/bench/nephele_netcdf_raw_read" ]; then
    raw="$b/tests/bench/nephele_netcdf_raw_read"
    break
  fi
done
[ -n "$raw" ] || { echo "convert_speed.sh: no build has tests/bench/nephele_netcdf_raw_read" >&2; exit 1; }
runs="$out/runs.tsv"
printf 'variant\tround\twall_s\tcpu_s\tminor_faults\tmax_rss_kb\n' > "$runs"
measure() {  # label round command...
  local label=$1 round=$2
  shift 2
  /usr/bin/time -f '%e %U %S %R %M' -o "$out/time.txt" "$@" > "$out/$label.log" 2>&1
  read -r wall user sys faults rss < "$out/time.txt"
  printf '%s\t%d\t%s\t%s\t%s\t%s\n' "$label" "$round" "$wall" "$(echo "$user + $sys" | bc -l)" "$faults" "$rss" >> "$runs"
}
all=("raw" "${variants[@]}")
[ -n "${RAW_ENV:-}" ] && all=("raw" "raw_env" "${variants[@]}")
for ((r = 0; r < rounds; ++r)); do
  for ((i = 0; i < ${#all[@]}; ++i)); do
    v=${all[$(((i + r) % ${#all[@]}))]}
    if [ "$v" = raw ]; then
      measure raw "$r" "$raw" "$input"
      continue
    fi
    if [ "$v" = raw_env ]; then
      measure raw_env "$r" env "$RAW_ENV" "$raw" "$input"
      continue
    fi
    label=${v%%=*}
    spec=${v#*=}
    build=${spec%%@*}
    envs=()
    [ "$spec" != "$build" ] && envs=("${spec#*@}")
    rm -f "$out/$label.nph"
    measure "$label" "$r" env "${envs[@]}" "$build/src/cli/nephele" convert "$input" -o "$out/$label.nph" --no-progress
  done
done
python3 - "$runs" <<'EOF'
import csv, statistics, sys
rows = list(csv.DictReader(open(sys.argv[1]), delimiter="\t"))
labels = list(dict.fromkeys(r["variant"] for r in rows))
med = {l: {k: statistics.median(float(r[k]) for r in rows if r["variant"] == l)
           for k in ("wall_s", "cpu_s", "minor_faults", "max_rss_kb")} for l in labels}
print(f"{'variant':<14} {'wall s':>8} {'CPU s':>8} {'wall/raw':>9} {'CPU/raw':>8} {'faults':>10} {'peak MB':>8}  (medians of {len(rows)//len(labels)})")
for l in labels:
    m = med[l]
    print(f"{l:<14} {m['wall_s']:8.2f} {m['cpu_s']:8.2f} {m['wall_s']/med['raw']['wall_s']:9.2f} "
          f"{m['cpu_s']/med['raw']['cpu_s']:8.2f} {m['minor_faults']:10.0f} {m['max_rss_kb']*1.024/1000:8.0f}")
EOF
firstlabel=${variants[0]%%=*}
for v in "${variants[@]:1}"; do
  label=${v%%=*}
  if cmp -s "$out/$firstlabel.nph" "$out/$label.nph"; then
    echo "$label.nph: identical to $firstlabel.nph"
  else
    echo "$label.nph: DIFFERS from $firstlabel.nph"
  fi
done
