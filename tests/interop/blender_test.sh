#!/usr/bin/env bash
# Blender as a third-party consumer of `nephele export-vdb` (label `blender`; .ci/run runs it,
# `make test` does not: Blender is 65 MB to download, 246 MB installed, tools/debian-packages-blender.txt).
# usage: blender_test.sh NEPHELE NEPHELE_GEN WORKDIR
# The tiny generated storm (Lambert, 3 km) -> .nph -> VDB of timestep 1 -> Blender (Cycles, CPU)
# renders it top-down with an absorbing volume -> blender_check.py compares Blender's alpha with
# 1 − exp(−τ) from the exported extinction. Tolerances: Cycles' sampling noise measured at 64
# samples is 0.011 max / 0.0003 mean in alpha (0.037 / 0.0011 at 16 samples); allowed 0.03 / 0.002.
# A half-voxel misplacement measured 0.06 max / 0.011 mean and a 0.5 px centroid shift (> 0.1 px).
set -euo pipefail
nephele=$1 gen=$2 work=$3
here=$(cd "$(dirname "$0")" && pwd)
command -v blender >/dev/null ||
  { echo "FAIL: no blender; install it with: bash tools/install-deps.sh tools/debian-packages-blender.txt" >&2; exit 1; }
rm -rf "$work" && mkdir -p "$work"
"$gen" wrf --proj lambert --times 2 -o "$work/storm.nc" >/dev/null
"$nephele" convert "$work/storm.nc" -o "$work/storm.nph" --no-progress
"$nephele" export-vdb "$work/storm.nph" -o "$work/vdb/storm" -t 1
vdb=$work/vdb/storm_0001.vdb
columns=$(/usr/bin/python3 -c "
import pyopenvdb, sys
g = pyopenvdb.read(sys.argv[1], 'density')
print(g.metadata['nephele_nx'], g.metadata['nephele_ny'], sep='x')" "$vdb")
start=$(date +%s.%N)
blender -b --factory-startup --python "$here/blender_vdb.py" -- absorption "$vdb" "$work/blender" \
  --columns "$columns" --samples 64 >"$work/blender.log" 2>&1 ||
  { tail -30 "$work/blender.log"; echo "FAIL: blender exited with an error" >&2; exit 1; }
echo "blender: ${columns} px, 64 samples, $(echo "$(date +%s.%N) - $start" | bc) s"
grep -q "blender_vdb: alpha" "$work/blender.log" || { tail -30 "$work/blender.log"; exit 1; }
/usr/bin/python3 "$here/blender_check.py" "$vdb" "$work/blender.npy" --max-abs 0.03 --mean-abs 0.002
