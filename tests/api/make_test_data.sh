#!/usr/bin/env bash
# Test data of the plugin API tests: a tiny generated storm (3 hourly timesteps, 40x36x20) as
# wrfout and converted to a .nph cache. usage: make_test_data.sh NEPHELE_GEN NEPHELE WORKDIR
set -euo pipefail
gen=$1 nephele=$2 work=$3
mkdir -p "$work"
"$gen" wrf --size tiny --times 3 -o "$work/storm.nc" >/dev/null
"$nephele" convert "$work/storm.nc" -o "$work/storm.nph" --no-progress >/dev/null
echo "api test data in $work: storm.nc, storm.nph"
