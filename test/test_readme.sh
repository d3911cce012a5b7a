#!/usr/bin/env bash
# The README's quick start "By hand" command block, run as written (every line, in order, stopping
# at the first failure) in a scratch copy of the project that shares this build folder, so that
# the files it writes (bar.h5, my_run.nml, ...) do not land in the project; with the environment
# studies/setup.sh gives (the project's .venv first on PATH). Lines that run the tests (`fpm test`,
# `bash test/run_tests.sh`) are left out and named: test/run_tests.sh runs the Fortran tests in a
# group of their own, and this test is part of it (run again here they would run twice, or recurse).
# The quick start's other blocks run the whole paper study (test_paper_pipeline.sh runs it small).
set -uo pipefail
cd "$(dirname "$0")/.."
root="$PWD"
source studies/setup.sh >/dev/null
set -uo pipefail
passed=0; failed=0
check() { if eval "$2"; then passed=$((passed+1)); else failed=$((failed+1)); echo "FAIL $1"; fi; }

# the fenced block after the line 'By hand, once set up:'
block="$(awk '/^By hand, once set up:/ {found=1; next}
              found && /^```sh/ {inside=1; next}
              inside && /^```/ {exit}
              inside {print}' README.md)"
check "README has a 'By hand' block" "[ -n \"\$block\" ]"
check "the block runs the program with fpm run" "grep -q 'fpm run' <<< \"\$block\""
tests_re='^[[:space:]]*(fpm[[:space:]]+test|bash[[:space:]]+test/run_tests\.sh)([[:space:]]|$)'
left_out="$(grep -E "$tests_re" <<< "$block")"
block="$(grep -v -E "$tests_re" <<< "$block")"
[ -z "$left_out" ] || echo "test_readme: left out (test/run_tests.sh runs the tests in their own groups): $left_out"

scratch="$(mktemp -d)"
git ls-files -z --cached --others --exclude-standard | xargs -0 cp --parents -t "$scratch" 2>/dev/null
ln -s "$root/build" "$scratch/build"
# the project venv (studies/setup.sh), for a block that activates it, and the post-processing package
# it has installed (editable), so that studies/setup.sh run from the copy finds it installed from
# here and leaves it pointing at this checkout
ln -s "$root/.venv" "$scratch/.venv"
rm -rf "$scratch/postprocess" && ln -s "$root/postprocess" "$scratch/postprocess"
log="$root/build/test_scratch/readme.log"
mkdir -p "$(dirname "$log")"
(cd "$scratch" && bash -e -x -o pipefail -c "$block") > "$log" 2>&1
status=$?
check "the 'By hand' block exits 0 as written" "[ $status = 0 ]"
check "it wrote bar.h5 (the built-in case)" "[ -s \"$scratch/bar.h5\" ]"
check "no ERROR STOP trace (fpm ran mpm1d alone)" "! grep -q 'ERROR STOP\|<ERROR>' \"$log\""
check "--help printed the usage" "grep -q 'usage' \"$log\""
[ "$failed" = 0 ] || tail -n 40 "$log"
rm -rf "$scratch"
echo "test_readme: $passed passed, $failed failed"
[ "$failed" = 0 ]
