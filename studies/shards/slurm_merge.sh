#!/usr/bin/env bash
# Merge the shards of a SLURM array sweep (studies/shards/slurm_array.sh) into one file, or tell
# which tasks are missing. Run as the dependent job that slurm_submit.sh submits, or by hand:
#   bash studies/shards/slurm_merge.sh OUTDIR            check every task_<i>.exit, then merge
#   bash studies/shards/slurm_merge.sh OUTDIR --failed   print the ids (1,5,7) whose exit file is
#                                                        missing or not 0 (for --array=), nothing
#                                                        when all are done
#   bash studies/shards/slurm_merge.sh OUTDIR --status   one line per task that is not done
# It reads N, the executable and the file name from OUTDIR/submit.env (written by slurm_submit.sh).
# An incomplete set is refused: first here by the exit files, then by `mpm1d merge` itself, which
# refuses missing, repeated or foreign shards. The merge job writes OUTDIR/merge.exit.
#SBATCH --job-name=mpm1d-merge
#SBATCH --cpus-per-task=1
#SBATCH --time=00:10:00
# sbatch passes the submitting environment (loaded modules included) to the job; where a site
# uses --export=NONE, load here what mpm1d was built with, e.g.:
# module load gcc/12 hdf5/1.12
set -euo pipefail
out="${1:?usage: slurm_merge.sh OUTDIR [--failed|--status]}"
mode="${2:-merge}"
out="$(cd "$out" && pwd)"
[ -f "$out/submit.env" ] || { echo "slurm_merge: $out/submit.env missing (submit with slurm_submit.sh)" >&2; exit 2; }
# shellcheck disable=SC1091
source "$out/submit.env"   # SHARDS, EXE, NAME, CPUS_PER_TASK

failed=()
report=()
for i in $(seq 1 "$SHARDS"); do
  f="$out/task_$i.exit"
  if [ ! -f "$f" ]; then
    failed+=("$i"); report+=("task $i: no exit file (not run yet, running, or killed without a trace)")
  elif [ "$(cat "$f")" != 0 ]; then
    log="$(ls -t "$out"/logs/shard_"$i"_job*.log 2>/dev/null | head -n 1 || true)"
    failed+=("$i"); report+=("task $i: exit $(cat "$f")${log:+ (log: $log)}")
  fi
done
ids="$(IFS=,; echo "${failed[*]:-}")"

case "$mode" in
  --failed) [ -z "$ids" ] || echo "$ids"; exit 0 ;;
  --status)
    [ "${#report[@]}" = 0 ] || printf '%s\n' "${report[@]}"
    echo "$((SHARDS - ${#failed[@]})) of $SHARDS tasks done"
    exit 0 ;;
  merge) ;;
  *) echo "slurm_merge: unknown option '$mode'" >&2; exit 2 ;;
esac

trap 'rc=$?; echo "$rc" > "$out/merge.exit.tmp.$$" && mv -f "$out/merge.exit.tmp.$$" "$out/merge.exit"' EXIT
rm -f "$out/merge.exit"
if [ -n "$ids" ]; then
  printf 'slurm_merge: %s\n' "${report[@]}" >&2
  echo "slurm_merge: refusing to merge an incomplete set; resubmit the tasks with" >&2
  echo "  bash studies/shards/slurm_submit.sh $out/sweep.nml $out $SHARDS --array=$ids" >&2
  exit 1
fi
base="${NAME%.h5}"
"$EXE" merge "$out/$NAME" "$out/${base}"_shard*of"$(printf %03d "$SHARDS")".h5
