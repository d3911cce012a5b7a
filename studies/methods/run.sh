#!/usr/bin/env bash
# The cures side by side (docs/theory.md, The cures), one command:
#   1. mesh series, USL, 2 particles per element, of ten methods (FLIP, PIC and APIC with the hat,
#      cpGIMP and the quadratic B-splines with FLIP, the total-Lagrangian formulation, CPDI, XPIC(2),
#      FMPM(2), ASFLIP(0.99)) on four scenes: the vibrating bar with the linear and the Hencky law
#      (v0 = 0.1 m/s, one period, dt = 0.1 dx/c), the plastic wave (its defaults), the manufactured
#      solution at A/L = 0.05 (one period, dt = 0.1 dx/c); the coarser meshes timed (one thread,
#      the sweep's timing pass), the finer ones only for the error (`_more`; `_floor`: the bars at 3200
#      elements with FLIP, the total-Lagrangian formulation and CPDI, which change the quadrature whose
#      change as particles cross cells makes the hat's floor; the transfers do not touch it);
#   2. the bar of the linear law at v0 = 0.01 c (particles cross cells), MUSL, 100 elements x 2, dt =
#      0.1 dx/c, 5 periods, for FLIP, PIC, the blend, XPIC(2, 4, 8), FMPM(2, 4, 8) and ASFLIP: the
#      particles' velocities at the end (velocity noise against the mode's damping) and the energy
#      (MUSL: under USL the cell-crossing instability stops every one of them within the 5 periods);
#   then summary.md with the tables (each method's errors and orders, the cheapest run to each target
#   error, noise against energy) and the figures (analyze.py; mpm1d_post.studies.methods).
# The runs take the path mpm1d chooses for them (kernels = 'auto': the fused kernels where they apply,
# CPDI's lean step under USL, else the generic path: docs/performance.md, Which runs take the fused
# kernels), so that the run times are those a user gets.
# Usage: bash studies/methods/run.sh [output folder]     (default: out/methods)
# A run or sweep whose file is in the folder already is not run again (files are written whole, under a
# temporary name first): an interrupted study goes on where it stopped; a fresh folder runs everything.
# MPM1D_QUICK=1 shrinks the meshes (10-40 elements timed, 80 untimed) and the noise runs (20 elements,
# one period), for testing the pipeline in about a minute; the numbers are then not the study's.
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
cd "$root"
source studies/setup.sh
set -euo pipefail
out="$(mkdir -p "${1:-out/methods}" && cd "${1:-out/methods}" && pwd)"
export OMP_NUM_THREADS=1
par="${MPM1D_THREADS:-2}"   # threads of the sweeps' error passes (results do not depend on it); timing passes use one
start=$(date +%s.%N)
load=$(cut -d' ' -f1 /proc/loadavg 2>/dev/null || echo nan)   # other work on the machine while the study runs

echo "== building"
exe="$(mpm1d_build)"  # -march=native unless PORTABLE=1 (studies/setup.sh)
timed="50,100,200,400"; more="800,1600"; floor="3200"; timing=0.05
noise_elements=100; noise_periods=5.0
if [ "${MPM1D_QUICK:-0}" = 1 ]; then
  timed="10,20,40"; more="80"; floor=""; timing=0.002; noise_elements=20; noise_periods=1.0
fi

# method name -> its &discretisation variables
method_variables() {
  case "$1" in
    flip) echo "shape='linear', transfer='flip'" ;;
    pic) echo "shape='linear', transfer='pic'" ;;
    apic) echo "shape='linear', transfer='apic'" ;;
    blend) echo "shape='linear', transfer='blend', flip_fraction=0.99" ;;
    cpgimp) echo "shape='cpgimp', transfer='flip'" ;;
    bspline2) echo "shape='bspline2', transfer='flip'" ;;
    total) echo "shape='linear', transfer='flip', formulation='total'" ;;
    cpdi) echo "shape='cpdi', transfer='flip'" ;;
    xpic*) echo "shape='linear', transfer='xpic', xpic_order=${1#xpic}" ;;
    fmpm*) echo "shape='linear', transfer='fmpm', fmpm_order=${1#fmpm}" ;;
    asflip) echo "shape='linear', transfer='asflip', asflip_alpha=0.99" ;;
    *) echo "studies/methods/run.sh: unknown method $1" >&2; return 1 ;;
  esac
}
# scene name -> its &scene, &material and &run groups
scene_groups() {
  case "$1" in
    bar_linear) echo "&scene kind='vibrating_bar', velocity_amplitude=0.1 /
