#!/usr/bin/env python3
"""Pipeline test of the methods study: runs `MPM1D_QUICK=1 bash studies/methods/run.sh` (about a minute)
through the real executable into a temporary folder and checks that every sweep and noise run, the figures
and summary.md are written with every section; from the quick meshes (10-80 elements): on the linear-law bar
the total-Lagrangian formulation and CPDI converge at second order and PIC at first order at best; on the
manufactured solution at A/L = 0.05 CPDI converges at second order where the hat with FLIP diverges; on the
bar at v0 = 0.01 c PIC loses more than half the energy while FLIP, XPIC(m) and FMPM(k) keep 99 %; the
answer table has a row per scene and target. Plain script: last line `N passed, M failed`, exit status 1 on
any failure."""

import os
import re
import sys

from mpm1d_post.study_checks import Checks, run_quick

HERE = os.path.dirname(os.path.abspath(__file__))
METHODS = ('flip', 'pic', 'apic', 'cpgimp', 'bspline2', 'total', 'cpdi', 'xpic2', 'fmpm2', 'asflip')
SCENES = ('bar_linear', 'bar_hencky', 'wave', 'manufactured')
NOISE = ('flip', 'pic', 'blend', 'xpic2', 'xpic4', 'xpic8', 'fmpm2', 'fmpm4', 'fmpm8', 'asflip')


def last_order(section: str, method: str):
    """The last successive order of a method's row in a convergence table (None when there is no row)."""
    m = re.search(rf'^\| {method} \((?:[^()]|\([^)]*\))*\)(?: \| [^|]*)+ \| (?:[-0-9.]+, )*([-0-9.]+) \|$', section,
                  re.M)
    return (float(m.group(1)), m.group(0)) if m else (None, 'no row')


def main() -> int:
    check = Checks()
    out, proc = run_quick(HERE, 'mpm1d_methods_', timeout=900)
    check('run.sh (quick) exits 0', proc.returncode == 0, proc.stdout[-2000:] + proc.stderr[-2000:])
    missing = [f'{s}_{m}{x}.h5' for s in SCENES for m in METHODS for x in ('', '_more')
               if not os.path.isfile(os.path.join(out, f'{s}_{m}{x}.h5'))]
    missing += [f'noise_{m}.h5' for m in NOISE if not os.path.isfile(os.path.join(out, f'noise_{m}.h5'))]
    check('every sweep and noise run written', not missing, str(missing))
    for name in ('methods_convergence.png', 'methods_error_vs_time.png'):
        png = os.path.join(out, name)
        check(f'{name} written', os.path.isfile(png) and os.path.getsize(png) > 10000)
    path = os.path.join(out, 'summary.md')
    text = open(path).read() if os.path.isfile(path) else ''
    for heading in ('### vibrating bar, linear law', '### vibrating bar, Hencky law', '### plastic wave',
                    '### manufactured solution, A/L = 0.05', '## The answer table', '## Noise against energy'):
        check(f'summary has section "{heading}"', heading in text)
    bar = text[text.find('### vibrating bar, linear law'):text.find('### vibrating bar, Hencky law')]
    for method in ('total', 'cpdi'):
        order, row = last_order(bar, method)
        check(f'linear-law bar: {method} at second order', order is not None and abs(order - 2) < 0.1, row)
    order, row = last_order(bar, 'pic')
    check('linear-law bar: PIC at first order at best', order is not None and order < 1.2, row)
    manufactured = text[text.find('### manufactured solution'):text.find('## The answer table')]
    order, row = last_order(manufactured, 'cpdi')
    check('manufactured: CPDI at second order', order is not None and order >= 1.8, row)
    order, row = last_order(manufactured, 'flip')
    check('manufactured: the hat with FLIP does not converge', order is not None and order < 0, row)
    noise = {m.group(1): float(m.group(2)) for m in
             re.finditer(r'^\| (\w+) \| ok \| [^|]* \| [^|]* \| ([0-9.e+-]+) \| [^|]* \|$', text, re.M)}
    check('noise: every transfer completes', set(noise) == set(NOISE), str(noise))
    check('noise: PIC loses more than half the energy', noise.get('pic', 1.0) < 0.5, str(noise.get('pic')))
    keep = [m for m in ('flip', 'xpic2', 'xpic4', 'xpic8', 'fmpm2', 'fmpm4', 'fmpm8') if noise.get(m, 0.0) < 0.99]
    check('noise: FLIP, XPIC(m) and FMPM(k) keep 99 % of the energy', not keep, str(keep))
    answers = re.findall(r'^\| ([^|]+) \| (0\.01|0\.001|0\.0001) \|', text, re.M)
    check('answer table: a row per scene and target', len(answers) == 12, str(answers))
    passed, failed = sum(check.results), len(check.results) - sum(check.results)
    print(f'{passed} passed, {failed} failed')
    return 0 if failed == 0 else 1


if __name__ == '__main__':
    sys.exit(main())
