#!/usr/bin/env bash
# Implicit and quasi-static integration against explicit, one command (about 10 minutes on 2 cores):
#   1. the bar (law linear): u_cm error against run time, explicit USL/MUSL at stable time steps and
#      implicit (Newmark's trapezoidal rule, lumped and consistent mass) up to 16 times the explicit limit,
#      elements 20..320, 2 particles per element (sweeps with a timing pass, one thread);
#   2. temporal order of the trapezoidal rule (self-convergence in dt on a fixed mesh) and the energy of
#      the linear bar over 100 periods (explicit USF/USL/MUSL against implicit lumped and consistent);
#   3. stability: the first dt fraction at which each explicit scheme fails (20 elements, 20 periods),
#      and implicit runs up to dt_fraction 1000;
#   4. stiff composites: a soft segment driven at its end, then a stiff one, impedance ratios 1e1..1e6
#      (equal densities: the wave speeds differ by the same ratio): explicit at dt = 0.5 dx/c_stiff (where
#      its step count fits the budget; beyond it the cost is extrapolated from its measured cost per
#      particle-step) against implicit at 0.5 and 2 dx/c_soft; the u_cm error and the L1 stress error;
#   5. Newton iterations against dt (Hencky bar at 1 % strain, elastoplastic plastic wave) and against
#      load steps (quasi-static column, Hencky and elastoplastic);
#   6. the cut cell: every shape at one particle per cell with the bar's free end crossing into empty
#      cells, ghost_penalty 0..1; the quasi-static column (quadratic and cubic B-splines) with its top
#      swept across span edges: the tangent's reciprocal condition number and the error, with and without
#      the ghost penalty;
#   7. the static column against its closed forms (linear, Hencky, elastoplastic), 20..160 elements;
#   8. the cost per particle-step of an implicit step against an explicit one (4000 particles);
#   then summary.md with the numbers and figures (analyze.py).
# Usage: bash studies/implicit/run.sh [output folder]     (default: out/implicit)
# MPM1D_QUICK=1 shrinks every list (seconds): for testing the pipeline; the numbers are not the study's.
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
cd "$root"
source studies/setup.sh
set -euo pipefail
out="$(mkdir -p "${1:-out/implicit}" && cd "${1:-out/implicit}" && pwd)"
export OMP_NUM_THREADS=1
par="${MPM1D_THREADS:-2}"   # threads of the sweeps' error passes (results do not depend on it)
start=$(date +%s.%N)
load=$(cut -d' ' -f1 /proc/loadavg 2>/dev/null || echo nan)

echo "== building"
exe="$(mpm1d_build)"
quick="${MPM1D_QUICK:-0}"
timing=0.05
bar_elements="20,40,80,160,320"; temporal_elements=40; temporal_ks="8.0,4.0,2.0,1.0,0.5,0.25"; energy_periods=100.0
explicit_ks="[0.05*i for i in range(10, 61)]"; implicit_ks="1.0,10.0,100.0,1000.0"
ratios="1e1 3e1 1e2 1e3 1e4 1e5 1e6"; composite_elements="100 200 400"; explicit_budget=1.0e9  # particle-steps
newton_ks="0.25 1 4 16 64"; load_steps="1 2 5 10 20 50"; penalties="0 0.001 0.01 0.1 1"; cut_scan=48
static_elements="20 40 80 160"; cost_elements=2000; cost_min_time=1.0
if [ "$quick" = 1 ]; then
  timing=0.005; bar_elements="10,20"; temporal_elements=10; temporal_ks="4.0,2.0,1.0,0.5"; energy_periods=5.0
  explicit_ks="[0.1*i for i in range(5, 31)]"; implicit_ks="1.0,100.0"
  ratios="1e1 1e2 1e4"; composite_elements="50 100"; explicit_budget=1.0e6
  newton_ks="1 16"; load_steps="1 5"; penalties="0 0.1"; cut_scan=8
  static_elements="10 20"; cost_elements=200; cost_min_time=0.05
fi
period=$("$PYTHON" -c "print(4*25.0/(200e9/7800)**0.5)")   # the bar's: 4 L/c

# one run: single NAME 'namelist text' (NAME.nml, NAME.h5, NAME.log); a stopped run is kept (its status)
single() {
  printf "%s\n&output file='%s' /\n" "$2" "$out/$1.h5" > "$out/$1.nml"
  "$exe" --quiet "$out/$1.nml" > "$out/$1.log" 2>&1 || true
}
# one sweep: sweep NAME 'namelist text with its &sweep group'
sweep() {
  printf "%s\n&output file='%s' /\n" "$2" "$out/$1.h5" > "$out/$1.nml"
  "$exe" "$out/$1.nml" > "$out/$1.log" 2>&1 || true
  tail -n 1 "$out/$1.log"
}

