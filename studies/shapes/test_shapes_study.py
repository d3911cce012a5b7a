#!/usr/bin/env python3
"""Pipeline test of the shapes study: runs `MPM1D_QUICK=1 bash studies/shapes/run.sh` (seconds)
through the real executables into a temporary folder and checks that the sweeps, the prediction,
the speed table, the figures and summary.md are written with every section, that USL converges at
about second order for every shape at small amplitude (PIC at first order at best), that the measured USL limit of GIMP at
4 particles per element lies within 0.1 of the prediction for the stretched bar; from the tiny runs of the added
sections: temporal orders (USF 1, USL 2 with FLIP; PIC's change grows as dt falls), energy drift (USF and MUSL with
FLIP conserve to 1e-3 over the quick run, PIC loses over 10 %), the B-splines' second order on the manufactured
scene with both ends fixed (the mirror at x = L), linear's stress noise under grid crossing above every wide
shape's, the answer table with three targets. The study's computations are tested on synthetic data by
postprocess/tests/test_study_shapes.py.
Plain script: last line `N passed, M failed`, exit status 1 on any failure."""

import csv
import os
import re
import sys

from mpm1d_post.study_checks import Checks, run_quick

HERE = os.path.dirname(os.path.abspath(__file__))


def main() -> int:
    check = Checks()
    out, proc = run_quick(HERE, 'mpm1d_shapes_', timeout=900)
    check('run.sh (quick) exits 0', proc.returncode == 0, proc.stdout[-2000:] + proc.stderr[-2000:])
    for name in ('convergence_small.h5', 'convergence_large.h5', 'transfers_small.h5', 'transfers_large.h5',
                 'stability.h5', 'predicted_shapes.csv', 'temporal_small.h5', 'table2.h5', 'energy_small.h5',
                 'manufactured.h5', 'speed.csv', 'summary.md'):
        check(f'{name} written', os.path.isfile(os.path.join(out, name)))
    for name in ('error_vs_time.png', 'table2_error_maps_usf.png', 'table2_error_maps_usl.png', 'crossing_stress.png',
                 'crossing_energy.png', 'energy_small.png', 'energy_large.png', 'error_profiles.png'):
        png = os.path.join(out, name)
        check(f'{name} written', os.path.isfile(png) and os.path.getsize(png) > 10000)
    text = open(os.path.join(out, 'summary.md')).read() if os.path.isfile(os.path.join(out, 'summary.md')) else ''
    for heading in ('Spatial convergence, small amplitude', 'Large motion', 'Transfers, USL, v0 = 0.1 m/s',
                    'Transfers, USL, v0 = 0.01 c', 'Error against run time',
                    'Critical time-step fraction', 'Throughput', 'Temporal convergence, v0 = 0.1 m/s',
                    "Table-2 sweep for every shape", 'Grid crossing under large motion', 'Energy over',
                    'Observed spatial orders on every scene', 'What limits each order', 'For a target relative error',
                    'Pareto front', 'Run time of the study'):
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
    # temporal convergence: the last observed order of the linear rows
    for scheme, expected in (('usf', 1.0), ('usl', 2.0)):
        m = re.search(rf'^\| {scheme} \| linear \| flip \|(?: [^|]* \|){{2}} ([-0-9.]+) \| [^|]* \|$', text, re.M)
        check(f'temporal order of {scheme} linear flip about {expected}', m is not None and abs(float(m.group(1)) - expected) < 0.25,
              m.group(0) if m else 'no row')
    m = re.search(r'^\| usl \| linear \| pic \| ([0-9.e+-]+) \| ([0-9.e+-]+) \|', text, re.M)
    check("PIC's change grows as dt falls (no convergence in dt)", m is not None and float(m.group(2)) > float(m.group(1)),
          m.group(0) if m else 'no row')
    # energy drift: USF and MUSL with FLIP conserve, PIC dissipates
    section = text[text.find('## Energy over'):]
    for scheme in ('usf', 'musl'):
        m = re.search(rf'^\| {scheme} \| linear \| ([-+0-9.e]+) \| ([-+0-9.e]+) \|', section, re.M)
        check(f'{scheme} linear: FLIP drift below 1e-3, PIC loses over 10 %',
              m is not None and abs(float(m.group(1))) < 1e-3 and float(m.group(2)) < -0.1, m.group(0) if m else 'no row')
    # manufactured, both ends fixed: B-splines second order at small strain (the mirror at x = L)
    section = text[text.find('### Manufactured solution, A/L = 1e-06'):]
    for shape in ('bspline2', 'bspline3'):
        m = re.search(rf'^\| usl \| {shape} \|.*\| [-0-9.]+, ([-0-9.]+) \|$', section, re.M)
        check(f'manufactured A/L = 1e-6, usl {shape}: last order at least 1.8', m is not None and float(m.group(1)) >= 1.8,
              m.group(0) if m else 'no row')
    # grid crossing: linear's stress noise above every wide shape's (MUSL: every run completes)
    noise = {m.group(1): float(m.group(2)) for m in
             re.finditer(r'^\| musl \| (\w+) \| ok \| [^|]* \| [^|]* \| [^|]* \| ([0-9.e+-]+) \|$', text, re.M)}
    check('grid crossing: linear noisier than every wide shape (MUSL)', len(noise) == 5 and
          all(noise['linear'] > 3 * noise[h] for h in noise if h != 'linear'), str(noise))
    answers = re.findall(r'^\| (1e-0[234]) \| (\w+ \w+ \w+ \d+ el\.|none of the measured runs) \|', text, re.M)
    check('answer table: one row per target 1e-2, 1e-3, 1e-4', [a[0] for a in answers] == ['1e-02', '1e-03', '1e-04'],
          str(answers))
    with open(os.path.join(out, 'speed.csv')) as handle:
        rows = list(csv.DictReader(handle))
    check('speed: every shape timed', {r['shape'] for r in rows} == {'linear', 'ugimp', 'cpgimp', 'bspline2', 'bspline3'})
    passed, failed = sum(check.results), len(check.results) - sum(check.results)
    print(f'{passed} passed, {failed} failed')
    return 0 if failed == 0 else 1


if __name__ == '__main__':
    sys.exit(main())
