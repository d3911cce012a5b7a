#!/usr/bin/env bash
# End-to-end check of the paper study's pipeline on a small real sweep: the executable, the
# sweep files, the single runs and the post-processing with the real interpreter and packages.
# Every figure must be written and the summary must carry its sections.
set -uo pipefail
cd "$(dirname "$0")/../.."
out=build/test_scratch/paper
rm -rf "$out"
passed=0; failed=0
check() { if eval "$2"; then passed=$((passed+1)); else failed=$((failed+1)); echo "FAIL $1"; fi; }
MPM1D_QUICK=1 bash studies/paper/run.sh "$out" > "$out.log" 2>&1
check "pipeline exits 0" "[ $? = 0 ]"
for f in fig3b_ucm_verification fig4_error_map_usf fig7_error_map_usl fig5_time_map_usf fig8_time_map_usl \
         fig6_time_fits_usf fig9_time_fits_usl fig10_initial_velocity error_vs_time; do
  check "$f.png written" "[ -s $out/$f.png ]"
done
check "summary written" "[ -s $out/summary.md ]"
for section in '## Findings' 'Pareto' 'R²' 'Total wall time' 'Verification case'; do
  check "summary has '$section'" "grep -q '$section' $out/summary.md"
done
check "no partial files left" "! ls $out/*.part >/dev/null 2>&1"
[ "$failed" = 0 ] || cat "$out.log"
echo "test_paper_pipeline: $passed passed, $failed failed"
[ "$failed" = 0 ]
