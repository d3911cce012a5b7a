"""The implicit study (studies/implicit/run.sh, whose analyze.py calls `main`): tables and figures from
the runs and sweeps in the output folder; summary.md (every number in it computed here from those files).
Usage: python studies/implicit/analyze.py OUTPUT_FOLDER [--elapsed S] [--load L] [--quick 0|1]"""
import argparse
import glob
import math
import os
import re

import matplotlib
matplotlib.use('Agg')
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from ..limits import stability_limit  # noqa: E402
from ..loader import Sweep, load_run, load_sweep  # noqa: E402
from ..orders import difference_at_common_times, successive_orders  # noqa: E402
from ..pareto import pareto_front  # noqa: E402
from ..tables import markdown_table, number  # noqa: E402

BAR_C = (200e9 / 7800.0) ** 0.5
SOFT_C = (1e8 / 1000.0) ** 0.5


def sweep_table(path) -> Sweep:
    """Every case of a sweep, stopped ones too (the stability limits are where cases stop)."""
    return load_sweep(path, cases='all')


def runs(out, pattern):
    """{name: Run} of the single runs whose file name matches `pattern` (a glob in the output folder)."""
    found = {}
    for path in sorted(glob.glob(os.path.join(out, pattern + '.h5'))):
        found[os.path.basename(path)[:-3]] = load_run(path)
    return found


def value(run, name, default=float('nan')):
    v = run.summary.get(name, default)
    return float(v) if not isinstance(v, (str, bytes)) else v


def status(run):
    return str(run.summary.get('status_name', ''))


def fmt(x, digits=3):
    return number(x, f'.{digits}g', missing='n/a')


# ------------------------------------------------------------------ 1. the bar

def bar_section(out, lines):
    ex = sweep_table(os.path.join(out, 'bar_explicit.h5')).cases
    im = sweep_table(os.path.join(out, 'bar_implicit.h5')).cases
    rows = []
    for i in range(len(ex['index'])):
        rows.append(dict(method=f"explicit {ex['scheme'][i]}", elements=int(ex['elements'][i]),
                         k=float(ex['dt_fraction'][i]), error=float(ex['relative_error'][i]),
                         time=float(ex['run_time'][i]), ok=int(ex['status'][i]) == 0))
    for i in range(len(im['index'])):
        rows.append(dict(method=f"implicit {im['mass'][i]}", elements=int(im['elements'][i]),
                         k=float(im['dt_fraction'][i]), error=float(im['relative_error'][i]),
                         time=float(im['run_time'][i]), ok=int(im['status'][i]) == 0))
    ok = [r for r in rows if r['ok'] and r['time'] > 0]
    times = np.array([r['time'] for r in ok])
    errors = np.array([r['error'] for r in ok])
    front = pareto_front(times, errors)
    fig, ax = plt.subplots(figsize=(7.5, 5))
    markers = {'explicit usl': 'o', 'explicit musl': 's', 'implicit lumped': '^', 'implicit consistent': 'v'}
    for method, marker in markers.items():
        sel = [r for r in ok if r['method'] == method]
        ax.loglog([r['time'] for r in sel], [r['error'] for r in sel], marker, label=method, alpha=0.8)
    ax.loglog(times[front], errors[front], 'k-', lw=0.8, label='Pareto front')
    ax.set_xlabel('run time (s, median of the timing pass, one thread)')
    ax.set_ylabel('relative u_cm error (max over 2 periods / exact amplitude)')
    ax.set_title('Vibrating bar, law linear, 2 particles per element: error against cost\n'
                 'explicit dt <= 0.5 dx/c, implicit dt = 0.25..16 dx/c; elements 20..160', fontsize=9)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(out, 'bar_error_vs_time.png'), dpi=120)
    plt.close(fig)
    lines += ['## 1. The bar: error against run time', '',
              'Law `linear` (the paper\'s exact solution is exact for it), 2 particles per element, 2 periods. '
              'Figure: `bar_error_vs_time.png`. The Pareto front (no run both faster and more accurate):', '']
    lines += markdown_table(['method', 'elements', 'dt_fraction', 'relative error', 'run time (s)'],
                            [[ok[i]['method'], ok[i]['elements'], f"{ok[i]['k']:g}", fmt(ok[i]['error']),
                              fmt(ok[i]['time'])] for i in front])
    lines.append('')
    counts = {m: sum(1 for i in front if ok[i]['method'] == m) for m in markers}
    lines.append('On the front: ' + ', '.join(f'{m} {c}' for m, c in counts.items()) + f' (of {len(front)}).')
    # at equal elements and the largest stable explicit step against implicit at 4x it
    pairs = []
    for n in sorted({r['elements'] for r in ok}):
        e = [r for r in ok if r['elements'] == n and r['method'] == 'explicit usl' and r['k'] == 0.5]
        i = [r for r in ok if r['elements'] == n and r['method'] == 'implicit lumped' and r['k'] == 1.0]
        c = [r for r in ok if r['elements'] == n and r['method'] == 'implicit consistent' and r['k'] == 1.0]
        if e and i and c:
            pairs.append((n, e[0], i[0], c[0]))
    if pairs:
        lines += ['', 'At equal elements: explicit USL at dt = 0.5 dx/c against implicit at dt = dx/c (twice the step):', '']
        lines += markdown_table(['elements', 'USL error', 'USL time (s)', 'implicit lumped error', 'time (s)',
                                 'implicit consistent error', 'time (s)'],
                                [[n] + [fmt(run[key]) for run in (e, i, c) for key in ('error', 'time')]
                                 for n, e, i, c in pairs])
    lines.append('')
    return ok, front


