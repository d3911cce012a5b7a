#!/usr/bin/env bash
# The SLURM job array (studies/shards/slurm_*.sh) on a live single-node SLURM cluster started on
# this machine (studies/shards/slurm_cluster.sh, in a private folder, on loopback):
#   1. a sweep of 300 cases (both schemes, part of the paper's Table 2) submitted as 8 array tasks
#      with a dependent merge job: every task's exit file is 0 and the merged file equals an
#      unsharded run of the same sweep in every /cases column except the timings;
#   2. the same sweep in 4 tasks of 2 CPUs, one task made to fail (its output cannot be written):
#      the failure is in its exit file, the dependent merge is cancelled, the merge script and
#      `mpm1d merge` both refuse the incomplete set, and resubmitting --array=<that id> completes it;
#   3. a task cancelled while it runs leaves exit 143 in its exit file and its file with the case
#      not run (status not_run: the sweep wrote what it finished);
#   4. slurm_submit.sh asks mpm1d (--dry-run) for the case count and the output file: N greater than
#      the cases is refused before anything is queued; a namelist with file = "x y.h5" (double
#      quotes, a space) runs and merges into OUTDIR/x y.h5;
#   5. the cluster is stopped and its daemons are gone.
# Skipped (exit 0, "skipped: <reason>") only where SLURM cannot be installed or started (neither
# root nor passwordless sudo; as a sudo user the daemons run through sudo and the jobs as the user).
# Usage: bash test/end_to_end/test_slurm.sh
set -uo pipefail
cd "$(dirname "$0")/../.."
root="$PWD"
source studies/setup.sh
set -uo pipefail
passed=0; failed=0
check() { if eval "$2"; then passed=$((passed+1)); else failed=$((failed+1)); echo "FAIL $1"; fi; }
t_start=$SECONDS
scratch="$root/build/test_scratch/slurm"
rm -rf "$scratch"; mkdir -p "$scratch"
# the cluster in a short private folder and on its own ports (below the ephemeral range), apart from
# any cluster of the user or another run of this test
export SLURM_CLUSTER_DIR; SLURM_CLUSTER_DIR="$(mktemp -d /tmp/mpm1d-slurm-test.XXXXXX)"
export SLURM_CLUSTER_PORT="${SLURM_CLUSTER_PORT:-$((20000 + ($$ % 4000) * 2))}"
cluster="bash $root/studies/shards/slurm_cluster.sh"
export SLURM_CONF="$SLURM_CLUSTER_DIR/slurm.conf"
limit="${SLURM_TEST_WAIT:-240}"   # seconds to wait for one submission's merge job

cleanup() { $cluster down >/dev/null 2>&1; rm -rf "$SLURM_CLUSTER_DIR"; }
trap cleanup EXIT

$cluster up > "$scratch/cluster_up.log" 2>&1
rc=$?
case "$rc" in
  0) ;;
  4) echo "test_slurm: skipped: slurm-wlm/munge could not be installed ($(tail -n 1 "$scratch/cluster_up.log"))"; exit 0 ;;
  5) echo "test_slurm: skipped: the SLURM daemons need root or passwordless sudo"; exit 0 ;;
  *) cat "$scratch/cluster_up.log"; echo "FAIL cluster up (exit $rc)"; echo "test_slurm: 0 passed, 1 failed"; exit 1 ;;
esac
check "cluster up: node idle" "[ \"\$(sinfo -h -o %T)\" = idle ]"
pids="$(cat "$SLURM_CLUSTER_DIR"/run/{munged,slurmctld,slurmd}.pid 2>/dev/null | tr '\n' ' ')"
check "three daemon pid files" "[ \$(echo $pids | wc -w) = 3 ]"

fpm build --profile release > /dev/null 2>&1
exe="$root/$(fpm run --profile release --target mpm1d --runner echo 2>/dev/null | tail -n 1)"

# 2 schemes x 6 element counts x 5 particle counts x 5 time steps = 300 cases, no timing pass
cat > "$scratch/sweep.nml" <<'EOF'
&output file='sweep_test.h5' /
&sweep schemes='usf', 'usl', elements=1, 3, 7, 10, 20, 50, particles_per_element=1, 2, 4, 7, 10,
       dt_fractions=0.05, 0.15, 0.25, 0.35, 0.50, min_time=0 /
