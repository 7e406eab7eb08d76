#!/usr/bin/env bash
# End to end `nephele render` of one scene, old binary against new (issue 19, "Done means": the demo
# at 1080p ≥ 4× faster; docs/benchmarks.md "End to end"). Each variant renders the scene with
# output.paths replaced by one PNG and output.width/height by the size given, interleaved with the
# order rotated per round; wall and CPU (user + system, llvmpipe's threads included) seconds,
# page faults and peak RSS from GNU time, medians over the rounds and ratios against the first
# variant (> 1: faster than it); then the 8-bit PNG difference of the last round's images
# (oiiotool --diff) against the first variant's.
# Usage: tools/render_speed.sh OUT_DIR ROUNDS SCENE_JSON WIDTHxHEIGHT LABEL=BUILD_DIR[+KNOB=VALUE...][@ENV=VALUE...] [...]
#   e.g. tools/render_speed.sh /tmp/rs 3 out/demo.json 1920x1080 old=/tmp/old-build new=build
#        tools/render_speed.sh /tmp/rs 3 out/demo.json 1920x1080 full=build half=build+cloud_resolution=2
#        tools/render_speed.sh /tmp/rs 3 out/demo.json 1280x720 off=build@NEPHELE_CACHE_DIR=off \
#          warm=build@NEPHELE_CACHE_DIR=/tmp/rs/cache
# (BUILD_DIR/src/cli/nephele is run; each +KNOB=VALUE is set in the scene's quality.overrides, each
# @ENV=VALUE in the environment of that variant's runs.)
set -euo pipefail
out=$1
rounds=$2
scene=$3
size=$4
shift 4
variants=("$@")
mkdir -p "$out"
runs="$out/runs.tsv"
printf 'variant\tround\twall_s\tcpu_s\tminor_faults\tmax_rss_kb\n' > "$runs"
for v in "${variants[@]}"; do
  label=${v%%=*}
  rest=${v#*=}
  rest=${rest%%@*}
  overrides=""
  [[ $rest == *+* ]] && overrides=${rest#*+}
  python3 - "$scene" "$out/$label.png" "$size" "$overrides" > "$out/$label.json" <<'PY'
import json, re, sys
t = re.sub(r"^\s*//.*$", "", open(sys.argv[1]).read(), flags=re.M)
s = json.loads(t)
w, h = (int(x) for x in sys.argv[3].split("x"))
s["output"]["paths"] = [sys.argv[2]]
s["output"]["width"], s["output"]["height"] = w, h
for kv in filter(None, sys.argv[4].split("+")):
    k, v = kv.split("=", 1)
    s.setdefault("quality", {}).setdefault("overrides", {})[k] = json.loads(v)
print(json.dumps(s))
PY
done
for ((r = 0; r < rounds; ++r)); do
  for ((i = 0; i < ${#variants[@]}; ++i)); do
    v=${variants[$(((i + r) % ${#variants[@]}))]}
    label=${v%%=*}
    build=${v#*=}
    envs=()
    [[ $build == *@* ]] && IFS=@ read -r -a envs <<< "${build#*@}"
    build=${build%%@*}
    build=${build%%+*}
    /usr/bin/time -f '%e %U %S %R %M' -o "$out/time.txt" env "${envs[@]}" "$build/src/cli/nephele" render "$out/$label.json" \
      > "$out/$label.log" 2>&1
    read -r wall user sys faults rss < "$out/time.txt"
    printf '%s\t%d\t%s\t%s\t%s\t%s\n' "$label" "$r" "$wall" "$(echo "$user + $sys" | bc -l)" "$faults" "$rss" >> "$runs"
  done
done
python3 - "$runs" <<'PY'
import csv, statistics, sys
rows = list(csv.DictReader(open(sys.argv[1]), delimiter="\t"))
labels = list(dict.fromkeys(r["variant"] for r in rows))
med = {l: {k: statistics.median(float(r[k]) for r in rows if r["variant"] == l)
           for k in ("wall_s", "cpu_s", "minor_faults", "max_rss_kb")} for l in labels}
first = labels[0]
print(f"{'variant':<10} {'wall s':>8} {'CPU s':>8} {first + '/wall':>10} {first + '/CPU':>10} {'faults':>10} {'peak MB':>8}"
      f"  (medians of {len(rows) // len(labels)})")
for l in labels:
    m = med[l]
    print(f"{l:<10} {m['wall_s']:8.2f} {m['cpu_s']:8.2f} {med[first]['wall_s'] / m['wall_s']:10.2f} "
          f"{med[first]['cpu_s'] / m['cpu_s']:10.2f} {m['minor_faults']:10.0f} {m['max_rss_kb'] * 1.024 / 1000:8.0f}")
PY
first=${variants[0]%%=*}
for v in "${variants[@]:1}"; do
  label=${v%%=*}
  echo "$label vs $first (8-bit PNG levels, oiiotool --diff):"
  oiiotool "$out/$first.png" "$out/$label.png" --diff 2>&1 | grep -E 'Mean error|Max error' || true
done
