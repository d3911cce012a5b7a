#!/usr/bin/env bash
# The README's quick start "By hand" command block, run as written (every line, in order, stopping
# at the first failure) in a scratch copy of the project that shares this build folder, so that
# the files it writes (bar.h5, my_run.nml, ...) do not land in the project. The quick start's
# other blocks run the whole paper study (test_paper_pipeline.sh runs it small) and the whole test
# suite (this test is part of it: running it here would recurse); they are not run here.
set -uo pipefail
cd "$(dirname "$0")/.."
root="$PWD"
passed=0; failed=0
check() { if eval "$2"; then passed=$((passed+1)); else failed=$((failed+1)); echo "FAIL $1"; fi; }

# the fenced block after the line 'By hand, once set up:'
block="$(awk '/^By hand, once set up:/ {found=1; next}
              found && /^```sh/ {inside=1; next}
              inside && /^```/ {exit}
              inside {print}' README.md)"
check "README has a 'By hand' block" "[ -n \"\$block\" ]"
check "the block runs the program with fpm run" "grep -q 'fpm run' <<< \"\$block\""

scratch="$(mktemp -d)"
git ls-files -z --cached --others --exclude-standard | xargs -0 cp --parents -t "$scratch" 2>/dev/null
ln -s "$root/build" "$scratch/build"
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