echo "== 1. the bar: error against run time"
sweep bar_explicit "&material law='linear' /
&discretisation particles_per_element=2 /
&run periods=2.0 /
&sweep schemes='usl','musl', elements=$bar_elements, dt_fractions=0.1,0.25,0.5,
       min_time=$timing, threads=$par, timing_threads=1, progress=.false. /"
sweep bar_implicit "&material law='linear' /
&discretisation integrator='implicit', particles_per_element=2 /
&run periods=2.0 /
&sweep mass='lumped','consistent', elements=$bar_elements, dt_fractions=0.25,1.0,4.0,16.0,
       min_time=$timing, threads=$par, timing_threads=1, progress=.false. /"

echo "== 2. temporal order and energy over $energy_periods periods"
sweep temporal "&material law='linear' /
&discretisation integrator='implicit', elements=$temporal_elements, particles_per_element=2 /
&run periods=1.0 /
&sweep mass='lumped','consistent', dt_fractions=$temporal_ks, histories=.true., min_time=0, threads=$par,
       progress=.false. /"
sweep energy_explicit "&material law='linear' /
&discretisation elements=20, particles_per_element=2, dt_fraction=0.5 /
&run periods=$energy_periods /
&sweep schemes='usf','usl','musl', histories=.true., min_time=0, threads=$par, progress=.false. /"
sweep energy_implicit "&material law='linear' /
&discretisation integrator='implicit', elements=20, particles_per_element=2 /
&run periods=$energy_periods /
&sweep mass='lumped','consistent', dt_fractions=0.5,1.0,4.0, histories=.true., min_time=0, threads=$par,
       progress=.false. /"

echo "== 3. stability limits"
sweep stability_explicit "&material law='linear' /
&discretisation elements=20 /
&run periods=20.0 /
&sweep schemes='usf','usl','musl', particles_per_element=1,2, dt_fractions=$("$PYTHON" -c "print(','.join(f'{k:.4g}' for k in $explicit_ks))"),
       min_time=0, threads=$par, progress=.false. /"
sweep stability_implicit "&material law='linear' /
&discretisation integrator='implicit', elements=400, particles_per_element=2 /
&run periods=4.0 /
&sweep mass='lumped','consistent', dt_fractions=$implicit_ks, min_time=0, threads=$par, progress=.false. /"

echo "== 4. stiff composites"
soft_c=$("$PYTHON" -c "print((1e8/1000)**0.5)")
end_time=$("$PYTHON" -c "print(1.5*0.5/$soft_c)")
for ratio in $ratios; do
  stiff=$("$PYTHON" -c "print(f'{1e8*$ratio**2:.6g}')")
  scene="&scene kind='composite_bar', lengths=0.5,0.5, youngs_moduli=1e8,$stiff, densities=1000,1000, drive_velocity=0.01 /
&material law='linear' /
&run end_time=$end_time /"
  for n in $composite_elements; do
    # explicit at dt = 0.5 dx/c_stiff: its particle-steps against the budget (beyond it: extrapolated)
    if "$PYTHON" -c "import sys; sys.exit(0 if $end_time/(0.5/$n/($soft_c*$ratio))*2*$n <= $explicit_budget else 1)"; then
      single "composite_${ratio}_${n}_explicit" "$scene
&discretisation elements=$n, particles_per_element=2, dt_fraction=0.5 /"
    fi
    for courant in 0.5 2; do
      k=$("$PYTHON" -c "print(f'{$courant*$ratio:.6g}')")
      single "composite_${ratio}_${n}_implicit_$courant" "$scene
&discretisation integrator='implicit', elements=$n, particles_per_element=2, dt_fraction=$k /"
    done
  done
done

echo "== 5. Newton iterations against dt and load steps"
strain1=$("$PYTHON" -c "print(0.01*(200e9/7800)**0.5)")
for k in $newton_ks; do
  single "newton_bar_$k" "&scene velocity_amplitude=$strain1 /
&discretisation integrator='implicit', elements=40, particles_per_element=2, dt_fraction=$k /
&run periods=1.0 /"
  single "newton_plastic_$k" "&scene kind='plastic_wave', length=1.0, youngs_modulus=1e10, density=1000.0, drive_velocity=5.0 /
