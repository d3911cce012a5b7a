#!/usr/bin/env bash
# Submit a sweep as a SLURM job array of N shards (studies/shards/slurm_array.sh) and a merge job
# that runs when every task has succeeded (--dependency=afterok; it is cancelled if one fails).
# Run it on the login node, from anywhere:
#   bash studies/shards/slurm_submit.sh SWEEP.nml OUTDIR N [--array=IDS] [--cpus-per-task=K] [sbatch options]
#   e.g. bash studies/shards/slurm_submit.sh studies/shards/sweep.nml out/shards 16 --partition=short --time=00:20:00
# The first submission builds mpm1d (fpm build --profile release) unless MPM1D_EXE names an
# executable, copies the executable and the namelist into OUTDIR (every task and every
# resubmission then runs the same binary on the same sweep) and records N, the executable and
# the CPUs per task in OUTDIR/submit.env. Other options (partition, account, time, qos...) go to
# both sbatch calls. The sweep's case count and output file come from mpm1d itself
# (`mpm1d SWEEP.nml --dry-run --shard 1/N`, any namelist syntax: file = "x y.h5" too), and N greater
# than the case count is refused before anything is submitted.
# A task stopped by its time limit (SIGTERM) writes the cases it finished; resubmitted, it continues
# them (--resume) instead of starting over.
# Resubmit failed tasks only (the exit files tell which; the ids as slurm_merge.sh --failed prints):
#   bash studies/shards/slurm_submit.sh SWEEP.nml OUTDIR N --array=$(bash studies/shards/slurm_merge.sh OUTDIR --failed)
# The merge job of a resubmission merges every shard in OUTDIR, old and new.
# Prints `array_job=<id>` and `merge_job=<id>` on standard output.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/../.." && pwd)"
usage="usage: slurm_submit.sh SWEEP.nml OUTDIR N [--array=IDS] [--cpus-per-task=K] [sbatch options]"
input="${1:?$usage}"; outarg="${2:?$usage}"; shards="${3:?$usage}"
shift 3
ids=""; cpus=""; extra=()
for a in "$@"; do
  case "$a" in
    --array=*) ids="${a#--array=}"; [ -n "$ids" ] || { echo "slurm_submit: --array= is empty: nothing to submit" >&2; exit 3; } ;;
    --cpus-per-task=*) cpus="${a#--cpus-per-task=}" ;;
    *) extra+=("$a") ;;
  esac
done
fail() { echo "slurm_submit: $*" >&2; exit 2; }
[[ "$shards" =~ ^[0-9]+$ ]] && [ "$shards" -ge 1 ] && [ "$shards" -le 999 ] || fail "N must be 1..999 (got '$shards')"
[ -f "$input" ] || fail "no namelist '$input'"
command -v sbatch >/dev/null 2>&1 || fail "sbatch not found (no SLURM here?)"
mkdir -p "$outarg/logs"
out="$(cd "$outarg" && pwd)"

# the namelist as given (the tasks write into OUTDIR: slurm_array.sh overrides output.file); a
# different sweep already in OUTDIR is refused
nml="$(cat "$input")"
if [ -f "$out/submit.env" ]; then
  # shellcheck disable=SC1091
  source "$out/submit.env"
  [ "$SHARDS" = "$shards" ] || fail "$out holds a sweep in $SHARDS shards, not $shards"
  [ "$nml" = "$(cat "$out/sweep.nml")" ] || fail "$out holds a different sweep ($out/sweep.nml); use another folder"
  # the same thread count everywhere: mpm1d merge refuses shards whose namelists differ
  if [ -n "$cpus" ] && [ "$cpus" != "$CPUS_PER_TASK" ]; then
    fail "$out was submitted with --cpus-per-task=$CPUS_PER_TASK; resubmit with the same"
  fi
  cpus="$CPUS_PER_TASK"; exe="$EXE"
  [ -x "$exe" ] || fail "executable $exe is gone"
  name="$NAME"
else
  cpus="${cpus:-1}"
  [[ "$cpus" =~ ^[0-9]+$ ]] && [ "$cpus" -ge 1 ] || fail "--cpus-per-task must be >= 1"
  if [ -n "${MPM1D_EXE:-}" ]; then
    src="$MPM1D_EXE"
  else
    (cd "$root" && fpm build --profile release >/dev/null)
    src="$root/$(cd "$root" && fpm run --profile release --target mpm1d --runner echo 2>/dev/null | tail -n 1)"
  fi
  [ -x "$src" ] || fail "executable '$src' not found"
  # ask mpm1d: the number of cases and the output file (it refuses N > cases, and any bad input)
  dry="$("$src" "$input" --dry-run --shard "1/$shards" 2>&1)" || fail "mpm1d refuses the sweep of $input in $shards shards:
$dry"
  cases="$(sed -n 's/^cases: //p' <<<"$dry")"; output="$(sed -n 's/^output: //p' <<<"$dry")"
  [[ "$cases" =~ ^[0-9]+$ ]] && [ -n "$output" ] || fail "no case count or output file from '$src $input --dry-run':
$dry"
  [ "$shards" -le "$cases" ] || fail "N = $shards shards for a sweep of $cases cases: a task would have none"
  name="$(basename "$output")"
  exe="$out/mpm1d"
  cp "$src" "$exe.tmp.$$" && mv -f "$exe.tmp.$$" "$exe"
  printf '%s\n' "$nml" > "$out/sweep.nml"
  printf 'SHARDS=%q\nEXE=%q\nNAME=%q\nCPUS_PER_TASK=%q\n' "$shards" "$exe" "$name" "$cpus" > "$out/submit.env"
fi
ids="${ids:-1-$shards}"
# every id (ranges a-b, lists, an optional %limit) within 1..N
spec="${ids%%\%*}"
for part in ${spec//,/ }; do
  [[ "$part" =~ ^([0-9]+)(-([0-9]+))?$ ]] || fail "--array='$ids': give ids and ranges like 1-8 or 3,5"
  lo="${BASH_REMATCH[1]}"; hi="${BASH_REMATCH[3]:-$lo}"
  [ "$lo" -ge 1 ] && [ "$hi" -le "$shards" ] && [ "$lo" -le "$hi" ] || fail "--array='$ids' is outside 1..$shards"
done

array_job=$(sbatch --parsable --array="$ids" --cpus-per-task="$cpus" --job-name=mpm1d-sweep \
  --output="$out/logs/shard_%a_job%A.log" "${extra[@]}" \
  "$here/slurm_array.sh" "$out/sweep.nml" "$out" "$shards" "$exe")
array_job="${array_job%%;*}"
merge_job=$(sbatch --parsable --dependency="afterok:$array_job" --kill-on-invalid-dep=yes \
  --job-name=mpm1d-merge --cpus-per-task=1 --output="$out/logs/merge_job%j.log" "${extra[@]}" \
  "$here/slurm_merge.sh" "$out")
merge_job="${merge_job%%;*}"
echo "$(date -u +%FT%TZ) array_job=$array_job array=$ids merge_job=$merge_job" >> "$out/jobs.txt"
echo "slurm_submit: tasks $ids of $shards as job $array_job ($cpus cpus each), merge as job $merge_job" \
  "-> $out/$name; exit codes in $out/task_<id>.exit" >&2
echo "array_job=$array_job"
echo "merge_job=$merge_job"
