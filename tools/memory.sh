#!/usr/bin/env bash
# Peak memory of `nephele render` (issue 19, docs/benchmarks.md "Memory"): the maximum resident set
# size (GNU time's "Maximum resident set size"; on llvmpipe GL texture storage is process memory)
# of each binary on each scene, the binaries interleaved with the order rotated per round, and the
# peak per million voxels of the scene's grid. Also the 8-bit PNG difference of the last round's
# images (oiiotool --diff) between the first binary and each other one, and, for binaries that log
# them (NEPHELE_LOG=debug: "memory after <phase>", core/process_memory.h), the resident and peak
# memory after each phase of the last round (where the peak is reached and what is held after).
# Usage: tools/memory.sh OUT_DIR ROUNDS SCENE_JSON[,SCENE_JSON...] BUILD_DIR [BUILD_DIR...]
# Each scene must write exactly one .png path (output.paths); it is redirected per binary and
# round into OUT_DIR. The voxel count is read from `nephele info` of the scene's data.path.
set -euo pipefail
out=$1
rounds=$2
IFS=, read -r -a scenes <<< "$3"
shift 3
builds=("$@")
mkdir -p "$out"
printf '%-24s %-28s %5s %12s %10s %10s\n' scene binary round peak_MB Mvoxels MB_per_Mvox
for scene in "${scenes[@]}"; do
  name=$(basename "$scene" .json)
  data=$(python3 -c 'import json,re,sys; t=re.sub(r"^\s*//.*$","",open(sys.argv[1]).read(),flags=re.M); print(json.loads(t)["data"]["path"])' "$scene")
  dims=$("${builds[0]}/src/cli/nephele" info "$data" 2>/dev/null | grep -m1 -oE '[0-9]+ x [0-9]+ x [0-9]+' || true)
  [ -n "$dims" ] || { echo "memory.sh: no grid size in \`nephele info $data\`" >&2; exit 1; }
  mvox=$(python3 -c 'import sys; a=[int(x) for x in sys.argv[1].split(" x ")]; print(a[0]*a[1]*a[2]/1e6)' "$dims")
  for ((r = 0; r < rounds; ++r)); do
    for ((i = 0; i < ${#builds[@]}; ++i)); do
      b=${builds[$(((i + r) % ${#builds[@]}))]}
      tag=$(echo "$b" | tr '/' '_' | sed 's/^_//')
      png="$out/$name-$tag.png"
      python3 - "$scene" "$png" > "$out/$name-$tag.json" <<'EOF'
import json, re, sys
t = re.sub(r"^\s*//.*$", "", open(sys.argv[1]).read(), flags=re.M)
s = json.loads(t)
s["output"]["paths"] = [sys.argv[2]]
print(json.dumps(s))
EOF
      NEPHELE_LOG=debug /usr/bin/time -v "$b/src/cli/nephele" render "$out/$name-$tag.json" > "$out/$name-$tag.log" 2>&1
      kb=$(grep -oP 'Maximum resident set size \(kbytes\): \K[0-9]+' "$out/$name-$tag.log")
      printf '%-24s %-28s %5d %12.1f %10.2f %10.2f\n' "$name" "$b" "$r" "$(echo "$kb*1.024/1000" | bc -l)" "$mvox" \
        "$(echo "$kb*1.024/1000/$mvox" | bc -l)"
    done
  done
  for b in "${builds[@]}"; do
    tag=$(echo "$b" | tr '/' '_' | sed 's/^_//')
    if grep -q 'memory after' "$out/$name-$tag.log"; then
      echo "$name: $b, by phase (resident / peak so far, MB):"
      grep -oP 'memory after \K.*' "$out/$name-$tag.log" | sed 's/^/  /'
    fi
  done
  first=$(echo "${builds[0]}" | tr '/' '_' | sed 's/^_//')
  for ((i = 1; i < ${#builds[@]}; ++i)); do
    tag=$(echo "${builds[$i]}" | tr '/' '_' | sed 's/^_//')
    echo "$name: ${builds[0]} vs ${builds[$i]} (8-bit PNG levels, oiiotool --diff):"
    oiiotool "$out/$name-$first.png" "$out/$name-$tag.png" --diff 2>&1 | grep -E 'Mean error|Max error' || true
  done
done
