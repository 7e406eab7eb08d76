#!/usr/bin/env bash
# Frame-to-frame coherence of the sub-grid detail across interpolated timesteps (issue 13 "Done
# means: Coherence"; docs/detail.md "Coherence across timesteps"). Renders one animation of the
# coarse storm (`nephele-gen wrf --case storm`, 72 × 64 × 30 at 10 km, its cells moving with the
# wind) through TIMES hourly timesteps, FPS frames per timestep interval, for each timestep blend
# of INTERPOLATIONS (linear: the cross-fade; motion: motion-compensated, engine/dataset.h TimeBlend;
# the labels of the non-linear ones end in -<interpolation>), at the demo's oblique view (heights
# × 8, sun 140°/35°), WIDTH × HEIGHT, for
#   none            the data-true field,
#   <level>-fixed   detail subtle/full with the noise fixed in world space (the file without U, V:
#                   nccopy -V drops them, so the noise has no wind to follow; TKE, W, CLDFRA stay),
#   <level>-advected detail subtle/full with the noise advected by the model's U, V (volume/detail.h
#                   DetailFlow),
# and prints, per pair of consecutive frames, the mean absolute difference of the cloud layer's
# luminance and alpha in 8-bit levels (tools/frame_diff.py). Then renders frame 0 a second time per
# detailed variant and checks that it is byte-identical (a still scene renders identically).
# Usage: tools/detail_coherence.sh [BUILD_DIR [OUT_DIR]]
#   env: TIMES (3), FPS (4), WIDTH (320), HEIGHT (180), LEVELS ("subtle full"), KINDS ("fixed
#        advected"), INTERPOLATIONS ("linear"; "linear motion" for docs/animation.md), WIND (vortex:
#        the generator's U, V, which do not move the cells; steering: U, V = the cells' drift,
#        nephele-gen --steering-wind; tools/motion_blend.sh), NEPHELE_GL (egl)
set -euo pipefail
build=$(cd "${1:-build}" && pwd)
out=${2:-/tmp/detail-coherence}
times=${TIMES:-3}
fps=${FPS:-4}
width=${WIDTH:-320}
height=${HEIGHT:-180}
levels=${LEVELS:-subtle full}
kinds=${KINDS:-fixed advected}
interps=${INTERPOLATIONS:-linear}
gen_flags=()
[ "${WIND:-vortex}" = steering ] && gen_flags=(--steering-wind)
export NEPHELE_GL=${NEPHELE_GL:-egl} NEPHELE_LOG=${NEPHELE_LOG:-warn}
nephele=$build/src/cli/nephele
gen=$build/data_tools/nephele-gen
mkdir -p "$out"
storm=$out/storm.nc
calm=$out/storm-no-wind.nc
if [ ! -f "$storm" ]; then
  "$gen" wrf --case storm --times "$times" "${gen_flags[@]}" -o "$storm" > /dev/null
fi
if [ ! -f "$calm" ]; then
  vars=$(ncdump -h "$storm" | sed -n '/^variables:/,/^\/\/ global/p' |
    sed -nE 's/^\t[a-z]+ ([A-Za-z0-9_]+)\(.*/\1/p' | grep -vxE 'U|V' | paste -sd, -)
  nccopy -V "$vars" "$storm" "$calm"
fi
last=$((times - 1))
scene() {  # level data interpolation -> scene file on stdout
  cat <<EOF
{
  "data": { "path": "$2" },
  "camera": { "preset": "oblique", "fov_deg": 40 },
  "sun": { "azimuth_deg": 140, "elevation_deg": 35 },
  "quality": { "preset": "broadcast", "overrides": { "detail": "$1" } },
  "output": { "width": $width, "height": $height },
  "height_exaggeration": 8,
  "animation": { "from": 0, "to": $last, "fps": $fps, "duration_s": $last, "interpolation": "$3" }
}
EOF
}
render() {  # label level data interpolation
  local dir=$out/$1
  scene "$2" "$3" "$4" > "$out/$1.json"
  local t0=$SECONDS
  "$nephele" animate "$out/$1.json" -o "$dir" --format png --layer --no-progress > "$out/$1.log" 2>&1
  echo "$1: $(ls "$dir"/layer_*.png | wc -l) frames in $((SECONDS - t0)) s" >&2
}
labels=()
detailed=()
for interp in $interps; do
  suffix=$([ "$interp" = linear ] || echo "-$interp")
  render "none$suffix" none "$storm" "$interp"
  labels+=("none$suffix=$out/none$suffix")
  for level in $levels; do
    for kind in $kinds; do
      data=$([ "$kind" = fixed ] && echo "$calm" || echo "$storm")
      render "$level-$kind$suffix" "$level" "$data" "$interp"
      labels+=("$level-$kind$suffix=$out/$level-$kind$suffix")
      detailed+=("$level-$kind$suffix")
    done
  done
done
echo "# $times timesteps, $fps frames per timestep interval, $width x $height, coarse storm, blends: $interps"
python3 "$(dirname "$0")/frame_diff.py" "${labels[@]}"
# A still scene: frame 0 again, byte for byte.
for label in "${detailed[@]}"; do
  rm -rf "$out/$label-again"
  "$nephele" animate "$out/$label.json" -o "$out/$label-again" --format png --layer --frames 0:0 --no-progress \
    > /dev/null 2>&1
  if cmp -s "$out/$label/layer_000000.png" "$out/$label-again/layer_000000.png"; then
    echo "$label: frame 0 rendered twice: byte-identical"
  else
    echo "$label: frame 0 rendered twice: DIFFERS" && exit 1
  fi
done
