#!/usr/bin/env python3
"""Pipeline test of the materials study: runs `MPM1D_QUICK=1 bash studies/materials/run.sh` (the plastic
wave at 50-200 elements, short stability sweeps, a small speed and memory run; seconds) into a temporary
folder and checks what it reports:
- the files and figures are written and every plastic-wave case completed;
- the study's own exact solution (mpm1d_post.studies.materials, written independently of the Fortran scene) gives the fronts
  the scene reports; its finite-strain solution tends to the small-strain one as V -> 0 and differs from it
  by well under 1 % at the study's V/c = 4e-3;
- uGIMP converges (the error falls from 50 to 200 elements), the precursor stands where c_e T puts it, the
  energy balance closes within 2 % at 200 elements;
- plasticity does not lower the bar's critical time step (elastic unloading keeps E);
- the elastoplastic law carries 16 bytes per particle more than hencky (two doubles), the linear law none.
Plain script: last line `N passed, M failed`, exit status 1 on any failure.
"""

import csv
import os
import sys

import numpy as np

from mpm1d_post.loader import load_run, load_sweep
from mpm1d_post.study_checks import Checks, run_quick
from mpm1d_post.studies import materials as analyze

HERE = os.path.dirname(os.path.abspath(__file__))


def main() -> int:
    check = Checks()
    out, proc = run_quick(HERE, 'mpm1d_materials_', timeout=900)
    check('run.sh (quick) exits 0', proc.returncode == 0, '' if proc.returncode == 0 else proc.stderr[-2000:])
    for name in ('wave.h5', 'wave_fine.h5', 'summary.md', 'wave_convergence.png', 'wave_error_vs_time.png',
                 'wave_profiles.png', 'wave_energy.png', 'bar_laws.png', 'speed.csv', 'memory.csv'):
        check(f'{name} written', os.path.isfile(os.path.join(out, name)))
    if proc.returncode != 0:
        print(f'{sum(check.results)} passed, {len(check.results) - sum(check.results)} failed')
        return 1
    wave_sweep = load_sweep(os.path.join(out, 'wave.h5'), cases='all')
    wave = wave_sweep.cases
    check('every plastic-wave case completed', bool(np.all(wave_sweep.ok)))

    run = load_run(os.path.join(out, 'single_ugimp_200.h5'))
    E, rho, sy, H, V, L = analyze.material(run)
    ss = analyze.small_strain(E, rho, sy, H, V)
    s = run.summary
    for key, name in (('c1', 'elastic_wave_speed'), ('c2', 'plastic_wave_speed'), ('s1', 'precursor_stress'),
                      ('s2', 'plastic_stress'), ('v1', 'precursor_velocity')):
        check(f'exact {name}: the study\'s formula = the scene\'s', abs(ss[key] / float(s[name]) - 1) < 1e-12,
              f'{ss[key]} vs {s[name]}')
    fs = analyze.finite_strain(E, rho, sy, H, V)
    check('finite strain: plastic stress within 1 % of small strain, and higher (the bar stiffens in compression)',
          0 < fs['s2'] / ss['s2'] - 1 < 0.01, f'{fs["s2"] / ss["s2"] - 1:.2e}')
    small = analyze.finite_strain(E, rho, sy, H, 1e-3 * V), analyze.small_strain(E, rho, sy, H, 1e-3 * V)
    check('finite strain -> small strain as V -> 0 (one elastic wave, 1e-5)',
          abs(small[0]['s2'] / small[1]['s2'] - 1) < 1e-5 and abs(small[0]['c1'] / small[1]['c1'] - 1) < 1e-5)

    m = wave_sweep.where(scheme='usl', shape='ugimp', transfer='flip')
    fine_sweep = load_sweep(os.path.join(out, 'wave_fine.h5'))
    fine = fine_sweep.cases
    mf = fine_sweep.where(scheme='usl', shape='ugimp')
    coarse = float(wave['relative_error'][m][np.argmin(wave['elements'][m])])
    finest = float(fine['relative_error'][mf][np.argmax(fine['elements'][mf])])
    check('uGIMP USL: the error falls from 50 to 200 elements', finest < 0.7 * coarse, f'{coarse:.3g} -> {finest:.3g}')
    check('the precursor stands at c_e T (1 %)', abs(float(s['measured_precursor_front']) / float(s['precursor_front'])
                                                     - 1) < 0.01)
    check('energy balance within 2 % at 200 elements', abs(float(s['energy_balance'])) < 0.02, f'{s["energy_balance"]}')

    hencky = load_sweep(os.path.join(out, 'stability_bar_hencky.h5'), cases='all')
    plastic = load_sweep(os.path.join(out, 'stability_bar_elastoplastic.h5'), cases='all')
    worst = min(analyze.critical(plastic, sc, sh) - analyze.critical(hencky, sc, sh)
                for sc in analyze.SCHEMES for sh in analyze.SHAPES)
    check('plasticity does not lower the bar\'s critical dt fraction (within one step of the sweep)',
          worst >= -0.2 - 1e-9, f'largest drop {worst:.2f}')

    with open(os.path.join(out, 'memory.csv')) as f:
        rows = [r for r in csv.DictReader(f) if r['max_rss_kib'].strip().isdigit()]
    rss = {(r['law'], int(r['particles'])): int(r['max_rss_kib']) * 1024 for r in rows}
    n = max(p for _, p in rss)
    extra = {law: (rss[(law, n)] - rss[('hencky', n)]) / n for law in ('linear', 'elastoplastic') if (law, n) in rss}
    check('elastoplastic: 16 bytes per particle more than hencky (12 to 21 measured)',
          12 <= extra.get('elastoplastic', 0) <= 21, f'{extra}')
    check('linear: no more than hencky (under 4 bytes per particle)', abs(extra.get('linear', 99)) < 4, f'{extra}')
    text = open(os.path.join(out, 'summary.md')).read()
    check('summary has the answer table and the Pareto front', 'For a target relative L1 error' in text
          and 'Pareto front' in text)
    print(f'{sum(check.results)} passed, {len(check.results) - sum(check.results)} failed')
    return 0 if all(check.results) else 1


if __name__ == '__main__':
    sys.exit(main())