# ------------------------------------------------------------------ 2. temporal order, energy

def self_convergence(sweep: Sweep, **criteria):
    """The cases matching `criteria` by dt_fraction from the largest: the fractions, the largest difference of
    each case's u_cm history from the next one's at their common times, and the orders of those differences."""
    idx = sweep.rows('dt_fraction', descending=True, **criteria)
    ks = sweep.cases['dt_fraction'][idx]
    diffs = [difference_at_common_times(sweep.histories[a]['ucm'], sweep.histories[b]['ucm'],
                                        stride=int(round(ka / kb)))
             for a, b, ka, kb in zip(idx[:-1], idx[1:], ks[:-1], ks[1:])]
    return ks, diffs, successive_orders(ks[:-1], diffs)


def temporal_section(out, lines):
    sweep = sweep_table(os.path.join(out, 'temporal.h5'))
    lines += ['## 2. Temporal order and energy', '',
              'Self-convergence in dt on a fixed mesh (law linear, 2 particles per element, 1 period): the '
              'largest difference of successive u_cm histories at their common times, and the order '
              'log2 of the ratio of successive differences.', '']
    orders, rows = {}, []
    for mass in ('lumped', 'consistent'):
        ks, diffs, found = self_convergence(sweep, mass=mass)
        orders[mass] = list(found)
        for j, d in enumerate(diffs):
            rows.append([mass, f'{ks[j]:g} / {ks[j + 1]:g}', fmt(d), fmt(orders[mass][j - 1] if j > 0 else None, 3)])
    lines += markdown_table(['mass', 'dt_fraction pair', 'max difference (m)', 'order'], rows)
    lines.append('')
    # energy over many periods
    # left: every run (symlog); right: |E - E0|/E0 of the implicit runs on a log scale, where the consistent
    # mass's round-off level shows beside the lumped mass's loss
    fig, (ax, ax_implicit) = plt.subplots(1, 2, figsize=(12, 4.5))
    table = []
    drifts = {}
    for name, label_of in (('energy_explicit.h5', lambda c, i: f"explicit {c['scheme'][i]}"),
                           ('energy_implicit.h5', lambda c, i: f"implicit {c['mass'][i]}")):
        energy_sweep = sweep_table(os.path.join(out, name))
        c = energy_sweep.cases
        for i in range(len(energy_sweep)):
            hist = energy_sweep.histories[i]
            energy = hist['kinetic_energy'] + hist['strain_energy']
            change = (energy - energy[0]) / energy[0]
            label = label_of(c, i)
            k = float(c['dt_fraction'][i])
            table.append([label, f'{k:g}', fmt(change[-1]), fmt(np.max(np.abs(change)))])
            drifts[(label, k)] = change[-1]
            periods = hist['time'] / (4 * 25.0 / BAR_C)
            ax.plot(periods, change, label=f'{label}, k = {k:g}', lw=0.8)
            if label.startswith('implicit'):
                ax_implicit.semilogy(periods[1:], np.maximum(np.abs(change[1:]), 1e-17), label=f'{label}, k = {k:g}',
                                     lw=0.8)
    ax_implicit.set_xlabel('periods')
    ax_implicit.set_ylabel('|E - E0|/E0 (floored at 1e-17)')
    ax_implicit.set_title('The trapezoidal rule: consistent mass at round-off, lumped mass loses', fontsize=9)
    ax_implicit.legend(fontsize=7)
    ax.set_yscale('symlog', linthresh=1e-12)
    ax.set_xlabel('periods')
    ax.set_ylabel('(E - E0)/E0, E = kinetic + strain energy of the particles')
    ax.set_title('Energy of the linear bar (20 elements x 2): explicit against the trapezoidal rule', fontsize=9)
    ax.legend(fontsize=7, ncol=2)
    fig.tight_layout()
    fig.savefig(os.path.join(out, 'energy_drift.png'), dpi=120)
    plt.close(fig)
    periods = float(np.max(periods))
    lines += [f'Energy of the linear bar over {periods:g} periods (figure `energy_drift.png`):', '']
    lines += markdown_table(['run', 'dt_fraction', 'final energy change', 'largest deviation'], table) + ['']
    return orders, drifts