EOF
cases=300
mkdir -p "$scratch/unsharded"
sed "s|file='sweep_test.h5'|file='$scratch/unsharded/sweep_test.h5'|" "$scratch/sweep.nml" > "$scratch/unsharded/sweep.nml"
OMP_NUM_THREADS=1 "$exe" "$scratch/unsharded/sweep.nml" --threads 1 > "$scratch/unsharded/log" 2>&1
check "unsharded reference run" "[ -s $scratch/unsharded/sweep_test.h5 ]"

# same_cases A B: every /cases column equal (NaN equal to NaN) except run_time and repeats
same_cases() {
  "$PYTHON" - "$1" "$2" <<'EOF'
import sys
import h5py, numpy as np
skip = {'run_time', 'repeats'}
with h5py.File(sys.argv[1], 'r') as a, h5py.File(sys.argv[2], 'r') as b:
    ka, kb = set(a['cases']), set(b['cases'])
    if ka != kb:
        sys.exit(f'columns differ: {sorted(ka ^ kb)}')
    bad = []
    for k in sorted(ka - skip):
        x, y = a['cases'][k][()], b['cases'][k][()]
        nan = x.dtype.kind == 'f'
        if x.shape != y.shape or not np.array_equal(x, y, equal_nan=nan):
            bad.append(k)
    if bad:
        sys.exit(f'columns differ: {bad}')
    print(f'{len(ka - skip)} columns of {len(a["cases/index"])} cases equal')
EOF
}
# wait_gone JOB: until squeue no longer lists the job (or its tasks); 1 after $limit seconds
wait_gone() {
  local t0=$SECONDS
  while [ -n "$(squeue -h -j "$1" 2>/dev/null)" ]; do
    [ $((SECONDS - t0)) -lt "$limit" ] || { echo "job $1 still queued after $limit s"; squeue; return 1; }
    sleep 0.5
  done
}
exits() { local i s=""; for i in $(seq 1 "$2"); do s="$s $(cat "$1/task_$i.exit" 2>/dev/null || echo -)"; done; echo "${s# }"; }
job_state() { scontrol show job "$1" 2>/dev/null | sed -n 's/.*JobState=\([A-Z_]*\).*/\1/p' | head -n 1; }

echo "-- 1. $cases cases in 8 array tasks + merge"
runA="$scratch/run8"
t0=$(date +%s.%N)
bash studies/shards/slurm_submit.sh "$scratch/sweep.nml" "$runA" 8 --partition=debug --time=00:05:00 \
  > "$scratch/submit8.out" 2> "$scratch/submit8.err"
check "submit exits 0" "[ $? = 0 ]"
array_job=$(sed -n 's/^array_job=//p' "$scratch/submit8.out"); merge_job=$(sed -n 's/^merge_job=//p' "$scratch/submit8.out")
check "submit prints both job ids" "[[ '$array_job' =~ ^[0-9]+$ && '$merge_job' =~ ^[0-9]+$ ]]"
check "merge job depends on the array job" "scontrol show job $merge_job | grep -q 'Dependency=afterok:${array_job}'"
check "sbatch options reach both jobs" "scontrol show job $array_job | grep -q 'TimeLimit=00:05:00' && scontrol show job $merge_job | grep -q 'TimeLimit=00:05:00'"
wait_gone "$merge_job"
t1=$(date +%s.%N)
submit_to_merged=$("$PYTHON" -c "print(f'{$t1 - $t0:.1f}')")
check "8 tasks exit 0 (exit files: $(exits "$runA" 8))" "[ '$(exits "$runA" 8)' = '0 0 0 0 0 0 0 0' ]"
check "merge job exit 0" "[ \"\$(cat $runA/merge.exit 2>/dev/null)\" = 0 ]"
check "merged file written" "[ -s $runA/sweep_test.h5 ]"
check "merged = unsharded (all /cases columns but timings)" "same_cases $runA/sweep_test.h5 $scratch/unsharded/sweep_test.h5"
check "tasks ran 1 thread with OMP_NUM_THREADS=1" "[ \$(grep -l '1 cpus, OMP_NUM_THREADS=1,' $runA/logs/shard_*_job$array_job.log | wc -l) = 8 ]"
check "tasks ran the executable copied at submit time" "grep -q 'OMP_NUM_THREADS=1, $runA/mpm1d' $runA/logs/shard_1_job$array_job.log"
check "no partial files" "! ls $runA/*.part >/dev/null 2>&1"
echo "   submit to merged file: $submit_to_merged s"

