#!/usr/bin/env bash
# Lays nephele's compositing passes over another map with OpenImageIO's oiiotool, as a compositor
# (Nuke, Fusion, Resolve) would (docs/passes.md):
#
#   out = cloud + (1 − cloud.A) · (map · shadow + sky)
#
# usage: composite.sh PASSES.exr MAP.exr OUT.png
#   PASSES.exr  `nephele render scene.json -o PASSES.exr --passes` (layers cloud, shadow, sky)
#   MAP.exr     the station's own map, linear RGB, the same camera and size (here: the ground pass
#               of a second nephele render with another basemap and shadows off)
#   OUT.png     the composite, through the same ACES fitted curve and sRGB encoding as
#               `nephele render`'s PNGs (Narkowicz 2016: x = 0.6c, x(2.51x+0.03)/(x(2.43x+0.59)+0.14))
set -euo pipefail
[ $# -eq 3 ] || { sed -n '2,14p' "$0" >&2; exit 2; }
passes=$1 map=$2 out=$3
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
oiiotool "$passes" --ch cloud.R,cloud.G,cloud.B,cloud.A --chnames R,G,B,A -o "$tmp/cloud.exr"
oiiotool "$passes" --ch shadow.Y,shadow.Y,shadow.Y --chnames R,G,B -o "$tmp/shadow.exr"
oiiotool "$passes" --ch sky.R,sky.G,sky.B --chnames R,G,B -o "$tmp/sky.exr"
# the map, shadowed by the clouds, seen through the air, then the clouds over it
oiiotool "$map" --ch R,G,B "$tmp/shadow.exr" --mul "$tmp/sky.exr" --add --ch R,G,B,A=1.0 -o "$tmp/under.exr"
oiiotool "$tmp/cloud.exr" "$tmp/under.exr" --over --ch R,G,B --mulc 0.6 -o "$tmp/x.exr"
# the display transform of nephele's PNGs
oiiotool "$tmp/x.exr" --dup --mulc 2.51 --addc 0.03 --mul -o "$tmp/num.exr"
oiiotool "$tmp/x.exr" --dup --mulc 2.43 --addc 0.59 --mul --addc 0.14 -o "$tmp/den.exr"
oiiotool "$tmp/num.exr" "$tmp/den.exr" --div --clamp:min=0:max=1 --colorconvert linear sRGB -d uint8 -o "$out"
echo "wrote $out"
