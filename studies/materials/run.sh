#!/usr/bin/env bash
# Materials (issue 26), one command: the plastic wave (kind='plastic_wave', law='elastoplastic') against its
# exact small-strain solution, and the bar with the linear law beyond Hencky's floor.
#   1. the plastic wave over every scheme x shape x transfer, 50..800 elements, timed (one thread): error
#      against run time, Pareto front, answer table, orders;
#   2. finer meshes (1600, 3200) with FLIP: orders per scheme and shape;
#   3. single runs (USL; linear and uGIMP, 50..3200 elements) with a snapshot at the end time: stress profiles
#      against the exact solution, the measured fronts and plateaus, cell crossings (the non-monotone
#      convergence of linear shapes), and an elastic control (law hencky driven at v1: the precursor's
#      state without plasticity); one run with snapshots through time for the energy balance;
#   4. stability with plasticity: critical dt fraction per scheme x shape, the bar elastoplastic (yielding)
#      against hencky (20 elements, 20 periods), and the plastic wave (200 elements);
#   5. the bar with both elastic laws (USL, linear, uGIMP, quadratic B-splines; v0 = 0.1 m/s);
#   6. speed of the laws on the generic path (paired rounds, one thread) and the memory each carries;
#   then summary.md and the figures (analyze.py).
# Usage: bash studies/materials/run.sh [output folder]    (default: out/materials)
# MPM1D_QUICK=1 shrinks every list (seconds; the numbers are then not the study's).
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
cd "$root"
source studies/setup.sh
set -euo pipefail
out="$(mkdir -p "${1:-out/materials}" && cd "${1:-out/materials}" && pwd)"
export OMP_NUM_THREADS=1
par="${MPM1D_THREADS:-2}"   # threads of the sweeps' error passes (results do not depend on it)
start=$(date +%s.%N)
load=$(cut -d' ' -f1 /proc/loadavg 2>/dev/null || echo nan)

echo "== building"
exe="$(mpm1d_build)"  # -march=native unless PORTABLE=1 (studies/setup.sh)
quick="${MPM1D_QUICK:-0}"
elements="50, 100, 200, 400, 800"; fine="1600, 3200"; timing=0.01; singles="50 100 200 400 800 1600 3200"
ks="[0.3 + 0.02*i for i in range(126)]"; wave_ks="[0.3 + 0.02*i for i in range(126)]"; wave_stability=200
bar_elements="100, 200, 400, 800, 1600"; speed_elements=25000; speed_rounds="1 2 3 4 5"; memory_elements=250000
energy_elements=400
if [ "$quick" = 1 ]; then
  elements="50, 100"; fine="200"; timing=0.001; singles="50 100 200"; ks="[0.3 + 0.2*i for i in range(13)]"
  wave_ks="[0.3 + 0.2*i for i in range(13)]"; wave_stability=50; bar_elements="100, 200"; speed_elements=1000
  speed_rounds="1"; memory_elements=50000; energy_elements=100
fi
# steel, a 1 m bar driven at 20 m/s: v1 = sigma_y/(rho c_e) = 6.33 m/s, so it yields
wave="&scene kind='plastic_wave', length=1.0, youngs_modulus=200.0e9, density=7800.0, drive_velocity=20.0 /
&material law='elastoplastic', yield_stress=250.0e6, hardening_modulus=10.0e9 /"
end_time=$("$PYTHON" -c "print(f'{0.8*1.0/(200e9/7800)**0.5:.12g}')")   # the default, 0.8 L/c_e

echo "== 1. the plastic wave: every scheme x shape x transfer, timed"
cat > "$out/wave.nml" <<NML
$wave
&discretisation particles_per_element=2, dt_fraction=0.2, flip_fraction=0.99 /
&output file='$out/wave.h5' /
&sweep scheme='usf', 'usl', 'musl', shape='linear', 'ugimp', 'cpgimp', 'bspline2', 'bspline3',
       transfer='flip', 'pic', 'blend', 'apic', elements=$elements,
       min_time=$timing, threads=$par, timing_threads=1, progress=.false. /
NML
"$exe" "$out/wave.nml" > "$out/wave.log" 2>&1 || true
tail -n 2 "$out/wave.log"

