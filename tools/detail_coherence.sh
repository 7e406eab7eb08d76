#!/usr/bin/env bash
# Frame-to-frame coherence of the sub-grid detail across interpolated timesteps (issue 13 "Done
# means: Coherence"; docs/detail.md "Coherence across timesteps"). Renders one animation of the
# coarse storm (`nephele-gen wrf --case storm`, 72 × 64 × 30 at 10 km, its cells moving with the
# wind) through TIMES hourly timesteps, FPS frames per timestep interval (linear blend between
# timesteps), at the demo's oblique view (heights × 8, sun 140°/35°), WIDTH × HEIGHT, for
#   none            the data-true field,
#   <level>-fixed   detail subtle/full with the noise fixed in world space (the file without U, V:
#                   nccopy -V drops them, so the noise has no wind to follow; TKE, W, CLDFRA stay),
#   <level>-advected detail subtle/full with the noise advected by the model's U, V (volume/detail.h
#                   DetailFlow),
# and prints, per pair of consecutive frames, the mean absolute difference of the cloud layer's
# luminance and alpha in 8-bit levels (tools/frame_diff.py). Then renders frame 0 a second time per
# detailed variant and checks that it is byte-identical (a still scene renders identically).
# Usage: tools/detail_coherence.sh [BUILD_DIR [OUT_DIR]]
#   env: TIMES (3), FPS (4), WIDTH (320), HEIGHT (180), LEVELS ("subtle full"), NEPHELE_GL (egl)
set -euo pipefail
build=$(cd "${1:-build}" && pwd)
out=${2:-/tmp/detail-coherence}
times=${TIMES:-3}
fps=${FPS:-4}
width=${WIDTH:-320}
height=${HEIGHT:-180}
levels=${LEVELS:-subtle full}
export NEPHELE_GL=${NEPHELE_GL:-egl} NEPHELE_LOG=${NEPHELE_LOG:-warn}
nephele=$build/src/cli/nephele
gen=$build/data_tools/nephele-gen
mkdir -p "$out"
storm=$out/storm.nc
calm=$out/storm-no-wind.nc
if [ ! -f "$storm" ]; then
  "$gen" wrf --case storm --times "$times" -o "$storm" > /dev/null
fi
if [ ! -f "$calm" ]; then
  vars=$(ncdump -h "$storm" | sed -n '/^variables:/,/^\/\/ global/p' |
    sed -nE 's/^\t[a-z]+ ([A-Za-z0-9_]+)\(.*/\1/p' | grep -vxE 'U|V' | paste -sd, -)
  nccopy -V "$vars" "$storm" "$calm"
fi
last=$((times - 1))
scene() {  # level data -> scene file on stdout
  cat <<EOF
{
  "data": { "path": "$2" },
  "camera": { "preset": "oblique", "fov_deg": 40 },
  "sun": { "azimuth_deg": 140, "elevation_deg": 35 },
  "quality": { "preset": "broadcast", "overrides": { "detail": "$1" } },
  "output": { "width": $width, "height": $height },
  "height_exaggeration": 8,
  "animation": { "from": 0, "to": $last, "fps": $fps, "duration_s": $last, "interpolation": "linear" }
}
EOF
}
render() {  # label level data
  local dir=$out/$1
  scene "$2" "$3" > "$out/$1.json"
  local t0=$SECONDS
  "$nephele" animate "$out/$1.json" -o "$dir" --format png --layer --no-progress > "$out/$1.log" 2>&1
  echo "$1: $(ls "$dir"/layer_*.png | wc -l) frames in $((SECONDS - t0)) s" >&2
}
labels=("none=$out/none")
render none none "$storm"
for level in $levels; do
  render "$level-fixed" "$level" "$calm"
  render "$level-advected" "$level" "$storm"
  labels+=("$level-fixed=$out/$level-fixed" "$level-advected=$out/$level-advected")
done
echo "# $times timesteps, $fps frames per timestep interval, $width x $height, coarse storm"
python3 "$(dirname "$0")/frame_diff.py" "${labels[@]}"
# A still scene: frame 0 again, byte for byte.
for level in $levels; do
  for kind in fixed advected; do
    label=$level-$kind
    rm -rf "$out/$label-again"
    "$nephele" animate "$out/$label.json" -o "$out/$label-again" --format png --layer --frames 0:0 --no-progress \
      > /dev/null 2>&1
    if cmp -s "$out/$label/layer_000000.png" "$out/$label-again/layer_000000.png"; then
      echo "$label: frame 0 rendered twice: byte-identical"
    else
      echo "$label: frame 0 rendered twice: DIFFERS" && exit 1
    fi
  done
done
