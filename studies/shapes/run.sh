#!/usr/bin/env bash
# Shape functions and transfers on the vibrating bar, one command, about 2-3 minutes on 2 cores:
#   1. spatial convergence per scheme x shape, 10..320 elements x 4 particles, k = 0.25 (32 steps per
#      element per 2 periods: the step count doubles exactly with the elements), 2 periods,
#      at small amplitude (v0 = 0.1 m/s, against the exact solution) and at v0 = 0.01 c (the free
#      end crosses cells; against the finest run, since the exact solution is linear theory and
#      the material is sigma = E ln F), with run times (timing pass, one thread);
#   1b. every transfer (FLIP, PIC, blend 0.99, APIC) x shape under USL, both amplitudes;
#   2. the critical dt fraction per scheme x shape x ppc (20 elements, 20 periods; first failing k),
#      and as predicted by the amplification matrix of the frozen step (at rest and stretched);
#   3. throughput of every shape and transfer on the generic path, and of every shape with FLIP on the
#      fused kernels, against linear on the fused kernels, paired in one run (mpm1d_bench throughput,
#      one thread, interleaved repeats);
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
par="${MPM1D_THREADS:-2}"   # threads of the sweeps' error passes (results do not depend on it); timing passes use one
start=$(date +%s.%N)
load=$(cut -d' ' -f1 /proc/loadavg 2>/dev/null || echo nan)   # other work on the machine while the study runs

echo "== building"
exe="$(mpm1d_build)"  # -march=native unless PORTABLE=1 (studies/setup.sh)
bench="$(mpm1d_build --example mpm1d_bench)"
shapes="'linear','ugimp','cpgimp','bspline2','bspline3'"
quick="${MPM1D_QUICK:-0}"
timing=0.02; dk=0.01; bench_steps=2000000
elements="10,20,40,80,160,320"; transfer_elements="10,20,40,80,160"; ks="[0.02*i for i in range(10, 151)]"; rounds="1 2 3 4 5"; sizes="2500 25000"
temporal_elements=80; temporal_ks="0.4,0.2,0.1,0.05,0.025"
table2_elements="1,3,7,10,20,50"; table2_ppc="1,2,3,4,5,6,7,8,9,10"; table2_ks="0.05,0.10,0.15,0.20,0.25,0.30,0.35,0.40,0.45,0.50"
crossing_elements=160; crossing_periods=5.0; energy_periods=100.0; manufactured_elements="20,40,80,160,320"
column_elements="25 50 100 200"; column_finest=200; column_k=0.0125
if [ "$quick" = 1 ]; then
  elements="10,20,40"; transfer_elements="10,20,40"; ks="[0.1*i for i in range(3, 31)]"; rounds="1"; sizes="2500"
  temporal_elements=20; temporal_ks="0.4,0.2,0.1"; table2_elements="1,3,10"; table2_ppc="1,2,4"; table2_ks="0.10,0.25,0.50"
  crossing_elements=80; crossing_periods=2.0; energy_periods=5.0; manufactured_elements="10,20,40"
  column_elements="10 20 40"; column_finest=40; column_k=0.1; timing=0.002; dk=0.05; bench_steps=200000
fi
# bar: period 4 L/c = 2.1966e-3 s (L = 25 m, c = sqrt(200e9/7800)); snapshots of the crossing runs at
# a quarter and a whole period past the first two, when the stress is largest and the bar at rest
period=$("$PYTHON" -c "print(4*25.0/(200e9/7800)**0.5)")
crossing_snapshots=$("$PYTHON" -c "p=$period; print(', '.join(f'{t*p:.9g}' for t in (0.25, 1.25, $crossing_periods - 0.75)))")
profile_bar_time=$("$PYTHON" -c "print(f'{1.75*$period:.9g}')")

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
       histories=.true., min_time=$timing, threads=$par, timing_threads=1, progress=.false. /
NML
  "$exe" "$out/convergence_$amp.nml" > "$out/convergence_$amp.log" 2>&1 || true
  tail -n 2 "$out/convergence_$amp.log"
done

echo "== transfers (every scheme x shape; timed at small amplitude)"
for amp in small large; do
  v0=0.1; min_time=$(awk -v t="$timing" 'BEGIN{print t/2}'); [ "$amp" = large ] && v0=$large && min_time=0
  cat > "$out/transfers_$amp.nml" <<NML
&scene velocity_amplitude=$v0 /
&discretisation particles_per_element=4, dt_fraction=0.25, flip_fraction=0.99 /
&run periods=2.0 /
&output file='$out/transfers_$amp.h5' /
&sweep schemes='usf','usl','musl', shapes=$shapes, transfers='flip','pic','blend','apic', elements=$transfer_elements,
       min_time=$min_time, threads=$par, timing_threads=1, progress=.false. /
