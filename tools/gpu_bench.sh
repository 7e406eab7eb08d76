#!/usr/bin/env bash
# The GPU run of issue 19 item 5, as one prepared script for the lent NVIDIA machine (docs/benchmarks.md
# "On an NVIDIA GPU"). Here: tools/gpu_prepare.sh; then, through the device tool, from the repo root
# with .gpu and .gl carried: bash tools/gpu_bench.sh. Writes into $OUT (at most 8 files): summary.txt
# (everything printed), frame.json (Google Benchmark), render-tests.txt, and the demo's 1080p frames.
# Each step has its own time limit, so that a slow one leaves the rest their turn. Environment:
# GPU_BENCH_FILTER (the frame benchmarks to run), GPU_TEST_SECONDS (the render tests' time),
# GPU_TEST_SUITES (a regex of the test suites to run; all by default), GPU_ANIMATE=1 (nephele
# animate's throughput with one and four writer threads).
set -u
out=${OUT:-/tmp/nephele-gpu-out}
mkdir -p "$out"
exec > >(tee -a "$out/summary.txt") 2>&1
t0=$(date +%s)
step() { echo; echo "== [$(($(date +%s) - t0)) s] $*"; }
TIMEFORMAT='   time: wall %R s, user %U s, sys %S s'

step "GL dispatch and driver"
if [ -n "${OUT:-}" ]; then  # on the device machine only: glvnd from Debian's packages (device README)
  for f in .gl/*.deb; do dpkg -x "$f" /; done
  ldconfig
fi
vendor=/usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json
[ -f "$vendor" ] && export __EGL_VENDOR_LIBRARY_FILENAMES=$vendor
nvidia-smi --query-gpu=name,driver_version,memory.total,clocks.max.sm,clocks.max.mem --format=csv
nproc
work=/tmp/nephele-gpu
rm -rf "$work" && mkdir -p "$work"
tar -C "$work" -xJf .gpu/gb.tar.xz
b=$work/gb
export LD_LIBRARY_PATH=$b/lib NEPHELE_GL=egl NEPHELE_OCIO_CONFIG=$b/ocio/config.ocio NEPHELE_LOG=info
export PROJ_DATA=$b/proj PROJ_LIB=$b/proj NEPHELE_NC_PROBE=$b/bin/nephele-nc-probe
[ -e /work/main ] || { mkdir -p /work && ln -s "$PWD" /work/main; }  # the tests' NEPHELE_SOURCE_DIR
"$b/bin/nephele" --version

step "the demo storm (make demo's: 500 x 500 x 60, 3 km)"
time timeout 150 "$b/bin/nephele-gen" wrf --case hurricane-cells --size realistic --times 1 -o "$work/w.nc"
time timeout 90 "$b/bin/nephele" convert "$work/w.nc" -o "$work/storm.nph"
rm -f "$work/w.nc"
for view in demo demo-golden-hour; do
  sed -e "s|@DATA@|$work/storm.nph|; s|@OUT@|$work|g" \
      -e "s|/usr/share/marble/data/maps/earth/bluemarble/bluemarble.jpg|$PWD/.gpu/bluemarble.jpg|" \
      -e 's|"width": [0-9]*, "height": [0-9]*|"width": 1920, "height": 1080|' \
      "examples/scenes/$view.json.in" > "$work/$view.json"
done
for run in 1 2 3; do
  step "nephele render demo.json, 1920 x 1080, run $run"
  time timeout 60 "$b/bin/nephele" render "$work/demo.json"
done
step "nephele render demo-golden-hour.json, 1920 x 1080"
time timeout 300 "$b/bin/nephele" render "$work/demo-golden-hour.json"  # the radiance volume: 10⁶ photons
cp "$work/hurricane.png" "$out/hurricane-nvidia.png" 2>/dev/null
cp "$work/hurricane-golden-hour.png" "$out/hurricane-golden-hour-nvidia.png" 2>/dev/null

if [ "${GPU_ANIMATE:-0}" = 1 ]; then  # nephele animate's throughput: 25 camera-only 1080p frames, PNG + EXR
  sed -e 's|"view": "flat"|"view": "flat", "animation": { "from": 0, "to": 0, "fps": 24, "duration_s": 1.0, "camera_keyframes": [ { "at_s": 0, "preset": "overview", "fov_deg": 40, "distance_scale": 0.5 }, { "at_s": 1.0, "preset": "overview", "fov_deg": 40, "distance_scale": 0.45, "azimuth_deg": 190 } ] }|' \
    "$work/demo.json" > "$work/anim.json"
  for threads in 1 4 1 4; do
    step "nephele animate, 25 frames 1920 x 1080, PNG + EXR, --write-threads $threads"
    rm -rf "$work/seq"
    time NEPHELE_LOG=debug timeout 120 "$b/bin/nephele" animate "$work/anim.json" -o "$work/seq" --format png,exr \
      --write-threads "$threads" --no-progress > "$work/anim.txt" 2>&1
    grep -E "^animate: [0-9]" "$work/anim.txt"
    awk '/files written in/ { w += $(NF-1); n++ } / s \(load / { for (i = 1; i <= NF; i++) if ($i == "s" && $(i+1) == "(load") r += $(i-1) }
         END { printf "   frames %d: render (to the hand-over) %.2f s in all, files written %.2f s in all\n", n, r, w / 1000 }' "$work/anim.txt"
  done
fi

step "frame benchmark (old/new variants interleaved; the demo at 1920 x 1080 too)"
time NEPHELE_BENCH_WIDTH=1920 NEPHELE_LOG=warn timeout 200 "$b/bin/nephele_frame_benchmarks" \
  --benchmark_filter="${GPU_BENCH_FILTER:-BM_FrameVariants|BM_EyePassDefaults|BM_DlmPruning|BM_DetailCost/scene:0/width:1920|BM_MultipleScatteringCost/scene:0/width:1920}" \
  --benchmark_out="$out/frame.json" --benchmark_out_format=json

step "fetch kernel (the machine's trilinear fetch rate)"
time NEPHELE_LOG=warn timeout 45 "$b/bin/nephele_gl_benchmarks" --benchmark_min_time=0.2

step "render tests on the NVIDIA EGL device (GPU against the CPU twin, goldens), one process per suite"
deadline=$(($(date +%s) + ${GPU_TEST_SECONDS:-150}))
for suite in $("$b/bin/nephele_render_tests" --gtest_list_tests 2>/dev/null | grep -E '^[A-Za-z].*\.$' |
               grep -E "${GPU_TEST_SUITES:-.}"); do
  left=$((deadline - $(date +%s)))
  [ "$left" -gt 5 ] || { echo "   $suite: not run (time)"; continue; }
  NEPHELE_LOG=error timeout "$left" "$b/bin/nephele_render_tests" --gtest_filter="$suite*" > "$work/suite.txt" 2>&1
  rc=$?
  cat "$work/suite.txt" >> "$out/render-tests.txt"
  echo "   $suite rc=$rc: $(grep -cE '^\[       OK \]' "$work/suite.txt") passed, $(grep -E '^\[  FAILED  \].*ms\)' "$work/suite.txt" | sed 's/\[  FAILED  \] //; s/ (.*//' | tr '\n' ' ')$([ $rc -gt 1 ] && echo "; crashed in: $(grep -E '^\[ RUN      \]' "$work/suite.txt" | tail -1)")"
done
step "done"
