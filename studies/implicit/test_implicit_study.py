#!/usr/bin/env python3
"""Pipeline test of the implicit study: runs `MPM1D_QUICK=1 bash studies/implicit/run.sh` (about a minute)
through the real executable into a temporary folder and checks that the runs, the figures and summary.md
are written with every section, and, from the tiny runs: the trapezoidal rule's self-convergence order
(1.8 to 2.2), the consistent mass's energy conserved over the quick run (below 1e-9) while the lumped mass
loses some, every implicit run of the stability section completed, the stiff composite's implicit runs
faster than explicit at the largest ratio with a u_cm error within 2x, the ghost penalty raising the cut
cell's smallest rcond on the bar with B-splines, and the static column's cpGIMP orders near 2.
Plain script: last line `N passed, M failed`, exit status 1 on any failure."""

import os
import re
import sys

from mpm1d_post.study_checks import Checks, run_quick

HERE = os.path.dirname(os.path.abspath(__file__))


def numbers(text, pattern):
    return [float(x) for x in re.findall(pattern, text, re.M)]


def main() -> int:
    check = Checks()
    out, proc = run_quick(HERE, 'mpm1d_implicit_', timeout=1800)
    check('run.sh (quick) exits 0', proc.returncode == 0, proc.stdout[-2000:] + proc.stderr[-2000:])
    for name in ('bar_explicit.h5', 'bar_implicit.h5', 'temporal.h5', 'energy_explicit.h5', 'energy_implicit.h5',
                 'stability_explicit.h5', 'stability_implicit.h5', 'cost_explicit.h5', 'cost_implicit.h5',
                 'summary.md'):
        check(f'{name} written', os.path.isfile(os.path.join(out, name)))
    for name in ('bar_error_vs_time.png', 'energy_drift.png', 'composite_cost.png', 'composite_error_vs_time.png',
                 'newton_vs_dt.png', 'cut_cell.png', 'static_column.png'):
        png = os.path.join(out, name)
        check(f'{name} written', os.path.isfile(png) and os.path.getsize(png) > 10000)
    path = os.path.join(out, 'summary.md')
    text = open(path).read() if os.path.isfile(path) else ''
    for heading in ('## Answers', '## 1. The bar', '## 2. Temporal order and energy', '## 3. Stability limits',
                    '## 4. Stiff composites', '## 5. Newton iterations', '## 6. The cut cell',
                    '## 7. The static column', '## 8. Cost per particle-step'):
        check(f'summary has {heading}', heading in text)
    orders = numbers(text, r'\| (?:lumped|consistent) \| [0-9.]+ / [0-9.]+ \| [0-9.e+-]+ \| ([0-9.]+) \|')
    check('trapezoidal rule: self-convergence orders 1.8 to 2.2', orders and all(1.8 < o < 2.2 for o in orders),
          str(orders))
    # the energy table's rows: run, dt_fraction, final change, largest deviation
    consistent = numbers(text, r'^\| implicit consistent \| [0-9.]+ \| ([-0-9.e+]+) \| [0-9.e+-]+ \|$')
    lumped = numbers(text, r'^\| implicit lumped \| [0-9.]+ \| ([-0-9.e+]+) \| [0-9.e+-]+ \|$')
    check('consistent mass conserves the energy (below 1e-9)', consistent and all(abs(v) < 1e-9 for v in consistent),
          str(consistent))
    check('lumped mass loses energy, never gains', lumped and all(v < 0 for v in lumped), str(lumped))
    implicit_rows = re.findall(r'\| (?:lumped|consistent) \| [0-9.]+ \| \d+ \| (\w+) \| [0-9.e+-]+ \| [0-9.e+-]+ \|',
                               text)
    check('every implicit stability run completed', implicit_rows and all(s == 'ok' for s in implicit_rows),
          str(implicit_rows))
    crossover = re.search(r'Crossover .*?: (.*)\.\n', text)
    check('the composite shows a crossover', crossover is not None and 'r = ' in crossover.group(1),
          crossover.group(1) if crossover else 'no line')
    rcond = dict((float(g), float(r)) for g, r in
                 re.findall(r'\| bspline2 \| ([0-9.]+) \| ok \| ([0-9.e+-]+) \|', text))
    check('ghost penalty raises the cut cell\'s rcond by 100x (bspline2 bar)',
          0.0 in rcond and 0.1 in rcond and rcond[0.1] > 100 * rcond[0.0], str(rcond))
    static = numbers(text, r'\| (?:linear law|Hencky|elastoplastic), cpGIMP \| \d+ \| [0-9.e+-]+ \| ([0-9.]+) \|')
    check('static column, cpGIMP: orders 1.7 to 2.3', static and all(1.7 < o < 2.3 for o in static), str(static))
    passed, failed = sum(check.results), len(check.results) - sum(check.results)
    print(f'{passed} passed, {failed} failed')
    return 1 if failed else 0


if __name__ == '__main__':
    sys.exit(main())