NML
  "$exe" "$out/transfers_$amp.nml" > "$out/transfers_$amp.log" 2>&1 || true
  tail -n 2 "$out/transfers_$amp.log"
done

echo "== temporal convergence (dt halved at a fixed mesh)"
# 2 periods = 8 L/c and dt = k dx/c: 8 elements/k steps, so halving k doubles the step count exactly
# and the coarse run's times are every other time of the fine one.
for amp in small large; do
  # (flip_fraction only where the blend is swept: given to FLIP alone it is refused, as unused)
  v0=0.1; transfers="'flip','pic','blend','apic'"; blend=", flip_fraction=0.99"
  [ "$amp" = large ] && v0=$large && transfers="'flip'" && blend=""
  cat > "$out/temporal_$amp.nml" <<NML
&scene velocity_amplitude=$v0 /
&discretisation elements=$temporal_elements, particles_per_element=4$blend /
&run periods=2.0 /
&output file='$out/temporal_$amp.h5' /
&sweep schemes='usf','usl','musl', shapes=$shapes, transfers=$transfers, dt_fractions=$temporal_ks,
       histories=.true., min_time=0, threads=$par, progress=.false. /
NML
  "$exe" "$out/temporal_$amp.nml" > "$out/temporal_$amp.log" 2>&1 || true
  tail -n 2 "$out/temporal_$amp.log"
done

echo "== the founding paper's Table-2 sweep for each shape (USF, USL)"
cat > "$out/table2.nml" <<NML
&scene velocity_amplitude=0.1 /
&run periods=2.0 /
&output file='$out/table2.h5' /
&sweep schemes='usf','usl', shapes=$shapes, elements=$table2_elements, particles_per_element=$table2_ppc,
       dt_fractions=$table2_ks, min_time=0, threads=$par, progress=.false. /
NML
"$exe" "$out/table2.nml" > "$out/table2.log" 2>&1 || true
tail -n 2 "$out/table2.log"

echo "== grid crossing: single runs at v0 = 0.01 c with stress snapshots and energy histories"
for scheme in usf usl musl; do
  for shape in linear ugimp cpgimp bspline2 bspline3; do
    cat > "$out/crossing_${scheme}_$shape.nml" <<NML
&scene velocity_amplitude=$large /
&discretisation scheme='$scheme', shape='$shape', elements=$crossing_elements, particles_per_element=4, dt_fraction=0.25 /
&run periods=$crossing_periods /
&output file='$out/crossing_${scheme}_$shape.h5', snapshot_times=$crossing_snapshots /
NML
    "$exe" "$out/crossing_${scheme}_$shape.nml" > "$out/crossing_${scheme}_$shape.log" 2>&1 || true
  done
done

echo "== energy over $energy_periods periods (every scheme x shape x transfer, both amplitudes)"
for amp in small large; do
  v0=0.1; [ "$amp" = large ] && v0=$large
  cat > "$out/energy_$amp.nml" <<NML
&scene velocity_amplitude=$v0 /
&discretisation elements=20, particles_per_element=4, dt_fraction=0.25, flip_fraction=0.99 /
&run periods=$energy_periods /
&output file='$out/energy_$amp.h5' /
&sweep schemes='usf','usl','musl', shapes=$shapes, transfers='flip','pic','blend','apic',
       histories=.true., min_time=0, threads=$par, progress=.false. /
NML
  "$exe" "$out/energy_$amp.nml" > "$out/energy_$amp.log" 2>&1 || true
  tail -n 2 "$out/energy_$amp.log"
done

echo "== manufactured solution (both ends fixed) at A/L = 1e-6, 1e-3, 0.05: orders per scheme x shape"
cat > "$out/manufactured.nml" <<NML
&scene kind='manufactured', length=1.0, youngs_modulus=1.0e7, density=1000.0 /
&discretisation particles_per_element=2, dt_fraction=0.1 /
&run periods=1.0 /
&output file='$out/manufactured.h5' /
&sweep schemes='usf','usl','musl', shapes=$shapes, amplitudes=1.0e-6, 1.0e-3, 0.05, elements=$manufactured_elements,
       min_time=0, threads=$par, progress=.false. /
NML
"$exe" "$out/manufactured.nml" > "$out/manufactured.log" 2>&1 || true
tail -n 2 "$out/manufactured.log"

echo "== where the error sits: particle errors along the body (bar and manufactured, USL, every shape)"
for shape in linear ugimp cpgimp bspline2 bspline3; do
  cat > "$out/profile_bar_$shape.nml" <<NML
