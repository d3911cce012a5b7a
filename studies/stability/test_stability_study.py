#!/usr/bin/env python3
"""Pipeline test of the stability study: runs `MPM1D_QUICK=1 bash studies/stability/run.sh`
(a few cases per class, seconds) through the real executable into a temporary folder and checks
that the sweeps, figures and summary.md are written, that every check of the summary passes, and
that the measured critical fraction of USL at ppc = 1 (20 elements) lies within +-0.05 of the
predicted one. Plain script: last line `N passed, M failed`, exit status 1 on any failure.
"""

import csv
import os
import re
import sys

from mpm1d_post.study_checks import Checks, run_quick

HERE = os.path.dirname(os.path.abspath(__file__))

FIGURES = ('stability_map.png', 'stability_map_zoom.png', 'stability_map_1element.png', 'scale.png',
           'large_motion.png', 'long_energy.png', 'modes.png')
SWEEPS = ('map.h5', 'coarse.h5', 'large.h5', 'long100.h5', 'long1000.h5', 'modes.h5',
          'fine_e10000.h5', 'largest.h5')



def main() -> int:
    check = Checks()
    out, proc = run_quick(HERE, 'mpm1d_stability_', timeout=600)
    check('run.sh (quick) exits 0', proc.returncode == 0, proc.stdout[-2000:] + proc.stderr[-2000:])
    for name in SWEEPS:
        check(f'{name} written', os.path.isfile(os.path.join(out, name)))
    check('scale_*.h5 written', any(n.startswith('scale_') and n.endswith('.h5') for n in os.listdir(out)))
    for name in FIGURES:
        path = os.path.join(out, name)
        check(f'{name} written', os.path.isfile(path) and os.path.getsize(path) > 10000)
    summary = os.path.join(out, 'summary.md')
    text = open(summary).read() if os.path.isfile(summary) else ''
    check('summary.md written', bool(text))
    for heading in ('1. Time-step stability map', '1b. Time-step stability on one element',
                    '2. Stiffness and scale', '3. Large motion', '4. Long runs', '5. High modes',
                    '6. Very coarse and very fine meshes', 'Total wall time'):
        check(f'summary has section "{heading}"', heading in text)
    m = re.search(r'## Checks: (\d+) passed, (\d+) failed', text)
    check('summary checks all pass', m is not None and int(m.group(2)) == 0 and int(m.group(1)) > 20,
          m.group(0) if m else 'no checks line')
    check('code version in summary', 'Code version: mpm1d' in text)

    # measured critical fraction, USL ppc 1, 20 elements, against the prediction
    from mpm1d_post.studies.stability import critical_table, load
    sweep = load(os.path.join(out, 'map.h5'))
    measured, first, _ = critical_table(sweep, 'usl', 1, 20)
    with open(os.path.join(out, 'predicted', 'predicted_critical.csv'), newline='') as fh:
        kc = [float(r['k_crit']) for r in csv.DictReader(fh)
              if r['scheme'] == 'usl' and r['particles_per_element'] == '1' and r['elements'] == '20'][0]
    check(f'USL ppc 1: measured k_crit {measured:g} within 0.05 of predicted {kc:.4f}',
          abs(measured - kc) <= 0.05, f'difference {measured - kc:.4f}')
    check('USL ppc 1: the first failing case trips a guard above the prediction',
          first is not None and sweep.cases['dt_fraction'][first] > kc)
    passed, failed = sum(check.results), len(check.results) - sum(check.results)
    print(f'{passed} passed, {failed} failed')
    return 0 if failed == 0 else 1


if __name__ == '__main__':
    sys.exit(main())