# ------------------------------------------------------------------ 3. stability

def stability_section(out, lines):
    sweep = sweep_table(os.path.join(out, 'stability_explicit.h5'))
    c = sweep.cases
    lines += ['## 3. Stability limits', '', 'Explicit: the first dt fraction at which the run stops (20 elements, '
              '20 periods, law linear), and the guard that stopped it:', '']
    limits, rows = {}, []
    for scheme in ('usf', 'usl', 'musl'):
        for ppc in sorted(set(c['particles_per_element'])):
            m = sweep.rows(scheme=scheme, particles_per_element=ppc)
            limit = stability_limit(c['dt_fraction'][m], c['status'][m])
            limits[(scheme, int(ppc))] = limit.first_failing
            rows.append([scheme, int(ppc), fmt(limit.stable), fmt(limit.first_failing),
                         c['status_name'][m][limit.first_index] if limit.found else 'none'])
    lines += markdown_table(['scheme', 'particles per element', 'largest completed', 'first failing', 'guard'], rows)
    implicit = sweep_table(os.path.join(out, 'stability_implicit.h5'))
    ci = implicit.cases
    lines += ['', 'Implicit (400 elements x 2, 4 periods, law linear): every dt fraction completes; the largest '
              'energy ratio reached (1 or below: the trapezoidal rule does not gain energy):', '']
    lines += markdown_table(['mass', 'dt_fraction', 'steps', 'status', 'max energy ratio', 'relative u_cm error'],
                            [[ci['mass'][i], f"{ci['dt_fraction'][i]:g}", int(ci['steps'][i]), ci['status_name'][i],
                              fmt(ci['max_energy_ratio'][i], 6), fmt(ci['relative_error'][i])]
                             for i in np.argsort(ci['dt_fraction'] + 1e9 * (ci['mass'] == 'consistent'))])
    lines.append('')
    implicit_ok = bool(np.all(implicit.ok))
    return limits, implicit_ok


# ------------------------------------------------------------------ 4. stiff composites

def ucm_error(run):
    h = run.history
    return float(np.max(np.abs(h['ucm'] - h['ucm_exact'])) / np.max(np.abs(h['ucm_exact'])))


def crossovers(data):
    """Per element count, the smallest stiffness ratio at which implicit at dt = 0.5 dx/c_soft runs faster than
    explicit with a u_cm error at most twice explicit's: {elements: (ratio, implicit time / explicit time)}.
    `data`: rows with ratio, n (elements), method ('explicit' or 'implicit C_soft = 0.5'), time, ucm."""
    found = {}
    for n in sorted({d['n'] for d in data}):
        for ratio in sorted({d['ratio'] for d in data}):
            e = [d for d in data if d['ratio'] == ratio and d['n'] == n and d['method'] == 'explicit']
            i = [d for d in data if d['ratio'] == ratio and d['n'] == n and d['method'] == 'implicit C_soft = 0.5']
            if e and i and i[0]['time'] < e[0]['time'] and i[0]['ucm'] <= 2 * e[0]['ucm'] + 1e-12:
                found[n] = (ratio, i[0]['time'] / e[0]['time'])
                break
    return found


