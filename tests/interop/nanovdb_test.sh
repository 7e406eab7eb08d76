#!/usr/bin/env bash
# NanoVDB export (issue 16): `nephele export-vdb --nanovdb` of the generated storm, read back by
# NanoVDB's own tools (nanovdb_validate: checksums and tree structure; nanovdb_print: the grids)
# and by nephele_nanovdb_check (every voxel against the .nph, transform against the OpenVDB one).
# usage: nanovdb_test.sh NEPHELE NEPHELE_GEN NANOVDB_CHECK WORKDIR
set -euo pipefail
nephele=$1 gen=$2 check=$3 work=$4
fail() { echo "FAIL: $*" >&2; exit 1; }
rm -rf "$work" && mkdir -p "$work"
"$gen" wrf --times 2 -o "$work/wrfout.nc" >/dev/null
"$nephele" convert "$work/wrfout.nc" -o "$work/storm.nph" --no-progress >/dev/null
"$nephele" export-vdb "$work/storm.nph" -o "$work/vdb/storm" --nanovdb --stats >"$work/stats"
for t in 0000 0001; do
  [ -s "$work/vdb/storm_$t.vdb" ] || fail "no storm_$t.vdb"
  [ -s "$work/vdb/storm_$t.nvdb" ] || fail "no storm_$t.nvdb"
done
grep -q "nanovdb_file_bytes=" "$work/stats" || fail "--stats does not report the NanoVDB file: $(cat "$work/stats")"
[ -z "$(ls -A "$work/vdb" | grep -v -E '^storm_000[01]\.n?vdb$')" ] || fail "stray files: $(ls -A "$work/vdb")"
nanovdb_validate "$work/vdb/storm_0000.nvdb" "$work/vdb/storm_0001.nvdb" >"$work/validate" 2>&1 ||
  fail "nanovdb_validate: $(cat "$work/validate")"
nanovdb_print -s "$work/vdb/storm_0001.nvdb" >"$work/print" 2>&1 || fail "nanovdb_print: $(cat "$work/print")"
for g in ice_extinction water_extinction density; do
  grep -q "$g" "$work/print" || fail "nanovdb_print lists no grid $g: $(cat "$work/print")"
done
"$check" "$work/storm.nph" "$work/vdb/storm_0000.nvdb" 0
"$check" "$work/storm.nph" "$work/vdb/storm_0001.nvdb" 1
echo "NanoVDB export checked"
