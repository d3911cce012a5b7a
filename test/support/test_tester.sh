#!/usr/bin/env bash
# The tester's named cases (test/support/mpm_testing.f90), through real test programs: a case named on
# the command line runs alone, --list lists the cases and runs none, a name that is no case or an
# unknown option ends with exit status 2 and the list, MPM1D_LONG_TESTS takes 0 or 1 only, a long
# case is skipped (and counted) unless asked for. Each check is named; the failures are printed.
set -uo pipefail
cd "$(dirname "$0")/../.."
mapfile -t exe < <(fpm test --profile release --runner echo test_banded test_implicit_long 2>/dev/null | tail -n 2)
banded="${exe[0]}"; long="${exe[1]}"
passed=0; failed=0
check() { if eval "$2"; then passed=$((passed+1)); else failed=$((failed+1)); echo "FAIL $1"; fi; }
run() { "$@" > out.txt 2> err.txt; echo $? > rc.txt; }
rc() { cat rc.txt; }
scratch=build/test_scratch/tester
rm -rf "$scratch"; mkdir -p "$scratch"
banded="$PWD/$banded"; long="$PWD/$long"
cd "$scratch"

run "$banded"
check "every case runs without names" "[ $(rc) = 0 ] && grep -q '^  laplacian: ' out.txt && grep -q '^  random_matrices: ' out.txt && grep -q '^  singular: ' out.txt"
all_passed=$(sed -n 's/^test_banded: \([0-9]*\) passed, 0 failed$/\1/p' out.txt)
run "$banded" singular
check "a named case runs alone" "[ $(rc) = 0 ] && grep -q '^  singular: ' out.txt && ! grep -q 'laplacian' out.txt && ! grep -q 'random_matrices' out.txt"
check "the program counts only the named case's checks" "grep -q \"^test_banded: \$(sed -n 's/^  singular: \([0-9]*\) passed, 0 failed$/\1/p' out.txt) passed, 0 failed$\" out.txt"
run "$banded" singular laplacian
check "two named cases run, in the program's order" "[ $(rc) = 0 ] && [ \"\$(grep -o '^  [a-z_]*:' out.txt | tr -d ' :' | tr '\n' ' ')\" = 'laplacian singular ' ]"
run "$banded" --list
check "--list lists the cases and runs none" "[ $(rc) = 0 ] && [ \"\$(tr '\n' ' ' < out.txt)\" = 'laplacian random_matrices singular negated_solve ' ]"
run "$banded" laplasian
check "an unknown case: exit 2" "[ $(rc) = 2 ]"
check "an unknown case: named, with the list" "grep -qF \"test_banded: no case is named 'laplasian'; its cases: laplacian, random_matrices, singular, negated_solve\" err.txt"
check "an unknown case: nothing runs" "! grep -q 'passed' out.txt"
run "$banded" --frob
check "an unknown option: exit 2, named" "[ $(rc) = 2 ] && grep -qF \"unknown option '--frob'\" err.txt"
MPM1D_LONG_TESTS=yes run "$banded"
check "MPM1D_LONG_TESTS=yes refused with the values allowed" "[ $(rc) = 2 ] && grep -qF \"MPM1D_LONG_TESTS is 'yes' (allowed: 1 runs the long cases, 0 or unset not)\" err.txt"
MPM1D_LONG_TESTS=0 run "$banded"
check "MPM1D_LONG_TESTS=0 runs what no variable runs" "[ $(rc) = 0 ] && grep -q \"^test_banded: $all_passed passed, 0 failed$\" out.txt"
run "$long"
check "long cases skipped without MPM1D_LONG_TESTS, and counted" "[ $(rc) = 0 ] && grep -q '^test_implicit_long: 0 passed, 0 failed, 3 skipped$' out.txt && [ \$(grep -c 'skipped (a long case' out.txt) = 3 ]"
run "$long" --list
check "--list marks the long cases" "[ $(rc) = 0 ] && [ \$(grep -c ' (long)$' out.txt) = 3 ]"

echo "test_tester: $passed passed, $failed failed"
[ "$failed" = 0 ]
