#!/usr/bin/env bash
# The GLFW host example under Xvfb: 3 frames at 320x180, the last compared with the golden image.
# usage: embed_glfw_test.sh XVFB_RUN EMBED_GLFW PLUGIN IMAGE_DIFF GOLDEN WORKDIR
#
# Tolerance: the host's scene and nephele's clouds are both rasterised/ray cast by llvmpipe,
# deterministically (no temporal jitter); differences come from another Mesa/LLVM version's
# float rounding at triangle edges and in the ray march. Allowed: max 24 codes at a few edge
# pixels, mean 0.5 codes. Regenerate with tests/api/regenerate_goldens.sh after a deliberate change.
set -euo pipefail
xvfb=$1 embed=$2 plugin=$3 diff=$4 golden=$5 work=$6
out=$work/embed-glfw
rm -rf "$out" && mkdir -p "$out"
# NEPHELE_TEST_GLFW_PRELOAD: the sanitizer build's LD_PRELOAD for the example alone, not for
# xvfb-run and Xvfb (tests/support/CMakeLists.txt, keep_libraries_mapped.c).
preload=()
[ -z "${NEPHELE_TEST_GLFW_PRELOAD:-}" ] || preload=(env "LD_PRELOAD=$NEPHELE_TEST_GLFW_PRELOAD")
# -a alone starts probing at :99 like the other Xvfb tests; under ctest -j two probes can pick the
# same number, so start ours elsewhere.
NEPHELE_LOG=warn "$xvfb" -a -n $((200 + $$ % 700)) -s "-screen 0 640x480x24 -noreset" \
  "${preload[@]}" "$embed" "$work/storm.nph" --plugin "$plugin" --size 320x180 --time 1 --frames 3 --screenshot "$out/frame.ppm"
"$diff" "$out/frame.ppm" "$golden" 24 0.5 embed_glfw
