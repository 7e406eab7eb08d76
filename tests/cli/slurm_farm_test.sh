#!/usr/bin/env bash
# A one-node Slurm cluster started and stopped by this test (munged, slurmctld and slurmd from
# Debian, no cgroups, everything under one temporary folder and on free ports): runs the
# examples/03-slurm-farm recipe — a job array of `nephele animate --chunk I/N` and an encode job
# `--dependency=afterok` — and checks that every frame is byte-identical to one local run and that
# the video was encoded. Whatever it started is stopped on exit, pass or fail.
# usage: slurm_farm_test.sh NEPHELE NEPHELE_GEN SOURCE_DIR WORKDIR
set -uo pipefail
nephele=$(realpath "$1") gen=$2 src=$3 work=$4
fail() { echo "FAIL [slurm-farm]: $*" >&2; for l in "$work"/log/*.log "$work"/out/*.log; do [ -f "$l" ] && { echo "--- $l" >&2; tail -n 20 "$l" >&2; }; done; exit 1; }
for tool in munged slurmctld slurmd sbatch sinfo; do
  command -v "$tool" >/dev/null || fail "$tool is not installed (tools/debian-packages.txt: munge, slurmctld, slurmd, slurm-client)"
done

pids=()
cleanup() {
  for p in "${pids[@]}"; do kill "$p" 2>/dev/null; done
  for p in "${pids[@]}"; do wait "$p" 2>/dev/null; done
  [ -f "$work/munge/munged.pid" ] && kill "$(cat "$work/munge/munged.pid")" 2>/dev/null
  return 0
}
trap cleanup EXIT
rm -rf "$work" && mkdir -p "$work"/{munge,state,spool,log,out,local}
chmod 700 "$work/munge"

# --- munge: our own key, socket and daemon (root may run it with --force) ---------------------
dd if=/dev/urandom of="$work/munge/munge.key" bs=1024 count=1 status=none
chmod 400 "$work/munge/munge.key"
munged --force --key-file="$work/munge/munge.key" --socket="$work/munge/munge.sock" \
  --pid-file="$work/munge/munged.pid" --log-file="$work/log/munged.log" --seed-file="$work/munge/seed" ||
  fail "munged did not start"

# --- slurm.conf: this host as controller and only node, free ports from the kernel --------------
free_port() { python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'; }
host=$(hostname -s)
cpus=$(nproc)
cat >"$work/slurm.conf" <<CONF
ClusterName=nephele-test
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=$(free_port)
SlurmdPort=$(free_port)
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket=$work/munge/munge.sock
CredType=cred/munge
StateSaveLocation=$work/state
SlurmdSpoolDir=$work/spool
SlurmctldPidFile=$work/slurmctld.pid
SlurmdPidFile=$work/slurmd.pid
SlurmctldLogFile=$work/log/slurmctld.log
SlurmdLogFile=$work/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SwitchType=switch/none
MpiDefault=none
SchedulerType=sched/builtin
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
ReturnToService=2
NodeName=$host NodeAddr=127.0.0.1 CPUs=$cpus State=UNKNOWN
PartitionName=test Nodes=ALL Default=YES MaxTime=INFINITE State=UP OverSubscribe=YES
CONF
export SLURM_CONF=$work/slurm.conf
slurmctld -D -i -f "$SLURM_CONF" >"$work/log/slurmctld.out" 2>&1 &
pids+=($!)
slurmd -D -f "$SLURM_CONF" >"$work/log/slurmd.out" 2>&1 &
pids+=($!)

# --- data and scene: 10 frames of the tiny storm at 64x36 ------------------------------------------
"$gen" wrf --times 3 -o "$work/wrfout.nc" >/dev/null || fail "nephele-gen failed"
"$nephele" convert "$work/wrfout.nc" -o "$work/storm.nph" --no-progress >/dev/null || fail "convert failed"
cat >"$work/scene.json" <<'JSON'
{
  "data": { "path": "storm.nph" },
  "camera": { "preset": "oblique" },
  "sun": { "azimuth_deg": 140, "elevation_deg": 35 },
  "quality": "draft",
  "output": { "width": 64, "height": 36 },
  "height_exaggeration": 8,
  "animation": { "from": 0, "to": 2, "fps": 25, "duration_s": 0.36 }
}
JSON
NEPHELE_LOG=warn "$nephele" animate "$work/scene.json" -o "$work/local" --no-progress >/dev/null || fail "local run failed"

# --- the recipe: 3 chunks, then the encode job; --wait blocks until the encode job ends ----------
# (Slurm starts the jobs as soon as slurmd has registered: no readiness polling, no timeouts.)
NEPHELE="$nephele" NEPHELE_FARM_WAIT=1 NEPHELE_LOG=warn \
  bash "$src/examples/03-slurm-farm/submit.sh" "$work/scene.json" "$work/out" 3 "$work/out/animation.mov" ||
  fail "the Slurm recipe failed"

n=$(ls "$work/local" | grep -c '^frame_.*\.png$')
[ "$n" -eq 10 ] || fail "the local run wrote $n frames, expected 10"
for f in "$work"/local/frame_*.png; do
  cmp -s "$f" "$work/out/$(basename "$f")" || fail "farm frame $(basename "$f") differs from the local run"
done
[ "$(ls "$work/out" | grep -c '^slurm-frames-.*\.log$')" -eq 3 ] || fail "expected 3 array-task logs: $(ls "$work/out")"
frames=$(ffprobe -v error -count_frames -select_streams v:0 -show_entries stream=nb_read_frames -of csv=p=0 \
  "$work/out/animation.mov") || fail "ffprobe could not read the encoded video"
[ "$frames" -eq 10 ] || fail "the encoded video has $frames frames, expected 10"
echo "slurm-farm: 10 frames from 3 array tasks byte-identical to one local run; video encoded after afterok"