&scene velocity_amplitude=0.1 /
&discretisation scheme='usl', shape='$shape', elements=40, particles_per_element=4, dt_fraction=0.25 /
&run periods=2.0 /
&output file='$out/profile_bar_$shape.h5', history=.false., snapshot_times=$profile_bar_time /
NML
  "$exe" "$out/profile_bar_$shape.nml" > "$out/profile_bar_$shape.log" 2>&1 || true
  cat > "$out/profile_manufactured_$shape.nml" <<NML
&scene kind='manufactured', length=1.0, youngs_modulus=1.0e7, density=1000.0, amplitude=1.0e-6 /
&discretisation scheme='usl', shape='$shape', elements=40, particles_per_element=2, dt_fraction=0.1 /
&run periods=1.0 /
&output file='$out/profile_manufactured_$shape.h5', history=.false., snapshot_times=0.005 /
NML
  "$exe" "$out/profile_manufactured_$shape.nml" > "$out/profile_manufactured_$shape.log" 2>&1 || true
done

echo "== column under gravity (body force at the fixed end): every shape, dt fixed across meshes"
# dt = column_k dx_finest / c on every mesh (k scaled with the elements), so that the time-step part
# of the error (the sudden load, O(dt)) is the same small amount on every mesh; and at k = 0.2 as in
# studies/scenes for comparison.
for e in $column_elements; do
  k=$("$PYTHON" -c "print($column_k * $e / $column_finest)")
  cat > "$out/column_e$e.nml" <<NML
&scene kind='column', length=25.0, youngs_modulus=200.0e9, density=7800.0, gravity=9.81 /
&discretisation elements=$e, particles_per_element=2, dt_fraction=$k /
&run periods=2.0 /
&output file='$out/column_e$e.h5' /
&sweep schemes='usf','usl','musl', shapes=$shapes, min_time=0, threads=$par, progress=.false. /
NML
  "$exe" "$out/column_e$e.nml" > "$out/column_e$e.log" 2>&1 || true
done

echo "== critical time-step fractions"
fractions=$("$PYTHON" -c "print(', '.join(f'{k:.2f}' for k in $ks))")
cat > "$out/stability.nml" <<NML
&discretisation elements=20 /
&run periods=20.0 /
&output file='$out/stability.h5' /
&sweep schemes='usf','usl','musl', shapes=$shapes, particles_per_element=1,2,4,
       dt_fractions=$fractions, min_time=0, threads=$par, progress=.false. /
NML
"$exe" "$out/stability.nml" > "$out/stability.log" 2>&1 || true
tail -n 1 "$out/stability.log"

echo "== predicted critical time-step fractions (studies/stability/linear_stability.py)"
"$PYTHON" studies/stability/linear_stability.py --shapes linear,ugimp,cpgimp,bspline2,bspline3 --ppc 1,2,4 \
  --elements 20 --dk $dk --out "$out" | tail -n 1

echo "== throughput (particle-steps/s, one thread, interleaved)"
echo "scheme,elements,ppc,particles,threads,steps,repeat,seconds,particle_steps_per_s,shape,transfer,path,round" > "$out/speed.csv"
for repeat in $rounds; do
  for size in $sizes; do
    steps=$((bench_steps / size))
    for scheme in usf usl musl; do
      "$bench" throughput $scheme $size 4 $steps 1 1 fused linear flip | sed "s/\$/,fused,$repeat/" >> "$out/speed.csv"
      for shape in linear ugimp cpgimp bspline2 bspline3; do
        "$bench" throughput $scheme $size 4 $steps 1 1 generic $shape flip | sed "s/\$/,generic,$repeat/" >> "$out/speed.csv"
      done
      for shape in ugimp cpgimp bspline2 bspline3; do
        "$bench" throughput $scheme $size 4 $steps 1 1 fused $shape flip | sed "s/\$/,fused,$repeat/" >> "$out/speed.csv"
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
end=$(date +%s.%N)
{ times; } > "$out/times.txt"   # this shell's and its children's CPU time (user, system)
cpu=$(tail -n 1 "$out/times.txt" | awk '{print $1}')   # the runs' user time
awk -v a="$start" -v b="$end" -v l="$load" -v n="$(getconf _NPROCESSORS_ONLN)" -v c="$cpu" \
  'BEGIN{printf "%.1f %s %s %s\n", b-a, l, n, c}' > "$out/wall_time.txt"
"$PYTHON" studies/shapes/analyze.py "$out"
echo "wrote $out/summary.md (seconds of runs, load average at the start, cores, CPU time: $(cat "$out/wall_time.txt"))"
