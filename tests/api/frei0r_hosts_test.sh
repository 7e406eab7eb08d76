#!/usr/bin/env bash
# The frei0r source plugin in the hosts a playout chain runs — GStreamer (gst-plugins-bad's frei0r
# elements: frei0r-src-nephele-clouds) and MLT (melt, producer frei0r.nephele_clouds) — driven by
# the host's stream clock, against `nephele render` of the same timesteps.
# usage: frei0r_hosts_test.sh HOST NEPHELE PLUGIN_DIR IMAGE_DIFF WORKDIR   (HOST: gstreamer | mlt;
#        WORKDIR holds storm.nph, 3 timesteps)
#
# Clock: time = 0 and clock = 0.5 (x 10 = 5 timesteps per second) at 5 frames/s, so frame k is at
# stream time k/5 s and shows timestep k: frame 0 = timestep 0, frame 1 = timestep 1. A plugin that
# ignored the host's clock would show timestep 0 twice, which differs from timestep 1 by far more
# than the tolerance (checked below).
# Tolerance (as api.frei0r): the same Session renders both; the display transform runs on the GPU in
# float for the plugin and on the CPU for the PNG, so at most 1 code per channel from rounding;
# allowed max 2 codes, mean 0.25 codes.
set -euo pipefail
host=$1 nephele=$2 plugin_dir=$3 diff=$4 work=$5
out=$work/frei0r-$host
rm -rf "$out" && mkdir -p "$out"
w=160 h=90
for t in 0 1; do
  cat >"$out/scene$t.json" <<JSON
{
  "data": { "path": "$work/storm.nph", "timestep": $t },
  "camera": { "preset": "oblique" },
  "sun": { "azimuth_deg": 135, "elevation_deg": 45 },
  "quality": "draft",
  "output": { "width": $w, "height": $h }
}
JSON
  NEPHELE_LOG=warn "$nephele" render "$out/scene$t.json" -o "$out/reference$t.png"
done
export FREI0R_PATH=$plugin_dir NEPHELE_LOG=warn
case $host in
  gstreamer)
    # A private registry: the scan sees FREI0R_PATH and nothing cached from elsewhere.
    export GST_REGISTRY=$out/registry.bin
    gst-inspect-1.0 frei0r-src-nephele-clouds >"$out/inspect.txt" ||
      { echo "FAIL: GStreamer does not list frei0r-src-nephele-clouds (FREI0R_PATH=$plugin_dir)" >&2; exit 1; }
    grep -q "clock" "$out/inspect.txt" || { echo "FAIL: no clock property:" >&2; cat "$out/inspect.txt" >&2; exit 1; }
    gst-launch-1.0 -q frei0r-src-nephele-clouds dataset="$work/storm.nph" time=0 camera=oblique \
      sun-azimuth=0.375 sun-elevation=0.5 quality=draft clock=0.5 num-buffers=2 \
      ! "video/x-raw,format=RGBA,width=$w,height=$h,framerate=5/1" ! pngenc ! multifilesink location="$out/frame%d.png"
    ;;
  mlt)
    melt -silent -quiet frei0r.nephele_clouds dataset="$work/storm.nph" time=0 camera=oblique sun_azimuth=0.375 \
      sun_elevation=0.5 quality=draft clock=0.5 out=1 \
      -profile atsc_720p_25 -consumer avformat:"$out/frame%d.png" width=$w height=$h frame_rate_num=5 frame_rate_den=1 \
      sample_aspect_num=1 sample_aspect_den=1 progressive=1 real_time=0 vcodec=png pix_fmt=rgba mlt_image_format=rgba
    # melt numbers from 1
    for k in 0 1; do mv "$out/frame$((k + 1)).png" "$out/frame$k.png.tmp"; done
    for k in 0 1; do mv "$out/frame$k.png.tmp" "$out/frame$k.png"; done
    ;;
  *) echo "usage: $0 gstreamer|mlt ..." >&2; exit 2 ;;
esac
for k in 0 1; do
  [ -f "$out/frame$k.png" ] || { echo "FAIL: $host wrote no frame $k: $(ls "$out")" >&2; exit 1; }
  "$diff" "$out/frame$k.png" "$out/reference$k.png" 2 0.25 "$host.frame$k"
done
# the clock must matter: timestep 1 is not within the tolerance of timestep 0
if "$diff" "$out/reference0.png" "$out/reference1.png" 2 0.25 "$host.clock-check" >/dev/null 2>&1; then
  echo "FAIL: timesteps 0 and 1 are within the tolerance: the test cannot see the clock" >&2
  exit 1
fi
echo "$host: frames 0 and 1 at 5 fps with clock 0.5 match nephele render of timesteps 0 and 1"
