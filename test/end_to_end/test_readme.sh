#!/usr/bin/env bash
# The README's first run ("By hand, once set up:" command block), run as written (every line, in
# order, stopping at the first failure) in a scratch copy of the project that shares this build
# folder, with HOME set to a scratch folder, so that what it installs ($HOME/.local/bin/mpm1d) and
# the files it writes ($HOME/mpm1d-first/bar.h5, sweep.h5, ...) land neither in the project nor in
# the real home; with the environment studies/setup.sh gives (the project's .venv first on PATH).
# Then the README's Python block ("Reading the results in Python") with .venv/bin/python in that
# folder: it must print the best completed case. Lines that run the tests (`fpm test`,
# `bash test/run_tests.sh`) are left out and named: test/run_tests.sh runs the Fortran tests in a
# group of their own, and this test is part of it (run again here they would run twice, or recurse).
# The quick start's other blocks run the whole paper study (test_paper_pipeline.sh runs it small).
set -uo pipefail
cd "$(dirname "$0")/../.."
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
check "the block installs mpm1d and runs it in a folder of its own" \
  "grep -q 'fpm install' <<< \"\$block\" && grep -q '^mpm1d ' <<< \"\$block\""
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
home="$scratch/home"
mkdir -p "$home"
(cd "$scratch" && HOME="$home" bash -e -x -o pipefail -c "$block") > "$log" 2>&1
status=$?
# the Python block after the heading 'Reading the results in Python'
python_block="$(awk '/^## Reading the results in Python/ {found=1; next}
                     found && /^```python/ {inside=1; next}
                     inside && /^```/ {exit}
                     inside {print}' README.md)"
check "README has a Python block" "[ -n \"\$python_block\" ]"
first="$home/mpm1d-first"
(cd "$first" 2>/dev/null && "$root/.venv/bin/python" -c "$python_block") > "$log.python" 2>&1
python_status=$?
check "the Python block exits 0 in the first run's folder" "[ $python_status = 0 ]"
check "it prints the best case's max_error, a finite number, and its run_time" \
  "grep -Eq 'max_error [0-9][0-9.e+-]*\$' \"$log.python\" && grep -Eq 'run_time [0-9][0-9.e+-]*\$' \"$log.python\""
check "the sweep left its stopped cases out and said so" "grep -q 'left out' \"$log.python\""
# the section's second Python block: the same sweep through mpm1d_post.sweep, which runs the mpm1d the
# 'By hand' block installed (found on PATH: no MPM1D_EXE), in a folder of its own
api_block="$(awk '/^## Reading the results in Python/ {found=1; next}
                  found && /^## / {exit}
                  found && /^```python/ {blocks++; if (blocks == 2) {inside=1; next}}
                  inside && /^```/ {exit}
                  inside {print}' README.md)"
check "README has a second Python block, with mpm1d_post.sweep" "grep -q 'mpm1d_post.sweep' <<< \"\$api_block\""
(cd "$first" 2>/dev/null && env -u MPM1D_EXE PATH="$home/.local/bin:$PATH" "$root/.venv/bin/python" -c "$api_block") \
  > "$log.api" 2>&1
api_status=$?
check "the API block exits 0 with the installed mpm1d" "[ $api_status = 0 ]"
check "it prints the best case as the first block does: USL, 80 elements, dt = 0.2 dx/c" \
  "grep -Eq 'scheme +usl\$' \"$log.api\" && grep -Eq 'elements +80\$' \"$log.api\" && grep -Eq 'dt_fraction +0.2\$' \"$log.api\""
# the built-in case as the README names it: what mpm1d with no input echoes
check "the README names the built-in case's scheme and mesh as mpm1d runs it" \
  "grep -q \"built-in verification case (the paper's bar, \$(sed -n 's/^# \\([a-z]*\\), \\([0-9]*\\) elements.*/\\2 elements, \\U\\1/p' \"$log\" | head -n 1))\" README.md"
check "the 'By hand' block exits 0 as written" "[ $status = 0 ]"
check "it installed mpm1d into \$HOME/.local/bin" "[ -x \"$home/.local/bin/mpm1d\" ]"
check "it wrote bar.h5 (the built-in case) in its own folder" "[ -s \"$first/bar.h5\" ]"
check "it wrote sweep.h5 and sweep_b2.h5 there" "[ -s \"$first/sweep.h5\" ] && [ -s \"$first/sweep_b2.h5\" ]"
check "it wrote run.h5 with snapshots, its figures and the animation" \
  "h5ls \"$first/run.h5/snapshots\" > /dev/null 2>&1 && [ -s \"$first/figures/snapshots.png\" ] && [ -s \"$first/wave.gif\" ]"
check "no ERROR STOP trace (fpm ran mpm1d alone)" "! grep -q 'ERROR STOP\|<ERROR>' \"$log\""
check "--help printed the usage" "grep -q 'usage' \"$log\""
[ "$failed" = 0 ] || { tail -n 40 "$log"; cat "$log.python" "$log.api" 2>/dev/null; }
rm -rf "$scratch"
echo "test_readme: $passed passed, $failed failed"
[ "$failed" = 0 ]
