#!/usr/bin/env bash
# The tests of mpm1d, in two tiers, after installing what is missing (studies/setup.sh: apt packages
# and the project's .venv; nothing into the system's Python).
#   bash test/run_tests.sh         the default tier, minutes: the build, the generated sources' check
#                                  (test/generate.sh --check), the source folders' layers
#                                  (test/unit/check_layers.py), the Fortran tests (every program of
#                                  fpm.toml's test list, but their long cases), the tester's named
#                                  cases, the cross-check against an independent NumPy implementation,
#                                  the post-processing tests, the command line, the hostile-input
#                                  suite, a full disk on every write path (test/cli/test_full_disk.py),
#                                  sweeps killed at 24 moments and resumed (test/cli/test_sweep_kill.py),
#                                  single runs killed and restarted (test/cli/test_restart.py),
#                                  sweep determinism (3 two-thread sweeps), the README's
#                                  commands, the study pipelines and tests (but their long cases:
#                                  long_cases in this script)
#   bash test/run_tests.sh --all   the same, the Fortran tests with their long cases (large runs on 1
#                                  and 2 threads: MPM1D_LONG_TESTS=1), then the second tier:
#                                  test/end_to_end/test_*_long.sh (1000 shards merged), sweep
#                                  determinism with 20 two-thread sweeps (instead of 3), the API
#                                  documentation (docs/build_api.sh: FORD, no warnings), the long
#                                  cases of the study tests, and the SLURM job array on a live
#                                  single-node cluster
# Every group runs (a failure does not stop the others); the end shows each group's result, wall time
# and CPU time (of the processes the group waited for: the SLURM daemons' and jobs' are not counted).
# Exit status 0 only if every group passed. Logs: build/test_logs/<group>.log.
set -euo pipefail
cd "$(dirname "$0")/.."
all=0
for arg in "$@"; do
  case "$arg" in
    --all) all=1 ;;
    -h|--help) sed -n '2,23p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "run_tests.sh: unknown argument '$arg' (allowed: --all, --help)" >&2; exit 2 ;;
  esac
done
# the study scripts build for this machine's CPU unless PORTABLE=1: the tests use the one release build
if [ -z "${FLAGS+x}" ]; then export PORTABLE=1; fi
source studies/setup.sh
set -euo pipefail
export OMP_NUM_THREADS="${OMP_NUM_THREADS:-2}"
logs=build/test_logs
mkdir -p "$logs"

# CPU seconds (user + system) of the waited-for children of this shell, from the builtin `times`
# (run in this shell, not in a $(...) subshell, whose counts start at zero); result in $cpu_now
times_file="$logs/.times"
child_cpu() {
  times > "$times_file"
  cpu_now=$(awk 'NR == 2 { t = 0; for (i = 1; i <= 2; i++) { split($i, a, "m"); t += a[1]*60 + a[2] }; printf "%.2f", t }' "$times_file")
}
summary=()
failed=0
# group NAME COMMAND...: runs COMMAND, shows and logs its output, records result, wall and CPU time
group() {
  local name="$1"; shift
  local log="$logs/${name//[^A-Za-z0-9_.-]/_}.log" start cpu rc result wall
  echo "== $name"
  start=$(date +%s.%N); child_cpu; cpu=$cpu_now
  set +e
  "$@" 2>&1 | tee "$log"
  rc=${PIPESTATUS[0]}
  set -e
  wall=$(awk -v a="$start" -v b="$(date +%s.%N)" 'BEGIN { printf "%.1f", b - a }')
  child_cpu; cpu=$(awk -v a="$cpu" -v b="$cpu_now" 'BEGIN { printf "%.1f", b - a }')
  if [ "$rc" != 0 ]; then result=FAIL; failed=1
  elif tail -n 1 "$log" | grep -qE '^[A-Za-z0-9_]+: skipped'; then result=skipped  # e.g. 'test_slurm: skipped: <why>'
  else result=ok; fi
  summary+=("$(printf '%-8s %-64s %8s %8s' "$result" "$name" "$wall" "$cpu")")
}

