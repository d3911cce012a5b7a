#!/usr/bin/env bash
# Speed of mpm1d: particle-steps per second of each scheme for 1e2..1e7 particles (one thread; every
# shape and transfer on the generic path, and every shape with FLIP on the fused kernels, against the
# fused linear ones),
# memory bandwidth (STREAM-style triad and update, and the traffic of one USL pass with no arithmetic;
# 1 and 2 threads) and the bounds they imply, OpenMP speed-up inside
# one run, cost of a study against elements^2 * ppc / dt_fraction, and memory per particle.
# Every scene and transfer against the fused bar (whole runs, set-up included, 1e4 and 1e6 particles),
# the elastoplastic bar against the Hencky bar shape by shape, an implicit step against an explicit one,
# and the Table-2 error pass paired against an older build (OLD_MPM1D=path: wall-time medians of
# alternate runs, 1 and 2 threads; OLD_PORTABLE_MPM1D=path pairs the portable build with it too; with
# CALLGRIND=1 also valgrind's instruction counts, which a busy machine does not change; for the scenes'
# whole runs, the elastoplastic and the implicit runs too).
# Writes CSV files, benchmark.png and summary.md to the output folder (default out/benchmark).
# Usage: bash studies/benchmark/run.sh [output folder]
#   PARTS='...' runs only some parts (default: all of bandwidth throughput generic shapes threads
#   sweep study memory ratios plastic implicit table2); REPEATS (default 3) rounds of each paired
#   measurement.
# Built for this machine's CPU (-march=native, as every study script, with fpm's release flags without
# -funroll-loops; studies/setup.sh): PORTABLE=1 for fpm's plain release profile, or FLAGS='...' for
# other flags. -march=native is for local runs
# only (the binary uses this machine's vector instructions), not for portable builds.
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
cd "$root"
source studies/setup.sh
set -euo pipefail
out="${1:-out/benchmark}"
mkdir -p "$out"
bench="$(mpm1d_build --example mpm1d_bench)"
REPEATS="${REPEATS:-3}"
PARTS="${PARTS:-bandwidth throughput generic shapes threads sweep study memory ratios plastic implicit table2}"
want() { [[ " $PARTS " == *" $1 "* ]]; }
# instructions NAME BENCH-ARGUMENTS...: the bench's run under callgrind (its profile $out/callgrind_NAME.out),
# printing the inclusive instruction count of its timed runs (timed_run)
instructions() {
  local name="$1"; shift
  valgrind --tool=callgrind --callgrind-out-file="$out/callgrind_$name.out" "$bench" "$@" > /dev/null 2>&1
  callgrind_annotate --inclusive=yes "$out/callgrind_$name.out" | awk '/timed_run/ {gsub(/,/, "", $1); print $1; exit}'
}
mpm1d="$(mpm1d_build)"
mpm1d_build_options
echo "build: fpm build ${mpm1d_fpm_options[*]}" > "$out/flags.txt"
gfortran --version | head -n 1 >> "$out/flags.txt"
lscpu | grep -E 'Model name|^CPU\(s\)|L3' >> "$out/flags.txt" || true

if want bandwidth; then
echo "== bandwidth" >&2
echo "kernel,threads,bytes_per_element,repeat,seconds,bytes_per_s" > "$out/bandwidth.csv"
"$bench" stream 40000000 5 >> "$out/bandwidth.csv"
fi

if want throughput; then
echo "== one-thread throughput" >&2
echo "scheme,elements,ppc,particles,threads,steps,repeat,seconds,particle_steps_per_s" > "$out/throughput.csv"
for scheme in usf usl musl; do
  for n in 100 1000 10000 100000 1000000 10000000; do
    elements=$((n / 10)); steps=$((50000000 / n)); [ "$steps" -lt 5 ] && steps=5
    "$bench" throughput $scheme $elements 10 $steps "$REPEATS" 1 >> "$out/throughput.csv"
  done
done
fi

if want generic; then
echo "== generic path against the fused kernels (paired, one thread)" >&2
echo "kernels,scheme,elements,ppc,particles,threads,steps,repeat,seconds,particle_steps_per_s" > "$out/generic.csv"
for scheme in usf usl musl; do
  for n in 1000 10000 100000 1000000; do
    for r in $(seq "$REPEATS"); do
      for kernels in fused generic; do  # alternately, so that both see the same load
        "$bench" throughput $scheme $((n / 10)) 10 $((20000000 / n)) 1 1 $kernels | sed "s/^/$kernels,/" >> "$out/generic.csv"
      done
    done
  done
done
fi