def composite_section(out, lines):
    found = runs(out, 'composite_*')
    pattern = re.compile(r'composite_([0-9.e+]+)_(\d+)_(explicit|implicit_([0-9.]+))$')
    data = []
    for name, run in found.items():
        m = pattern.match(name)
        if not m:
            continue
        ratio, n = float(m.group(1)), int(m.group(2))
        method = 'explicit' if m.group(3) == 'explicit' else f'implicit C_soft = {m.group(4)}'
        steps = value(run, 'steps')
        particles = value(run, 'particles')
        data.append(dict(ratio=ratio, n=n, method=method, time=value(run, 'run_time'), steps=steps,
                         particles=particles, ucm=ucm_error(run) if status(run) == 'ok' else float('nan'),
                         l1=value(run, 'relative_error'), status=status(run), measured=True,
                         newton=value(run, 'newton_iterations'), floor=value(run, 'newton_floor_steps')))
    explicit = [d for d in data if d['method'] == 'explicit' and d['status'] == 'ok']
    per_step = np.median([d['time'] / (d['steps'] * d['particles']) for d in explicit]) if explicit else float('nan')
    ratios = sorted({d['ratio'] for d in data})
    elements = sorted({d['n'] for d in data})
    # explicit beyond the budget: its steps at 0.5 dx/c_stiff times the cost per particle-step measured at the
    # largest ratio run at that resolution (the run time holds the scene's exact solution too, whose fronts
    # grow with r: a cost per step taken from smaller runs would understate it); its errors those of that run
    # (the stiff segment is rigid already)
    for ratio in ratios:
        for n in elements:
            if any(d['ratio'] == ratio and d['n'] == n and d['method'] == 'explicit' for d in data):
                continue
            end_time = 1.5 * 0.5 / SOFT_C
            steps = math.ceil(end_time / (0.5 * (1.0 / n) / (SOFT_C * ratio)))
            measured = [d for d in explicit if d['n'] == n]
            last = max(measured, key=lambda d: d['ratio']) if measured else None
            cost = last['time'] / (last['steps'] * last['particles']) if last else per_step
            data.append(dict(ratio=ratio, n=n, method='explicit', time=steps * 2 * n * cost, steps=steps,
                             particles=2 * n, ucm=last['ucm'] if last else float('nan'),
                             l1=last['l1'] if last else float('nan'), status='extrapolated', measured=False,
                             newton=float('nan'), floor=float('nan')))
    lines += ['## 4. Stiff composites', '',
              'A soft segment (E = 1e8 Pa, rho = 1000 kg/m^3, 0.5 m) driven at its free end at 0.01 m/s, then a '
              'stiff one (E = 1e8 r^2, same density: impedance and wave-speed ratio r, 0.5 m), law linear, 2 '
              'particles per element, until the wave has crossed the soft segment and come half-way back '
              '(1.5 L_soft/c_soft). Explicit USL at dt = 0.5 dx/c_stiff, measured up to '
              f'the budget of particle-steps and beyond it extrapolated (its step count times its cost per '
              'particle-step at the largest ratio measured at the same elements; median over all measured runs '
              f'{fmt(per_step)} s; errors of that run); implicit at '
              'dt = 0.5 and 2 dx/c_soft (dt_fraction 0.5 r and 2 r). Errors: u_cm against the exact u_cm '
              '(the drive force is the soft end\'s stress: the soft dynamics), and the scene\'s L1 stress error '
              'at the end time (dominated by the stiff segment\'s ringing, which no run resolves after 1e2..1e6 '
              'reflections). Figures `composite_cost.png`, `composite_error_vs_time.png`.', '']
    lines += markdown_table(['ratio', 'elements', 'method', 'status', 'steps', 'run time (s)', 'u_cm error',
                             'L1 stress error', 'Newton solves/step', 'floor steps'],
                            [[f"{d['ratio']:.0e}", d['n'], d['method'], d['status'], int(d['steps'])]
                             + [fmt(d[key]) for key in ('time', 'ucm', 'l1', 'newton', 'floor')]
                             for d in sorted(data, key=lambda d: (d['ratio'], d['n'], d['method']))])
    lines.append('')
    crossover = crossovers(data)
    speedup = {}
    for ratio in ratios:
        for n in elements:
            e = [d for d in data if d['ratio'] == ratio and d['n'] == n and d['method'] == 'explicit']
            i = [d for d in data if d['ratio'] == ratio and d['n'] == n and d['method'] == 'implicit C_soft = 0.5']
            if e and i:
                speedup[(ratio, n)] = e[0]['time'] / i[0]['time']
    # the time-per-step ratio that sets the crossover: r* = (implicit cost per step)/(explicit cost per step),
    # both from the runs at the smallest ratio (whose exact solution has the fewest fronts: the set-up and the
    # final error evaluation, in the run time, grow with their number)
    smallest = min(ratios)
    implicit = [d for d in data if d['method'] == 'implicit C_soft = 0.5' and d['status'] == 'ok' and d['ratio'] == smallest]
    explicit_small = [d for d in explicit if d['ratio'] == smallest]
    implicit_step = np.median([d['time'] / (d['steps'] * d['particles']) for d in implicit]) if implicit else float('nan')
    explicit_step = np.median([d['time'] / (d['steps'] * d['particles']) for d in explicit_small]) if explicit_small else per_step
    predicted = implicit_step / explicit_step
    lines += ['Crossover (the smallest ratio at which implicit at dt = 0.5 dx/c_soft runs faster than explicit at the '
              'same elements, u_cm error within 2x): ' + ('; '.join(f'{n} elements: r = {r:.0e} (implicit time '
                                                                      f'{fmt(f)} of explicit)'
                                                                      for n, (r, f) in sorted(crossover.items()))
                                                            or 'none in the ratios run') + '.',
              f'Both take the same step count at r = 1 (dt = 0.5 dx/c); explicit needs r times more as r grows, so '
              f'implicit pays from r* = (cost of an implicit particle-step)/(cost of an explicit one) = '
              f'{fmt(implicit_step)}/{fmt(explicit_step)} = {fmt(predicted)} on (measured at r = {smallest:.0e}); '
              f'at r = {ratios[-1]:.0e} explicit would take {fmt(max(speedup.get((ratios[-1], n), 0) for n in elements))} '
              'times longer. The time step of the crossover: implicit at dt = 0.5 dx/c_soft, i.e. dt_fraction '
              f'0.5 r* = {fmt(0.5 * predicted)} of the stiff segment\'s dx/c.', '']
    fig, ax = plt.subplots(figsize=(7, 4.5))
    for n in elements:
        for method, style in (('explicit', 'o-'), ('implicit C_soft = 0.5', '^-'), ('implicit C_soft = 2', 'v--')):
            sel = sorted([d for d in data if d['n'] == n and d['method'] == method], key=lambda d: d['ratio'])
            if not sel:
                continue
            line, = ax.loglog([d['ratio'] for d in sel], [d['time'] for d in sel], style, label=f'{method}, {n} el.')
            extra = [d for d in sel if not d['measured']]
            if extra:
                ax.loglog([d['ratio'] for d in extra], [d['time'] for d in extra], 'o', mfc='white',
                          color=line.get_color())
    ax.set_xlabel('impedance (and wave-speed) ratio r of the stiff to the soft segment')
    ax.set_ylabel('run time (s); open: explicit extrapolated')
    ax.set_title('Stiff composite: run time against stiffness ratio (law linear, 2 ppc)', fontsize=9)
    ax.legend(fontsize=7, ncol=2)
    fig.tight_layout()
    fig.savefig(os.path.join(out, 'composite_cost.png'), dpi=120)
    plt.close(fig)
    fig, ax = plt.subplots(figsize=(7, 4.5))
    for d in data:
        if not math.isfinite(d['ucm']):
            continue
        marker = 'o' if d['method'] == 'explicit' else ('^' if '0.5' in d['method'] else 'v')
        ax.loglog(d['time'], d['ucm'], marker, mfc='white' if not d['measured'] else None,
                  color=plt.cm.viridis(math.log10(d['ratio']) / 6.5))
    for r in ratios:
        ax.plot([], [], 's', color=plt.cm.viridis(math.log10(r) / 6.5), label=f'r = {r:.0e}')
    ax.plot([], [], 'ko', label='explicit (open: extrapolated)')
    ax.plot([], [], 'k^', label='implicit C_soft = 0.5')
    ax.plot([], [], 'kv', label='implicit C_soft = 2')
    ax.set_xlabel('run time (s)')
    ax.set_ylabel('relative u_cm error')
    ax.set_title('Stiff composite: u_cm error against run time, every ratio and resolution', fontsize=9)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(out, 'composite_error_vs_time.png'), dpi=120)
    plt.close(fig)
    return crossover, predicted, per_step, implicit_step, speedup


