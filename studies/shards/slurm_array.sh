#!/usr/bin/env bash
# One shard of a sweep per SLURM array task. Submit it with studies/shards/slurm_submit.sh, which
# builds once, resolves the executable, submits this array and a dependent merge job:
#   bash studies/shards/slurm_submit.sh studies/shards/sweep.nml out/shards 16
# or by hand (N = the number of shards; EXE = the mpm1d executable, resolved on the login node):
#   sbatch --array=1-N --cpus-per-task=K slurm_array.sh SWEEP.nml OUTDIR N EXE
# Task i runs shard i of N on SLURM_CPUS_PER_TASK threads (OMP_NUM_THREADS is set to the same)
# and writes OUTDIR/<name>_shardIIIofNNN.h5 and OUTDIR/task_<i>.exit (its exit code, written also
# when the shard fails or is cancelled), so failed tasks are visible without sacct and can be
# resubmitted alone: slurm_submit.sh ... --array=<ids>, or sbatch --array=<ids> as above. The output
# file's name is the namelist's (mpm1d --dry-run says it, whatever the namelist's quoting), in OUTDIR.
# A task stopped by its time limit (SIGTERM) writes the cases it finished (exit 143); run again, it
# continues them (mpm1d --resume) instead of starting over.
#SBATCH --job-name=mpm1d-sweep
#SBATCH --cpus-per-task=1
#SBATCH --time=00:30:00
#SBATCH --output=mpm1d-shard-%a_job%A.log
# sbatch passes the submitting environment (loaded modules included) to the job; where a site
# uses --export=NONE, load here what mpm1d was built with, e.g.:
# module load gcc/12 hdf5/1.12
set -euo pipefail
usage="usage: sbatch --array=1-N [--cpus-per-task=K] slurm_array.sh SWEEP.nml OUTDIR N [EXE]"
input="${1:?$usage}"
out="${2:?$usage}"
id="${SLURM_ARRAY_TASK_ID:?not an array task: $usage}"
shards="${3:-}"
if [ -z "$shards" ]; then
  # only a full 1-N array tells N; a resubmitted subset (--array=3,7) does not
  if [ "${SLURM_ARRAY_TASK_MIN:-}" = 1 ] && [ "${SLURM_ARRAY_TASK_MAX:-}" = "${SLURM_ARRAY_TASK_COUNT:-}" ]; then
    shards="$SLURM_ARRAY_TASK_COUNT"
  else
    echo "slurm_array: give the number of shards N (3rd argument): $usage" >&2; exit 2
  fi
fi
mkdir -p "$out"
out="$(cd "$out" && pwd)"
exit_file="$out/task_$id.exit"
rm -f "$exit_file"
# the exit code of this task, written however it ends (failure, time limit, scancel)
on_exit() {
  local rc=$?
  echo "$rc" > "$exit_file.tmp.$$" && mv -f "$exit_file.tmp.$$" "$exit_file"
  echo "slurm_array: task $id of $shards exit $rc at $(date -u +%FT%TZ)"
}
trap on_exit EXIT
trap 'exit 143' TERM
trap 'exit 130' INT

exe="${4:-${MPM1D_EXE:-}}"
if [ -z "$exe" ]; then
  # fallback: ask fpm in the submit folder (slurm_submit.sh passes the executable instead)
  exe="${SLURM_SUBMIT_DIR:-.}/$(cd "${SLURM_SUBMIT_DIR:-.}" && fpm run --profile release --target mpm1d --runner echo 2>/dev/null | tail -n 1)"
fi
[ -x "$exe" ] || { echo "slurm_array: executable '$exe' not found" >&2; exit 2; }
[ "$id" -ge 1 ] && [ "$id" -le "$shards" ] || { echo "slurm_array: task $id outside 1..$shards" >&2; exit 2; }

threads="${SLURM_CPUS_PER_TASK:-1}"
export OMP_NUM_THREADS="$threads"
echo "slurm_array: task $id of $shards, job ${SLURM_ARRAY_JOB_ID:-?}_$id on $(hostname -s), $threads cpus," \
  "OMP_NUM_THREADS=$OMP_NUM_THREADS, $exe"

# the output file of the sweep, in OUTDIR: its name as mpm1d reads it from the namelist, and this shard's
dry="$("$exe" "$input" --dry-run --shard "$id/$shards")" || exit 2
name="$(basename "$(sed -n 's/^output: //p' <<<"$dry")")"
[ -n "$name" ] || { echo "slurm_array: no output file from $exe $input --dry-run" >&2; exit 2; }
output="output.file=$out/$name"
dry="$("$exe" "$input" "$output" --dry-run --shard "$id/$shards")" || exit 2
shard_file="$(sed -n "s/^shard $id: [0-9]* cases*, //p" <<<"$dry")"
resume=()
if [ -f "$shard_file" ]; then  # an earlier try of this task wrote part of it (a time limit): go on from there
  resume=(--resume)
  echo "slurm_array: continuing $shard_file (--resume)"
fi
"$exe" "$input" "$output" --shard "$id/$shards" --threads "$threads" "${resume[@]}"
