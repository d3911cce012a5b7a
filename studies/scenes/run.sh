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
fpm build --profile release >/dev/null
exe="$root/$(fpm run --profile release --target mpm1d --runner echo 2>/dev/null | tail -n 1)"
files=()
for nml in studies/scenes/*.nml; do
  name="$(basename "$nml" .nml)"
  sed "s|file='$name.h5'|file='$out/$name.h5'|" "$nml" > "$out/$name.nml"
  "$exe" "$out/$name.nml" > "$out/$name.log"
  files+=("$out/$name.h5")
done
"$PYTHON" studies/scenes/report.py "$out" "${files[@]}"