# ------------------------------------------------------------------ 5. Newton

def newton_section(out, lines):
    lines += ['## 5. Newton iterations', '', 'Mean and largest linear solves per step (a law linear in the increment '
              'needs one):', '']
    table, cells = {}, []
    for kind, pattern in (('Hencky bar, strain 1 %', r'newton_bar_([0-9.]+)$'),
                          ('elastoplastic plastic wave', r'newton_plastic_([0-9.]+)$'),
                          ('quasi-static column, Hencky', r'newton_column_hencky_(\d+)$'),
                          ('quasi-static column, elastoplastic', r'newton_column_elastoplastic_(\d+)$')):
        rows = []
        for name, run in runs(out, 'newton_*').items():
            m = re.match(pattern, name)
            if m:
                rows.append((float(m.group(1)), run))
        for k, run in sorted(rows, key=lambda r: r[0]):
            mean, most = value(run, 'newton_iterations'), value(run, 'newton_iterations_max')
            table.setdefault(kind, []).append((k, mean, most))
            cells.append([kind, f'{k:g}', status(run), fmt(mean), fmt(most), fmt(value(run, 'relative_error'))])
    lines += markdown_table(['case', 'dt_fraction or load steps', 'status', 'mean', 'max', 'relative error'], cells)
    lines.append('')
    fig, ax = plt.subplots(figsize=(6.5, 4))
    for kind, rows in table.items():
        if 'column' in kind:
            continue
        ax.semilogx([r[0] for r in rows], [r[1] for r in rows], 'o-', label=f'{kind} (mean)')
        ax.semilogx([r[0] for r in rows], [r[2] for r in rows], 'x:', label=f'{kind} (max)')
    ax.set_xlabel('dt_fraction (dt c/dx)')
    ax.set_ylabel('linear solves per step')
    ax.set_title('Newton iterations against the time step', fontsize=9)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(out, 'newton_vs_dt.png'), dpi=120)
    plt.close(fig)
    return table