if want shapes; then
echo "== every shape and transfer against linear on the fused kernels (paired, one thread)" >&2
# each round: the fused linear run of a scheme, then every shape (FLIP) on the generic path, then (USL) every
# transfer of every shape, and every wide shape with FLIP on the fused kernels (the path a run takes);
# 4 particles per element; 1e3-1e5 particles in cache and 1e7 from memory
echo "scheme,elements,ppc,particles,threads,steps,repeat,seconds,particle_steps_per_s,shape,transfer,path,round" \
  > "$out/shapes.csv"
for n in 1000 10000 100000 10000000; do
  steps=$((20000000 / n)); [ "$steps" -lt 3 ] && steps=3
  for r in $(seq "$REPEATS"); do
    for scheme in usf usl musl; do
      "$bench" throughput $scheme $((n / 4)) 4 $steps 1 1 fused linear flip | sed "s/\$/,fused,$r/" >> "$out/shapes.csv"
      for shape in linear ugimp cpgimp bspline2 bspline3; do
        transfers=flip; [ "$scheme" = usl ] && transfers="flip pic blend apic"
        for transfer in $transfers; do
          "$bench" throughput $scheme $((n / 4)) 4 $steps 1 1 generic $shape $transfer \
            | sed "s/\$/,generic,$r/" >> "$out/shapes.csv"
        done
        case $shape in ugimp|cpgimp|bspline2|bspline3)
          "$bench" throughput $scheme $((n / 4)) 4 $steps 1 1 fused $shape flip | sed "s/\$/,fused,$r/" >> "$out/shapes.csv" ;;
        esac
      done
    done
  done
done
fi

if want threads; then
echo "== threads inside one run" >&2
head -n 1 "$out/throughput.csv" > "$out/threads.csv"
for scheme in usf usl musl; do
  for n in 1000000 10000000; do
    # 1 and 2 threads alternately, so that both see the same load of this shared machine
    for r in $(seq "$REPEATS"); do
      for threads in 1 2; do
        "$bench" throughput $scheme $((n / 10)) 10 $((100000000 / n)) 1 $threads >> "$out/threads.csv"
      done
    done
  done
done
fi

if want sweep; then
echo "== sweep throughput (Table-2 error pass, 1 and 2 threads)" >&2
cat > "$out/table2_sweep.nml" <<EOF
&scene kind='vibrating_bar', length=25.0, youngs_modulus=200.0e9, density=7800.0, velocity_amplitude=0.1, mode=1 /
&run periods=2.0 /
&output file='$out/table2_sweep.h5' /
&sweep schemes='usf', 'usl', elements=1, 3, 7, 10, 20, 50, particles_per_element=1, 2, 3, 4, 5, 6, 7, 8, 9, 10,
       dt_fractions=0.05, 0.10, 0.15, 0.20, 0.25, 0.30, 0.35, 0.40, 0.45, 0.50, min_time=0 /
EOF
echo "threads,repeat,cases,seconds" > "$out/sweep.csv"
for r in $(seq $((REPEATS + 2))); do
  for threads in 1 2; do  # alternately, so that both see the same load of this shared machine
    start=$EPOCHREALTIME
    "$mpm1d" "$out/table2_sweep.nml" --threads $threads >/dev/null 2>&1
    end=$EPOCHREALTIME
    echo "$threads,$r,1200,$(awk -v a="$start" -v b="$end" 'BEGIN { printf "%.4f", b - a }')" >> "$out/sweep.csv"
  done
done
fi

if want study; then
echo "== cost of a study (one period, USL)" >&2
period=0.019746  # 4 L / c for the default bar (L = 25 m, c = 5064 m/s)
echo "scheme,elements,ppc,dt_fraction,steps,particles,repeat,seconds" > "$out/study.csv"
for e in 100 200 400 800; do "$bench" study usl $e 4 0.2 $period "$REPEATS" >> "$out/study.csv"; done
for p in 1 2 8 16; do "$bench" study usl 200 $p 0.2 $period "$REPEATS" >> "$out/study.csv"; done
for k in 0.1 0.4 0.8; do "$bench" study usl 200 4 $k $period "$REPEATS" >> "$out/study.csv"; done
fi

if want memory; then
echo "== memory" >&2
echo "particles,elements,max_rss_kib" > "$out/memory.csv"
for n in 1000 10000000; do
  rss=$( { /usr/bin/time -v "$bench" throughput usl $((n / 10)) 10 2 1 1 >/dev/null; } 2>&1 \
         | awk -F: '/Maximum resident set size/ {gsub(/ /, "", $2); print $2}')
  echo "$n,$((n / 10)),$rss" >> "$out/memory.csv"
done
echo "particles,elements,max_rss_kib" > "$out/memory_generic.csv"
for n in 1000 1000000; do
  rss=$( { /usr/bin/time -v "$bench" throughput usl $((n / 10)) 10 2 1 1 generic >/dev/null; } 2>&1 \
         | awk -F: '/Maximum resident set size/ {gsub(/ /, "", $2); print $2}')
  echo "$n,$((n / 10)),$rss" >> "$out/memory_generic.csv"
