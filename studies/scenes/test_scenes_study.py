#!/usr/bin/env python3
"""Pipeline test of the scenes study: runs `MPM1D_QUICK=1 bash studies/scenes/run.sh` (seconds) through
the real executables into a temporary folder and checks that every section and figure is written, that
the impact's frictionless contact lasts 2L/c within 2 % and exchanges the velocities within 2.5 % while
contact='none' keeps the bars stuck, that momentum holds to round-off, that the bar's USL stability limit
is below its USF limit, and that the benchmark lists every scene with its bytes per particle (the fused
bar 44, the impact 72: its body index and per-particle Young's modulus).
Plain script: last line `N passed, M failed`, exit status 1 on any failure."""

import os
import re
import sys

from mpm1d_post.study_checks import Checks, run_quick

HERE = os.path.dirname(os.path.abspath(__file__))


def main() -> int:
    check = Checks()
    out, proc = run_quick(HERE, 'mpm1d_scenes_', timeout=900)
    check('run.sh (quick) exits 0', proc.returncode == 0, proc.stdout[-2000:] + proc.stderr[-2000:])
    for name in ('impact_frictionless_error.png', 'impact_none_error.png', 'field_impact.png', 'stability.png',
                 'time_convergence.png', 'bench_scenes.csv', 'summary.md'):
        path = os.path.join(out, name)
        check(f'{name} written', os.path.isfile(path) and os.path.getsize(path) > 100)
    path = os.path.join(out, 'summary.md')
    text = open(path, encoding='utf-8').read() if os.path.isfile(path) else ''
    for heading in ('## impact (impact_frictionless.h5)', '## impact (impact_none.h5)', '## Convergence in time',
                    '## Stability limit', '## Only what it needs', '### Impact: two identical steel bars'):
        check(f'summary has "{heading}"', heading in text)
    m = re.search(r'^\| frictionless \| ([0-9.]+) \| [0-9.]+ \| (-?[0-9.]+) \| (-?[0-9.]+) \| ([0-9.e+-]+) \|', text, re.M)
    check('impact frictionless: contact time 2L/c within 2 %', m is not None and abs(float(m.group(1)) - 1) < 0.02,
          m.group(0) if m else 'no row')
    check('impact frictionless: velocities exchanged within 2.5 %', m is not None and
          abs(float(m.group(2)) + 1) < 0.025 and abs(float(m.group(3)) - 1) < 0.025, m.group(0) if m else 'no row')
    check('impact frictionless: momentum to round-off', m is not None and float(m.group(4)) < 1e-13,
          m.group(0) if m else 'no row')
    m = re.search(r'^\| none \| ([0-9.]+) \|', text, re.M)
    check("impact none: in contact for the whole run (4L/c = 2 x 2L/c)", m is not None and float(m.group(1)) > 1.98,
          m.group(0) if m else 'no row')
    m = re.search(r'^\| vibrating_bar \| ([0-9.]+) \| ([0-9.]+) \| ([0-9.]+) \|', text, re.M)
    check("the bar's USL limit below its USF limit", m is not None and float(m.group(2)) < float(m.group(1)),
          m.group(0) if m else 'no row')
    # every scene runs on the fused kernels with FLIP and the hat; bytes per particle as counted in
    # docs/performance.md: x, X, v, stress, J and the cell, 44; the composite + mass, volume and modulus,
    # 68; the manufactured solution + its two factors and the force, 68; the impact + mass, volume,
    # modulus and the body index, 72; the generic path 120
    for scene, path_name, size in (('vibrating_bar', 'fused', 44), ('vibrating_bar', 'generic', 120),
                                   ('column', 'fused', 44), ('manufactured', 'fused', 68),
                                   ('composite_bar', 'fused', 68), ('impact_frictionless', 'fused', 72),
                                   ('impact_none', 'fused', 72)):
        m = re.search(rf'^\| {scene} \| {path_name} \| ([0-9]+) \|', text, re.M)
        check(f'benchmark: {scene} ({path_name}) {size} bytes per particle', m is not None and int(m.group(1)) == size,
              m.group(0) if m else 'no row')
    passed, failed = sum(check.results), len(check.results) - sum(check.results)
    print(f'{passed} passed, {failed} failed')
    return 0 if failed == 0 else 1


if __name__ == '__main__':
    sys.exit(main())