# ------------------------------------------------------------------ 6. cut cell

def cut_section(out, lines):
    lines += ['## 6. The cut cell', '', 'The bar (v0 = 30 m/s, 40 elements, one particle per cell, dt = dx/c, 2 '
              'periods, Hencky): its free end crosses into empty cells, and the node it reaches first carries a '
              'tiny mass (and for the wide shapes a tiny stiffness). Smallest reciprocal condition number of the '
              'tangent (1-norm, the Hager-Higham estimate of mpm_banded, the algorithm of LAPACK dgbcon; first '
              'iteration of each step), Newton solves, the lightest node met, '
              'and the error:', '']
    bar = {}
    for name, run in runs(out, 'cut_bar_*').items():
        m = re.match(r'cut_bar_(\w+?)_([0-9.]+)$', name)
        shape, g = m.group(1), float(m.group(2))
        bar[(shape, g)] = run
    lines += markdown_table(['shape', 'ghost_penalty', 'status', 'min rcond', 'lightest node / particle mass',
                             'Newton mean', 'max', 'relative error', 'max energy ratio'],
                            [[shape, f'{g:g}', status(run)]
                             + [fmt(value(run, key)) for key in ('tangent_rcond_min', 'min_node_mass_ratio',
                                                                  'newton_iterations', 'newton_iterations_max',
                                                                  'relative_error')]
                             + [fmt(value(run, 'max_energy_ratio'), 6)] for (shape, g), run in sorted(bar.items())])
    lines.append('')
    col = {}
    for name, run in runs(out, 'cut_column_*').items():
        m = re.match(r'cut_column_(\w+?)_([0-9.]+)_(\d+)$', name)
        col.setdefault((m.group(1), float(m.group(2))), []).append(run)
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    slopes = {}
    for (shape, g), rs in sorted(col.items()):
        # the top particle (X = L - dx/2) moved by the first of two load steps, in cells: where the second
        # step's tangent is formed
        cells = []
        for r in rs:
            length, n = float(r.config['length']), int(r.config['elements'])
            a = float(r.config['density']) * float(r.config['gravity']) / float(r.config['youngs_modulus'])
            top = length - 0.5 * length / n
            cells.append(0.5 * a * (length * top - 0.5 * top ** 2) / (length / n))
        cells = np.array(cells)
        rcond = np.array([value(r, 'tangent_rcond_min') for r in rs])
        error = np.array([value(r, 'relative_error') if status(r) == 'ok' else np.nan for r in rs])
        o = np.argsort(cells)
        style = dict(marker='o' if g == 0 else '^', mfc='white' if g > 0 else None, ls='-' if g > 0 else ':')
        axes[0].semilogy(cells[o], rcond[o], label=f'{shape}, ghost_penalty = {g:g}', **style)
        axes[1].semilogy(cells[o], error[o], label=f'{shape}, ghost_penalty = {g:g}', **style)
        slopes[(shape, g)] = (float(np.min(rcond)), int(sum(status(r) != 'ok' for r in rs)), len(rs),
                              float(np.nanmax(error)) if np.any(np.isfinite(error)) else float('nan'))
    axes[0].set_xlabel('top particle moved by the first load step (cells)')
    axes[0].set_ylabel('smallest reciprocal condition number of the tangent')
    axes[1].set_xlabel('top particle moved by the first load step (cells)')
    axes[1].set_ylabel('relative static error (runs that stopped: not shown)')
    axes[0].set_title('Quasi-static column, 1 ppc, 20 elements, 2 load steps: the cut cell\n'
                      '(B-splines; open triangles: ghost_penalty 0.1)', fontsize=9)
    axes[1].set_title('its error against the closed form', fontsize=9)
    axes[0].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(out, 'cut_cell.png'), dpi=120)
    plt.close(fig)
    lines += ['The quasi-static column (law linear, 20 elements, 1 particle per cell, 2 load steps), loaded so that '
              'its top particle has moved 0 to 2.4 cells at the second step, whose tangent then has nodes that '
              'particles are leaving (figure `cut_cell.png`). Without a mass term a node that only the tail of a '
              'basis function reaches has a nearly zero row, and with one particle per cell the cubic B-splines\' '
              'stiffness has fewer particles than unknowns near the free end (rank-deficient): those runs throw '
              'particles out of the grid from the first step:', '']
    lines += markdown_table(['shape', 'ghost_penalty', 'smallest rcond', 'runs stopped (of)',
                             'largest relative error of the completed'],
                            [[shape, f'{g:g}', fmt(smallest), f'{stopped} ({total})', fmt(worst)]
                             for (shape, g), (smallest, stopped, total, worst) in sorted(slopes.items())])
    lines.append('')
    return bar, slopes


