#!/usr/bin/env bash
# Run every test of mpm1d: installs what is missing, then
#   1. fpm test (Fortran unit, physics, HDF5 and command-line tests),
#   2. the cross-check of mpm1d against an independent NumPy implementation,
#   3. the Python post-processing tests (pytest, postprocess/tests),
#   4. the README's quick-start commands, the paper pipeline, the SLURM job array on a live single-node cluster, the study tests.
# Usage (from anywhere): bash test/run_tests.sh
set -euo pipefail
cd "$(dirname "$0")/.."
source studies/setup.sh
set -euo pipefail
export OMP_NUM_THREADS="${OMP_NUM_THREADS:-2}"
failed=0

echo "== fpm test"
# fpm 0.12 relinks a test program only when the same `fpm test` rebuilt one of its objects: after an
# `fpm build` that rebuilt the library, `fpm test` would run test programs linked against the old
# one. Removing them makes it link every test against the current library (a link, no compile).
rm -f build/gfortran_*/test/test_*
fpm test --profile release || failed=1

echo "== cross-check against the independent reference implementation"
"$PYTHON" test/reference/check_reference.py || failed=1

echo "== post-processing package (pytest)"
"$PYTHON" -m pytest -q -p no:cacheprovider postprocess || failed=1
echo "== the command line: overrides, standard input, --quiet, hostile input"
bash test/test_command_line.sh || failed=1

echo "== hostile input: the table-driven suite (test/hostile/cases.py)"
"$PYTHON" test/hostile/run_hostile.py || failed=1

echo "== sweeps give the same bits on 1 and 2 threads, every time"
bash test/test_sweep_determinism.sh || failed=1

echo "== the README's quick-start commands, as written"
bash test/test_readme.sh || failed=1

echo "== paper study pipeline on a small real sweep"
bash test/test_paper_pipeline.sh || failed=1

echo "== SLURM job array on a live single-node cluster (skipped where SLURM cannot be installed)"
bash test/test_slurm.sh || failed=1

for t in studies/*/test_*.py; do
  [ -f "$t" ] || continue
  echo "== $t"
  "$PYTHON" "$t" || failed=1
done

if [ "$failed" != 0 ]; then echo "SOME TESTS FAILED" >&2; exit 1; fi
echo "all test groups passed"
