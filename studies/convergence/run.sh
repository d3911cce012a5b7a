#!/usr/bin/env bash
# Spatial convergence of the vibrating bar to fine meshes (possible since the grid extends beyond the
# free end): USF and USL, 2 particles per element, 10 % of dx/c, half a period, elements 100 .. 6400,
# at three amplitudes v0 = 0.1, 0.01 and 0.001 m/s. Shows the second-order fall of the u_cm error and
# the floor where it meets the difference between the code's continuum law (sigma = E ln F, particles
# really moving) and the linear elasticity of the exact solution.
# Writes out/convergence/{convergence.h5, convergence.png, summary.md}.
# Usage: bash studies/convergence/run.sh [output folder]   (MPM1D_QUICK=1: up to 800 elements)
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
cd "$root"
source studies/setup.sh
set -euo pipefail
out="$(mkdir -p "${1:-out/convergence}" && cd "${1:-out/convergence}" && pwd)"
exe="$(mpm1d_build)"  # -march=native unless PORTABLE=1 (studies/setup.sh)
elements="100, 200, 400, 800, 1600, 3200, 6400"
[ "${MPM1D_QUICK:-0}" = 1 ] && elements="100, 200, 400, 800"
cat > "$out/convergence.nml" <<NML
! Spatial convergence of the bar: studies/convergence/run.sh
&discretisation particles_per_element=2, dt_fraction=0.1 /
&run periods=0.5 /
&output file='$out/convergence.h5' /
&sweep schemes='usf', 'usl', elements=$elements, velocity_amplitudes=0.1, 0.01, 0.001, min_time=0 /
NML
start=$EPOCHREALTIME
"$exe" "$out/convergence.nml" | grep -E '^(mpm1d|error pass|[0-9]+ cases|wrote)'
end=$EPOCHREALTIME
"$PYTHON" -m mpm1d_post.convergence "$out/convergence.h5" "$out" \
  --wall-time "$(awk -v a="$start" -v b="$end" 'BEGIN { printf "%.1f", b - a }')"
