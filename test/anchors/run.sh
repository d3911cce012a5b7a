#!/usr/bin/env bash
# Regression anchors: run a fixed set of cases with a given mpm1d executable and keep their HDF5
# files, so that two builds (before and after a refactor) can be compared dataset by dataset with
# compare.py. Not part of the test suite (it takes a few minutes); a developer's tool:
#   bash test/anchors/run.sh OLD_MPM1D out/anchors_old
#   bash test/anchors/run.sh NEW_MPM1D out/anchors_new
#   .venv/bin/python test/anchors/compare.py out/anchors_old out/anchors_new
# Sets (ANCHORS="paper generic fused plastic implicit large" by default, any subset):
#   paper    the founding paper's Table-2 sweeps (USF, USL, MUSL; 6 x 10 x 10 cases each, histories)
#   generic  every scene x scheme x shape x transfer on the generic path (kernels='generic')
#   fused    the bar, every scheme x shape with FLIP on the fused kernels, two amplitudes
#   plastic  the elastoplastic law, yielding, on the fused kernels: the bar (every scheme x shape x
#            transfer), the column, the composite bar and the frictionless impact (every scheme x shape)
#   implicit the implicit integrator: the bar (laws linear and hencky, lumped and consistent mass, time
#            steps of 0.5-4 dx/c) and the stiff composite bar
#   large    3e5-particle bar runs cut into segments (linear, each scheme; wide shapes with USL at
#            1.2e5), on 1 and 2 threads, with a snapshot of every particle at the end
set -euo pipefail
bin="$(cd "$(dirname "$1")" && pwd)/$(basename "$1")"; out="$2"
sets="${ANCHORS:-paper generic fused plastic implicit large}"
mkdir -p "$out"; cd "$out"
run() { # name, namelist text, [threads], [more &output variables]
  printf '%s\n&output file=%s %s /\n' "$2" "'$1.h5'" "${4:+, $4}" > "$1.nml"
  OMP_NUM_THREADS="${3:-2}" "$bin" --quiet "$1.nml" > "$1.log" 2>&1 || { echo "anchor $1 failed (see $out/$1.log)"; return 1; }
}
sw="histories=.true., min_time=0, threads=2, progress=.false."
for s in $sets; do case $s in
paper)
  for sch in usf usl musl; do
    run "paper_$sch" "&scene kind='vibrating_bar', length=25.0, youngs_modulus=200.0e9, density=7800.0, velocity_amplitude=0.1 /
&run periods=2.0 /
&sweep schemes='$sch', elements=1, 3, 7, 10, 20, 50, particles_per_element=1, 2, 3, 4, 5, 6, 7, 8, 9, 10,
 dt_fractions=0.05, 0.10, 0.15, 0.20, 0.25, 0.30, 0.35, 0.40, 0.45, 0.50, $sw /"
  done ;;
generic)
  lists="schemes='usf','usl','musl', shapes='linear','ugimp','cpgimp','bspline2','bspline3', transfers='flip','pic','blend','apic'"
  run generic_bar "&scene kind='vibrating_bar', velocity_amplitude=50.0 /
&discretisation elements=20, particles_per_element=2, dt_fraction=0.2, kernels='generic' /
&run periods=1.0 /
&sweep $lists, $sw /"
  run generic_column "&scene kind='column' /
&discretisation elements=20, particles_per_element=2, dt_fraction=0.2, kernels='generic' /
&run periods=1.0 /
&sweep $lists, $sw /"
  run generic_manufactured "&scene kind='manufactured', length=1.0, youngs_modulus=1.0e7, density=1000.0, amplitude=1.0e-3 /
&discretisation elements=20, particles_per_element=2, dt_fraction=0.1 /
&run periods=1.0 /
&sweep $lists, $sw /"
  run generic_composite "&scene kind='composite_bar', lengths=1.0, 1.0, youngs_moduli=16.0e6, 1.0e6, densities=1000.0, 1000.0, drive_velocity=0.01 /
&discretisation elements=40, particles_per_element=2, dt_fraction=0.2 /
&run periods=0.5 /
&sweep $lists, $sw /"
  for c in frictionless none; do
  run generic_impact_$c "&scene kind='impact', lengths=1.0, 1.0, youngs_moduli=200.0e9, 200.0e9, densities=7800.0, 7800.0, velocities=1.0, -1.0, gap=0.0, contact='$c' /