# ------------------------------------------------------------------ 7. static column

def static_section(out, lines):
    lines += ['## 7. The static column against its closed forms', '',
              'Errors max_p |x_p - X_p - u_static(X_p)| at full load (m) and orders between resolutions. '
              '"hat, 1 ppc, 1 step": strain 3e-3, one load step (the nodal values are exact, the error is '
              '(rho g/E) dx^2/8); the others at 30 % strain in 10 load steps.', '']
    table = []
    variants = {'linear law, hat, 1 ppc, 1 step': 'static_linear_hat_', 'linear law, hat, 2 ppc, 10 steps, 30 %': 'static_linear_hat10_',
                'linear law, cpGIMP': 'static_linear_cpgimp_', 'Hencky, cpGIMP': 'static_hencky_cpgimp_',
                'elastoplastic, cpGIMP': 'static_elastoplastic_cpgimp_'}
    results = {}
    fig, ax = plt.subplots(figsize=(6.5, 4.5))
    for label, prefix in variants.items():
        rows = []
        for name, run in runs(out, prefix + '*').items():
            m = re.match(re.escape(prefix) + r'(\d+)$', name)
            if m:
                rows.append((int(m.group(1)), value(run, 'max_error'), status(run)))
        rows.sort()
        results[label] = rows
        orders = [None] + list(successive_orders([r[0] for r in rows], [r[1] for r in rows])) if rows else []
        table += [[label, n, fmt(err), fmt(order, 3)] for (n, err, _), order in zip(rows, orders)]
        ax.loglog([r[0] for r in rows], [r[1] for r in rows], 'o-', label=label)
    ax.set_xlabel('elements')
    ax.set_ylabel('max particle displacement error (m)')
    ax.set_title('Quasi-static column under its weight (L = 1 m)', fontsize=9)
    lines += markdown_table(['variant', 'elements', 'error', 'order'], table)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(out, 'static_column.png'), dpi=120)
    plt.close(fig)
    lines += ['', 'With linear shape functions every load step after the first finds equilibrium on particles that no '
              'longer sit where the cells\' quadrature wants them: a cell\'s particles carry sigma J V0 for a cell '
              'full of material (the force sigma J instead of sigma), an error of the order of the strain that does '
              'not fall with the cell size. cpGIMP\'s particle domains (l_p0 J) tile the deformed body and converge.',
              '']
    return results


# ------------------------------------------------------------------ 8. cost

