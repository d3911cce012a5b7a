#!/usr/bin/env bash
# Spatial convergence of the vibrating bar to fine meshes with both elastic laws (issue 26): the code's
# hencky law (sigma = E ln F) and the linear law (sigma = E (J - 1), for which the linear-elastic exact
# solution is exact at any amplitude), 2 particles per element, 10 % of dx/c, half a period, at
# v0 = 0.1, 0.01 and 0.001 m/s:
#   linear.nml  linear shapes, USF and USL, 100 .. 3200 elements
#   wide.nml    uGIMP, cpGIMP, quadratic and cubic B-splines, USL, 100 .. 1600 elements
#   parts.nml   USL, one mesh, linear and uGIMP x both laws x the three amplitudes, with histories: the
#               error split into the model difference (hencky - linear law, uGIMP) and the linear shapes'
#               method error (linear - uGIMP, linear law)
# Writes out/convergence/{linear,wide,parts}.h5, convergence.png, parts.png and summary.md.
# Usage: bash studies/convergence/run.sh [output folder]   (MPM1D_QUICK=1: up to 800 elements with linear shapes, 400 with uGIMP,
# the only wide shape; seconds)
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
cd "$root"
source studies/setup.sh
set -euo pipefail
out="$(mkdir -p "${1:-out/convergence}" && cd "${1:-out/convergence}" && pwd)"
exe="$(mpm1d_build)"  # -march=native unless PORTABLE=1 (studies/setup.sh)
linear="100, 200, 400, 800, 1600, 3200"; wide="100, 200, 400, 800, 1600"
shapes="'ugimp', 'cpgimp', 'bspline2', 'bspline3'"; parts=1600
if [ "${MPM1D_QUICK:-0}" = 1 ]; then linear="100, 200, 400, 800"; wide="100, 200, 400"; shapes="'ugimp'"; parts=400; fi
common="&discretisation particles_per_element=2, dt_fraction=0.1 /
&run periods=0.5 /"
cat > "$out/linear.nml" <<NML
! Spatial convergence of the bar, linear shapes: studies/convergence/run.sh
$common
&output file='$out/linear.h5' /
&sweep scheme='usf', 'usl', law='hencky', 'linear', velocity_amplitude=0.1, 0.01, 0.001, elements=$linear,
       min_time=0 /
NML
cat > "$out/wide.nml" <<NML
! Spatial convergence of the bar, the wide shapes: studies/convergence/run.sh
$common
&output file='$out/wide.h5' /
&sweep scheme='usl', shape=$shapes, law='hencky', 'linear', velocity_amplitude=0.1, 0.01, 0.001,
       elements=$wide, min_time=0 /
NML
cat > "$out/parts.nml" <<NML
! The parts of the error (histories): studies/convergence/run.sh
$common
&output file='$out/parts.h5' /
&sweep scheme='usl', shape='linear', 'ugimp', law='hencky', 'linear', velocity_amplitude=0.1, 0.01, 0.001,
       elements=$parts, min_time=0, histories=.true. /
NML
start=$EPOCHREALTIME
for sweep in linear wide parts; do
  "$exe" --quiet "$out/$sweep.nml"
done
end=$EPOCHREALTIME
"$PYTHON" -m mpm1d_post.studies.convergence "$out/linear.h5" "$out/wide.h5" --parts "$out/parts.h5" --outdir "$out" \
  --wall-time "$(awk -v a="$start" -v b="$end" 'BEGIN { printf "%.1f", b - a }')"