echo "-- 2. 4 tasks of 2 CPUs, task 2 fails, resubmitted alone"
runB="$scratch/run4"
mkdir -p "$runB/sweep_test_shard002of004.h5"   # task 2's output is a folder: refused up front, exit 2
bash studies/shards/slurm_submit.sh "$scratch/sweep.nml" "$runB" 4 --cpus-per-task=2 > "$scratch/submit4.out" 2>&1
check "submit (4 x 2 CPUs) exits 0" "[ $? = 0 ]"
array_job=$(sed -n 's/^array_job=//p' "$scratch/submit4.out"); merge_job=$(sed -n 's/^merge_job=//p' "$scratch/submit4.out")
wait_gone "$array_job"; wait_gone "$merge_job"
check "failed task visible in its exit file (exit files: $(exits "$runB" 4))" "[ '$(exits "$runB" 4)' = '0 2 0 0' ]"
check "its log says why" "grep -q 'is an existing folder' $runB/logs/shard_2_job$array_job.log"
check "slurm_merge.sh --failed lists task 2" "[ \"\$(bash studies/shards/slurm_merge.sh $runB --failed)\" = 2 ]"
check "dependent merge cancelled, not run (state $(job_state "$merge_job"))" \
  "[ '$(job_state "$merge_job")' = CANCELLED ] && [ ! -e $runB/merge.exit ] && [ ! -e $runB/sweep_test.h5 ]"
check "tasks ran 2 threads with OMP_NUM_THREADS=2" "[ \$(grep -l '2 cpus, OMP_NUM_THREADS=2,' $runB/logs/shard_*_job$array_job.log | wc -l) = 4 ]"
check "shard files record 2 threads" "[ \"\$(h5dump -a /sweep/threads $runB/sweep_test_shard001of004.h5 | grep -o '(0): [0-9]*')\" = '(0): 2' ]"
sbatch --parsable --wait --output="$runB/logs/merge_by_hand.log" studies/shards/slurm_merge.sh "$runB" > /dev/null 2>&1
rc=$?
check "merge job on the incomplete set fails (exit $rc)" "[ $rc != 0 ] && [ \"\$(cat $runB/merge.exit 2>/dev/null)\" = 1 ] && [ ! -e $runB/sweep_test.h5 ]"
check "its log names the failed task and the resubmission" "grep -q 'task 2: exit 2' $runB/logs/merge_by_hand.log && grep -q -- '--array=2' $runB/logs/merge_by_hand.log"
"$exe" merge "$scratch/incomplete.h5" "$runB"/sweep_test_shard00[134]of004.h5 > "$scratch/merge_incomplete.log" 2>&1
rc=$?
check "mpm1d merge refuses the 3 of 4 shards (exit $rc)" "[ $rc != 0 ] && grep -Eq 'shards missing: +2 of 4' $scratch/merge_incomplete.log && [ ! -e $scratch/incomplete.h5 ]"
bash studies/shards/slurm_submit.sh "$scratch/sweep.nml" "$runB" 4 --cpus-per-task=1 --array=2 > /dev/null 2>&1
check "resubmission with other CPUs per task refused" "[ $? = 2 ]"
rmdir "$runB/sweep_test_shard002of004.h5"
t0=$(date +%s.%N)
bash studies/shards/slurm_submit.sh "$scratch/sweep.nml" "$runB" 4 --array="$(bash studies/shards/slurm_merge.sh "$runB" --failed)" \
  > "$scratch/resubmit.out" 2>&1
check "resubmit --array=2 exits 0" "[ $? = 0 ]"
array_job=$(sed -n 's/^array_job=//p' "$scratch/resubmit.out"); merge_job=$(sed -n 's/^merge_job=//p' "$scratch/resubmit.out")
check "resubmission runs task 2 only" "[ \"\$(scontrol show job $array_job | grep -c ArrayTaskId=)\" = 1 ] && scontrol show job $array_job | grep -q 'ArrayTaskId=2 '"
wait_gone "$merge_job"
t1=$(date +%s.%N)
check "after resubmission all 4 tasks exit 0 ($(exits "$runB" 4))" "[ '$(exits "$runB" 4)' = '0 0 0 0' ]"
check "merge after resubmission exit 0" "[ \"\$(cat $runB/merge.exit 2>/dev/null)\" = 0 ]"
check "merged after resubmission = unsharded" "same_cases $runB/sweep_test.h5 $scratch/unsharded/sweep_test.h5"
check "slurm_merge.sh --failed empty" "[ -z \"\$(bash studies/shards/slurm_merge.sh $runB --failed)\" ]"
bash studies/shards/slurm_submit.sh "$scratch/sweep.nml" "$runB" 4 --array="$(bash studies/shards/slurm_merge.sh "$runB" --failed)" > /dev/null 2>&1
check "resubmitting with nothing failed submits nothing" "[ $? = 3 ] && [ \$(wc -l < $runB/jobs.txt) = 2 ]"
echo "   resubmission to merged file: $("$PYTHON" -c "print(f'{$t1 - $t0:.1f}')") s"

