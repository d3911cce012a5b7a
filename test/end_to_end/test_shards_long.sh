#!/usr/bin/env bash
# Second tier (bash test/run_tests.sh --all): a sweep of 1000 cases run as 1000 shards of one case
# (1000 runs of mpm1d, about half a minute), then merged (issue 16, section 3):
#   - the 1000 shards write 1000 distinct names with the count's four digits;
#   - `mpm1d merge` takes them; its CPU time (user + system, which hardly depends on the machine's
#     load) is printed, not tested (no test depends on time): about 3-4 s since the merge is linear in
#     the shards (200 shards took 114 s when it was not);
#   - the merged table equals the unsharded sweep's (max_error and index).
# test/cli/test_cli_options.sh checks the names on shards 1, 10, 100 and 1000 of the same sweep.
set -uo pipefail
cd "$(dirname "$0")/../.."
root="$PWD"
source studies/setup.sh >/dev/null
set -uo pipefail
exe="$root/$(fpm run --profile release --target mpm1d --runner echo 2>/dev/null | tail -n 1)"
dir="$root/build/test_scratch/long_shards"
rm -rf "$dir"; mkdir -p "$dir"; cd "$dir"
passed=0; failed=0
check() { if eval "$2"; then passed=$((passed+1)); else failed=$((failed+1)); echo "FAIL $1"; fi; }
# CPU seconds (user + system) of this shell's waited-for children, from `times > times.txt` run just
# before in this shell (not in a $(...) subshell, whose counts start at zero)
children_cpu() {
  awk 'NR == 2 { t = 0; for (i = 1; i <= 2; i++) { split($i, a, "m"); t += a[1]*60 + a[2] }; printf "%.2f", t }' times.txt
}

els=$(seq -s, 1 250)
printf "&run periods=0.05 /\n&output file='m.h5', history=.false. /\n&sweep elements=$els, particles_per_element=1,2,3,4, min_time=0, progress=F /\n" > m.nml
mkdir -p shards1000
(cd shards1000 && for i in $(seq 1 1000); do OMP_NUM_THREADS=1 "$exe" ../m.nml output.file=m.h5 --shard "$i/1000" --threads 1 --quiet || echo "shard $i failed"; done) > shards.log 2>&1
check "test_1000_shard_names_distinct" "[ ! -s shards.log ] && [ \$(ls shards1000/m_shard*of1000.h5 | wc -l) = 1000 ] && [ -s shards1000/m_shard1000of1000.h5 ] && [ -s shards1000/m_shard0001of1000.h5 ]"
times > times.txt; before=$(children_cpu)
"$exe" merge merged1000.h5 shards1000/m_shard*.h5 > out.txt 2> err.txt; echo $? > rc.txt
times > times.txt; after=$(children_cpu)
merge_cpu=$(awk -v a="$before" -v b="$after" 'BEGIN{printf "%.1f", b-a}')
echo "   merge of 1000 shards: $merge_cpu s of CPU time"
check "test_merge_1000_shards" "[ \$(cat rc.txt) = 0 ]"
OMP_NUM_THREADS=2 "$exe" m.nml output.file=whole.h5 --quiet
check "test_merged_1000_equals_unsharded" "h5diff whole.h5 merged1000.h5 /cases/max_error && h5diff whole.h5 merged1000.h5 /cases/index"

echo "test_shards_long: $passed passed, $failed failed"
[ "$failed" = 0 ]