done
fi

if want ratios; then
echo "== every scene and transfer against the fused bar (whole runs, paired in rounds, one thread)" >&2
# USL, 2 particles per element, 200 steps, set-up included (run_simulation, as a user starts a run);
# each round: the fused bar, the bar on the generic path, PIC, blend, APIC, the column, the composite
# bar, the manufactured solution, the impact (frictionless, stuck), the bar with the cures (total-Lagrangian,
# CPDI, XPIC(2), FMPM(2), ASFLIP), then the bar's kernel alone
echo "size,round,scheme,run,path,particles,steps,bytes_per_particle,seconds,particle_steps_per_s" > "$out/ratios.csv"
for n in 10000 1000000; do
  "$bench" ratios $n 2 200 "$REPEATS" usl | sed "s/^/$n,/" >> "$out/ratios.csv"
done
if [ "${CALLGRIND:-0}" = 1 ] && command -v valgrind >/dev/null 2>&1; then
  # the instructions of each whole run at 1e4 particles (callgrind_annotate's inclusive count of timed_run)
  echo "run,instructions" > "$out/ratios_callgrind.csv"
  for run in bar bar_generic bar_pic bar_blend bar_apic column composite_bar manufactured impact_frictionless \
             impact_none bar_total bar_cpdi bar_xpic2 bar_fmpm2 bar_asflip; do
    echo "$run,$(instructions "ratios_$run" ratios 10000 2 200 1 usl "$run")" >> "$out/ratios_callgrind.csv"
  done
fi
fi

if want plastic; then
echo "== the elastoplastic bar against the Hencky bar, shape by shape (paired in rounds, one thread)" >&2
# USL, 2 particles per element, 200 steps, whole runs; the yield stress a third of the stress the bar
# reaches in the run, so that it yields (the last column: the fraction of the particles that did)
echo "size,round,scheme,shape,law,path,particles,steps,seconds,particle_steps_per_s,yielded_fraction" > "$out/plastic.csv"
for n in 10000 1000000; do
  "$bench" plastic $n 2 200 "$REPEATS" usl | sed "s/^/$n,/" >> "$out/plastic.csv"
done
if [ "${CALLGRIND:-0}" = 1 ] && command -v valgrind >/dev/null 2>&1; then
  echo "shape,law,instructions" > "$out/plastic_callgrind.csv"
  for shape in linear ugimp cpgimp bspline2 bspline3; do
    for law in hencky elastoplastic; do
      echo "$shape,$law,$(instructions "plastic_${shape}_$law" plastic 10000 2 200 1 usl "$shape" "$law")" \
        >> "$out/plastic_callgrind.csv"
    done
  done
fi
fi

if want implicit; then
echo "== an implicit step against an explicit one (1e5 particles, dt = 0.5 dx/c, paired in rounds, one thread)" >&2
# explicit: USL on the fused kernels, 200 steps; implicit: 20 steps; laws linear and hencky, both masses
echo "round,run,law,mass,particles,steps,seconds,particle_steps_per_s,solves_per_step,loop_seconds,loop_particle_steps_per_s" > "$out/implicit.csv"
"$bench" implicit 100000 2 20 "$REPEATS" >> "$out/implicit.csv"
if [ "${CALLGRIND:-0}" = 1 ] && command -v valgrind >/dev/null 2>&1; then
  # the instructions of each whole run at 2e4 particles (explicit 100 steps, implicit 10)
  echo "run,instructions" > "$out/implicit_callgrind.csv"
  for run in explicit_linear explicit_hencky implicit_linear_lumped implicit_hencky_lumped implicit_linear_consistent \
             implicit_hencky_consistent; do
    echo "$run,$(instructions "implicit_$run" implicit 20000 2 10 1 "$run")" >> "$out/implicit_callgrind.csv"
  done
fi
fi

