#!/usr/bin/env bash
# Run a sweep as N shards in parallel processes on this machine, then merge them.
# Each shard writes its own file; a failed shard can be rerun alone (same command with --shard).
# Usage: bash studies/shards/local_parallel.sh [shards] [sweep.nml] [output folder]
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
cd "$root"
source studies/setup.sh
set -euo pipefail
shards="${1:-2}"
input="${2:-studies/shards/sweep.nml}"
out="$(mkdir -p "${3:-out/shards}" && cd "${3:-out/shards}" && pwd)"
exe="$(mpm1d_build)"  # -march=native unless PORTABLE=1 (studies/setup.sh)
# the output file's name as mpm1d reads it (any quoting), in the output folder; the shards' files
dry="$("$exe" "$input" --dry-run --shard "1/$shards")"
name="$(basename "$(sed -n 's/^output: //p' <<<"$dry")")"
output="output.file=$out/$name"
mapfile -t files < <("$exe" "$input" "$output" --dry-run --shard "1/$shards" | sed -n 's/^shard [0-9]*: [0-9]* cases*, //p')
pids=()
for i in $(seq 1 "$shards"); do
  # one thread per shard process: the shards themselves are the parallelism
  OMP_NUM_THREADS=1 "$exe" "$input" "$output" --shard "$i/$shards" --threads 1 > "$out/shard$i.log" 2>&1 &
  pids+=($!)
done
status=0
for i in "${!pids[@]}"; do
  wait "${pids[$i]}" || { echo "shard $((i+1)) failed: see $out/shard$((i+1)).log" >&2; status=1; }
done
[ "$status" = 0 ] || exit 1
"$exe" merge "$out/$name" "${files[@]}"
