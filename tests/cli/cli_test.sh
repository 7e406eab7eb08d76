#!/usr/bin/env bash
# CLI tests of `nephele info` / `nephele convert` on generated tiny sample files.
# usage: cli_test.sh NEPHELE NEPHELE_GEN WORKDIR CASE [ARGS...]
# Each case checks exit codes and output; it fails (exit 1) with a message saying what differed.
set -uo pipefail
nephele=$1 gen=$2 work=$3 case=$4
shift 4
data=$work/data
# one output directory per test (the cases run in parallel under ctest -j)
out=$work/out-$case$(printf -- '-%s' "$@" | tr -c 'A-Za-z0-9_.-' '_')
fail() { echo "FAIL [$case]: $*" >&2; exit 1; }

# run CMD...: captures stdout/stderr/rc into $stdout $stderr $rc
run() {
  "$@" >"$out/stdout" 2>"$out/stderr"
  rc=$?
  stdout=$(cat "$out/stdout")
  stderr=$(cat "$out/stderr")
  echo "+ $* -> rc $rc" >&2
}
expect_rc() { [ "$rc" -eq "$1" ] || fail "exit status $rc, expected $1; stderr: $stderr"; }
expect_out() { grep -q -- "$1" "$out/stdout" || fail "stdout lacks '$1'; stdout: $stdout"; }
expect_err() { grep -q -- "$1" "$out/stderr" || fail "stderr lacks '$1'; stderr: $stderr"; }
expect_no_nph_left() {  # no output and no temporary file
  local left
  left=$(ls "$out" | grep -E '\.nph' || true)
  [ -z "$left" ] || fail "files left behind after a failed conversion: $left"
}
# expect_clear_and_opaque LAYER.exr: the storm is in the frame — its cloud layer's alpha has opaque
# cloud somewhere (> 0.95) and clear sky or ground elsewhere (< 0.05).
expect_clear_and_opaque() {
  local lo hi
  oiiotool "$1" --ch A --printstats -o "$out/alpha.exr" >"$out/alpha.stats" ||
    fail "oiiotool --printstats of the cloud layer failed"
  lo=$(grep 'Stats Min' "$out/alpha.stats" | sed 's/.*Min: //' | awk '{print $1}')
  hi=$(grep 'Stats Max' "$out/alpha.stats" | sed 's/.*Max: //' | awk '{print $1}')
  awk -v lo="$lo" -v hi="$hi" 'BEGIN { exit !(lo < 0.05 && hi > 0.95) }' ||
    fail "cloud layer alpha spans $lo .. $hi, expected clear and opaque pixels"
}

# animate_cache: a 6-timestep .nph of the tiny storm and a small scene animating timesteps 0-2
animate_cache() {
  "$nephele" convert "$data/wrfout_lambert_thompson.nc" -o "$out/a.nph" --no-progress >/dev/null ||
    fail "convert for animate failed"
  cat >"$out/scene.json" <<'JSON'
{
  "data": { "path": "a.nph" },
  "camera": { "preset": "oblique" },
  "sun": { "from_time": true },
  "quality": "draft",
  "output": { "width": 64, "height": 36 },
  "height_exaggeration": 8,
  "animation": {
    "from": 0, "to": "2026-09-01T14:00:00Z", "fps": 25, "duration_s": 0.36,
    "camera_keyframes": [ { "at_s": 0, "preset": "oblique" }, { "at_s": 0.36, "preset": "overview", "fov_deg": 35 } ]
  }
}
JSON
}

if [ "$case" != generate ]; then
  rm -rf "$out" && mkdir -p "$out"
fi

