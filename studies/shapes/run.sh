#!/usr/bin/env bash
# Shape functions and transfers on the vibrating bar, one command, a few minutes on one core:
#   1. spatial convergence per scheme x shape, 10..320 elements x 4 particles, k = 0.25 (32 steps per
#      element per 2 periods: the step count doubles exactly with the elements), 2 periods,
#      at small amplitude (v0 = 0.1 m/s, against the exact solution) and at v0 = 0.01 c (the free
#      end crosses cells; against the finest run, since the exact solution is linear theory and
#      the material is sigma = E ln F), with run times (timing pass, one thread);
#   1b. every transfer (FLIP, PIC, blend 0.99, APIC) x shape under USL, both amplitudes;
#   2. the critical dt fraction per scheme x shape x ppc (20 elements, 20 periods; first failing k),
#      and as predicted by the amplification matrix of the frozen step (at rest and stretched);
#   3. throughput of every shape and transfer on the generic path against linear on the fused
#      kernels, paired in one run (mpm1d_bench throughput, one thread, interleaved repeats);
#   then summary.md with the numbers and figures (analyze.py).
# Usage: bash studies/shapes/run.sh [output folder]     (default: out/shapes)
# MPM1D_QUICK=1 shrinks every list (10-40 elements, k in steps of 0.1 from 0.3, one speed round
# at 1e4 particles), for testing the whole pipeline in seconds; the numbers are then not the study's.
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
cd "$root"
source studies/setup.sh
set -euo pipefail
out="$(mkdir -p "${1:-out/shapes}" && cd "${1:-out/shapes}" && pwd)"
export OMP_NUM_THREADS=1

echo "== building"
exe="$(mpm1d_build)"  # -march=native unless PORTABLE=1 (studies/setup.sh)
bench="$(mpm1d_build --example mpm1d_bench)"
shapes="'linear','ugimp','cpgimp','bspline2','bspline3'"
quick="${MPM1D_QUICK:-0}"
elements="10,20,40,80,160,320"; transfer_elements="10,20,40,80,160"; ks="[0.02*i for i in range(10, 151)]"; rounds="1 2 3 4 5"; sizes="2500 25000"
if [ "$quick" = 1 ]; then
  elements="10,20,40"; transfer_elements="10,20,40"; ks="[0.1*i for i in range(3, 31)]"; rounds="1"; sizes="2500"
fi

echo "== convergence sweeps"
large=$("$PYTHON" -c "print(0.01*(200e9/7800)**0.5)")
for amp in small large; do
  v0=0.1; [ "$amp" = large ] && v0=$large
  cat > "$out/convergence_$amp.nml" <<NML
&scene velocity_amplitude=$v0 /
&discretisation particles_per_element=4, dt_fraction=0.25 /
&run periods=2.0 /
&output file='$out/convergence_$amp.h5' /
&sweep schemes='usf','usl','musl', shapes=$shapes, elements=$elements,
       histories=.true., min_time=0.02, threads=1, timing_threads=1, progress=.false. /
NML
  "$exe" "$out/convergence_$amp.nml" > "$out/convergence_$amp.log" 2>&1 || true
  tail -n 2 "$out/convergence_$amp.log"
done

echo "== transfers (USL, every shape)"
for amp in small large; do
  v0=0.1; [ "$amp" = large ] && v0=$large
  cat > "$out/transfers_$amp.nml" <<NML
&scene velocity_amplitude=$v0 /
&discretisation scheme='usl', particles_per_element=4, dt_fraction=0.25, flip_fraction=0.99 /
&run periods=2.0 /
&output file='$out/transfers_$amp.h5' /
&sweep shapes=$shapes, transfers='flip','pic','blend','apic', elements=$transfer_elements,
       min_time=0, threads=1, progress=.false. /
NML
  "$exe" "$out/transfers_$amp.nml" > "$out/transfers_$amp.log" 2>&1 || true
  tail -n 2 "$out/transfers_$amp.log"
done

echo "== critical time-step fractions"
fractions=$("$PYTHON" -c "print(', '.join(f'{k:.2f}' for k in $ks))")
cat > "$out/stability.nml" <<NML
&discretisation elements=20 /
&run periods=20.0 /
&output file='$out/stability.h5' /
&sweep schemes='usf','usl','musl', shapes=$shapes, particles_per_element=1,2,4,
       dt_fractions=$fractions, min_time=0, threads=1, progress=.false. /
NML
"$exe" "$out/stability.nml" > "$out/stability.log" 2>&1 || true
tail -n 1 "$out/stability.log"

echo "== predicted critical time-step fractions (studies/stability/linear_stability.py)"
"$PYTHON" studies/stability/linear_stability.py --shapes linear,ugimp,cpgimp,bspline2,bspline3 --ppc 1,2,4 \
  --elements 20 --dk 0.01 --out "$out" | tail -n 1

echo "== throughput (particle-steps/s, one thread, interleaved)"
echo "scheme,elements,ppc,particles,threads,steps,repeat,seconds,particle_steps_per_s,shape,transfer,path,round" > "$out/speed.csv"
for repeat in $rounds; do
  for size in $sizes; do
    steps=$((2000000 / size))
    for scheme in usf usl musl; do
      "$bench" throughput $scheme $size 4 $steps 1 1 fused | sed "s/\$/,linear,flip,fused,$repeat/" >> "$out/speed.csv"
      for shape in linear ugimp cpgimp bspline2 bspline3; do
        "$bench" throughput $scheme $size 4 $steps 1 1 generic $shape flip | sed "s/\$/,generic,$repeat/" >> "$out/speed.csv"
      done
    done
    for shape in linear bspline2; do
      for transfer in pic blend apic; do
        "$bench" throughput usl $size 4 $steps 1 1 generic $shape $transfer | sed "s/\$/,generic,$repeat/" >> "$out/speed.csv"
      done
    done
  done
done

echo "== summary"
"$PYTHON" studies/shapes/analyze.py "$out"
echo "wrote $out/summary.md"
