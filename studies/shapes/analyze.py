"""Tables and figures of studies/shapes/run.sh: reads the sweep files and speed.csv in the output
folder and writes summary.md (every number in it is computed here from those files) and
error_vs_time.png.  Usage: python analyze.py OUTPUT_FOLDER"""
import argparse
import csv
import pathlib

import h5py
import numpy as np

SHAPES = ['linear', 'ugimp', 'cpgimp', 'bspline2', 'bspline3']
SCHEMES = ['usf', 'usl', 'musl']


def text(values):
    return np.array([v.decode() if isinstance(v, bytes) else str(v) for v in values])


def load(path):
    with h5py.File(path, 'r') as f:
        cases = {k: f['cases'][k][()] for k in f['cases'].keys()}
        for k in ('scheme', 'shape', 'transfer', 'status_name'):
            cases[k] = text(cases[k])
        histories = {}
        if 'histories' in f:
            for i in cases['index']:
                g = f['histories'].get(f'{i:06d}')
                if g is not None:
                    histories[int(i)] = g['ucm'][()]
    return cases, histories


def orders(errors, elements):
    return [np.log(errors[i] / errors[i + 1]) / np.log(elements[i + 1] / elements[i]) for i in range(len(errors) - 1)]


def convergence_table(cases, histories, against_finest):
    rows = []
    for scheme in SCHEMES:
        for shape in SHAPES:
            m = (cases['scheme'] == scheme) & (cases['shape'] == shape)
            o = np.argsort(cases['elements'][m])
            el = cases['elements'][m][o]
            err = cases['relative_error'][m][o]
            ok = cases['status'][m][o] == 0
            idx = cases['index'][m][o]
            amplitude = cases['max_error'][m][o][0] / err[0]
            if against_finest:
                # successive differences max_t |u_h - u_h/2| (the fine history at every other step)
                diff = []
                for a, b in zip(idx[:-1], idx[1:]):
                    ua, ub = histories.get(int(a)), histories.get(int(b))
                    if ua is None or ub is None or len(ub) != 2 * len(ua) - 1:
                        diff.append(np.nan)
                    else:
                        diff.append(np.max(np.abs(ua - ub[::2])) / amplitude)
                measure = np.array(diff)
                used = el[:-1]
            else:
                measure, used = err, el
            ords = orders(measure, used)
            rows.append((scheme, shape, el, err, ok, measure, used, ords))
    return rows