def cost_section(out, lines):
    rows = []
    for name, label_of in (('cost_explicit.h5', lambda c, i: f"explicit usl, {c['law'][i]}, "
                            + ('fused' if c['law'][i] == 'hencky' else 'generic')),
                           ('cost_generic.h5', lambda c, i: f"explicit usl, {c['law'][i]}, generic"),
                           ('cost_implicit.h5', lambda c, i: f"implicit, {c['law'][i]}, {c['mass'][i]} mass")):
        c = sweep_table(os.path.join(out, name)).cases
        for i in range(len(c['index'])):
            rate = c['steps'][i] * c['particles'][i] / c['run_time'][i]
            rows.append((label_of(c, i), float(rate), float(c['run_time_spread'][i])))
    base = {label: rate for label, rate, _ in rows}
    reference = base.get('explicit usl, linear, generic', float('nan'))
    lines += ['## 8. Cost per particle-step', '', f'Bar of {int(c["particles"][0])} particles, dt = 0.5 dx/c, 0.1 '
              'period, one thread, timing pass (median of repeats; spread = interquartile range / median):', '']
    lines += markdown_table(['path', 'particle-steps/s', 'spread', 'cost relative to explicit linear generic'],
                            [[label, fmt(rate), fmt(spread, 2), fmt(reference / rate)] for label, rate, spread in rows])
    lines.append('')
    return rows, reference


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument('out')
    parser.add_argument('--elapsed', default='?')
    parser.add_argument('--load', default='?')
    parser.add_argument('--quick', default='0')
    args = parser.parse_args(argv)
    out = args.out
    mode = 'quick mode: MPM1D_QUICK=1, the numbers are not the study\'s' if args.quick == '1' else 'full'
    lines = ['# Implicit and quasi-static integration against explicit', '',
             f'Written by `studies/implicit/analyze.py` from the runs of `bash studies/implicit/run.sh` '
             f'({mode}; {args.elapsed} s, load average {args.load} at the start, 2 cores shared).', '']
    answers = ['## Answers', '']
    bar_ok, front = bar_section(out, lines)
    orders, drifts = temporal_section(out, lines)
    limits, implicit_ok = stability_section(out, lines)
    crossover, predicted, per_step, implicit_step, speedup = composite_section(out, lines)
    newton = newton_section(out, lines)
    bar_cut, slopes = cut_section(out, lines)
    static = static_section(out, lines)
    cost, reference = cost_section(out, lines)
    answers.append('- Temporal order of the trapezoidal rule (self-convergence): lumped ' +
                   ', '.join(fmt(o, 3) for o in orders['lumped']) + '; consistent ' +
                   ', '.join(fmt(o, 3) for o in orders['consistent']) + '.')
    consistent = [v for (label, k), v in drifts.items() if label == 'implicit consistent']
    lumped = [v for (label, k), v in drifts.items() if label == 'implicit lumped']
    explicit = [(label, v) for (label, k), v in drifts.items() if label.startswith('explicit')]
    answers.append('- Energy over the run (final change): implicit consistent ' + ', '.join(fmt(v) for v in consistent) +
                   '; implicit lumped ' + ', '.join(fmt(v) for v in lumped) + '; ' +
                   ', '.join(f'{label} {fmt(v)}' for label, v in explicit) + '.')
    answers.append('- Explicit stability limits (first failing dt fraction, 1 ppc): ' +
                   ', '.join(f'{s} {fmt(limits.get((s, 1)))}' for s in ('usf', 'usl', 'musl')) +
                   f'; implicit runs up to dt_fraction 1000 all completed: {implicit_ok}.')
    answers.append('- Stiff composites: implicit pays from r* = ' + fmt(predicted) + ' (its cost per particle-step over '
                   'explicit\'s, both at 0.5 dx/c of their wave); measured crossover: ' +
                   ('; '.join(f'{n} elements r = {r:.0e}' for n, (r, f) in sorted(crossover.items())) or 'none') + '.')
    answers.append(f'- Cost per particle-step, implicit (linear law, lumped) over explicit USL generic (linear): '
                   f'{fmt(next((reference / rate for label, rate, _ in cost if label == "implicit, linear, lumped mass"), float("nan")))}.')
    lines[4:4] = answers + ['']
    with open(os.path.join(out, 'summary.md'), 'w') as f:
        f.write('\n'.join(lines) + '\n')
    return 0


if __name__ == '__main__':
    raise SystemExit(main())