echo "-- 3. a task cancelled while it runs leaves exit 143"
runC="$scratch/cancel"
cat > "$scratch/long.nml" <<'EOF2'
&output file='long.h5' /
&run periods=20000 /
&sweep schemes='usl', elements=50, particles_per_element=10, dt_fractions=0.05, min_time=0 /
EOF2
bash studies/shards/slurm_submit.sh "$scratch/long.nml" "$runC" 1 > "$scratch/submit_long.out" 2>&1
array_job=$(sed -n 's/^array_job=//p' "$scratch/submit_long.out"); merge_job=$(sed -n 's/^merge_job=//p' "$scratch/submit_long.out")
# cancelled once mpm1d has printed its sweep's header into the task's log (from there on it catches
# SIGTERM and writes the case as not run): a known point, not a time (300 s: only a guard)
t0=$SECONDS
until grep -qs 'sweep of' "$runC/logs/shard_1_job${array_job}.log" || [ $((SECONDS - t0)) -gt 300 ]; do sleep 0.2; done
scancel "$array_job"
wait_gone "$array_job"; wait_gone "$merge_job"
check "cancelled task's exit file says 143 ($(cat "$runC/task_1.exit" 2>/dev/null))" "[ \"\$(cat $runC/task_1.exit 2>/dev/null)\" = 143 ]"
check "its merge cancelled (state $(job_state "$merge_job"))" "[ '$(job_state "$merge_job")' = CANCELLED ] && [ ! -e $runC/merge.exit ]"
check "the cancelled sweep wrote its file: the case not run" \
  "h5dump -d /cases/status_name $runC/long.h5 2>/dev/null | grep -q '(0): \"not_run\"'"

echo "-- 4. the case count and the output file from mpm1d --dry-run"
runD="$scratch/toomany"
printf '&output file = "x y.h5" /\n&sweep elements=3, 4, 5, min_time=0 /\n' > "$scratch/quoted.nml"
bash studies/shards/slurm_submit.sh "$scratch/quoted.nml" "$runD" 4 > "$scratch/submit_toomany.out" 2>&1
rc=$?
check "N = 4 shards of 3 cases refused before submitting (exit $rc)" \
  "[ $rc = 2 ] && grep -q \"shards = 4 is more than the sweep's 3 cases\" $scratch/submit_toomany.out && [ ! -e $runD/jobs.txt ]"
runE="$scratch/quoted"
bash studies/shards/slurm_submit.sh "$scratch/quoted.nml" "$runE" 3 > "$scratch/submit_quoted.out" 2>&1
check "file = \"x y.h5\" submits (exit $?)" "[ -n \"\$(sed -n 's/^merge_job=//p' $scratch/submit_quoted.out)\" ]"
wait_gone "$(sed -n 's/^merge_job=//p' "$scratch/submit_quoted.out")"
check "3 tasks and the merge exit 0, into OUTDIR/x y.h5 ($(exits "$runE" 3))" \
  "[ '$(exits "$runE" 3)' = '0 0 0' ] && [ \"\$(cat $runE/merge.exit 2>/dev/null)\" = 0 ] && [ -s '$runE/x y.h5' ]"

echo "-- 5. cluster down"
trap - EXIT
$cluster down > "$scratch/cluster_down.log" 2>&1
check "cluster down exits 0" "[ $? = 0 ]"
for p in $pids; do check "daemon $p gone" "[ ! -d /proc/$p ]"; done
check "status reports nothing running" "! $cluster status > /dev/null 2>&1"
rm -rf "$SLURM_CLUSTER_DIR"

echo "test_slurm: $cases cases in 8 shards, submit to merged file $submit_to_merged s; test $((SECONDS - t_start)) s"
echo "test_slurm: $passed passed, $failed failed"
[ "$failed" = 0 ]
