#!/usr/bin/env bash
# Renders a nephele animation on a Slurm cluster: a job array of N contiguous frame chunks
# (`nephele animate --chunk I/N`), then one encode job that starts only when every chunk succeeded
# (`--dependency=afterok`). Frames are byte-identical to one local run (the jitter is a hash of the
# pixel, docs/animation.md), so chunks may run on any node in any order; a re-submitted chunk skips
# the frames it already finished.
#
# Usage: submit.sh SCENE OUT_DIR [CHUNKS] [VIDEO]
#   SCENE    scene file (or a wrfout/ICON/.nph file for a quick look), on storage every node sees
#   OUT_DIR  shared folder for frame_NNNNNN.png and the logs
#   CHUNKS   array size (default 8)
#   VIDEO    the encode job's output (default OUT_DIR/animation.mov, ProRes 4444 with alpha)
# Environment: NEPHELE (the nephele binary, default `nephele` on PATH), SBATCH_ARGS (extra sbatch
# options for both jobs, e.g. "--partition=render --time=1:00:00"), NEPHELE_FARM_WAIT=1 (block until
# the encode job has finished and return its exit status: for scripts and tests).
# Prints the two job ids.
set -euo pipefail
if [ $# -lt 2 ]; then
  sed -n '2,20p' "$0" >&2
  exit 2
fi
scene=$(realpath "$1")
out=$(realpath -m "$2")
chunks=${3:-8}
video=${4:-$out/animation.mov}
nephele=${NEPHELE:-nephele}
here=$(cd "$(dirname "$0")" && pwd)
mkdir -p "$out"
# shellcheck disable=SC2086
frames=$(sbatch --parsable ${SBATCH_ARGS:-} --array="0-$((chunks - 1))" --job-name=nephele-frames \
  --output="$out/slurm-frames-%A_%a.log" \
  --export=ALL,NEPHELE="$nephele",NEPHELE_SCENE="$scene",NEPHELE_OUT="$out",NEPHELE_CHUNKS="$chunks" \
  "$here/render-chunk.sbatch")
frames=${frames%%;*}
wait_flag=()
[ "${NEPHELE_FARM_WAIT:-0}" = 1 ] && wait_flag=(--wait)
# shellcheck disable=SC2086
encode=$(sbatch --parsable ${SBATCH_ARGS:-} "${wait_flag[@]}" --dependency="afterok:$frames" --kill-on-invalid-dep=yes \
  --job-name=nephele-encode --output="$out/slurm-encode-%j.log" \
  --export=ALL,NEPHELE="$nephele",NEPHELE_SCENE="$scene",NEPHELE_OUT="$out",NEPHELE_VIDEO="$video" \
  "$here/encode.sbatch")
echo "frames job $frames (array 0-$((chunks - 1))), encode job ${encode%%;*}"
