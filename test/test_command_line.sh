#!/usr/bin/env bash
# mpm1d's command line as shell scripts use it: overrides group.name=value (validated, echoed and
# stored in /config like the namelist's values; a misspelled one named in the message), the
# namelist from standard input ('-'), --quiet; and defects found by hostile input (issue 16).
# Each check is named; the run stops at nothing, and prints the failures.
set -uo pipefail
cd "$(dirname "$0")/.."
root="$PWD"
exe="$root/$(fpm run --profile release --target mpm1d --runner echo 2>/dev/null | tail -n 1)"
dir="$root/build/test_scratch/command_line"
rm -rf "$dir"; mkdir -p "$dir"; cd "$dir"
passed=0; failed=0
check() { if eval "$2"; then passed=$((passed+1)); else failed=$((failed+1)); echo "FAIL $1"; fi; }
run() { "$exe" "$@" > out.txt 2> err.txt; echo $? > rc.txt; }
rc() { cat rc.txt; }
attr() { h5dump -a "/config/$2" "$1" 2>/dev/null | sed -n 's/^ *(0): *//p' | tr -d '"' | sed 's/ *$//'; }

printf "&discretisation elements=10 /\n&run periods=1.0 /\n&output file='a.h5', history=.false. /\n" > a.nml

# ---- overrides
run a.nml discretisation.elements=40 discretisation.scheme=musl
check "test_override_runs" "[ $(rc) = 0 ]"
check "test_override_echoed" "grep -q 'elements=40' out.txt && grep -q \"scheme='musl'\" out.txt"
check "test_override_in_config" "[ \"\$(attr a.h5 elements)\" = 40 ] && [ \"\$(attr a.h5 scheme)\" = musl ]"
run a.nml run.end_time=0.01
check "test_override_end_time_replaces_periods" "[ $(rc) = 0 ] && grep -q 'end_time=' out.txt && ! grep -q 'periods=' out.txt"
run a.nml discretisation.elemnts=40
check "test_misspelled_override_exit_2" "[ $(rc) = 2 ]"
check "test_misspelled_override_named" "grep -q \"command line 'discretisation.elemnts=40'\" err.txt && grep -q elemnts err.txt"
run a.nml discretization.elements=40
check "test_unknown_group_override_named" "[ $(rc) = 2 ] && grep -q 'discretization' err.txt"
run a.nml scene.length=-1
check "test_override_validated" "[ $(rc) = 2 ] && grep -q \"command line 'scene.length=-1'\" err.txt && grep -q 'out of range' err.txt"
run a.nml discretisation.elements=4x
check "test_bad_override_value" "[ $(rc) = 2 ] && grep -q 'elements' err.txt"
run a.nml --frob
check "test_unknown_option" "[ $(rc) = 2 ] && grep -q frob err.txt"
run a.nml b.nml
check "test_two_inputs_refused" "[ $(rc) = 2 ] && grep -q 'too many arguments' err.txt"
printf "&output file='s.h5' /\n&sweep elements=1,2, min_time=0 /\n" > s.nml
run s.nml sweep.schemes=usf,musl sweep.elements=3,5,7
check "test_sweep_overrides" "[ $(rc) = 0 ] && grep -q 'sweep of 6 cases' out.txt"
run s.nml sweep.elemets=3
check "test_sweep_override_misspelled" "[ $(rc) = 2 ] && grep -q \"command line 'sweep.elemets=3'\" err.txt"

# ---- standard input and --quiet
"$exe" - run.periods=0.5 < a.nml > out.txt 2> err.txt; echo $? > rc.txt
check "test_stdin_input" "[ $(rc) = 0 ] && grep -q 'periods=0.5' out.txt && [ -s a.h5 ]"
printf "&scene lenght=3 /\n" | "$exe" - > out.txt 2> err.txt; echo $? > rc.txt
check "test_stdin_error_names_standard_input" "[ $(rc) = 2 ] && grep -q 'standard input:1' err.txt"
run a.nml --quiet
check "test_quiet_prints_nothing" "[ $(rc) = 0 ] && [ ! -s out.txt ] && [ -s a.h5 ]"
run s.nml --quiet
check "test_quiet_sweep_prints_nothing" "[ $(rc) = 0 ] && [ ! -s out.txt ] && [ -s s.h5 ]"

# ---- readable terminal output (the echoed namelist keeps full precision)
run a.nml discretisation.particles_per_element=1 discretisation.dt_fraction=0.1
check "test_summary_line_readable" "grep -q '^# usl, 10 elements, 1 particle per element, dt = 0.1 dx/c = 4.94e-05 s, 400 steps' out.txt"
check "test_echo_keeps_full_precision" "grep -q 'dt_fraction=0.10000000000000001' out.txt"
check "test_result_lines_readable" "grep -E '^max \|u_cm - u_cm,exact\| = [0-9.]+e-[0-9]+ m \([0-9.]+ % of the exact amplitude [0-9.e+-]+ m\)$' out.txt >/dev/null"
check "test_no_long_numbers_outside_echo" "! grep -v '^&' out.txt | grep -E '[0-9]{8,}|E-[0-9]' >/dev/null"
printf "&discretisation scheme='usl', dt_fraction=3.0 /\n&output file='u.h5' /\n" > u.nml
run u.nml
guard_step=$(sed -n 's/.*tripped at step \([0-9]*\) of \([0-9]*\).*/\1 of \2/p' err.txt)
check "test_guard_exit_1" "[ $(rc) = 1 ]"
check "test_same_step_count_in_summary_and_guard" "[ -n \"$guard_step\" ] && grep -q \"stopped by a guard at step $guard_step\" out.txt"
check "test_guard_message_readable" "! grep -E '[0-9]\.[0-9]{7,}' err.txt >/dev/null"
check "test_guard_message_full_in_file" "h5dump -d /summary/message u.h5 | grep -E '[0-9]\.[0-9]{8,}' >/dev/null"
printf "&output file='one.h5' /\n&sweep elements=3, min_time=0 /\n" > one.nml
run one.nml --threads 1
check "test_sweep_plurals" "grep -q 'sweep of 1 case\$' out.txt && grep -q 'on 1 thread;' out.txt && grep -q '^1 case completed' out.txt"

echo "test_command_line: $passed passed, $failed failed"
[ "$failed" = 0 ]
