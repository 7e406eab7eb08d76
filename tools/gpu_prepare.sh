#!/usr/bin/env bash
# Prepares .gpu/ (ignored through .git/info/exclude) for tools/gpu_bench.sh on the lent NVIDIA
# machine, which has a driver and a CUDA image but none of Debian 12's libraries: the built
# programs, stripped, with their library closure (tools/gpu_bundle.py: GDAL's and OpenImageIO's
# optional format back-ends replaced by stubs), the OCIO config, Blue Marble, and the glvnd
# packages the device README asks for. Usage: tools/gpu_prepare.sh [build-dir]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=$(cd "${1:-$root/build}" && pwd)
cd "$root"
grep -qx '/.gpu/' .git/info/exclude 2>/dev/null || echo /.gpu/ >> .git/info/exclude
grep -qx '/.gl/' .git/info/exclude 2>/dev/null || echo /.gl/ >> .git/info/exclude
stage=$(mktemp -d)
trap 'rm -rf "$stage"' EXIT
progs=(src/cli/nephele data_tools/nephele-gen tests/bench/nephele_frame_benchmarks tests/bench/nephele_gl_benchmarks
       tests/render/nephele_render_tests)
mkdir -p "$stage/gb/bin" "$stage/gb/ocio"
for p in "${progs[@]}"; do strip -o "$stage/gb/bin/$(basename "$p")" "$build/$p"; done
stubs=(libopenvdb libavcodec libavformat libavutil libswscale libheif libdcm libopencv libjxl libraw libicu libcurl
       libeccodes libX11 libodbc libarmadillo libqhull libxerces libpoppler libcfitsio libpq libkml libfyba
       libspatialite libmariadb libfreexl libogdi libgeos libdfalt libmfhdfalt libblosc)
python3 tools/gpu_bundle.py "$stage/gb" "${progs[@]/#/$build/}" "${stubs[@]/#/--stub=}"
cp "$build"/share/nephele/ocio/* "$stage/gb/ocio/"
mkdir -p "$stage/gb/proj" && cp /usr/share/proj/proj.db "$stage/gb/proj/"  # PROJ's CRS database
strip -o "$stage/gb/bin/nephele-nc-probe" "$build/src/io/nephele-nc-probe"
rm -rf .gpu && mkdir -p .gpu
tar -C "$stage" -cJf .gpu/gb.tar.xz gb
cp /usr/share/marble/data/maps/earth/bluemarble/bluemarble.jpg .gpu/
if [ ! -d .gl ] || ! ls .gl/*.deb > /dev/null 2>&1; then
  mkdir -p .gl /tmp/amd64/partial
  o='-oAPT::Architecture=amd64 -oAPT::Architectures=amd64 -oDir::State::Lists=/tmp/amd64'
  apt-get $o update -qq
  (cd .gl && apt-get $o download libvulkan1 libegl1 libglvnd0 libopengl0 libgl1 libglx0 libgles2)
fi
du -sh .gpu .gl
