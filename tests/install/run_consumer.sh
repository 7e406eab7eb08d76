#!/usr/bin/env bash
# Installs this build into a temporary prefix, then configures, builds and runs a separate
# project that does find_package(nephele). Usage: run_consumer.sh <build-dir> <source-dir>
set -euo pipefail
build=$1 src=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cmake --install "$build" --prefix "$work/prefix" > "$work/install.log"
# Only the public interface is installed (issue 17): nephele/nephele.h is the one header.
headers=$(cd "$work/prefix/include" && find . -type f | sort)
[ "$headers" = "./nephele/nephele.h" ] || { echo "installed headers other than nephele/nephele.h:"; echo "$headers"; exit 1; }
if find "$work/prefix/lib" -name '*.a' | grep -q .; then echo "static libraries installed:"; find "$work/prefix/lib" -name '*.a'; exit 1; fi
# OpenImageIO behind the image codec module (src/scene/image_codec.h): installed in <libdir>/nephele,
# and the installed nephele writes its images through that one (not the build tree's).
module=$(find "$work/prefix" -name nephele_image_codec.so -path '*/nephele/*')
[ -n "$module" ] || { echo "nephele_image_codec.so not installed under <libdir>/nephele"; exit 1; }
"$build/data_tools/nephele-gen" wrf --size tiny --times 1 -o "$work/storm.nc" > /dev/null
NEPHELE_LOG=debug "$work/prefix/bin/nephele" render "$work/storm.nc" -o "$work/storm.png" --width 32 --height 18 \
  > "$work/render.log" 2>&1 || { cat "$work/render.log"; exit 1; }
grep -q "image codec: $module" "$work/render.log" ||
  { echo "the installed nephele did not use the installed module $module:"; grep "image codec" "$work/render.log"; exit 1; }
[ -s "$work/storm.png" ] || { echo "the installed nephele wrote no image"; exit 1; }
cmake -S "$src/tests/install/consumer" -B "$work/build" -G Ninja -DCMAKE_PREFIX_PATH="$work/prefix" \
      -DCMAKE_BUILD_TYPE=Release > "$work/configure.log" || { cat "$work/configure.log"; exit 1; }
cmake --build "$work/build" > "$work/build.log" || { cat "$work/build.log"; exit 1; }
NEPHELE_LOG=warn "$work/build/consumer"
"$work/build/api_consumer"
# The plugin C API through pkg-config: C99, only the installed header and libnephele.so.0.
export PKG_CONFIG_PATH="$work/prefix/lib/pkgconfig"
cc -std=c99 -Wall -Wextra -Wpedantic -Werror "$src/tests/install/api_consumer.c" -o "$work/api_consumer" \
   $(pkg-config --cflags --libs nephele)
readelf -d "$work/api_consumer" | grep -q 'NEEDED.*libnephele.so.0' || { echo "api_consumer does not need libnephele.so.0"; exit 1; }
LD_LIBRARY_PATH="$work/prefix/lib" "$work/api_consumer"