case $case in
  generate)  # fixture: the standard tiny set and a second file continuing the Lambert series
    rm -rf "$data" && mkdir -p "$data"
    "$gen" all --dir "$data" >/dev/null || fail "nephele-gen all failed"
    "$gen" wrf --times 2 --start-hour 6 -o "$data/wrfout_lambert_thompson_b.nc" >/dev/null ||
      fail "nephele-gen wrf (series) failed"
    "$gen" icon --grib2 "$data/icon_grib2" >/dev/null || fail "nephele-gen icon --grib2 failed"
    ;;
  help)
    run "$nephele" --help
    expect_rc 0; expect_out "info"; expect_out "convert"
    run "$nephele" convert --help
    expect_rc 0; expect_out "--preset"; expect_out "--dz"; expect_out "nes2008"
    ;;
  info)  # every generated file, ARGS: file name
    run "$nephele" info "$data/$1"
    expect_rc 0; expect_out "timesteps"; expect_out "grid"; expect_out "q cloud"
    case $1 in
      *wsm3*) expect_out "MP_PHYSICS = 3";;
      *thompson*) expect_out "MP_PHYSICS = 8"; expect_out "N ice";;
      icon_regular*) expect_out "cloud cover \[0-1\]     0 \.\. "; expect_out "consistency   [1-9][0-9]* cells with CLC = 0";;
    esac
    ;;
  convert)  # ARGS: file name, expected timesteps; then `info --verify` on the result
    run "$nephele" convert "$data/$1" -o "$out/x.nph" --stats
    expect_rc 0; expect_out "timesteps=$2"; expect_out "peak_rss_mb="
    run "$nephele" info --verify "$out/x.nph"
    expect_rc 0; expect_out "verified      all $2 chunks"; expect_out "max ice"
    [ "$(ls "$out")" = "$(printf 'stderr\nstdout\nx.nph')" ] || fail "unexpected files: $(ls "$out")"
    ;;
  series)  # two files of one storm: one time-ordered cache, nes2008 preset, overrides
    run "$nephele" convert "$data/wrfout_lambert_thompson_b.nc" "$data/wrfout_lambert_thompson.nc" \
      -o "$out/s.nph" --preset nes2008 --dz 500 --radius snow=1mm --no-progress
    expect_rc 0
    run "$nephele" info "$out/s.nph"
    expect_rc 0; expect_out "timesteps     8"; expect_out "dz 500 m"; expect_out "preset nes2008+snow=1mm"
    # time order across files: the first file's 12:00 comes first, the second file's 18:00 later
    grep -A1 "timesteps     8" "$out/stdout" | grep -q "2026-09-01T12:00:00Z" || fail "not time-ordered: $stdout"
    expect_out "7 2026-09-01T19:00:00Z"
    expect_out "wind U, V"  # kept for the motion blend (docs/animation.md) ...
    for wind in windy calm; do
      run "$nephele" convert "$data/wrfout_lambert_thompson.nc" -o "$out/$wind.nph" --no-progress \
        $([ $wind = calm ] && echo --no-wind)
      expect_rc 0
    done
    run "$nephele" info "$out/calm.nph"
    expect_rc 0; expect_out "timesteps     6"
    if grep -q "wind U, V" "$out/stdout"; then fail "--no-wind kept the wind: $stdout"; fi  # ... unless left out
    [ "$(stat -c %s "$out/calm.nph")" -lt "$(stat -c %s "$out/windy.nph")" ] || fail "--no-wind file not smaller"
    ;;
  mixed-grids)  # Lambert and Mercator storms have the same size but not the same grid
    run "$nephele" convert "$data/wrfout_lambert_wsm3.nc" "$data/wrfout_mercator_wsm3.nc" -o "$out/m.nph"
    expect_rc 1; expect_err "another grid"; expect_no_nph_left
    ;;
  progress)  # forced progress bar goes to stderr, stdout stays clean
    run "$nephele" convert "$data/icon_regular.nc" -o "$out/p.nph" --progress
    expect_rc 0; expect_err "2/2"; [ -z "$stdout" ] || fail "stdout not empty: $stdout"
    ;;
  not-netcdf)
    echo "this is not a weather model" >"$out/notes.nc"
    run "$nephele" convert "$out/notes.nc" -o "$out/bad.nph"
    expect_rc 1; expect_err "notes.nc"; rm "$out/notes.nc"; expect_no_nph_left
    run "$nephele" info "$out/stdout"
    expect_rc 1; expect_err "stdout"
    ;;
  truncated)  # a wrfout cut in the middle: error naming it, no partial output
    head -c 300000 "$data/wrfout_lambert_wsm3.nc" >"$out/cut.nc"
    run "$nephele" convert "$out/cut.nc" -o "$out/cut.nph"
    expect_rc 1; expect_err "cut.nc"; expect_no_nph_left
    run "$nephele" info "$out/cut.nc"
    expect_rc 1; expect_err "cut.nc"
    ;;
  corrupt-nph)  # a flipped byte inside a chunk: info --verify names file and chunk
    run "$nephele" convert "$data/wrfout_mercator_wsm3.nc" -o "$out/c.nph"
    expect_rc 0
    size=$(stat -c %s "$out/c.nph")
    printf '\xff\xff\xff\xff' | dd of="$out/c.nph" bs=1 seek=$((size / 2)) conv=notrunc status=none
    run "$nephele" info --verify "$out/c.nph"
    expect_rc 1; expect_err "c.nph"; expect_err "chunk"
    head -c 1000 "$out/c.nph" >"$out/short.nph"
    run "$nephele" info "$out/short.nph"
    expect_rc 1; expect_err "short.nph"; expect_err "truncated"
    ;;
  animate-split)  # --frames 0:9 in one run = 0:4 + 5:9 on "two machines" (one without prefetch), byte for byte
    animate_cache
    run "$nephele" animate "$out/scene.json" -o "$out/one" --format png,exr --layer --no-progress
    expect_rc 0; expect_out "rendered 10 frames"
    [ "$(ls "$out/one" | head -3 | tr '\n' ' ')" = "frame_000000.exr frame_000000.png frame_000001.exr " ] ||
      fail "unexpected names: $(ls "$out/one" | head -3)"
    [ "$(ls -A "$out/one" | wc -l)" = 40 ] || fail "expected 40 files (10 frames x png/exr x frame/layer): $(ls -A "$out/one")"
    # three writer threads here (the files of up to three frames written while the next renders)
    run "$nephele" animate "$out/scene.json" -o "$out/two" --format png,exr --layer --frames 0:4 --write-threads 3
    expect_rc 0; expect_out "rendered 5 frames"
    run "$nephele" animate "$out/scene.json" -o "$out/two" --format png,exr --layer --frames 5:9 --no-prefetch
    expect_rc 0; expect_out "rendered 5 frames"
    for f in "$out"/one/*; do
      cmp -s "$f" "$out/two/$(basename "$f")" || fail "$(basename "$f") differs between one run and two"
    done
    # held timesteps: frame 4 reuses the light map in one run and builds it afresh when a machine starts there
    sed 's/"fps": 25,/"fps": 25, "sun_follows_clock": false,/' "$out/scene.json" >"$out/held.json"
    run "$nephele" animate "$out/held.json" -o "$out/held" --interpolation step --from 0 --to 3
    expect_rc 0; expect_out "DLM reused on [1-9]"
    run "$nephele" animate "$out/held.json" -o "$out/held-late" --interpolation step --from 0 --to 3 --frames 4:9
    expect_rc 0
    for f in "$out"/held-late/*; do
      cmp -s "$f" "$out/held/$(basename "$f")" || fail "$(basename "$f") differs when the sub-range starts there"
    done
    ;;
  animate-chunks)  # --chunk I/N and --frames A-B (render-farm forms) = one run, byte for byte
    animate_cache
    run "$nephele" animate "$out/scene.json" -o "$out/one" --no-progress
    expect_rc 0
    for i in 0 1 2; do
      run "$nephele" animate "$out/scene.json" -o "$out/chunks" --chunk "$i/3" --no-progress
      expect_rc 0
    done
    run "$nephele" animate "$out/scene.json" -o "$out/dash" --frames 3-6 --no-progress
    expect_rc 0
    expect_out "frames 3 to 6"
    n=$(ls "$out/one" | grep -c '^frame_.*\.png$')
    [ "$n" -eq 10 ] || fail "one run wrote $n frames, expected 10"
    for f in "$out"/one/frame_*.png; do
      cmp -s "$f" "$out/chunks/$(basename "$f")" || fail "chunked $(basename "$f") differs from the one-run frame"
    done
    [ "$(ls "$out/dash" | grep -c '^frame_')" -eq 4 ] || fail "--frames 3-6 wrote $(ls "$out/dash") "
    cmp -s "$out/one/frame_000004.png" "$out/dash/frame_000004.png" || fail "--frames 3-6 frame 4 differs"
    run "$nephele" animate "$out/scene.json" -o "$out/empty" --chunk 0/12 --no-progress  # 10 frames, 12 chunks: chunk 0 is empty
    expect_rc 0
    expect_out "rendered 0 frames"
    for bad in 3/3 1/0 x/2 2 -1/4; do
      run "$nephele" animate "$out/scene.json" -o "$out/bad" --chunk "$bad"
      expect_rc 2
      expect_err "--chunk"
    done
    run "$nephele" animate "$out/scene.json" -o "$out/bad" --chunk 0/2 --frames 0:1
    expect_rc 2
    expect_err "either --frames or --chunk"
    ;;
  grib2)  # ICON GRIB2 written by ecCodes (nephele-gen icon --grib2) from icon_regular.nc's scene: DWD's folder, one file
    "$gen" icon --grib2 "$out/dwd" --grib2-packing grid_ieee >/dev/null || fail "nephele-gen icon --grib2 failed"
    "$gen" icon --grib2 "$out/one" --grib2-layout single --grib2-packing grid_ccsds >/dev/null ||
      fail "nephele-gen icon --grib2 --grib2-layout single failed"
    # ecCodes' own tools read what the C API wrote, with DWD's names (centre 78, edzw)
    run grib_ls -p centre,shortName,level "$out/dwd/icon-d2_germany_regular-lat-lon_time-invariant_2026031812_000_21_hhl.grib2"
    expect_rc 0; expect_out "edzw *HHL *21"
    run "$nephele" info "$out/dwd"
    expect_rc 0; expect_out "ICON GRIB2 regular lat-lon (381 files, 381 messages"; expect_out "timesteps     2"
    expect_out "HHL 21 levels x 1 times"; expect_out "q cloud"; expect_out "consistency   [1-9][0-9]* cells"
    run "$nephele" info "$out/one/icon_scene.grib2" --no-ranges
    expect_rc 0; expect_out "(1 files, 381 messages"; expect_out "1 2026-03-18T13:00:00Z"
    # a quoted pattern; only the temperature files: the heights are missing
    run "$nephele" info "$out/dwd/*_t.grib2"
    expect_rc 1; expect_err "no HHL"; expect_err "_hhl.grib2"
    # IEEE packing holds the NetCDF floats: the caches' per-timestep maxima print the same
    for input in "$out/dwd" "$data/icon_regular.nc"; do
      run "$nephele" convert "$input" -o "$out/$(basename "$input").nph" --no-progress
      expect_rc 0
      run "$nephele" info "$out/$(basename "$input").nph"
      expect_rc 0
      grep -o "max ice .* /m  max water .* /m" "$out/stdout" >"$out/$(basename "$input").maxima"
    done
    [ "$(wc -l <"$out/dwd.maxima")" -eq 2 ] || fail "expected 2 timesteps: $(cat "$out/dwd.maxima")"
    cmp -s "$out/dwd.maxima" "$out/icon_regular.nc.maxima" ||
      fail "GRIB2 and NetCDF caches differ: $(cat "$out/dwd.maxima") vs $(cat "$out/icon_regular.nc.maxima")"
    run "$nephele" convert "$out/one/icon_scene.grib2" -o "$out/one.nph" --no-progress
    expect_rc 0
    ;;
  quicklook)  # a data file instead of a scene: framed automatically; the printed scene re-renders the same bytes
    for f in wrfout_lambert_thompson.nc icon_regular.nc icon_grib2; do  # icon_grib2: DWD's folder of GRIB2 files
      run "$nephele" render "$data/$f" -o "$out/$f.png" --width 96 --height 54 --print-scene
      expect_rc 0
      [ -s "$out/$f.png" ] || fail "quick look of $f wrote no image"
      cp "$out/stdout" "$out/$f.scene.json"
      grep -q '"preset": "oblique"' "$out/$f.scene.json" || fail "printed scene of $f: $stdout"
      run "$nephele" render "$out/$f.scene.json" -o "$out/$f.again.png"
      expect_rc 0
      cmp -s "$out/$f.png" "$out/$f.again.png" || fail "re-rendering the printed scene of $f gave other bytes"
    done
    grep -q '"basemap"' "$out/wrfout_lambert_thompson.nc.scene.json" || fail "no Blue Marble under georeferenced WRF data"
    "$nephele" convert "$data/wrfout_lambert_thompson.nc" -o "$out/q.nph" --no-progress >/dev/null || fail "convert failed"
    run "$nephele" render "$out/q.nph" --print-scene   # print only: no output given, nothing rendered
    expect_rc 0
    expect_out '"height_exaggeration"'
    run "$nephele" render "$out/q.nph"
    expect_rc 2
    expect_err "no output"
    run "$nephele" render "$out/wrfout_lambert_thompson.nc.scene.json" --print-scene
    expect_rc 2
    expect_err "already a scene file"
    ;;
  hurricane-cells)  # make demo's storm (nephele-gen wrf --case hurricane-cells): generates, converts, renders
    run "$gen" wrf --case hurricane-cells --times 1 -o "$out/cells.nc"
    expect_rc 0
    run "$nephele" convert "$out/cells.nc" -o "$out/cells.nph" --no-progress
    expect_rc 0
    run "$nephele" info --verify "$out/cells.nph"
    expect_rc 0; expect_out "verified      all 1 chunks"
    run "$nephele" render "$out/cells.nph" -o "$out/cells.png" --width 160 --height 90 --layer "$out/layer.exr"
    expect_rc 0
    [ -s "$out/cells.png" ] || fail "no image of the cellular hurricane"
    # The storm is in the frame: opaque cloud somewhere, clear sky or sea elsewhere.
    expect_clear_and_opaque "$out/layer.exr"
    ;;
  alpine-storm)  # make demo's terrain shot (nephele-gen wrf --case alpine-storm): generates, converts, renders
    run "$gen" wrf --case alpine-storm -o "$out/alpine.nc" --dem "$out/alpine-dem.tif"
    expect_rc 0
    expect_out "alpine-dem.tif: DEM 960x768 pixels of 500 m"
    run "$nephele" convert "$out/alpine.nc" -o "$out/alpine.nph" --no-progress
    expect_rc 0
    run "$nephele" info "$out/alpine.nph"
    expect_rc 0; expect_out "grid          160 x 128 x"
    # The model's own terrain: HGT from the valley floors to the summits.
    expect_out "terrain \[m\]   1[0-9][0-9] .. 4[0-9][0-9][0-9]"
    run "$nephele" render "$out/alpine.nph" -o "$out/alpine.png" --width 160 --height 90 --layer "$out/layer.exr"
    expect_rc 0
    [ -s "$out/alpine.png" ] || fail "no image of the alpine storm"
    # Its finer DEM, in the model's projection, covers the model's footprint exactly: every point of
    # the lattice refined 6 times (3 km / 500 m) has a height from it.
    run "$nephele" render "$out/alpine.nph" -o "$out/alpine-dem.png" --width 96 --height 54 --dem "$out/alpine-dem.tif"
    expect_rc 0
    expect_err "heights on 737280 of 737280 lattice points (6x the model's cell)"
    run "$gen" wrf --case storm -o "$out/storm.nc" --dem "$out/storm-dem.tif"
    expect_rc 1
    expect_err "for --case alpine-storm only"
    expect_clear_and_opaque "$out/layer.exr"
    ;;
  basemap)  # --basemap FILE: a user raster through GDAL under the storm; an ungeoreferenced one is refused
    # A uniform red world in EPSG:4326 as a PNG with a world file and GDAL's .aux.xml (CRS): the
    # ground of the frame must turn red where Blue Marble's sea is blue.
    oiiotool --pattern constant:color=0.8,0.1,0.1 360x180 3 -d uint8 -o "$out/world.png" || fail "oiiotool failed"
    printf '1\n0\n0\n-1\n-179.5\n89.5\n' >"$out/world.pgw"
    cat >"$out/world.png.aux.xml" <<'XML'
<PAMDataset>
  <SRS dataAxisToSRSAxisMapping="2,1">GEOGCS["WGS 84",DATUM["WGS_1984",SPHEROID["WGS 84",6378137,298.257223563]],PRIMEM["Greenwich",0],UNIT["degree",0.0174532925199433],AUTHORITY["EPSG","4326"]]</SRS>
</PAMDataset>
XML
    for map in default red; do
      [ "$map" = red ] && extra=(--basemap "$out/world.png") || extra=()
      run "$nephele" render "$data/wrfout_lambert_thompson.nc" -o "$out/$map.png" --width 160 --height 90 "${extra[@]}"
      expect_rc 0
      # the lower-left corner of the oblique view is open ground (sea) in front of the storm
      oiiotool "$out/$map.png" --cut 40x20+0+70 --printstats -o "$out/$map-corner.png" >"$out/$map.stats" ||
        fail "oiiotool --printstats of $map.png failed"
    done
    read -r r g b _ < <(grep 'Stats Avg' "$out/red.stats" | sed 's/.*Avg: //')
    read -r r0 g0 b0 _ < <(grep 'Stats Avg' "$out/default.stats" | sed 's/.*Avg: //')
    awk -v r="$r" -v b="$b" -v r0="$r0" -v b0="$b0" 'BEGIN { exit !(r > 0.35 && r > b + 0.1 && r0 < b0) }' ||
      fail "the ground is not the red basemap: mean RGB $r $g $b (Blue Marble: $r0 $g0 $b0)"
    # A PNG without georeference that is not a whole-Earth 2:1 image: refused, naming the file.
    oiiotool --pattern constant:color=0.8,0.1,0.1 300x180 3 -d uint8 -o "$out/plain.png" || fail "oiiotool failed"
    run "$nephele" render "$data/wrfout_lambert_thompson.nc" -o "$out/plain-out.png" --width 32 --height 18 --basemap "$out/plain.png"
    expect_rc 1; expect_err "plain.png"; expect_err "has no coordinate reference system"
    [ ! -e "$out/plain-out.png" ] || fail "an image was written although the basemap was refused"
    run "$nephele" render "$data/wrfout_lambert_thompson.nc" -o "$out/none-out.png" --basemap "$out/missing.tif"
    expect_rc 1; expect_err "missing.tif"
    ;;
  image-codec)  # OpenImageIO only in the module the first image write loads (scene/image_codec.h, issue 19)
    module=${NEPHELE_TEST_IMAGE_CODEC:?the test sets NEPHELE_TEST_IMAGE_CODEC}
    readelf -d "$nephele" | grep NEEDED >"$out/needed" || fail "readelf -d of nephele failed"
    ! grep -q OpenImageIO "$out/needed" || fail "nephele links OpenImageIO: $(grep OpenImageIO "$out/needed")"
    readelf -d "$module" | grep -q 'NEEDED.*OpenImageIO' || fail "the module $module does not link OpenImageIO"
    # Nothing that writes no image needs the module: info runs with it missing.
    NEPHELE_IMAGE_CODEC=/nonexistent/codec.so run "$nephele" info "$data/wrfout_lambert_thompson.nc"
    expect_rc 0
    # A render with the module missing: a clear error naming the image and the path tried, and the
    # image already there is kept as it was.
    printf 'earlier frame' >"$out/kept.png"
    NEPHELE_IMAGE_CODEC=/nonexistent/codec.so run "$nephele" render "$data/wrfout_lambert_thompson.nc" \
      -o "$out/kept.png" --width 32 --height 18
    expect_rc 1; expect_err "kept.png: cannot write or read images"; expect_err "/nonexistent/codec.so"
    expect_err "NEPHELE_IMAGE_CODEC"
    ! grep -q "ray cast" "$out/stderr" || fail "the frame was rendered before the missing module was found"
    ! grep -q "converting" "$out/stderr" || fail "the quick look converted the data before the module was checked"
    # animate: stopped before frame 0, nothing written
    NEPHELE_IMAGE_CODEC=/nonexistent/codec.so run "$nephele" animate "$data/wrfout_lambert_thompson.nc" \
      -o "$out/frames" --width 32 --height 18
    expect_rc 1; expect_err "cannot write or read images"
    [ -z "$(ls -A "$out/frames" 2>/dev/null)" ] || fail "animate wrote frames: $(ls -A "$out/frames")"
    [ "$(cat "$out/kept.png")" = "earlier frame" ] || fail "the image already written was changed"
    ls -a "$out" | grep -q partial && fail "a partial file was left: $(ls -a "$out")"
    # With the module: the same render writes the PNG.
    run "$nephele" render "$data/wrfout_lambert_thompson.nc" -o "$out/kept.png" --width 32 --height 18
    expect_rc 0
    oiiotool --info "$out/kept.png" | grep -q "32 x  *18" || fail "the render wrote no 32 x 18 PNG"
    ;;
  dem)  # --dem FILE: a user DEM through GDAL (docs/terrain.md "A user DEM"); a DEM in centimetres is refused
    # ESRI ASCII grids (GDAL's AAIGrid) in EPSG:4326 over the storm's region: 1500 m everywhere, and
    # the same in centimetres; one without its .prj (no CRS).
    for unit in m cm nocrs; do
      awk -v unit="$unit" 'BEGIN {
        printf "ncols 100\nnrows 100\nxllcorner -100\nyllcorner 0\ncellsize 0.5\nNODATA_value -9999\n";
        for (j = 0; j < 100; ++j) { for (i = 0; i < 100; ++i) printf "%.1f ", unit == "cm" ? 150000 : 1500; printf "\n" }
      }' >"$out/dem-$unit.asc"
      [ "$unit" = nocrs ] || printf 'GEOGCS["WGS 84",DATUM["WGS_1984",SPHEROID["WGS 84",6378137,298.257223563]],PRIMEM["Greenwich",0],UNIT["degree",0.0174532925199433]]' >"$out/dem-$unit.prj"
    done
    NEPHELE_LOG=info run "$nephele" render "$data/wrfout_lambert_thompson.nc" -o "$out/dem.png" --width 64 --height 36 --dem "$out/dem-m.asc"
    expect_rc 0
    grep -E -q 'DEM .*dem-m.asc: heights on [1-9][0-9]* of [0-9]+ (model columns|lattice points)' "$out/stderr" ||
      fail "the DEM did not reach the model's columns; stderr: $stderr"
    run "$nephele" render "$data/wrfout_lambert_thompson.nc" -o "$out/dem-cm.png" --width 32 --height 18 --dem "$out/dem-cm.asc"
    expect_rc 1; expect_err "dem-cm.asc"; expect_err "expected metres above sea level"
    [ ! -e "$out/dem-cm.png" ] || fail "an image was written although the DEM was refused"
    run "$nephele" render "$data/wrfout_lambert_thompson.nc" -o "$out/dem-nocrs.png" --width 32 --height 18 --dem "$out/dem-nocrs.asc"
    expect_rc 1; expect_err "dem-nocrs.asc"; expect_err "has no coordinate reference system"
    ;;
  exposure)  # output.exposure "sun": the EXR is the fixed-exposure one times 2^(the offset logged)
    animate_cache
    for mode in fixed sun; do
      python3 - "$out/scene.json" "$mode" "$out/$mode.json" <<'PY' || fail "could not write $mode.json"
import json, sys
s = json.load(open(sys.argv[1]))
s["sun"] = {"azimuth_deg": 250, "elevation_deg": 5}
del s["animation"]
s["output"]["exposure"] = sys.argv[2]
json.dump(s, open(sys.argv[3], "w"))
PY
      run "$nephele" render "$out/$mode.json" -o "$out/$mode.exr"
      expect_rc 0
    done
    expect_err "exposure follows the sun (5.0 deg)"
    offset=$(sed -n 's/.*exposure follows the sun (5.0 deg): [^(]*(\([-+0-9.]*\) over.*/\1/p' "$out/stderr")
    [ -n "$offset" ] || fail "no exposure offset logged: $stderr"
    for mode in fixed sun; do
      oiiotool "$out/$mode.exr" --printstats 2>&1 | sed -n 's/.*Stats Avg: *\([0-9.e+-]*\) \([0-9.e+-]*\) \([0-9.e+-]*\) \([0-9.e+-]*\).*/\1 \2 \3 \4/p' >"$out/$mode.avg"
    done
    python3 - "$offset" "$out/fixed.avg" "$out/sun.avg" <<'PY' || fail "the sun exposure is not the fixed one times 2^$offset"
