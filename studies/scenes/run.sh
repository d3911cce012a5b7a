#!/usr/bin/env bash
# The scenes study (README, Scenes): each scene's error against elements (and against run time) for
# USF, USL and MUSL (one sweep namelist per scene in this folder), its error against dt at a fixed
# mesh, its stability limit (a sweep of dt_fraction, next to the bar's), pictures of the fields
# against the exact solutions (the impact's interface stress and u_cm,1 against time, frictionless
# and stuck), the benchmark's bytes per particle and particle-steps/s per scene, and summary.md.
# Takes two to three minutes on two cores; MPM1D_QUICK=1 (the pipeline test) runs a few seconds'
# worth: two resolutions, a coarse dt_fraction grid, short runs.
# Usage: bash studies/scenes/run.sh [output folder]     (default: out/scenes)
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
cd "$root"
source studies/setup.sh
set -euo pipefail
out="$(mkdir -p "${1:-out/scenes}" && cd "${1:-out/scenes}" && pwd)"
exe="$(mpm1d_build)"  # -march=native unless PORTABLE=1 (studies/setup.sh)
quick="${MPM1D_QUICK:-0}"
sweep_quick=()
if [ "$quick" = 1 ]; then sweep_quick=(sweep.elements=50,100 sweep.min_time=0.002); fi
files=()
for nml in studies/scenes/*.nml; do
  name="$(basename "$nml" .nml)"
  sed "s|file='$name.h5'|file='$out/$name.h5'|" "$nml" > "$out/$name.nml"
  "$exe" "$out/$name.nml" "${sweep_quick[@]}" > "$out/$name.log"
  files+=("$out/$name.h5")
done
# one run per scene with a snapshot, for the pictures of the fields against the exact solutions
fields=()
single() { # name, snapshot time, namelist groups
  printf '%s\n' "$3" "&output file='$out/$1.h5', snapshot_times=$2 /" > "$out/$1.nml"
  "$exe" "$out/$1.nml" > "$out/$1.log"
  fields+=("$out/$1.h5")
}
single field_column 0.0079 "&scene kind='column', length=25.0, youngs_modulus=200.0e9, density=7800.0, gravity=9.81 /
&discretisation scheme='usl', elements=50, particles_per_element=2, dt_fraction=0.2 /
&run end_time=0.0079 /"
single field_manufactured 0.005 "&scene kind='manufactured', length=1.0, youngs_modulus=1.0e7, density=1000.0, amplitude=0.05 /
&discretisation scheme='usl', elements=50, particles_per_element=2, dt_fraction=0.2 /
&run end_time=0.005 /"
# the impact: 64 snapshots over 2 periods (4L/c), frictionless and stuck
impact_scene="&scene kind='impact', lengths=1.0, 1.0, youngs_moduli=200.0e9, 200.0e9, densities=7800.0, 7800.0, velocities=1.0, -1.0, gap=0.0"
impact_times="$("$PYTHON" -c "print(', '.join(f'{k * 4.0 / (200.0e9 / 7800.0) ** 0.5 / 64:.9e}' for k in range(64)))")"
for contact in frictionless none; do
  single "field_impact_$contact" "$impact_times" "$impact_scene, contact='$contact' /
&discretisation scheme='usl', elements=200, particles_per_element=2, dt_fraction=0.2 /
&run periods=2.0 /"
done
single field_composite 0.03 "&scene kind='composite_bar', lengths=1.0, 1.0, youngs_moduli=16.0e6, 1.0e6, densities=1000.0, 1000.0, drive_velocity=0.01 /
&discretisation scheme='usl', elements=200, particles_per_element=2, dt_fraction=0.2 /
&run end_time=0.03 /"
# stability: each scene (and the bar) over dt_fraction 0.05 to 2.6 in steps of 0.05, 25 elements x 2
# particles, long runs; the limit is the largest fraction below the first that a guard stops
fractions="$("$PYTHON" -c "print(', '.join(f'{0.05 * k:.2f}' for k in range(1, 53)))")"
long=20; impact_long=10
if [ "$quick" = 1 ]; then
  fractions="$("$PYTHON" -c "print(', '.join(f'{0.25 * k:.2f}' for k in range(1, 11)))")"; long=4; impact_long=4
fi
stability=()
limit() { # name, namelist groups (scene, run)
  printf '%s\n' "$2" "&discretisation elements=25, particles_per_element=2 /" \
    "&output file='$out/$1.h5' /" "&sweep schemes='usf', 'usl', 'musl', dt_fractions=$fractions, min_time=0 /" \
    > "$out/$1.nml"
  "$exe" "$out/$1.nml" > "$out/$1.log"
  stability+=("$out/$1.h5")
}
limit stability_vibrating_bar "&scene kind='vibrating_bar', length=25.0 /
&run periods=$long /"
limit stability_column "&scene kind='column', length=25.0 /
&run periods=$long /"
limit stability_manufactured "&scene kind='manufactured', length=1.0, youngs_modulus=1.0e7, density=1000.0, amplitude=1.0e-6 /
&run periods=$long /"
limit stability_composite "&scene kind='composite_bar', lengths=1.0, 1.0, youngs_moduli=16.0e6, 1.0e6, densities=1000.0, 1000.0, drive_velocity=0.01 /
&run end_time=0.2 /"
limit stability_impact_frictionless "$impact_scene, contact='frictionless' /
&run periods=$impact_long /"
limit stability_impact_none "$impact_scene, contact='none' /
&run periods=$impact_long /"
# convergence in time: dt_fraction halved at a fixed mesh (100 elements x 2; the impact 200)
timing=()
time_fractions="0.4, 0.2, 0.1, 0.05"
if [ "$quick" = 1 ]; then time_fractions="0.4, 0.2"; fi
in_time() { # name, elements, namelist groups (scene, run)
  printf '%s\n' "$3" "&discretisation elements=$2, particles_per_element=2 /" "&output file='$out/$1.h5' /" \
    "&sweep schemes='usf', 'usl', 'musl', dt_fractions=$time_fractions, min_time=0 /" > "$out/$1.nml"
  "$exe" "$out/$1.nml" > "$out/$1.log"
  timing+=("$out/$1.h5")
}
in_time time_column 100 "&scene kind='column', length=25.0 /
&run periods=2 /"
in_time time_manufactured 100 "&scene kind='manufactured', length=1.0, youngs_modulus=1.0e7, density=1000.0, amplitude=1.0e-6 /
&run periods=1 /"
in_time time_composite 100 "&scene kind='composite_bar', lengths=1.0, 1.0, youngs_moduli=16.0e6, 1.0e6, densities=1000.0, 1000.0, drive_velocity=0.01 /
&run end_time=0.03 /"
in_time time_impact_frictionless 200 "$impact_scene, contact='frictionless' /
&run periods=2 /"
in_time time_impact_none 200 "$impact_scene, contact='none' /
&run periods=2 /"
# "only what it needs": bytes per particle and particle-steps/s of each scene (the benchmark's scenes mode)
bench="$(mpm1d_build --example mpm1d_bench)"
if [ "$quick" = 1 ]; then "$bench" scenes 200 2 200 3 > "$out/bench_scenes.csv"
else "$bench" scenes 2000 2 1000 5 > "$out/bench_scenes.csv"; fi
"$PYTHON" studies/scenes/report.py "$out" "${files[@]}" --fields "${fields[@]}" --stability "${stability[@]}" \
  --time "${timing[@]}" --bench "$out/bench_scenes.csv"