if want table2; then
echo "== Table-2 error pass against an older build (OLD_MPM1D, OLD_PORTABLE_MPM1D), 1 and 2 threads" >&2
# the paper's Table-2 sweeps (USF and USL apart, 600 cases each, no timing pass), this build and
# $OLD_MPM1D alternately (and, with OLD_PORTABLE_MPM1D, this code's portable build and that one); whole
# process wall time. CALLGRIND=1: instruction counts, one thread.
echo "build,binary,scheme,threads,repeat,seconds" > "$out/table2.csv"
t2() { # scheme threads file
  cat <<EOF
&scene kind='vibrating_bar', length=25.0, youngs_modulus=200.0e9, density=7800.0, velocity_amplitude=0.1, mode=1 /
&run periods=2.0 /
&output file='$3' /
&sweep schemes='$1', elements=1, 3, 7, 10, 20, 50, particles_per_element=1, 2, 3, 4, 5, 6, 7, 8, 9, 10,
       dt_fractions=0.05, 0.10, 0.15, 0.20, 0.25, 0.30, 0.35, 0.40, 0.45, 0.50, min_time=0, threads=$2,
       progress=.false. /
EOF
}
# the builds to pair: this one (FLAGS) with OLD_MPM1D, and the portable one with OLD_PORTABLE_MPM1D
builds="flags"; [ -n "${OLD_PORTABLE_MPM1D:-}" ] && builds="flags portable"
portable_mpm1d=""
[ -n "${OLD_PORTABLE_MPM1D:-}" ] && portable_mpm1d="$(FLAGS="" mpm1d_build)"
binaries="new"; [ -n "${OLD_MPM1D:-}" ] && binaries="new old"
exe_of() { # build binary
  case "$1,$2" in
    flags,new) echo "$mpm1d" ;; flags,old) echo "$OLD_MPM1D" ;;
    portable,new) echo "$portable_mpm1d" ;; portable,old) echo "$OLD_PORTABLE_MPM1D" ;;
  esac
}
# (a CSV field, quoted: the study build's flags may hold commas, as -mtune-ctrl's list does)
build_name() { if [ "$1" = flags ] && [ -n "$FLAGS" ]; then echo "\"$FLAGS\""; else echo portable; fi; }
# One-thread pairs run at once, one on each of two cores, which swap every round: both builds then see
# the same neighbours on this shared machine, minute by minute (alternate runs a few seconds apart saw
# load that came and went between them: rounds spread 0.6-1.5 in one run). Without two cores or
# taskset, and for two threads, the builds run alternately.
cores=$(nproc 2>/dev/null || echo 1)
concurrent=0; [ "$cores" -ge 2 ] && command -v taskset >/dev/null 2>&1 && [ "$binaries" = "new old" ] && concurrent=1
timed() { # label exe namelist [core]: one line of table2.csv
  local start end
  start=$EPOCHREALTIME
  if [ -n "${4:-}" ]; then taskset -c "$4" "$2" "$3" >/dev/null 2>&1; else "$2" "$3" >/dev/null 2>&1; fi
  end=$EPOCHREALTIME
  echo "$1,$(awk -v a="$start" -v b="$end" 'BEGIN { printf "%.4f", b - a }')"
}
for r in $(seq $((REPEATS + 2))); do
  for build in $builds; do
    for scheme in usf usl; do
      for threads in 1 2; do
        for b in $binaries; do t2 $scheme $threads "$out/t2_$b.h5" > "$out/t2_$b.nml"; done
        if [ "$threads" = 1 ] && [ "$concurrent" = 1 ]; then
          timed "$(build_name $build),new,$scheme,1,$r" "$(exe_of $build new)" "$out/t2_new.nml" $((r % 2)) \
            > "$out/t2_new.time" &
          timed "$(build_name $build),old,$scheme,1,$r" "$(exe_of $build old)" "$out/t2_old.nml" $(((r + 1) % 2)) \
            > "$out/t2_old.time" &
          wait
          cat "$out/t2_new.time" "$out/t2_old.time" >> "$out/table2.csv"
        else
          for b in $binaries; do
            timed "$(build_name $build),$b,$scheme,$threads,$r" "$(exe_of $build $b)" "$out/t2_$b.nml" >> "$out/table2.csv"
          done
        fi
      done
    done
  done
done
rm -f "$out/t2_new.time" "$out/t2_old.time"
if [ "${CALLGRIND:-0}" = 1 ] && command -v valgrind >/dev/null 2>&1; then
  # with the simulated caches: the level-1 instruction and data caches' misses (a step whose code or data do not
  # fit in them costs time that the instruction count does not show)
  echo "build,binary,scheme,instructions,i1_misses,d1_misses" > "$out/table2_callgrind.csv"
  for build in $builds; do
    for scheme in usf usl; do
      for b in $binaries; do
        exe="$(exe_of $build $b)"
        t2 $scheme 1 "$out/t2_$b.h5" > "$out/t2_$b.nml"
        log="$out/callgrind_${build}_${b}_$scheme.log"
        valgrind --tool=callgrind --cache-sim=yes --callgrind-out-file="$out/callgrind_${build}_${b}_$scheme.out" "$exe" \
          "$out/t2_$b.nml" > "$log" 2>&1
        echo "$(build_name $build),$b,$scheme,$(awk '/Collected/ {gsub(/,/, "", $4); print $4}' "$log"),$(awk \
          '/I1 +misses/ {gsub(/,/, "", $4); print $4}' "$log"),$(awk \
          '/D1 +misses/ {gsub(/,/, "", $4); print $4}' "$log")" >> "$out/table2_callgrind.csv"
      done
    done
  done
fi
fi

"$PYTHON" studies/benchmark/report.py "$out"
echo "wrote $out/summary.md and $out/benchmark.png" >&2