&material law='elastoplastic', yield_stress=1e7, hardening_modulus=1e9 /
&discretisation integrator='implicit', elements=200, particles_per_element=2, dt_fraction=$k /"
done
for ls in $load_steps; do
  for law in hencky elastoplastic; do
    extra=""; [ "$law" = elastoplastic ] && extra=", yield_stress=1e9, hardening_modulus=2e9"
    single "newton_column_${law}_$ls" "&scene kind='column', length=1.0, youngs_modulus=1e10, density=1000.0, gravity=3e6 /
&material law='$law'$extra /
&discretisation integrator='quasi_static', shape='cpgimp', elements=40, particles_per_element=2, load_steps=$ls /
&guards max_cell_move=100 /"
  done
done

echo "== 6. the cut cell"
for shape in bspline2 ugimp linear bspline3; do
  for g in $penalties; do
    single "cut_bar_${shape}_$g" "&scene velocity_amplitude=30.0 /
&discretisation integrator='implicit', shape='$shape', elements=40, particles_per_element=1, dt_fraction=1.0, ghost_penalty=$g /
&run periods=2.0 /"
  done
done
# the column's top swept across span edges: |u(L)| = (rho g/E) L^2/2 from 0 to 4.8 cells (20 cells, 1 m) in
# two load steps, so that the second step's tangent is formed with the top moved by 0 to 2.4 cells
for i in $(seq 1 $cut_scan); do
  gravity=$("$PYTHON" -c "print(f'{4.8*0.05*$i/$cut_scan*2*1e10/1000:.6g}')")
  for shape in bspline2 bspline3; do
    for g in 0 0.1; do
      single "cut_column_${shape}_${g}_$i" "&scene kind='column', length=1.0, youngs_modulus=1e10, density=1000.0, gravity=$gravity /
&material law='linear' /
&discretisation integrator='quasi_static', shape='$shape', elements=20, particles_per_element=1, load_steps=2, ghost_penalty=$g /
&guards max_cell_move=100 /"
    done
  done
done

echo "== 7. the static column against its closed forms"
for n in $static_elements; do
  single "static_linear_hat_$n" "&scene kind='column', length=1.0, youngs_modulus=1e10, density=1000.0, gravity=3e4 /
&material law='linear' /
&discretisation integrator='quasi_static', elements=$n, particles_per_element=1, load_steps=1 /"
  single "static_linear_hat10_$n" "&scene kind='column', length=1.0, youngs_modulus=1e10, density=1000.0, gravity=3e6 /
&material law='linear' /
&discretisation integrator='quasi_static', elements=$n, particles_per_element=2, load_steps=10 /
&guards max_cell_move=100 /"
  for law in linear hencky elastoplastic; do
    extra=""; [ "$law" = elastoplastic ] && extra=", yield_stress=1e9, hardening_modulus=2e9"
    single "static_${law}_cpgimp_$n" "&scene kind='column', length=1.0, youngs_modulus=1e10, density=1000.0, gravity=3e6 /
&material law='$law'$extra /
&discretisation integrator='quasi_static', shape='cpgimp', elements=$n, particles_per_element=2, load_steps=10 /
&guards max_cell_move=100 /"
  done
done

echo "== 8. cost per particle-step"
sweep cost_explicit "&discretisation elements=$cost_elements, particles_per_element=2, dt_fraction=0.5 /
&run periods=0.1 /
&sweep law='hencky','linear', min_time=$cost_min_time, threads=1, timing_threads=1, progress=.false. /"
sweep cost_generic "&discretisation elements=$cost_elements, particles_per_element=2, dt_fraction=0.5, kernels='generic' /
&run periods=0.1 /
&sweep law='hencky', min_time=$cost_min_time, threads=1, timing_threads=1, progress=.false. /"
sweep cost_implicit "&discretisation integrator='implicit', elements=$cost_elements, particles_per_element=2, dt_fraction=0.5 /
&run periods=0.1 /
&sweep law='linear','hencky', mass='lumped','consistent', min_time=$cost_min_time, threads=1, timing_threads=1,
       progress=.false. /"

elapsed=$("$PYTHON" -c "import time; print(f'{time.time()-$start:.0f}')")
echo "== analysis (study took ${elapsed} s, load average at start $load)"
"$PYTHON" studies/implicit/analyze.py "$out" --elapsed "$elapsed" --load "$load" --quick "$quick"
echo "summary: $out/summary.md"
