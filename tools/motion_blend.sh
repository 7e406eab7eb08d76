#!/usr/bin/env bash
# Motion-compensated against linear blending between timesteps (engine/dataset.h TimeBlend;
# docs/animation.md "Between two timesteps"), on the coarse storm (`nephele-gen wrf --case storm`:
# 72 × 64 × 30 at 10 km, hourly) written as one file per hour, 12, 13 and 14 UTC, so that a
# series can leave an hour out:
#  1. Against the model's own in-between state: the series (12, 14 UTC) at w = ½ — linear,
#     motion, and step (12 UTC held) — against the 13 UTC timestep itself, rendered with the same
#     camera (every run frames the series' first timestep, 12 UTC), per detail level: mean absolute
#     difference of the premultiplied cloud layer in 8-bit levels (tools/frame_diff.py --truth).
#  2. The strip: the series (12, 13, 14 UTC) at 4 frames per interval, frames 3, 4, 5 (w ¾, the
#     13 UTC timestep, w ¼) at a closer view, one row per blend and detail level, stacked with
#     ffmpeg into OUT_DIR/strip.png.
# The demo's oblique view (heights × 8, sun 140°/35°), broadcast preset. WIND=vortex (default): the
# files' U, V are the generator's vortex, which does NOT move the storm's cells (they drift at
# (−4, 3) m/s and its shield stays); WIND=steering: U, V are that drift (nephele-gen --steering-wind),
# the wind the cells move with.
# Usage: tools/motion_blend.sh [BUILD_DIR [OUT_DIR]]
#   env: WIDTH (320), HEIGHT (180) for 1; STRIP_WIDTH (480), STRIP_HEIGHT (270), DISTANCE (0.45) for
#        2; LEVELS ("none full"); WIND (vortex); NEPHELE_GL (egl)
set -euo pipefail
build=$(cd "${1:-build}" && pwd)
out=${2:-/tmp/motion-blend}
width=${WIDTH:-320}
height=${HEIGHT:-180}
strip_width=${STRIP_WIDTH:-480}
strip_height=${STRIP_HEIGHT:-270}
distance=${DISTANCE:-0.45}
levels=${LEVELS:-none full}
wind=${WIND:-vortex}
export NEPHELE_GL=${NEPHELE_GL:-egl} NEPHELE_LOG=${NEPHELE_LOG:-warn}
nephele=$build/src/cli/nephele
gen=$build/data_tools/nephele-gen
tools=$(cd "$(dirname "$0")" && pwd)
mkdir -p "$out"
case $wind in
  vortex) gen_flags=() ;;
  steering) gen_flags=(--steering-wind) ;;
  *) echo "WIND=$wind: expected vortex or steering" >&2 && exit 2 ;;
esac
for h in 0 1 2; do
  [ -f "$out/storm-$h.nc" ] ||
    "$gen" wrf --case storm --times 1 --start-hour "$h" "${gen_flags[@]}" -o "$out/storm-$h.nc" > /dev/null
done
scene() {  # level interpolation from to fps duration width height distance -> scene file on stdout
  cat <<JSON
{
  "data": { "path": "$out/storm-0.nc" },
  "camera": { "preset": "oblique", "fov_deg": 40, "distance_scale": $9 },
  "sun": { "azimuth_deg": 140, "elevation_deg": 35 },
  "quality": { "preset": "broadcast", "overrides": { "detail": "$1" } },
  "output": { "width": $7, "height": $8 },
  "height_exaggeration": 8,
  "animation": { "from": $3, "to": $4, "fps": $5, "duration_s": $6, "interpolation": "$2" }
}
JSON
}
animate() {  # label frames scene-args... -- data files...
  local label=$1 frames=$2
  shift 2
  local args=()
  while [ "$1" != -- ]; do args+=("$1") && shift; done
  shift
  scene "${args[@]}" > "$out/$label.json"
  rm -rf "$out/$label"
  "$nephele" animate "$out/$label.json" --data "$@" -o "$out/$label" --format png --layer --frames "$frames" \
    --no-progress > "$out/$label.log" 2>&1
}
echo "# 1. w = 1/2 between 12 and 14 UTC against 13 UTC, $width x $height, coarse storm, wind: $wind"
for level in $levels; do
  # frame 1 of 0 → 2 at 1 frame/s over 2 s: index 1, the 13 UTC timestep
  animate "truth-$level" 1:1 "$level" linear 0 2 1 2 "$width" "$height" 1 -- "$out"/storm-{0,1,2}.nc
  runs=()
  for interp in linear motion step; do
    # frame 1 of 0 → 1 at 2 frames/s over 1 s: index ½ of the series (12, 14 UTC)
    animate "half-$level-$interp" 1:1 "$level" "$interp" 0 1 2 1 "$width" "$height" 1 -- "$out"/storm-{0,2}.nc
    runs+=("$level, $interp=$out/half-$level-$interp/layer_000001.png")
  done
  python3 "$tools/frame_diff.py" --truth "$out/truth-$level/layer_000001.png" "${runs[@]}"
done
echo "# 2. strip: frames 3, 4, 5 (w 3/4, 13 UTC, w 1/4), $strip_width x $strip_height, distance x $distance"
rows=()
for level in $levels; do
  for interp in linear motion; do
    animate "strip-$level-$interp" 3:5 "$level" "$interp" 0 2 4 2 "$strip_width" "$strip_height" "$distance" \
      -- "$out"/storm-{0,1,2}.nc
    row=$out/row-$level-$interp.png
    ffmpeg -loglevel error -y -i "$out/strip-$level-$interp/frame_000003.png" \
      -i "$out/strip-$level-$interp/frame_000004.png" -i "$out/strip-$level-$interp/frame_000005.png" \
      -filter_complex hstack=inputs=3 "$row"
    rows+=(-i "$row")
    echo "row $((${#rows[@]} / 2)): detail $level, $interp"
  done
done
ffmpeg -loglevel error -y "${rows[@]}" -filter_complex "vstack=inputs=$((${#rows[@]} / 2))" "$out/strip.png"
echo "$out/strip.png"
