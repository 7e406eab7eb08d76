#!/usr/bin/env bash
# Where the eye pass's time goes (issue 19, docs/benchmarks.md "Where the eye pass's time goes"):
# builds `nephele` three times from this tree with glsl/render/clouds.comp cut back — `full` (as
# is), `nomarch` (the cloud march's loop never entered: the ground, sky, aerial perspective and
# passes per pixel remain) and `empty` (every invocation returns at once: the dispatch, the
# program's set-up and the read-back remain) — then renders a scene with each, with and without
# the atmosphere, interleaved, and prints the medians of the ray cast's wall time (the
# `ray cast WxH in N ms` log line) and of the process CPU time. The shader is restored and the
# build rebuilt as it was at the end (also on failure).
# Usage: tools/eye_pass_breakdown.sh OUT_DIR ROUNDS SCENE_JSON [BUILD_DIR]
#   e.g. tools/eye_pass_breakdown.sh /tmp/var 5 /tmp/demo540.json build
set -euo pipefail
out=$1
rounds=$2
scene=$3
build=${4:-build}
root=$(cd "$(dirname "$0")/.." && pwd)
shader="$root/glsl/render/clouds.comp"
mkdir -p "$out"
cp "$shader" "$out/clouds.comp.orig"
restore() {
  cp "$out/clouds.comp.orig" "$shader"
  cmake --build "$build" --target nephele > /dev/null
}
trap restore EXIT
variant() {  # name, python expression applied to the shader's text
  cp "$out/clouds.comp.orig" "$shader"
  python3 - "$shader" "$2" << 'EOF'
import sys
path, edit = sys.argv[1], sys.argv[2]
s = open(path).read()
t = eval(edit, {"s": s})
if edit != "s" and t == s:
    sys.exit("eye_pass_breakdown.sh: the edit no longer matches glsl/render/clouds.comp")
open(path, "w").write(t)
EOF
  cmake --build "$build" --target nephele > /dev/null
  mkdir -p "$out/$1"
  cp "$build/src/cli/nephele" "$out/$1/nephele"
}
variant full "s"
variant nomarch "s.replace('while (t < span.y && Tacc > u_min_transmittance) {', 'while (t < span.y && Tacc > u_min_transmittance && u_step_m < 0.0) {', 1)"
variant empty "s.replace('if (any(greaterThanEqual(px, u_size))) return;', 'if (any(greaterThanEqual(px, u_size)) || u_step_m > 0.0) return;', 1)"
python3 - "$scene" "$out" << 'EOF'
import json, re, sys
t = re.sub(r"^\s*//.*$", "", open(sys.argv[1]).read(), flags=re.M)
s = json.loads(t)
s["output"]["paths"] = [sys.argv[2] + "/frame.png"]
json.dump(s, open(sys.argv[2] + "/atm.json", "w"))
s.setdefault("style", {})["atmosphere"] = False
json.dump(s, open(sys.argv[2] + "/noatm.json", "w"))
EOF
for v in full nomarch empty; do  # warm the shader caches
  for a in atm noatm; do NEPHELE_LOG=warn "$out/$v/nephele" render "$out/$a.json" > /dev/null 2>&1; done
done
: > "$out/runs.txt"
for ((r = 0; r < rounds; ++r)); do
  for v in full nomarch empty; do
    for a in atm noatm; do
      line=$(NEPHELE_LOG=debug /usr/bin/time -f 'cpu %U %S' "$out/$v/nephele" render "$out/$a.json" 2>&1 |
        grep -oE 'ray cast [0-9]+x[0-9]+ in [0-9]+ ms|^cpu [0-9.]+ [0-9.]+$' | tr '\n' ' ')
      echo "$r $v $a $line" >> "$out/runs.txt"
    done
  done
done
python3 - "$out/runs.txt" << 'EOF'
import collections, re, statistics, sys
wall, cpu = collections.defaultdict(list), collections.defaultdict(list)
for line in open(sys.argv[1]):
    p = line.split()
    wall[(p[1], p[2])].append(int(re.search(r" in (\d+) ms", line).group(1)))
    m = re.search(r"cpu ([0-9.]+) ([0-9.]+)", line)
    cpu[(p[1], p[2])].append(float(m.group(1)) + float(m.group(2)))
print(f"{'variant':10} {'atmosphere':10} {'ray cast ms':>12} {'process CPU s':>14}  (medians of {len(wall[('full', 'atm')])})")
for k in wall:
    print(f"{k[0]:10} {k[1]:10} {statistics.median(wall[k]):12.0f} {statistics.median(cpu[k]):14.2f}")
EOF
