#!/usr/bin/python3
"""Pipeline test of the shapes study: runs `MPM1D_QUICK=1 bash studies/shapes/run.sh` (seconds)
through the real executables into a temporary folder and checks that the sweeps, the prediction,
the speed table, the figure and summary.md are written with every section, that USL converges at
about second order for every shape at small amplitude (PIC at first order at best), and that the measured USL limit of GIMP at
4 particles per element lies within 0.1 of the prediction for the stretched bar.
Plain script: last line `N passed, M failed`, exit status 1 on any failure."""

import csv
import os
import re
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.abspath(os.path.join(HERE, '..', '..'))
results = []


def check(name, ok, detail=''):
    results.append(bool(ok))
    print(f"{'ok  ' if ok else 'FAIL'} {name}" + (f': {detail}' if detail and not ok else ''))


def main() -> int:
    out = tempfile.mkdtemp(prefix='mpm1d_shapes_')
    env = dict(os.environ, MPM1D_QUICK='1')
    proc = subprocess.run(['bash', os.path.join(HERE, 'run.sh'), out], cwd=ROOT, env=env,
                          capture_output=True, text=True, timeout=900)
    check('run.sh (quick) exits 0', proc.returncode == 0, proc.stdout[-2000:] + proc.stderr[-2000:])
    for name in ('convergence_small.h5', 'convergence_large.h5', 'transfers_small.h5', 'transfers_large.h5',
                 'stability.h5', 'predicted_shapes.csv',
                 'speed.csv', 'summary.md'):
        check(f'{name} written', os.path.isfile(os.path.join(out, name)))
    png = os.path.join(out, 'error_vs_time.png')
    check('error_vs_time.png written', os.path.isfile(png) and os.path.getsize(png) > 10000)
    text = open(os.path.join(out, 'summary.md')).read() if os.path.isfile(os.path.join(out, 'summary.md')) else ''
    for heading in ('Spatial convergence, small amplitude', 'Large motion', 'Transfers, USL, v0 = 0.1 m/s',
                    'Transfers, USL, v0 = 0.01 c', 'Error against run time',
                    'Critical time-step fraction', 'Throughput'):
        check(f'summary has section "{heading}"', heading in text)
    for shape in ('linear', 'ugimp', 'cpgimp', 'bspline2', 'bspline3'):
        m = re.search(rf'^\| usl \| {shape} \|.*\| ([0-9.]+), ([0-9.]+) \|$', text, re.M)
        check(f'usl {shape}: order about 2 at small amplitude', m is not None and abs(float(m.group(2)) - 2) < 0.2,
              m.group(0) if m else 'no row')
    m = re.search(r'^\| usl \| ugimp \| [^|]* \| [^|]* \| ([0-9.]+) / ([0-9.]+) / ([0-9.]+) \|$', text, re.M)
    check('usl ugimp 4 ppc: measured limit within 0.1 of the stretched prediction',
          m is not None and abs(float(m.group(1)) - float(m.group(3))) <= 0.1, m.group(0) if m else 'no row')
    m = re.search(r'^\| bspline3 \| pic \|.*\| ([0-9.]+), ([0-9.]+) \|$', text, re.M)
    check('PIC converges at first order at best', m is not None and float(m.group(2)) < 1.2, m.group(0) if m else 'no row')
    with open(os.path.join(out, 'speed.csv')) as handle:
        rows = list(csv.DictReader(handle))
    check('speed: every shape timed', {r['shape'] for r in rows} == {'linear', 'ugimp', 'cpgimp', 'bspline2', 'bspline3'})
    passed, failed = sum(results), len(results) - sum(results)
    print(f'{passed} passed, {failed} failed')
    return 0 if failed == 0 else 1


if __name__ == '__main__':
    sys.exit(main())
