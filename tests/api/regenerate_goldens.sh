#!/usr/bin/env bash
# Regenerates the golden image of api.embed_glfw and the README screenshot of examples/01-embed-glfw
# after a deliberate change to the example or the renderer. Look at both before committing them.
# usage: tests/api/regenerate_goldens.sh [BUILD_DIR]   (the build must have run api.data)
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
build=$(cd "${1:-$root/build}" && pwd)
work=$build/tests/api/work
embed=$build/examples/01-embed-glfw/embed_glfw
plugin=$build/src/api/libnephele.so.0
[ -f "$work/storm.nph" ] || bash "$root/tests/api/make_test_data.sh" "$build/data_tools/nephele-gen" "$build/src/cli/nephele" "$work"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
shot() {  # WxH output.png
  NEPHELE_LOG=warn xvfb-run -a -s "-screen 0 1280x720x24" "$embed" "$work/storm.nph" --plugin "$plugin" \
    --size "$1" --time 1 --frames 3 --screenshot "$tmp/shot.ppm"
  ffmpeg -nostdin -v error -y -i "$tmp/shot.ppm" "$2"
  echo "wrote $2"
}
shot 320x180 "$root/tests/api/golden/embed_glfw_320x180.png"
shot 960x540 "$root/examples/01-embed-glfw/screenshot.png"
