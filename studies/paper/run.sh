#!/usr/bin/env bash
# The founding paper's whole study (Tables 1-2, Figures 3b-10) for USF and USL, plus error
# against run time: builds mpm1d, runs both Table-2 sweeps (1200 runs; error pass in parallel,
# timing pass on one thread), the single runs behind Figs. 3b and 10, and writes every figure
# and summary.md into one folder.
# Usage: bash studies/paper/run.sh [output folder]     (default: out/paper)
# MPM1D_QUICK=1 shrinks the lists (3 element counts x 3 particle counts x 3 steps) and the
# timing pass, for testing the whole pipeline in seconds; the figures are then not the paper's.
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
cd "$root"
source studies/setup.sh
set -euo pipefail
out="$(mkdir -p "${1:-out/paper}" && cd "${1:-out/paper}" && pwd)"
start=$(date +%s.%N)

echo "== building mpm1d"
exe="$(mpm1d_build)"  # -march=native unless PORTABLE=1 (studies/setup.sh)

echo "== Table-2 sweeps (USF, USL)"
for scheme in usf usl; do
  # the study's namelist, with the output file placed in $out
  sed "s|file='sweep_$scheme.h5'|file='$out/sweep_$scheme.h5'|" "studies/paper/sweep_$scheme.nml" > "$out/sweep_$scheme.nml"
  if [ "${MPM1D_QUICK:-0}" = 1 ]; then
    sed -i -e 's/elements=1, 3, 7, 10, 20, 50/elements=1, 3, 10/' \
           -e 's/particles_per_element=1, 2, 3, 4, 5, 6, 7, 8, 9, 10/particles_per_element=1, 2, 10/' \
           -e 's/dt_fractions=0.05, .*0.50,/dt_fractions=0.05, 0.10, 0.50,/' \
           -e 's/min_time=0.01/min_time=0.001/' "$out/sweep_$scheme.nml"
  fi
  "$exe" "$out/sweep_$scheme.nml" | tee "$out/sweep_$scheme.log" | grep -E 'pass|cases|wrote'
done

echo "== single runs: Fig. 3b (verification case) and Fig. 10 (initial velocity field)"
runs=()
for scheme in usf usl; do
  cat > "$out/fig3b_$scheme.nml" <<NML
&discretisation scheme='$scheme', elements=20, particles_per_element=1, dt_fraction=0.1 /
&run periods=2.0 /
&output file='$out/fig3b_$scheme.h5' /
NML
  "$exe" "$out/fig3b_$scheme.nml" > "$out/fig3b_$scheme.log"
  runs+=("$out/fig3b_$scheme.h5")
done
for elements in 1 3 7 10; do
  cat > "$out/fig10_e$elements.nml" <<NML
&discretisation scheme='usl', elements=$elements, particles_per_element=1, dt_fraction=0.1 /
&run periods=2.0 /
&output file='$out/fig10_e$elements.h5', history=.false., snapshot_times=0.0 /
NML
  "$exe" "$out/fig10_e$elements.nml" > "$out/fig10_e$elements.log"
  runs+=("$out/fig10_e$elements.h5")
done

echo "== figures and summary"
"$PYTHON" -m mpm1d_post.studies.paper --usf "$out/sweep_usf.h5" --usl "$out/sweep_usl.h5" \
  --runs "${runs[@]}" -o "$out"
end=$(date +%s.%N)
total=$(awk -v a="$start" -v b="$end" 'BEGIN{printf "%.1f", b-a}')
printf '\n## Total wall time of this command\n\n%s s (`bash studies/paper/run.sh`, including the build check).\n' \
  "$total" >> "$out/summary.md"
echo "== done in $total s: figures and summary.md in $out"
