#!/usr/bin/env bash
# The paper's verification case (Fig. 3b): 20 elements, 1 particle per element, 10 % of dx/c,
# two periods, USF and USL. Builds mpm1d, runs both, writes out/verification/{usf,usl}.h5.
# Usage: bash studies/verification/run.sh [output folder]
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
cd "$root"
source studies/setup.sh
set -euo pipefail
out="${1:-out/verification}"
mkdir -p "$out"
exe="$(mpm1d_build)"  # -march=native unless PORTABLE=1 (studies/setup.sh)
for scheme in usf usl; do
  cat > "$out/$scheme.nml" <<NML
&discretisation scheme='$scheme', elements=20, particles_per_element=1, dt_fraction=0.1 /
&run periods=2.0 /
&output file='$out/$scheme.h5', snapshot_times=0.0 /
NML
  "$exe" "$out/$scheme.nml" | grep -E '^(max|steps|wrote)'
done
