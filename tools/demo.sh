#!/usr/bin/env bash
# make demo: generates the built-in sample hurricane (data_tools, NetCDF-C; `--case hurricane-cells`:
# eyewall towers, rainbands of convective cells, a banded outflow canopy, docs/rendering.md "The
# demo hurricane"), converts it to a .nph extinction cache and renders it over NASA Blue Marble
# (Debian marble-qt-data) to out/.
# Usage: tools/demo.sh [build-dir]. NEPHELE_DEMO_SIZE=tiny|realistic (default realistic, one
# timestep: ~1 min to generate and convert, then the render on llvmpipe).
set -euo pipefail
build=${1:-build}
root=$(cd "$(dirname "$0")/.." && pwd)
out="$root/out"
size=${NEPHELE_DEMO_SIZE:-realistic}
mkdir -p "$out"
gen="$build/data_tools/nephele-gen"
nephele="$build/src/cli/nephele"
# The cache keeps its name (examples/scenes/hurricane*.json read out/hurricane-realistic.nph); a
# stamp names the case it holds, so an out/ with the smooth storm's cache from before regenerates.
storm="$out/hurricane-$size.nph"
if [ ! -f "$storm" ] || [ "$(cat "$storm.case" 2>/dev/null)" != hurricane-cells ]; then
  echo "demo: generating the $size sample hurricane (wrfout, Lambert conformal, convective cells)"
  "$gen" wrf --case hurricane-cells --size "$size" --times 1 -o "$out/wrfout-hurricane-$size.nc"
  echo "demo: converting to ice/water extinction volumes"
  "$nephele" convert "$out/wrfout-hurricane-$size.nc" -o "$storm" --progress
  rm -f "$out/wrfout-hurricane-$size.nc"
  echo hurricane-cells > "$storm.case"
fi
# The terrain shot (issues 13/14): a 3 km convective storm over a generated mountain range, the
# model's own HGT (nephele-gen wrf --case alpine-storm: ridges and draining valleys, towers over the
# crests with anvils, cumulus over the slopes, valley fog; docs/terrain.md "A storm over the
# mountains"), and its range as a 500 m DEM in the model's projection (--dem: the same relief with
# finer ridges, read as a user DEM). Generate + convert: about 8 s on 2 cores.
alpine="$out/alpine-storm.nph"
if [ ! -f "$alpine" ] || [ ! -f "$out/alpine-dem.tif" ] || [ "$(cat "$alpine.case" 2>/dev/null)" != alpine-storm ]; then
  echo "demo: generating the storm over the mountains (wrfout at 3 km with HGT, W, TKE_PBL, CLDFRA)"
  "$gen" wrf --case alpine-storm -o "$out/wrfout-alpine-storm.nc" --dem "$out/alpine-dem.tif"
  "$nephele" convert "$out/wrfout-alpine-storm.nc" -o "$alpine" --progress
  rm -f "$out/wrfout-alpine-storm.nc"
  echo alpine-storm > "$alpine.case"
fi
sed "s|@DATA@|$alpine|; s|@OUT@|$out|g" "$root/examples/scenes/demo-terrain.json.in" > "$out/demo-terrain.json"
for view in demo demo-globe demo-golden-hour demo-dawn; do
  sed "s|@DATA@|$storm|; s|@OUT@|$out|g" "$root/examples/scenes/$view.json.in" > "$out/$view.json"
done
echo "demo: rendering the flat map view"
"$nephele" render "$out/demo.json" --layer "$out/hurricane-cloud-layer.exr"
echo "demo: rendering the globe view"
"$nephele" render "$out/demo-globe.json"
echo "demo: rendering the golden-hour oblique view (sun 5° high)"
"$nephele" render "$out/demo-golden-hour.json"
echo "demo: rendering the same view at dawn (sun 2° below the horizon, city lights)"
"$nephele" render "$out/demo-dawn.json"
echo "demo: rendering the storm over the mountains (terrain, golden hour, a tower 29 km away)"
"$nephele" render "$out/demo-terrain.json"
echo "demo: wrote $out/hurricane.png, $out/hurricane.exr, $out/hurricane-cloud-layer.exr (flat map)"
echo "demo: wrote $out/hurricane-globe.png and $out/hurricane-globe.exr (globe)"
echo "demo: wrote $out/hurricane-golden-hour.png and $out/hurricane-golden-hour.exr (golden hour)"
echo "demo: wrote $out/hurricane-dawn.png and $out/hurricane-dawn.exr (dawn)"
echo "demo: wrote $out/storm-terrain.png and $out/storm-terrain.exr (terrain)"
