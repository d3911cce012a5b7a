#!/usr/bin/env bash
# The scenes study (README, Scenes): each scene's error against elements for USF, USL and MUSL
# (one sweep namelist per scene in this folder), a figure per scene and summary.md with the
# observed orders. Takes well under a minute.
# Usage: bash studies/scenes/run.sh [output folder]     (default: out/scenes)
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
cd "$root"
source studies/setup.sh
set -euo pipefail
out="$(mkdir -p "${1:-out/scenes}" && cd "${1:-out/scenes}" && pwd)"
exe="$(mpm1d_build)"  # -march=native unless PORTABLE=1 (studies/setup.sh)
files=()
for nml in studies/scenes/*.nml; do
  name="$(basename "$nml" .nml)"
  sed "s|file='$name.h5'|file='$out/$name.h5'|" "$nml" > "$out/$name.nml"
  "$exe" "$out/$name.nml" > "$out/$name.log"
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
single field_composite 0.03 "&scene kind='composite_bar', lengths=1.0, 1.0, youngs_moduli=16.0e6, 1.0e6, densities=1000.0, 1000.0, drive_velocity=0.01 /
&discretisation scheme='usl', elements=200, particles_per_element=2, dt_fraction=0.2 /
&run end_time=0.03 /"
"$PYTHON" studies/scenes/report.py "$out" "${files[@]}" --fields "${fields[@]}"
