#!/usr/bin/env python3
"""Pipeline test of the convergence study: runs `MPM1D_QUICK=1 bash studies/convergence/run.sh` (linear
shapes 100 to 800 elements, uGIMP to 400, both elastic laws; seconds) into a temporary folder and checks the
physics it reports:
- hencky, linear shapes: second order at the smallest amplitude; at v0 = 0.1 m/s a floor from 400
  elements on of the order of v0/c (0.05 to 0.5 of it); USF's error the same at every amplitude and law;
- the linear law (sigma = E (J - 1): the exact solution is exact) with uGIMP keeps second order at
  v0 = 0.1 m/s, where Hencky with uGIMP is already more than twice its error (the model difference);
  with linear shapes the linear law stops on a floor (the method's);
- the split from the histories: the model difference (hencky - linear law, uGIMP) is the same multiple of
  v0/c at the three amplitudes (within 2 %), the linear shapes' method error (linear - uGIMP, linear law)
  has the other sign and is larger, and the parts add up to the run's error to round-off.
Plain script: last line `N passed, M failed`, exit status 1 on any failure.
"""

import os
import sys

import numpy as np

from mpm1d_post.studies.convergence import floor_start, parts, series, signed_peak
from mpm1d_post.orders import successive_orders
from mpm1d_post.loader import concatenate_sweeps, load_sweep

from mpm1d_post.study_checks import Checks, run_quick

HERE = os.path.dirname(os.path.abspath(__file__))


def main() -> int:
    check = Checks()
    out, proc = run_quick(HERE, 'mpm1d_convergence_', timeout=900)
    check('run.sh (quick) exits 0', proc.returncode == 0, '' if proc.returncode == 0 else proc.stderr[-2000:])
    for name in ('linear.h5', 'wide.h5', 'parts.h5', 'convergence.png', 'parts.png', 'summary.md'):
        check(f'{name} written', os.path.isfile(os.path.join(out, name)))
    if proc.returncode != 0:
        print(f'{sum(check.results)} passed, {len(check.results) - sum(check.results)} failed')
        return 1
    sweep = concatenate_sweeps([load_sweep(os.path.join(out, f), cases='all') for f in ('linear.h5', 'wide.h5')])
    c = sweep.cases
    check('every case completed', bool(np.all(sweep.ok)))
    c_ = np.sqrt(c['youngs_modulus'][0] / c['density'][0])

    ne, rel, _ = series(sweep, 'usl', 'linear', 'hencky', 0.001)
    order = float(np.mean(successive_orders(ne, rel)))
    check('hencky, linear shapes, v0 = 0.001 m/s: second order', 1.8 <= order <= 2.6, f'mean order {order:.2f}')
    ne, rel, _ = series(sweep, 'usl', 'linear', 'hencky', 0.1)
    start = floor_start(successive_orders(ne, rel))
    check('hencky, linear shapes, v0 = 0.1 m/s: a floor from 400 elements on', start is not None and ne[start] <= 400,
          f'floor from {ne[start] if start is not None else None}')
    floor = float(rel[start:].min()) if start is not None else float('nan')
    check('... of the order of v0/c', 0.05 <= floor / (0.1 / c_) <= 0.5, f'floor {floor:.3g} = {floor / (0.1 / c_):.3g} v0/c')
    for law in ('hencky', 'linear'):
        _, a, _ = series(sweep, 'usf', 'linear', law, 0.1)
        _, b, _ = series(sweep, 'usf', 'linear', law, 0.001)
        check(f'USF, {law}: the same error at every amplitude (its own discretisation error)',
              len(a) == len(b) > 0 and bool(np.all(np.abs(a / b - 1) < 0.1)), f'ratios {a / b}')

    ne, lin, _ = series(sweep, 'usl', 'ugimp', 'linear', 0.1)
    _, hen, _ = series(sweep, 'usl', 'ugimp', 'hencky', 0.1)
    order = float(successive_orders(ne, lin)[-1])
    check('linear law, uGIMP, v0 = 0.1 m/s: second order to the finest mesh', 1.8 <= order <= 2.3, f'order {order:.2f}')
    check('... where Hencky with uGIMP has more than twice its error', hen[-1] > 2 * lin[-1], f'{hen[-1]:.3g} vs {lin[-1]:.3g}')
    ne, rel, _ = series(sweep, 'usl', 'linear', 'linear', 0.1)
    check('linear law, linear shapes, v0 = 0.1 m/s: a floor (order below 0.5 at the last pair)',
          float(successive_orders(ne, rel)[-1]) < 0.5, f'orders {successive_orders(ne, rel)}')

    split = parts(load_sweep(os.path.join(out, 'parts.h5')))
    check('the split has the three amplitudes', len(split) == 3, f'{sorted(split)}')
    if split:
        model = np.array([signed_peak(p['model']) / p['ratio'] for p in split.values()])
        method = np.array([signed_peak(p['method']) / p['ratio'] for p in split.values()])
        check('model difference: the same multiple of v0/c at every amplitude (2 %)',
              bool(np.all(np.abs(model / model[0] - 1) < 0.02)) and abs(model[0]) > 0.1, f'{model}')
        check('method error of linear shapes: the other sign and larger (v0 = 0.1 and 0.01)',
              bool(np.all(model[:2] * method[:2] < 0) and np.all(np.abs(method[:2]) > np.abs(model[:2]))), f'{method}')
        worst = max(float(np.max(np.abs(p['residual']))) for p in split.values())
        check('the parts add up to the run\'s error (round-off)', worst < 1e-8, f'{worst:.2e}')
    print(f'{sum(check.results)} passed, {len(check.results) - sum(check.results)} failed')
    return 0 if all(check.results) else 1


if __name__ == '__main__':
    sys.exit(main())
