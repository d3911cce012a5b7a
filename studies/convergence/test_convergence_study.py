#!/usr/bin/python3
"""Pipeline test of the convergence study: runs `MPM1D_QUICK=1 bash studies/convergence/run.sh`
(100 to 800 elements, seconds) into a temporary folder and checks the physics it reports: USL at the
smallest amplitude converges at second order (order 2 of the mesh, within [1.8, 2.6]); USL at
v0 = 0.1 m/s stops falling from 400 elements on at a floor of the order of v0/c (between 0.05 and 0.5
of it: the model difference, not a discretisation error); USF's error is the same at every amplitude.
Plain script: last line `N passed, M failed`, exit status 1 on any failure.
"""

import os
import sys

import numpy as np

from mpm1d_post.convergence import floor_start, local_orders
from mpm1d_post.loader import load_sweep

from mpm1d_post.study_checks import Checks, run_quick

HERE = os.path.dirname(os.path.abspath(__file__))

results = []


def check(name, ok, detail=''):
    results.append(bool(ok))
    print(f"{'ok  ' if ok else 'FAIL'} {name}" + (f': {detail}' if detail else ''))


def series(c, scheme, v0):
    m = (c['scheme'] == scheme) & np.isclose(c['velocity_amplitude'], v0)
    idx = np.flatnonzero(m)[np.argsort(c['elements'][m])]
    return c['elements'][idx].astype(float), c['relative_error'][idx], idx


def main() -> int:
    out, proc = run_quick(HERE, 'mpm1d_convergence_', timeout=600)
    check('run.sh (quick) exits 0', proc.returncode == 0, '' if proc.returncode == 0 else proc.stderr[-2000:])
    for name in ('convergence.h5', 'convergence.png', 'summary.md'):
        check(f'{name} written', os.path.isfile(os.path.join(out, name)))
    if proc.returncode != 0:
        print(f'{sum(results)} passed, {len(results) - sum(results)} failed')
        return 1
    c = load_sweep(os.path.join(out, 'convergence.h5'), cases='all').cases
    check('every case completed', bool(np.all(c['status'] == 0)))
    ne, rel, _ = series(c, 'usl', 0.001)
    order = float(np.mean(local_orders(ne, rel)))
    check('USL, v0 = 0.001 m/s: second order', 1.8 <= order <= 2.6, f'mean order {order:.2f}')
    ne, rel, idx = series(c, 'usl', 0.1)
    start = floor_start(local_orders(ne, rel))
    check('USL, v0 = 0.1 m/s: a floor from 400 elements on', start is not None and ne[start] <= 400,
          f'floor from {ne[start] if start is not None else None}')
    ratio = 0.1 / np.sqrt(c['youngs_modulus'][idx[0]] / c['density'][idx[0]])
    floor = float(rel[start:].min()) if start is not None else float('nan')
    check('USL, v0 = 0.1 m/s: the floor is of the order of v0/c', 0.05 <= floor / ratio <= 0.5,
          f'floor {floor:.3g} = {floor / ratio:.3g} v0/c')
    _, a, _ = series(c, 'usf', 0.1)
    _, b, _ = series(c, 'usf', 0.001)
    check('USF: the same error at every amplitude (its own discretisation error)',
          bool(np.all(np.abs(a / b - 1) < 0.1)), f'largest ratio {np.max(a / b):.3f}')
    print(f'{sum(results)} passed, {len(results) - sum(results)} failed')
    return 0 if all(results) else 1


if __name__ == '__main__':
    sys.exit(main())
