#!/usr/bin/env bash
# The frei0r source plugin through Debian's ffmpeg (frei0r_src) against `nephele render` of the
# same scene: same data and timestep, camera preset, sun and quality preset, 8-bit sRGB output.
# usage: frei0r_test.sh FFMPEG NEPHELE PLUGIN_DIR IMAGE_DIFF WORKDIR (WORKDIR holds storm.nph)
#
# Tolerance: both paths cast the same rays through the same Session (same DLM, same jitter) and
# differ only in where the display transform runs — float on the GPU (composite.frag) vs on the
# CPU (scene::encodeSrgb8) — and in how 8-bit codes are rounded, so at most 1 code per channel.
# Allowed: max 2 codes, mean 0.25 codes.
set -euo pipefail
ffmpeg=$1 nephele=$2 plugin_dir=$3 diff=$4 work=$5
# A host's plugin scan must stay cheap (issue 15/17): the module links only libEGL and the C++
# runtime, and loads libnephele (and its image/NetCDF libraries) on the first instance.
needed=$(readelf -d "$plugin_dir/nephele_clouds.so" | sed -n 's/.*NEEDED.*\[\(.*\)\]/\1/p' | tr '\n' ' ')
for lib in libnephele libOpenImageIO libnetcdf libOpenColorIO libtbb libglfw; do
  case " $needed" in *" $lib"*) echo "nephele_clouds.so links $lib at load time (NEEDED: $needed)"; exit 1;; esac
done
out=$work/frei0r
rm -rf "$out" && mkdir -p "$out"
w=160 h=90
cat >"$out/scene.json" <<JSON
{
  "data": { "path": "$work/storm.nph", "timestep": 1 },
  "camera": { "preset": "oblique" },
  "sun": { "azimuth_deg": 135, "elevation_deg": 45 },
  "quality": "draft",
  "output": { "width": $w, "height": $h }
}
JSON
NEPHELE_LOG=warn "$nephele" render "$out/scene.json" -o "$out/reference.png"
# time 0.5 of 3 timesteps = index 1; sun 0.375 * 360 = 135 deg, 0.5 * 90 = 45 deg.
params="$work/storm.nph|0.5|oblique|0.375|0.5|draft|n"
FREI0R_PATH=$plugin_dir NEPHELE_LOG=warn "$ffmpeg" -nostdin -v error -y -f lavfi \
  -i "frei0r_src=size=${w}x${h}:framerate=5:filter_name=nephele_clouds:filter_params=$params" \
  -frames:v 2 "$out/frame%d.png"
for f in 1 2; do
  "$diff" "$out/frame$f.png" "$out/reference.png" 2 0.25 "frei0r.frame$f"
done