echo "== 2. finer meshes (FLIP)"
cat > "$out/wave_fine.nml" <<NML
$wave
&discretisation particles_per_element=2, dt_fraction=0.2 /
&output file='$out/wave_fine.h5' /
&sweep scheme='usf', 'usl', 'musl', shape='linear', 'ugimp', 'cpgimp', 'bspline2', 'bspline3', elements=$fine,
       min_time=0, threads=$par, progress=.false. /
NML
"$exe" "$out/wave_fine.nml" > "$out/wave_fine.log" 2>&1 || true
tail -n 2 "$out/wave_fine.log"

echo "== 3. single runs: profiles, fronts, crossings, the elastic control, energy through time"
v1=$("$PYTHON" -c "print(f'{250e6/(7800*(200e9/7800)**0.5):.12g}')")
single() { # name, namelist text: one run with its namelist kept
  printf '%s\n' "$2" > "$out/$1.nml"
  "$exe" --quiet "$out/$1.nml" > "$out/$1.log" 2>&1 || true
}
for shape in linear ugimp; do
  for e in $singles; do
    single "single_${shape}_$e" "$wave
&discretisation scheme='usl', shape='$shape', elements=$e, particles_per_element=2, dt_fraction=0.2 /
&output file='$out/single_${shape}_$e.h5', snapshot_times=$end_time /"
    [ "$shape" = linear ] && single "elastic_linear_$e" "&scene kind='plastic_wave', length=1.0, youngs_modulus=200.0e9, density=7800.0, drive_velocity=$v1 /
&discretisation scheme='usl', shape='linear', elements=$e, particles_per_element=2, dt_fraction=0.2 /
&output file='$out/elastic_linear_$e.h5', snapshot_times=$end_time /"
  done
done
finest="${singles##* }"   # the energy balance at the finest mesh against the strain: V = 10 and 40 m/s too
for v in 10 40; do
  single "balance_v$v" "${wave/drive_velocity=20.0/drive_velocity=$v.0}
&discretisation scheme='usl', shape='ugimp', elements=$finest, particles_per_element=2, dt_fraction=0.2 /
&output file='$out/balance_v$v.h5', history=.false. /"
done
times=$("$PYTHON" -c "print(', '.join(f'{$end_time*k/8:.12g}' for k in range(1, 9)))")
single energy "$wave
&discretisation scheme='usl', shape='ugimp', elements=$energy_elements, particles_per_element=2, dt_fraction=0.2 /
&output file='$out/energy.h5', snapshot_times=$times /"

echo "== 4. stability with plasticity"
fractions=$("$PYTHON" -c "print(', '.join(f'{k:.2f}' for k in $ks))")
for law in hencky elastoplastic; do
  material="&material law='$law' /"
  [ "$law" = elastoplastic ] && material="&material law='elastoplastic', yield_stress=250.0e6, hardening_modulus=10.0e9 /"
  cat > "$out/stability_bar_$law.nml" <<NML
&scene velocity_amplitude=20.0 /
$material
&discretisation elements=20, particles_per_element=2, kernels='generic' /
&run periods=20.0 /
&output file='$out/stability_bar_$law.h5' /
&sweep scheme='usf', 'usl', 'musl', shape='linear', 'ugimp', 'cpgimp', 'bspline2', 'bspline3',
       dt_fraction=$fractions, min_time=0, threads=$par, progress=.false. /
NML
  "$exe" "$out/stability_bar_$law.nml" > "$out/stability_bar_$law.log" 2>&1 || true
  tail -n 1 "$out/stability_bar_$law.log"
done
fractions=$("$PYTHON" -c "print(', '.join(f'{k:.2f}' for k in $wave_ks))")
cat > "$out/stability_wave.nml" <<NML
$wave
&discretisation elements=$wave_stability, particles_per_element=2 /
&output file='$out/stability_wave.h5' /
&sweep scheme='usf', 'usl', 'musl', shape='linear', 'ugimp', 'cpgimp', 'bspline2', 'bspline3',
       dt_fraction=$fractions, min_time=0, threads=$par, progress=.false. /
NML
"$exe" "$out/stability_wave.nml" > "$out/stability_wave.log" 2>&1 || true
tail -n 1 "$out/stability_wave.log"

