#!/usr/bin/env bash
# Numerical stability study of mpm1d: builds mpm1d, runs every sweep of this folder (time-step
# stability map for 20 and 1 element(s), stiffness and scale, large motion, long runs, high
# modes, very fine meshes), computes the predicted limits with linear_stability.py and writes the
# figures and summary.md with python -m mpm1d_post.studies.stability (postprocess/).
# Usage: bash studies/stability/run.sh [output folder]     (default: out/stability)
# MPM1D_QUICK=1 shrinks every list to a few cases (seconds), for the pipeline test
# (test_stability_study.py); the numbers are then not the study's.
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
cd "$root"
source studies/setup.sh
set -euo pipefail
out="$(mkdir -p "${1:-out/stability}" && cd "${1:-out/stability}" && pwd)"
here="$root/studies/stability"
quick="${MPM1D_QUICK:-0}"
start=$(date +%s.%N)
timings="$out/timings.txt"
: > "$timings"
now() { date +%s.%N; }
lap() {  # lap LABEL START: append the seconds since START to timings.txt
  awk -v l="$1" -v a="$2" -v b="$(now)" 'BEGIN{printf "%s %.2f\n", l, b-a}' >> "$timings"
}

echo "== building mpm1d"
t0=$(now)
exe="$(mpm1d_build)"  # -march=native unless PORTABLE=1 (studies/setup.sh)
lap build "$t0"

# prepare NAME [KEY=VALUE ...]: copy NAME.nml into $out with its output file placed in $out and,
# in quick mode, the given namelist variables replaced (KEY=VALUE, the whole list of KEY).
prepare() {
  local name="$1"; shift
  sed "s|file='$name.h5'|file='$out/$name.h5'|" "$here/$name.nml" > "$out/$name.nml"
  if [ "$quick" = 1 ] && [ $# -gt 0 ]; then
    "$PYTHON" - "$out/$name.nml" "$@" <<'PY'
import re, sys
path, pairs = sys.argv[1], sys.argv[2:]
text = open(path).read()
for pair in pairs:
    key, value = pair.split('=', 1)
    # the value of KEY runs to the next "NAME=" or to the "/" that ends the group
    pattern = re.compile(r'(?<![\w])(' + re.escape(key) + r'\s*=)(.*?)(?=,\s*\w+\s*=|\s*/)', re.S)
    # a &sweep list first (the same name may also be a base value of another group)
    at = text.find('&sweep')
    head, tail = (text[:at], text[at:]) if at >= 0 else ('', text)
    tail, n = pattern.subn(lambda m: m.group(1) + value, tail, count=1)
    if n == 0:
        head, n = pattern.subn(lambda m: m.group(1) + value, head, count=1)
    text = head + tail
    if n != 1:
        sys.exit(f'prepare: {key} not found in {path}')
open(path, 'w').write(text)
PY
  fi
}
# sweep NAME [KEY=VALUE ...]: prepare and run one sweep, log in $out/NAME.log
sweep() {
  local name="$1"
  prepare "$@"
  local t0; t0=$(now)
  "$exe" "$out/$name.nml" > "$out/$name.log" 2>&1 || { echo "mpm1d failed on $name.nml:"; cat "$out/$name.log"; exit 1; }
  grep -E 'sweep of|completed' "$out/$name.log" | tr '\n' ' ' | sed "s/^/   $name: /"; echo
  lap "$name" "$t0"
}

echo "== 1. time-step stability map (20 elements, ppc 1-8, k 0.1-2.5, 50 periods) and one element"
sweep map particles_per_element=1,2 \
  dt_fractions=0.1,0.5,0.65,0.7,0.705,0.71,0.72,0.75,0.76,1.7,1.72,1.74,2.0,2.01,2.05 periods=20.0
sweep coarse particles_per_element=1 dt_fractions=0.1,0.9,1.0,1.15,1.16,2.0,2.05

echo "== 2. stiffness and scale (E x rho, v0/c as in the paper)"
if [ "$quick" = 1 ]; then youngs="1.0e-3 200.0e9 1.0e15"; densities="1.0e-20 7800.0 1.0e20"
else youngs="1.0e-3 1.0 1.0e3 1.0e6 1.0e9 200.0e9 1.0e12 1.0e15"
     densities="1.0e-20 1.0e-10 1.0e-3 1.0 7800.0 1.0e10 1.0e20"; fi
t0=$(now); n=0
rm -f "$out"/scale_*.h5
for E in $youngs; do for rho in $densities; do
  n=$((n + 1)); tag=$(printf 'scale_%03d' "$n")
  # v0 = (0.1 / c_paper) * sqrt(E / rho), printed with 17 significant digits
  v0=$(awk -v e="$E" -v r="$rho" 'BEGIN{printf "%.17g", 0.1 / sqrt(200.0e9 / 7800.0) * sqrt(e / r)}')
  sed -e "s|@E@|$E|" -e "s|@RHO@|$rho|" -e "s|@V0@|$v0|" -e "s|file='scale.h5'|file='$out/$tag.h5'|" \
    "$here/scale_template.nml" > "$out/$tag.nml"
  "$exe" "$out/$tag.nml" > "$out/$tag.log" 2>&1 || { echo "mpm1d failed on $tag.nml:"; cat "$out/$tag.log"; exit 1; }
done; done
echo "   $n (E, rho) pairs x 3 schemes"
lap scale "$t0"

echo "== 3. large motion (v0/c 1e-5 .. 1, ppc 1, 4, 16, 100)"
sweep large particles_per_element=1,100 velocity_amplitudes=0.1,506.3696835418333,5063.696835418333

echo "== 4. long runs (100 and 1000 periods)"
sweep long100 particles_per_element=1 dt_fractions=0.5
sweep long1000 particles_per_element=1 dt_fractions=0.5

echo "== 5. high modes (20 elements, modes 1-20)"
sweep modes particles_per_element=1 modes=1,5,10,20

echo "== 6. very fine meshes (1e4, 1e5 elements, 200 steps) and the largest single run"
sweep fine_e10000 particles_per_element=1
if [ "$quick" = 1 ]; then rm -f "$out/fine_e100000.h5"; else sweep fine_e100000; fi
prepare largest particles_per_element=1
t0=$(now)
"$exe" "$out/largest.nml" > "$out/largest.log" 2>&1 || { echo "largest run failed:"; cat "$out/largest.log"; exit 1; }
lap largest "$t0"

echo "== predicted limits (linear_stability.py)"
t0=$(now)
if [ "$quick" = 1 ]; then ppcs="1,2,4,8"; else ppcs="1-8"; fi
("$PYTHON" -m mpm1d_post.linear_stability --ppc "$ppcs" --elements 1,20 --out "$out/predicted" > "$out/predicted.log")
lap predicted "$t0"

echo "== figures and summary"
t0=$(now)
"$PYTHON" -m mpm1d_post.studies.stability "$out" -o "$out" --predicted "$out/predicted/predicted_critical.csv" \
  --timings "$timings"
lap figures "$t0"
end=$(now)
total=$(awk -v a="$start" -v b="$end" 'BEGIN{printf "%.1f", b-a}')
printf '\n## Total wall time of this command\n\n%s s (`bash studies/stability/run.sh`%s, %s cores, including the build check; steps in `timings.txt`).\n' \
  "$total" "$([ "$quick" = 1 ] && echo ', MPM1D_QUICK=1')" "$(nproc)" >> "$out/summary.md"
echo "total $total" >> "$timings"
echo "== done in $total s: figures and summary.md in $out"
