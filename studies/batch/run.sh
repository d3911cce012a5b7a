#!/usr/bin/env bash
# A batch of single runs scripted in the shell, the way a study is often written by hand: one
# namelist, the scheme and the mesh changed on the command line (overrides group.name=value),
# then one Python call collects max_error and run_time of every run into results.csv.
# Usage: bash studies/batch/run.sh [output folder]          (default: out/batch)
# SCHEMES and ELEMENTS choose the loops (default: "usf usl musl" and "10 20 40 80").
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
cd "$root"
source studies/setup.sh
set -euo pipefail
out="$(mkdir -p "${1:-out/batch}" && cd "${1:-out/batch}" && pwd)"
exe="$(mpm1d_build)"  # -march=native unless PORTABLE=1 (studies/setup.sh)

cat > "$out/case.nml" <<'NML'
&scene velocity_amplitude=0.1, mode=1 /
&discretisation particles_per_element=2, dt_fraction=0.1 /
&run periods=2.0 /
&output history=.false. /
NML

for scheme in ${SCHEMES:-usf usl musl}; do
  for elements in ${ELEMENTS:-10 20 40 80}; do
    "$exe" "$out/case.nml" --quiet discretisation.scheme="$scheme" discretisation.elements="$elements" \
      output.file="$out/${scheme}_e${elements}.h5"
  done
done

"$PYTHON" - "$out" <<'PY'
import csv, sys
from pathlib import Path
from mpm1d_post import load_run
out = Path(sys.argv[1])
with open(out / 'results.csv', 'w', newline='') as f:
    w = csv.writer(f)
    w.writerow(['scheme', 'elements', 'max_error', 'run_time', 'status'])
    for path in sorted(out.glob('*_e*.h5')):
        run = load_run(path)
        w.writerow([run.scheme, run.elements, f"{run.summary['max_error']:.6e}",
                    f"{run.summary['run_time']:.3e}", run.summary['status_name']])
print('wrote', out / 'results.csv')
PY
