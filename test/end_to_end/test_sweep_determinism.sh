#!/usr/bin/env bash
# A sweep gives the same bits on 1 and 2 threads, every time: 7,200 short cases (so that the threads
# set up cases at the same moments as often as possible) once on 1 thread, then $SWEEP_REPEATS times
# (20 unless set; test/run_tests.sh: 3 in its default tier, 20 with --all) on 2 threads, each
# compared bit for bit (max_error, status, min_node_mass_ratio). Before case configurations were
# built one thread at a time (mpm_sweep, over_cases), about one such sweep in ten to a hundred ran a
# case on the wrong path, depending on the load of the machine.
set -uo pipefail
cd "$(dirname "$0")/../.."
source studies/setup.sh >/dev/null
set -uo pipefail
repeats="${SWEEP_REPEATS:-20}"
exe="$(fpm run --profile release --target mpm1d --runner echo 2>/dev/null | tail -n 1)"
out=build/test_scratch/determinism
rm -rf "$out"; mkdir -p "$out"
va=$(awk 'BEGIN { for (i = 1; i <= 100; i++) printf "%s%g", (i > 1 ? ", " : ""), 0.01 * i }')
for th in 1 2; do
  cat > "$out/t$th.nml" <<NML
&run end_time=5.0e-3 /
&output file='$out/t$th.h5' /
&sweep schemes='usf', 'usl', elements=1, 2, 3, particles_per_element=1, 2, 4, 8, dt_fractions=0.1, 0.3, 0.5,
       velocity_amplitudes=$va, min_time=0, threads=$th /
NML
done
passed=0; failed=0
"$exe" "$out/t1.nml" > /dev/null 2>&1 && passed=$((passed+1)) || { failed=$((failed+1)); echo "FAIL the 1-thread sweep ran"; }
differ=0
for i in $(seq "$repeats"); do
  "$exe" "$out/t2.nml" > /dev/null 2>&1 || { differ=$((differ+1)); continue; }
  for column in max_error status min_node_mass_ratio; do
    h5diff -q "$out/t1.h5" "$out/t2.h5" /cases/$column /cases/$column > /dev/null 2>&1 || { differ=$((differ+1)); break; }
  done
done
if [ "$differ" = 0 ]; then passed=$((passed+1)); echo "ok   $repeats two-thread sweeps of 7200 cases equal the one-thread sweep bit for bit"
else failed=$((failed+1)); echo "FAIL $differ of $repeats two-thread sweeps differ from the one-thread sweep"; fi
echo "test_sweep_determinism: $passed passed, $failed failed"
[ "$failed" = 0 ]