import math, sys
offset = float(sys.argv[1])
fixed, sun = ([float(x) for x in open(p).read().split()] for p in sys.argv[2:4])
assert 1.4 < offset < 1.9, f"offset {offset} EV at 5 deg: expected about +1.65 (half the 3.3 EV daylight drop)"
for c in range(3):  # colour scaled by 2^offset (half floats: 1e-3; the logged offset: 0.005 EV)
    assert fixed[c] > 0, f"channel {c} is black"
    ev = math.log2(sun[c] / fixed[c])
    assert abs(ev - offset) < 0.01, f"channel {c}: {ev:.4f} EV, logged {offset}"
assert abs(sun[3] - fixed[3]) < 1e-6, f"alpha changed: {fixed[3]} -> {sun[3]}"
print(f"sun exposure {offset:+.2f} EV, measured {math.log2(sun[1] / fixed[1]):+.4f}")
PY
    ;;
  passes)  # compositing passes: a multi-layer EXR as iinfo lists it, pass files, bad pass names, animate --passes
    animate_cache
    run "$nephele" render "$out/scene.json" -o "$out/p.exr" -o "$out/p.png" --passes \
      --pass shadow="$out/shadow.png" --pass depth="$out/depth.exr" --pass sky="$out/sky.exr"
    expect_rc 0
    iinfo -v "$out/p.exr" >"$out/iinfo" 2>&1 || fail "iinfo cannot read p.exr: $(cat "$out/iinfo")"
    for c in "R (half)" "A (half)" "Z (float)" "cloud.A (half)" "ground.B (half)" "sky.R (half)" "shadow.Y (half)"; do
      grep -q "$c" "$out/iinfo" || fail "p.exr lacks channel $c: $(grep 'channel list' "$out/iinfo")"
    done
    grep -q '16 channel' "$out/iinfo" || fail "p.exr: expected 16 channels: $(head -1 "$out/iinfo")"
    iinfo -v "$out/depth.exr" | grep -q 'channel list: Z$' || fail "depth.exr is not a Z-only image: $(iinfo -v "$out/depth.exr")"
    iinfo "$out/p.png" | grep -q '4 channel' || fail "p.png should hold the beauty only: $(iinfo "$out/p.png")"
    [ -s "$out/shadow.png" ] && [ -s "$out/sky.exr" ] || fail "pass files missing: $(ls "$out")"
    run "$nephele" render "$out/scene.json" --pass depth="$out/depth.png"
    expect_rc 1; expect_err "depth.png: a depth pass holds distances"
    run "$nephele" render "$out/scene.json" --pass albedo="$out/a.png"
    expect_rc 2; expect_err "NAME one of beauty, cloud, ground, sky, shadow, depth"
    run "$nephele" animate "$out/scene.json" -o "$out/seq" --format png,exr --passes --frames 0:1 --no-progress
    expect_rc 0
    for k in 000000 000001; do
      for f in frame_$k.png frame_$k.exr layer_$k.png ground_$k.png sky_$k.png shadow_$k.png; do
        [ -s "$out/seq/$f" ] || fail "animate --passes wrote no $f: $(ls "$out/seq")"
      done
      iinfo -v "$out/seq/frame_$k.exr" | grep -q 'shadow.Y' || fail "frame_$k.exr has no passes"
    done
    ;;
  colour)  # OpenColorIO outputs: ociocheck on the built config, PNGs vs oiiotool --ociodisplay, video colour tags
    cfg=$(dirname "$nephele")/../../share/nephele/ocio/config.ocio
    ociocheck --iconfig "$cfg" >"$out/ociocheck" 2>&1 || fail "ociocheck: $(tail -5 "$out/ociocheck")"
    grep -q -A1 'Validation' "$out/ociocheck" && grep -A1 'Validation' "$out/ociocheck" | grep -q passed ||
      fail "ociocheck did not pass: $(tail -5 "$out/ociocheck")"
    animate_cache
    # 1 code value: 1/255 for 8-bit SDR, 1/1023 for 10-bit HDR video (16-bit PNG). The reference
    # reads the half-float EXR, nephele encodes its float frame: half rounding moves a few near-black
    # pixels by a second 8-bit code (Rec.1886's slope is infinite at 0), hence 0.5 % of pixels may
    # differ by up to 3 codes (exact float agreement: scene.ColourOutput.EveryDisplayView...).
    for dv in "sRGB|nephele|uint8|0.00393|0.0118" "Rec.1886 Rec.709|ACES SDR video|uint8|0.00393|0.0118" \
              "Rec.2100-PQ|ACES HDR video|uint16|0.000978|0.000978" "Rec.2100-HLG|ACES HDR video|uint16|0.000978|0.000978"; do
      IFS='|' read -r d v bits tol hard <<<"$dv"
      run "$nephele" render "$out/scene.json" -o "$out/c.exr" -o "$out/c.png" --display "$d" --view "$v"
      expect_rc 0
      oiiotool --colorconfig "$cfg" "$out/c.exr" --ociodisplay "$d" "$v" -d "$bits" -o "$out/ref.png" ||
        fail "oiiotool --ociodisplay $d / $v failed"
      iinfo "$out/c.png" | grep -q "$bits png" || fail "$d: expected a $bits PNG: $(iinfo "$out/c.png")"
      oiiotool "$out/c.png" "$out/ref.png" --fail "$tol" --failpercent 0.5 --hardfail "$hard" --diff >"$out/diff" 2>&1 ||
        fail "$d / $v differs from oiiotool's conversion: $(cat "$out/diff")"
    done
    run "$nephele" render "$out/scene.json" -o "$out/c.png" --display "Rec.2020"
    expect_rc 1; expect_err '"Rec.2100-PQ"'
    run "$nephele" animate "$out/scene.json" -o "$out/hdr" --frames 0:2 --display Rec.2100-PQ --video "$out/hdr.mov" --no-progress
    expect_rc 0
    ffprobe -v error -show_streams "$out/hdr.mov" >"$out/probe" 2>&1 || fail "ffprobe: $(cat "$out/probe")"
    for tag in color_transfer=smpte2084 color_primaries=bt2020 color_space=bt2020nc; do
      grep -q "^$tag" "$out/probe" || fail "hdr.mov lacks $tag: $(grep color "$out/probe")"
    done
    ;;
  animate-resume)  # a second run skips complete frames without rewriting them
    animate_cache
    run "$nephele" animate "$out/scene.json" -o "$out/seq" --frames 0:4
    expect_rc 0
    before=$(stat -c '%n %Y.%y' "$out"/seq/*)
    NEPHELE_LOG=info run "$nephele" animate "$out/scene.json" -o "$out/seq"
    expect_rc 0; expect_out "rendered 5 frames, skipped 5 complete"; expect_err "frame 4: complete, skipped"
    [ "$(stat -c '%n %Y.%y' "$out"/seq/frame_00000[0-4].png)" = "$before" ] || fail "finished frames were rewritten"
    rm "$out/seq/frame_000007.png"   # a run killed while writing frame 7 left no file under its name
    run "$nephele" animate "$out/scene.json" -o "$out/seq"
    expect_rc 0; expect_out "rendered 1 frames, skipped 9 complete"
    [ -z "$(ls -A "$out/seq" | grep -v '^frame_0000[0-9][0-9].png$')" ] || fail "stray files: $(ls -A "$out/seq")"
    ;;
  animate-rising)  # animate straight on a wrfout whose cloud top rises = the .nph route (issue 18)
    # Each timestep converted on the fly is cropped to its own column; 2 km/h rising ice tops give
    # timesteps of different heights, which stopped `animate` at frame 1 before blendVolumes padded
    # them onto one grid. An explicit camera: a preset frames the first volume it sees, the cropped
    # timestep 0 on one route and the padded grid on the other. The .nph route stores 16-bit quantised extinction, hence the tolerance:
    # no pixel off by more than 16/255, at most 1 % of the pixels by more than 4/255. The default
    # (motion) blend: the .nph cache keeps U, V (0.01 m/s codes), so both routes move the timesteps.
    "$gen" wrf --times 3 --anvil-rise 2 -o "$out/rising.nc" >/dev/null || fail "nephele-gen --anvil-rise failed"
    run "$nephele" convert "$out/rising.nc" -o "$out/rising.nph" --no-progress
    expect_rc 0
    for src in rising.nc rising.nph; do
      cat >"$out/$src.json" <<JSON
{
  "data": { "path": "$src" },
  "camera": { "position_m": [-150000, -250000, 250000], "target_m": [300000, 270000, 5000], "fov_deg": 45 },
  "sun": { "azimuth_deg": 140, "elevation_deg": 35 },
  "quality": { "preset": "draft", "overrides": { "cloud_resolution": 1 } },
  "output": { "width": 96, "height": 54 },
  "height_exaggeration": 8,
  "animation": { "from": 0, "to": 2, "fps": 4, "duration_s": 1.0 }
}
JSON
      run "$nephele" animate "$out/$src.json" -o "$out/frames-$src" --no-progress
      expect_rc 0; expect_out "rendered 5 frames"
    done
    for f in "$out"/frames-rising.nph/*.png; do
      idiff -fail 0.016 -failpercent 1 -hardfail 0.063 -warn 0.016 -warnpercent 1 "$f" "$out/frames-rising.nc/$(basename "$f")" >"$out/idiff" 2>&1 ||
        fail "$(basename "$f"): the wrfout route differs from the .nph route: $(grep -E 'error|FAIL' "$out/idiff" | tr '\n' ' ')"
    done
    ;;
  animate-truncated)  # timestep 3's chunk cut short: frames 0-2 written and intact, a clear error at frame 3
    animate_cache
    run "$nephele" animate "$out/scene.json" -o "$out/good" --interpolation step --from 0 --to 5 --fps 1 --duration 5
    expect_rc 0; expect_out "rendered 6 frames"
    python3 - "$out/a.nph" 3 <<'PY' || fail "could not cut the chunk"
import json, struct, sys
path, t = sys.argv[1], int(sys.argv[2])
with open(path, 'r+b') as f:
    head = f.read(64)
    off, size = struct.unpack_from('<QQ', head, 16)
    f.seek(off); chunk = json.loads(f.read(size))['timesteps'][t]['chunk']
    half = chunk['bytes'] // 2   # the chunk's second half lost (zeros), as a cut-off copy leaves it
    f.seek(chunk['offset'] + half); f.write(b'\0' * (chunk['bytes'] - half))
PY
    # with writer threads too: the frames rendered before the error are written before it is reported
    run "$nephele" animate "$out/scene.json" -o "$out/cut" --interpolation step --from 0 --to 5 --fps 1 --duration 5 \
      --write-threads 3
    expect_rc 1; expect_err "frame 3"; expect_err "a.nph"; expect_err "chunk"
    [ "$(ls -A "$out/cut" | tr '\n' ' ')" = "frame_000000.png frame_000001.png frame_000002.png " ] ||
      fail "expected exactly frames 0-2 after the failure: $(ls -A "$out/cut")"
    for k in 0 1 2; do cmp -s "$out/good/frame_00000$k.png" "$out/cut/frame_00000$k.png" || fail "frame $k damaged"; done
    # a series of wrfout files with one cut short fails before any frame, naming that file
    head -c 300000 "$data/wrfout_lambert_thompson_b.nc" >"$out/cut_b.nc"
    run "$nephele" animate "$out/scene.json" -o "$out/series" --data "$data/wrfout_lambert_thompson.nc" "$out/cut_b.nc"
    expect_rc 1; expect_err "cut_b.nc"
    [ -z "$(ls -A "$out/series" 2>/dev/null)" ] || fail "frames written from a broken series: $(ls -A "$out/series")"
    ;;
  animate-video)  # ProRes 4444 with alpha from the cloud layer, via ffmpeg
    animate_cache
    run "$nephele" animate "$out/scene.json" -o "$out/seq" --layer --frames 0:3 --fps 59.94 --video "$out/clouds.mov"
    expect_rc 0; expect_out "wrote $out/clouds.mov"
    probe=$(ffprobe -v error -select_streams v:0 -show_entries stream=codec_name,profile,pix_fmt,r_frame_rate,nb_frames \
            -of default=nw=1 "$out/clouds.mov")
    # the ProRes decoder reports its own 12-bit alpha format for the 10-bit yuva444p10le encode
    for want in codec_name=prores profile=4444 pix_fmt=yuva444 r_frame_rate=60000/1001 nb_frames=4; do
      echo "$probe" | grep -q "$want" || fail "video lacks $want: $probe"
    done
    run "$nephele" animate "$out/scene.json" -o "$out/seq" --format exr --video "$out/x.mov"
    expect_rc 2; expect_err "png"
    ;;
  usage)
    run "$nephele" convert "$data/icon_regular.nc"   # no -o
    expect_rc 2; expect_err "output"
    run "$nephele" convert "$data/icon_regular.nc" -o "$out/u.nph" --preset nes2009
    expect_rc 2
    run "$nephele" convert "$data/icon_regular.nc" -o "$out/u.nph" --radius sleet=1mm
    expect_rc 2; expect_err "sleet"; expect_no_nph_left
    run "$nephele" convert "$out/missing.nc" -o "$out/u.nph"
    expect_rc 2; expect_err "missing.nc"
    run "$nephele"
    expect_rc 2
    # never replace an input or a non-.nph file by accident
    cp "$data/icon_regular.nc" "$out/in.nc"
    run "$nephele" convert "$out/in.nc" -o "$out/in.nc"
    expect_rc 2; expect_err "replace an input"
    cmp -s "$data/icon_regular.nc" "$out/in.nc" || fail "the input was modified"
    echo "notes" >"$out/notes.txt"
    run "$nephele" convert "$out/in.nc" -o "$out/notes.txt"
    expect_rc 2; expect_err "not a .nph file"
    run "$nephele" convert "$out/in.nc" -o "$out/notes.txt" --force
    expect_rc 0
    ;;
  *) fail "unknown case";;
esac
echo "PASS [$case]"