# Every test program (test/**/test_*.f90) is in fpm.toml's test list, with its folder, once: a program
# left out would never run (the tests are listed, not discovered: fpm.toml says why).
tests_listed() {
  local f n missing=0
  while IFS= read -r f; do
    n="$(basename "$f" .f90)"
    if [ "$(grep -c "{ name = \"$n\", *source-dir = \"$(dirname "$f")\", *main = \"$n.f90\" }" fpm.toml)" != 1 ]; then
      echo "FAIL $f: not in fpm.toml's test list (add: { name = \"$n\", source-dir = \"$(dirname "$f")\", main = \"$n.f90\" })"
      missing=$((missing + 1))
    fi
  done < <(find test -name 'test_*.f90' | sort)
  echo "tests_listed: $(find test -name 'test_*.f90' | wc -l) programs, $missing not listed"
  [ "$missing" = 0 ]
}

# cases of the Python tests that sweep sizes (the stability analysis up to 80 elements): second tier
long_cases=(
  studies/stability/test_linear_stability.py::test_bar_ppc1_kcrit_matches_analytic_formula
  studies/stability/test_linear_stability.py::test_usl_ppc1_tends_to_cfl_limit
  studies/stability/test_linear_stability.py::test_scan_step_does_not_miss_instability
)

start_all=$(date +%s.%N); child_cpu; cpu_all=$cpu_now

# fpm 0.12 relinks a test program only when the same command rebuilt one of its objects: after an
# `fpm build` that rebuilt the library, test programs linked against the old one would run. Removing
# them makes the build link every test against the current library (a link, no compile).
rm -f build/gfortran_*/test/test_*
# Likewise fpm 0.12 recompiles a test source (mpm_testing and the test programs) only when its own text
# changed or the same command rebuilt a module it uses: after an `fpm build` that rebuilt the library,
# a test object compiled against the old module files stays (a merge that changed a derived type then
# failed: 'Mismatch in components of derived type'). Test objects older than the newest library object
# are removed, so that they compile again (a few seconds; none when the last build included the tests).
for dir in build/gfortran_*/mpm1d; do
  newest="$(ls -t "$dir"/src_*.o 2>/dev/null | head -n 1 || true)"
  [ -z "$newest" ] || find "$dir" -maxdepth 1 -name 'test_*.o*' ! -newer "$newest" -delete
done
group "build (library, mpm1d, tests, examples)" fpm build --profile release --tests
group "generated sources up to date (test/generate.sh --check)" bash test/generate.sh --check
group "source folders in layers, no import cycle (test/unit/check_layers.py)" "$PYTHON" test/unit/check_layers.py
group "every test program in fpm.toml's test list" tests_listed
if [ "$all" = 0 ]; then
  group "Fortran tests (fpm test: every program, but the long cases)" fpm test --profile release
else
  group "Fortran tests with their long cases (fpm test, MPM1D_LONG_TESTS=1)" env MPM1D_LONG_TESTS=1 fpm test --profile release
fi
group "named cases run alone (test/support/test_tester.sh)" bash test/support/test_tester.sh
group "cross-check against an independent NumPy implementation" "$PYTHON" test/reference/check_reference.py
group "post-processing package (pytest postprocess)" "$PYTHON" -m pytest -q -p no:cacheprovider postprocess
group "tutorial notebook (test/end_to_end/run_notebook.py docs/tutorial.ipynb)" "$PYTHON" test/end_to_end/run_notebook.py docs/tutorial.ipynb
group "the command line (test/cli/test_cli_options.sh)" bash test/cli/test_cli_options.sh
group "hostile input (test/cli/hostile)" "$PYTHON" test/cli/hostile/run_hostile.py
group "a full disk on every write path (test/cli/test_full_disk.py)" "$PYTHON" test/cli/test_full_disk.py
group "sweeps killed with SIGKILL resume from their journal (test/cli/test_sweep_kill.py)" "$PYTHON" test/cli/test_sweep_kill.py
group "single runs killed restart from their checkpoint (test/cli/test_restart.py)" "$PYTHON" test/cli/test_restart.py
if [ "$all" = 0 ]; then
  group "sweeps bit-identical on 1 and 2 threads (3 sweeps)" env SWEEP_REPEATS=3 bash test/end_to_end/test_sweep_determinism.sh
fi
group "the README's commands (test/end_to_end/test_readme.sh)" bash test/end_to_end/test_readme.sh
group "paper study pipeline, small" bash test/end_to_end/test_paper_pipeline.sh
# study tests: plain scripts, or through pytest for a file with cases in the second tier
for t in studies/*/test_*.py; do
  [ -f "$t" ] || continue
  deselect=()
  for c in "${long_cases[@]}"; do [ "${c%%::*}" = "$t" ] && deselect+=(--deselect "$c"); done
  if [ "${#deselect[@]}" = 0 ]; then group "$t" "$PYTHON" "$t"
  else group "$t (but its long cases)" "$PYTHON" -m pytest -q -p no:cacheprovider "$t" "${deselect[@]}"; fi
done

if [ "$all" = 1 ]; then
  for t in test/end_to_end/test_*_long.sh; do
    [ -f "$t" ] && group "$t" bash "$t"
  done
  group "sweeps bit-identical on 1 and 2 threads (20 sweeps)" env SWEEP_REPEATS=20 bash test/end_to_end/test_sweep_determinism.sh
  group "API documentation builds without warnings (docs/build_api.sh)" bash docs/build_api.sh
  group "long cases of the study tests (pytest)" "$PYTHON" -m pytest -q -p no:cacheprovider "${long_cases[@]}"
  group "SLURM job array on a live single-node cluster" bash test/end_to_end/test_slurm.sh
fi

wall=$(awk -v a="$start_all" -v b="$(date +%s.%N)" 'BEGIN { printf "%.1f", b - a }')
child_cpu; cpu=$(awk -v a="$cpu_all" -v b="$cpu_now" 'BEGIN { printf "%.1f", b - a }')
echo
printf '%-8s %-64s %8s %8s\n' result "group ($([ "$all" = 1 ] && echo 'both tiers: --all' || echo 'default tier'))" "wall s" "CPU s"
printf '%s\n' "${summary[@]}"
printf '%-8s %-64s %8s %8s\n' "" total "$wall" "$cpu"
if [ "$failed" != 0 ]; then echo "SOME TESTS FAILED (logs: $logs/)" >&2; exit 1; fi
echo "all test groups passed"