&material law='linear' /
&run periods=1.0 /" ;;
    bar_hencky) echo "&scene kind='vibrating_bar', velocity_amplitude=0.1 /
&material law='hencky' /
&run periods=1.0 /" ;;
    wave) echo "&scene kind='plastic_wave' /" ;;
    manufactured) echo "&scene kind='manufactured', length=1.0, youngs_modulus=1.0e7, density=1000.0, amplitude=0.05 /
&material law='hencky' /
&run periods=1.0 /" ;;
  esac
}
# the dt fraction: the plastic wave's default, else 0.1
scene_dt() { case "$1" in wave) echo "" ;; *) echo ", dt_fraction=0.1" ;; esac; }

# sweep NAME SCENE METHOD ELEMENTS MIN_TIME: one mesh series into $out/NAME.h5
sweep() {
  local name="$1" scene="$2" method="$3" elements="$4" min_time="$5"
  if [ -f "$out/$name.h5" ]; then echo "$name: kept from an earlier run"; return; fi
  cat > "$out/$name.nml" <<NML
$(scene_groups "$scene")
&discretisation scheme='usl', particles_per_element=2$(scene_dt "$scene"), $(method_variables "$method") /
&output file='$out/$name.h5' /
&sweep elements=$elements, min_time=$min_time, threads=$par, timing_threads=1, progress=.false. /
NML
  "$exe" "$out/$name.nml" > "$out/$name.log" 2>&1 || true
  echo "$name: $(tail -n 1 "$out/$name.log")"
}

methods="flip pic apic cpgimp bspline2 total cpdi xpic2 fmpm2 asflip"
floor_methods=" flip total cpdi "
echo "== mesh series"
for scene in bar_linear bar_hencky wave manufactured; do
  for method in $methods; do
    sweep "${scene}_$method" "$scene" "$method" "$timed" "$timing"
    sweep "${scene}_${method}_more" "$scene" "$method" "$more" 0
    # the bars' floor (about 1.4e-5 relative with the hat from 800 elements): one mesh finer
    if [ -n "$floor" ] && [ "${scene%%_*}" = bar ] && [[ "$floor_methods" == *" $method "* ]]; then
      sweep "${scene}_${method}_floor" "$scene" "$method" "$floor" 0
    fi
  done
done

echo "== noise against energy (the linear-law bar at v0 = 0.01 c)"
v0=$("$PYTHON" -c "print(0.01*(200e9/7800)**0.5)")
# the end time: periods x the mode's period 4 L/c (L = 25 m), where the snapshot is taken
end_time=$("$PYTHON" -c "print(f'{$noise_periods*4*25.0/(200e9/7800)**0.5:.12g}')")
for method in flip pic blend xpic2 xpic4 xpic8 fmpm2 fmpm4 fmpm8 asflip; do
  if [ -f "$out/noise_$method.h5" ]; then echo "noise_$method: kept from an earlier run"; continue; fi
  cat > "$out/noise_$method.nml" <<NML
&scene kind='vibrating_bar', velocity_amplitude=$v0 /
&material law='linear' /
&run periods=$noise_periods /
&discretisation scheme='musl', elements=$noise_elements, particles_per_element=2, dt_fraction=0.1, $(method_variables "$method") /
&output file='$out/noise_$method.h5', snapshot_times=$end_time /
NML
  "$exe" --quiet "$out/noise_$method.nml" > "$out/noise_$method.log" 2>&1 || true
  echo "noise_$method: $(tail -n 1 "$out/noise_$method.log")"
done

echo "== summary"
end=$(date +%s.%N)
elapsed=$(awk -v a="$start" -v b="$end" 'BEGIN{printf "%.1f", b-a}')
"$PYTHON" studies/methods/analyze.py "$out" --elapsed "$elapsed" --load "$load"
echo "wrote $out/summary.md ($elapsed s, load average $load at the start)"
