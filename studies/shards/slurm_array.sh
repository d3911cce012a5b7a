#!/usr/bin/env bash
# A sweep as a SLURM job array: one shard per array task, then a dependent merge job.
#   sbatch --array=1-16 studies/shards/slurm_array.sh studies/shards/sweep.nml out/shards
#   sbatch --dependency=afterok:<array job id> --wrap \
#     "build/<profile>/app/mpm1d merge out/shards/sweep_both.h5 out/shards/sweep_both_shard*of016.h5"
# Build first on the login node: fpm build --profile release
#SBATCH --job-name=mpm1d-sweep
#SBATCH --cpus-per-task=2
#SBATCH --time=00:30:00
#SBATCH --output=mpm1d-shard-%a.log
set -euo pipefail
input="${1:?usage: sbatch --array=1-N slurm_array.sh sweep.nml outdir}"
out="${2:-out/shards}"
mkdir -p "$out"
exe="$(fpm run --profile release --target mpm1d --runner echo 2>/dev/null | tail -n 1)"
name=$(sed -n "s/.*file='\([^']*\)'.*/\1/p" "$input" | head -n 1)
sed "s|file='$name'|file='$out/$name'|" "$input" > "$out/sweep_task$SLURM_ARRAY_TASK_ID.nml"
export OMP_NUM_THREADS="${SLURM_CPUS_PER_TASK:-1}"
"$exe" "$out/sweep_task$SLURM_ARRAY_TASK_ID.nml" \
  --shard "$SLURM_ARRAY_TASK_ID/$SLURM_ARRAY_TASK_COUNT" --threads "$OMP_NUM_THREADS"