echo "== 5. the bar with both elastic laws"
cat > "$out/bar.nml" <<NML
&scene velocity_amplitude=0.1 /
&discretisation scheme='usl', particles_per_element=2, dt_fraction=0.1 /
&run periods=0.5 /
&output file='$out/bar.h5' /
&sweep shape='linear', 'ugimp', 'bspline2', law='hencky', 'linear', elements=$bar_elements,
       min_time=0, threads=$par, progress=.false. /
NML
"$exe" "$out/bar.nml" > "$out/bar.log" 2>&1 || true
tail -n 2 "$out/bar.log"

echo "== 6. speed (paired rounds, one thread) and memory of the laws on the generic path"
# the bar at 4 particles per element, 500 steps; elastoplastic never yielding (sigma_y = 1e30) and
# yielding (sigma_y = 1 MPa: nearly every particle yields within the run)
echo "round,law,particles,steps,run_time" > "$out/speed.csv"
steps_time=$("$PYTHON" -c "print(f'{500*0.1*25.0/$speed_elements/(200e9/7800)**0.5:.12g}')")
for round in $speed_rounds; do
  for law in hencky linear never_yielding yielding; do
    material="&material law='$law' /"
    [ "$law" = never_yielding ] && material="&material law='elastoplastic', yield_stress=1.0e30 /"
    [ "$law" = yielding ] && material="&material law='elastoplastic', yield_stress=1.0e6, hardening_modulus=1.0e9 /"
    single "speed_$law" "&scene velocity_amplitude=20.0 /
$material
&discretisation elements=$speed_elements, particles_per_element=4, dt_fraction=0.1, kernels='generic' /
&run end_time=$steps_time /
&output file='$out/speed.h5', history=.false. /"
    "$PYTHON" -c "
import h5py; s = h5py.File('$out/speed.h5')['summary']
print('$round,$law', int(s['particles'][()]), int(s['steps'][()]), repr(float(s['run_time'][()])), sep=',')" >> "$out/speed.csv"
  done
done
if command -v valgrind > /dev/null 2>&1; then   # instruction counts: repeatable under load
  portable="$(FLAGS='' mpm1d_build)"   # (valgrind does not run AVX-512 code: the plain release build)
  echo "law,instructions" > "$out/instructions.csv"
  cg_elements=$((speed_elements / 10))
  cg_time=$("$PYTHON" -c "print(f'{200*0.1*25.0/$cg_elements/(200e9/7800)**0.5:.12g}')")
  for law in hencky linear never_yielding yielding; do
    sed -e "s/elements=$speed_elements,/elements=$cg_elements,/" -e "s/end_time=$steps_time/end_time=$cg_time/" \
      "$out/speed_$law.nml" > "$out/callgrind_$law.nml"
    n=$(valgrind --tool=callgrind --callgrind-out-file=/dev/null "$portable" --quiet "$out/callgrind_$law.nml" 2>&1 \
        | sed -n 's/.*Collected : \([0-9]*\).*/\1/p')
    echo "$law,$n" >> "$out/instructions.csv"
  done
fi
echo "law,particles,max_rss_kib" > "$out/memory.csv"
for law in hencky linear elastoplastic; do
  for e in $memory_elements $((2 * memory_elements)); do
    printf '%s\n' "&scene velocity_amplitude=0.1 /" "&material law='$law' /" \
      "&discretisation elements=$e, particles_per_element=4, dt_fraction=0.1, kernels='generic' /" \
      "&run end_time=1.0e-7 /" "&output file='$out/memory.h5', history=.false. /" > "$out/memory_$law.nml"
    rss=$(/usr/bin/time -f '%M' "$exe" --quiet "$out/memory_$law.nml" 2>&1 >/dev/null | tail -n 1)
    echo "$law,$((4 * e)),$rss" >> "$out/memory.csv"
  done
done
rm -f "$out/speed.h5" "$out/memory.h5"

echo "== summary"
end=$(date +%s.%N)
awk -v a="$start" -v b="$end" -v l="$load" -v n="$(getconf _NPROCESSORS_ONLN)" \
  'BEGIN{printf "%.1f %s %s\n", b-a, l, n}' > "$out/wall_time.txt"
"$PYTHON" studies/materials/analyze.py "$out"
echo "wrote $out/summary.md (seconds, load average at the start, cores: $(cat "$out/wall_time.txt"))"