&discretisation elements=40, particles_per_element=2, dt_fraction=0.2 /
&run periods=1.0 /
&sweep $lists, $sw /"
  done ;;
fused)
  for v in 0.1 50.6; do
    run "fused_bar_v$v" "&scene kind='vibrating_bar', velocity_amplitude=$v /
&discretisation elements=40, particles_per_element=4, dt_fraction=0.2 /
&run periods=1.0 /
&sweep schemes='usf','usl','musl', shapes='linear','ugimp','cpgimp','bspline2','bspline3', $sw /"
  done ;;
plastic)
  run plastic_bar "&scene kind='vibrating_bar', velocity_amplitude=50.0 /
&material law='elastoplastic', yield_stress=2.0e8, hardening_modulus=1.0e10 /
&discretisation elements=20, particles_per_element=2, dt_fraction=0.2 /
&run periods=1.0 /
&sweep schemes='usf','usl','musl', shapes='linear','ugimp','cpgimp','bspline2','bspline3',
 transfers='flip','pic','blend','apic','asflip', $sw /"
  run plastic_column "&scene kind='column' /
&material law='elastoplastic', yield_stress=1.0e3, hardening_modulus=1.0e4 /
&discretisation elements=20, particles_per_element=2, dt_fraction=0.2 /
&run periods=1.0 /
&sweep schemes='usf','usl','musl', shapes='linear','ugimp','cpgimp','bspline2','bspline3', $sw /"
  run plastic_composite "&scene kind='composite_bar', lengths=1.0, 1.0, youngs_moduli=16.0e6, 1.0e6, densities=1000.0, 1000.0, drive_velocity=0.5 /
&material law='elastoplastic', yield_stresses=2.0e5, 1.0e5, hardening_moduli=1.0e6, 1.0e5 /
&discretisation elements=40, particles_per_element=2, dt_fraction=0.2 /
&run periods=0.5 /
&sweep schemes='usf','usl','musl', shapes='linear','ugimp','cpgimp','bspline2','bspline3', $sw /"
  run plastic_impact "&scene kind='impact', lengths=1.0, 1.0, youngs_moduli=200.0e9, 200.0e9, densities=7800.0, 7800.0, velocities=10.0, -10.0, gap=0.0, contact='frictionless' /
&material law='elastoplastic', yield_stresses=2.0e8, 1.0e8, hardening_moduli=1.0e10, 1.0e9 /
&discretisation elements=40, particles_per_element=2, dt_fraction=0.2 /
&run periods=1.0 /
&sweep schemes='usf','usl','musl', shapes='linear','ugimp','cpgimp','bspline2','bspline3', $sw /"
  ;;
implicit)
  for law in linear hencky; do
    for mass in lumped consistent; do
      run "implicit_bar_${law}_$mass" "&scene kind='vibrating_bar', velocity_amplitude=50.0 /
&material law='$law' /
&discretisation integrator='implicit', mass='$mass', particles_per_element=2 /
&run periods=1.0 /
&sweep elements=20, 200, dt_fractions=0.5, 1.0, 4.0, $sw /"
    done
  done
  run implicit_composite "&scene kind='composite_bar', lengths=1.0, 1.0, youngs_moduli=1.0e9, 1.0e6, densities=1000.0, 1000.0, drive_velocity=0.01 /
&discretisation integrator='implicit', elements=40, particles_per_element=2, dt_fraction=2.0 /
&run periods=0.5 /
&sweep shapes='linear','ugimp','bspline2', $sw /"
  ;;
large)
  for t in 1 2; do
    for sch in usf usl musl; do
      run "large_linear_${sch}_t$t" "&scene kind='vibrating_bar', velocity_amplitude=0.1 /
&discretisation scheme='$sch', elements=30000, particles_per_element=10, dt_fraction=0.3 /
&run end_time=1.0e-4 /" "$t" "snapshot_times=1.0e-4"
    done
    for shp in ugimp cpgimp bspline2 bspline3; do
      run "large_${shp}_usl_t$t" "&scene kind='vibrating_bar', velocity_amplitude=50.6 /
&discretisation scheme='usl', shape='$shp', elements=30000, particles_per_element=4, dt_fraction=0.3 /
&run end_time=1.0e-4 /" "$t" "snapshot_times=1.0e-4"
    done
  done ;;
*) echo "unknown anchor set '$s'"; exit 2 ;;
esac; done
echo "anchors ($sets) written to $PWD"