def fmt(x):
    return 'nan' if not np.isfinite(x) else f'{x:.2e}'


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument('folder', type=pathlib.Path)
    args = parser.parse_args(argv)
    out = args.folder
    lines = ['# Shape functions on the vibrating bar', '',
             'Written by `studies/shapes/analyze.py` from the files `studies/shapes/run.sh` wrote in this folder. '
             'Bar: L = 25 m, E = 200 GPa, rho = 7800 kg/m^3, mode 1, 2 periods, 4 particles per element, '
             'dt = 0.25 dx/c, transfer FLIP; error = max over steps of |u_cm - u_cm,exact| / amplitude.', '']

    small, _ = load(out / 'convergence_small.h5')
    lines += ['## Spatial convergence, small amplitude (v0 = 0.1 m/s), against the exact solution', '',
              '| scheme | shape | ' + ' | '.join(f'{e} el.' for e in sorted(set(small['elements']))) +
              ' | observed orders (successive) |', '|---|---|' + '---|' * (len(set(small['elements'])) + 1)]
    for scheme, shape, el, err, ok, measure, used, ords in convergence_table(small, {}, False):
        cells = [fmt(e) + ('' if k else ' (guard)') for e, k in zip(err, ok)]
        lines.append(f'| {scheme} | {shape} | ' + ' | '.join(cells) + ' | ' + ', '.join(f'{o:.2f}' for o in ords) + ' |')

    large, hist = load(out / 'convergence_large.h5')
    lines += ['', '## Large motion, v0 = 0.01 c (the free end moves about 0.8 m)', '',
              'Against the exact solution of linear elasticity (the material is sigma = E ln F, so the error '
              'stops at the model difference, about 0.56 %), and the self-convergence measure '
              'd(E) = max_t |u_cm(E) - u_cm(2E)| / amplitude with its observed orders. "guard": a run stopped.', '',
              '| scheme | shape | error vs exact ' + ' / '.join(str(e) for e in sorted(set(large['elements']))) +
              ' el. | d(E), E = ' + ' / '.join(str(e) for e in sorted(set(large['elements']))[:-1]) +
              ' | orders of d |', '|---|---|---|---|---|']
    for scheme, shape, el, err, ok, measure, used, ords in convergence_table(large, hist, True):
        cells = ' / '.join(fmt(e) + ('' if k else ' (guard)') for e, k in zip(err, ok))
        lines.append(f'| {scheme} | {shape} | {cells} | ' + ' / '.join(fmt(d) for d in measure) + ' | ' +
                     ', '.join('nan' if not np.isfinite(o) else f'{o:.2f}' for o in ords) + ' |')

    for amp, title in (('small', 'v0 = 0.1 m/s'), ('large', 'v0 = 0.01 c')):
        path = out / f'transfers_{amp}.h5'
        if not path.exists():
            continue
        tr, _ = load(path)
        els = sorted(set(tr['elements']))
        lines += ['', f'## Transfers, USL, {title}: relative error against the exact solution per elements, '
                  'and the observed orders (blend: flip_fraction 0.99)', '',
                  '| shape | transfer | ' + ' | '.join(f'{e} el.' for e in els) + ' | orders |',
                  '|---|---|' + '---|' * (len(els) + 1)]
        for shape in SHAPES:
            for transfer in ('flip', 'pic', 'blend', 'apic'):
                m = (tr['shape'] == shape) & (tr['transfer'] == transfer)
                o = np.argsort(tr['elements'][m])
                err = tr['relative_error'][m][o]
                ok = tr['status'][m][o] == 0
                cells = [fmt(e) + ('' if k else ' (guard)') for e, k in zip(err, ok)]
                lines.append(f'| {shape} | {transfer} | ' + ' | '.join(cells) + ' | ' +
                             ', '.join(f'{x:.2f}' for x in orders(err, tr['elements'][m][o])) + ' |')

    # error against run time (small amplitude), Pareto front and the answer table
    t = small['run_time']
    e = small['relative_error']
    ok = small['status'] == 0
    label = np.array([f"{s} {h} {n} el." for s, h, n in zip(small['scheme'], small['shape'], small['elements'])])
    lines += ['', '## Error against run time (small amplitude, one thread, timing pass)', '',
              '![error against run time](error_vs_time.png)', '',
              '| target relative error | cheapest run reaching it | run time (s) | its error |', '|---|---|---|---|']
    for target in (1e-2, 1e-3, 1e-4):
        m = ok & (e <= target)
        if m.any():
            i = np.flatnonzero(m)[np.argmin(t[m])]
            lines.append(f'| {target:.0e} | {label[i]} | {t[i]:.2e} | {e[i]:.2e} |')
        else:
            lines.append(f'| {target:.0e} | none of the measured runs | | |')
    try:
        import matplotlib
        matplotlib.use('Agg')
        import matplotlib.pyplot as plt
        fig, axes = plt.subplots(1, 3, figsize=(13, 4.2), sharey=True)
        for ax, scheme in zip(axes, SCHEMES):
            for shape in SHAPES:
                m = ok & (small['scheme'] == scheme) & (small['shape'] == shape)
                o = np.argsort(t[m])
                ax.loglog(t[m][o], e[m][o], 'o-', label=shape)
            ax.set_title(f'{scheme.upper()}, 4 ppc, k = 0.25, v0 = 0.1 m/s')
            ax.set_xlabel('run time (s, one thread)')
            ax.grid(True, which='both', alpha=0.3)
        axes[0].set_ylabel('relative error of u_cm')
        axes[0].legend()
        fig.suptitle('Vibrating bar: error against run time per shape (10-320 elements)')
        fig.tight_layout()
        fig.savefig(out / 'error_vs_time.png', dpi=110)
    except ImportError:
        lines.append('(matplotlib missing: no figure)')

    stab, _ = load(out / 'stability.h5')
    predicted = {}
    if (out / 'predicted_shapes.csv').exists():
        with open(out / 'predicted_shapes.csv') as handle:
            for r in csv.DictReader(handle):
                predicted[(r['scheme'], r['shape'], int(r['particles_per_element']))] = (
                    float(r['k_crit_rest']), float(r['k_crit_stretched']))
    lines += ['', '## Critical time-step fraction, measured (largest stable k; 20 elements, 20 periods, '
              'v0 = 0.1 m/s, k in steps of 0.02 up to 3.0) / predicted at rest / predicted stretched by 1e-6',
              '', 'Predicted: spectral radius of the frozen one-step map (studies/stability/linear_stability.py '
              '--shapes), with the shapes as mpm1d builds them (mirror ghost, margin cell). "Stretched": the '
              'same at x (1 + 1e-6), where the end particle\'s box or support just enters the margin cell and '
              'its node is nearly empty.', '',
              '| scheme | shape | ppc = 1 | ppc = 2 | ppc = 4 |', '|---|---|---|---|---|']
    for scheme in SCHEMES:
        for shape in SHAPES:
            cells = []
            for ppc in (1, 2, 4):
                m = (stab['scheme'] == scheme) & (stab['shape'] == shape) & (stab['particles_per_element'] == ppc)
                k = stab['dt_fraction'][m]
                s = stab['status'][m]
                o = np.argsort(k)
                k, s = k[o], s[o]
                bad = np.flatnonzero(s != 0)
                if len(bad) == 0:
                    cell = f'> {k[-1]:.2f}'
                elif bad[0] == 0:
                    cell = f'< {k[0]:.2f}'
                else:
                    cell = f'{k[bad[0] - 1]:.2f}'
                if (scheme, shape, ppc) in predicted:
                    cell += ' / {:.3f} / {:.3f}'.format(*predicted[(scheme, shape, ppc)])
                cells.append(cell)
            lines.append(f'| {scheme} | {shape} | ' + ' | '.join(cells) + ' |')

    with open(out / 'speed.csv') as handle:
        rows = list(csv.DictReader(handle))
    lines += ['', '## Throughput (particle-steps/s, one thread; each generic run paired with the fused linear run '
              'of the same scheme, size and round, run just before it; median and range of the ratios over the '
              'rounds; on a shared machine the spread is large)', '',
              '| particles | scheme | shape | transfer | path | particle-steps/s (median) | ratio to fused linear: '
              'median (min-max) |', '|---|---|---|---|---|---|---|']
    rates, ratios = {}, {}
    fused = {(int(r['particles']), r['scheme'], r['round']): float(r['particle_steps_per_s'])
             for r in rows if r['path'] == 'fused'}
    for r in rows:
        key = (int(r['particles']), r['scheme'], r['shape'], r['transfer'], r['path'])
        rate = float(r['particle_steps_per_s'])
        base = fused.get((key[0], key[1], r['round']), fused.get((key[0], 'usl', r['round'])))
        rates.setdefault(key, []).append(rate)
        ratios.setdefault(key, []).append(rate / base)
    for key in sorted(rates, key=lambda k: (k[0], SCHEMES.index(k[1]), k[4] != 'fused', SHAPES.index(k[2]), k[3])):
        q = ratios[key]
        lines.append(f'| {key[0]} | {key[1]} | {key[2]} | {key[3]} | {key[4]} | {np.median(rates[key]):.3e} | '
                     f'{np.median(q):.2f} ({min(q):.2f}-{max(q):.2f}) |')
    (out / 'summary.md').write_text('\n'.join(lines) + '\n')
    return 0


if __name__ == '__main__':
    raise SystemExit(main())
