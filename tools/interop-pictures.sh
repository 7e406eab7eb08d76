#!/usr/bin/env bash
# docs/interop.md pictures: the generated hurricane exported with `nephele export-vdb`, rendered
# by Blender (Cycles, CPU) and by nephele from the same camera and sun, side by side.
# usage: tools/interop-pictures.sh [build-dir]   (NEPHELE_INTEROP_SIZE=tiny|realistic, default
# realistic; needs tools/debian-packages-blender.txt). Writes out/interop/.
set -euo pipefail
build=${1:-build}
root=$(cd "$(dirname "$0")/.." && pwd)
out=$root/out/interop
size=${NEPHELE_INTEROP_SIZE:-realistic}
samples=${NEPHELE_INTEROP_SAMPLES:-64}  # ~3.5 min for Blender on 2 busy cores
mkdir -p "$out"
nephele=$build/src/cli/nephele
if [ ! -f "$out/storm-$size.nph" ]; then
  "$build/data_tools/nephele-gen" wrf --size "$size" --times 1 -o "$out/storm-$size.nc"
  "$nephele" convert "$out/storm-$size.nc" -o "$out/storm-$size.nph" --no-progress
  rm -f "$out/storm-$size.nc"
fi
"$nephele" export-vdb "$out/storm-$size.nph" -o "$out/vdb/storm-$size" --stats | tee "$out/export-stats.txt"
vdb=$out/vdb/storm-${size}_0000.vdb
exaggeration=10 sun_az=200 sun_el=35
# One camera for both: oblique from the south-south-west (azimuth 200°, 28° up) at the centre of
# the footprint, in nephele's world frame (origin at the outer corner of cell (0, 0)) and in the
# VDB's projected frame (+ x0 − dx/2, y0 − dy/2); heights × the exaggeration in both.
read -r nephele_cam blender_cam < <(/usr/bin/python3 - "$vdb" "$exaggeration" <<'PY'
import math, sys, pyopenvdb
g = pyopenvdb.read(sys.argv[1], "density")
m, ex = g.metadata, float(sys.argv[2])
w, h = m["nephele_nx"] * m["nephele_dx_m"], m["nephele_ny"] * m["nephele_dy_m"]
target = (0.5 * w, 0.45 * h, 4000.0 * ex)
az, el, dist = math.radians(200.0), math.radians(28.0), 1.25 * max(w, h)
pos = (target[0] + dist * math.sin(az) * math.cos(el), target[1] + dist * math.cos(az) * math.cos(el),
       target[2] + dist * math.sin(el))
off = (m["nephele_x0_m"] - 0.5 * m["nephele_dx_m"], m["nephele_y0_m"] - 0.5 * m["nephele_dy_m"], 0.0)
n = ",".join(f"{v:.1f}" for v in pos + target)
b = ",".join(f"{p + o:.1f}" for p, o in zip(pos + target, off + off)) + ",40"
print(n, b)
PY
)
IFS=, read -r px py pz tx ty tz <<<"$nephele_cam"
cat >"$out/scene.json" <<JSON
{
  "description": "docs/interop.md: nephele's view of the storm Blender renders from the VDB export",
  "data": { "path": "storm-$size.nph", "timestep": 0 },
  "camera": { "position_m": [$px, $py, $pz], "target_m": [$tx, $ty, $tz], "fov_deg": 40 },
  "sun": { "azimuth_deg": $sun_az, "elevation_deg": $sun_el },
  "quality": "broadcast",
  "output": { "paths": ["nephele.png"], "width": 480, "height": 270 },
  "height_exaggeration": $exaggeration
}
JSON
"$nephele" render "$out/scene.json"
start=$(date +%s)
blender -b --factory-startup --python "$root/tests/interop/blender_vdb.py" -- beauty "$vdb" \
  "$out/blender" --size 480x270 --samples "$samples" --camera "$blender_cam" \
  --sun "$sun_az,$sun_el" --z-scale "$exaggeration" >"$out/blender.log" 2>&1 ||
  { tail -30 "$out/blender.log"; exit 1; }
echo "interop: Blender beauty render 480x270, $samples samples: $(( $(date +%s) - start )) s"
ffmpeg -loglevel error -y -i "$out/blender.png" -i "$out/nephele.png" -filter_complex hstack \
  "$out/interop-blender-nephele.png"
echo "interop: wrote $out/nephele.png, $out/blender.png and side by side $out/interop-blender-nephele.png"
echo "(docs/images/interop-blender-nephele.png is the latter)"
