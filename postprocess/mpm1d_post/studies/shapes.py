"""The shapes study (studies/shapes/run.sh, whose analyze.py calls `main`): reads the sweep files and
speed.csv in the output folder and writes summary.md (every number in it is computed here from those
files) and the figures.  Usage: python studies/shapes/analyze.py OUTPUT_FOLDER"""
import argparse
import csv
import os
import pathlib
from dataclasses import dataclass, field
from typing import Dict, List, Tuple

import numpy as np

from .. import figures as pf
from ..limits import stability_limit
from ..loader import Sweep, concatenate_sweeps, load_run, load_sweep
from ..orders import difference_at_common_times, observed_order, successive_orders
from ..pareto import cheapest_by_group_rows, cheapest_rows, pareto_front
from ..tables import markdown_table, number

SHAPES = ['linear', 'ugimp', 'cpgimp', 'bspline2', 'bspline3']
SCHEMES = ['usf', 'usl', 'musl']
TRANSFERS = ['flip', 'pic', 'blend', 'apic']
# the bar of every bar run here (README, What it computes)
BAR_L, BAR_E, BAR_RHO = 25.0, 200e9, 7800.0
BAR_C = (BAR_E / BAR_RHO) ** 0.5
BAR_BETA = np.pi / (2 * BAR_L)
BAR_OMEGA = BAR_BETA * BAR_C
BAR_PERIOD = 2 * np.pi / BAR_OMEGA


@dataclass
class Findings:
    """Numbers the sections pass to the closing "what limits each order" text."""
    #: Per amplitude ('small', 'large'): the rows of the temporal-convergence table (temporal_rows).
    temporal: Dict[str, List[dict]] = field(default_factory=dict)
    #: (scene, shape) -> the largest particle error near an end over the interior's (the profiles).
    profile: Dict[Tuple[str, str], float] = field(default_factory=dict)


def load(path) -> Sweep:
    """Every case of a sweep file: the tables mark the stopped ones, fits skip them."""
    return load_sweep(path, cases='all')


def amplitude_of(sweep: Sweep, index) -> float:
    """The exact amplitude the relative errors of the cases `index` divide by: max_error /
    relative_error of a completed case, or the same ratio of the errors before a stop."""
    c = sweep.cases
    ratios = np.concatenate([c['max_error'][index] / c['relative_error'][index],
                             c['error_before_stop'][index] / c['relative_error_before_stop'][index]])
    ratios = ratios[np.isfinite(ratios)]
    return float(np.median(ratios)) if ratios.size else np.nan


def result_cell(error, ok):
    """A table cell: the error of a completed case, 'guard' for one a guard stopped (no result)."""
    return fmt(error) if ok else 'guard'


def history_of(sweep: Sweep, i, name='ucm'):
    """History `name` of case i, None where the sweep stored none."""
    return sweep.histories[i][name] if i in sweep.histories else None


def convergence_table(sweep: Sweep, against_finest):
    """Per scheme x shape, by elements: (scheme, shape, elements, relative errors, completed, measure, its
    elements, its successive orders); the measure is the relative error, or with `against_finest` the
    self-convergence difference max_t |u_h - u_h/2| / amplitude of each mesh and the next."""
    rows = []
    c = sweep.cases
    for scheme in SCHEMES:
        for shape in SHAPES:
            idx = sweep.rows('elements', scheme=scheme, shape=shape)
            el, err, ok = c['elements'][idx], c['relative_error'][idx], sweep.ok[idx]
            amplitude = amplitude_of(sweep, idx)
            if against_finest:
                measure = np.array([difference_at_common_times(history_of(sweep, a), history_of(sweep, b)) / amplitude
                                    if oa and ob else np.nan
                                    for a, b, oa, ob in zip(idx[:-1], idx[1:], ok[:-1], ok[1:])])
                used = el[:-1]
            else:
                measure, used = err, el
            rows.append((scheme, shape, el, err, ok, measure, used, successive_orders(used, measure)))
    return rows


def fmt(x):
    return number(x, '.2e')


def plt_module():
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    return plt


SHAPE_COLOURS = {'linear': 'C0', 'ugimp': 'C1', 'cpgimp': 'C2', 'bspline2': 'C3', 'bspline3': 'C4'}
TRANSFER_MARKERS = {'flip': 'o', 'pic': 'v', 'blend': 's', 'apic': 'D'}
SCHEME_STYLES = {'usf': ':', 'usl': '-', 'musl': '--'}


def order_between(errors_by_elements, lo, hi):
    """Observed order between the meshes of lo and hi elements, nan where either error is missing."""
    return observed_order(lo, errors_by_elements.get(lo, np.nan), hi, errors_by_elements.get(hi, np.nan))


def fo(x, digits=2):
    return number(x, f'.{digits}f')


# --- temporal convergence ---------------------------------------------------------------------

def temporal_rows(sweep: Sweep):
    """Per scheme x shape x transfer: dt fractions (largest first), the differences
    d(k) = max_t |u_cm(k) - u_cm(k/2)| / amplitude, their observed orders, and the errors against
    the exact solution."""
    rows = []
    c = sweep.cases
    for scheme in SCHEMES:
        for shape in SHAPES:
            for transfer in TRANSFERS:
                idx = sweep.rows('dt_fraction', descending=True, scheme=scheme, shape=shape, transfer=transfer)
                if not idx.size:
                    continue
                ks, err, ok = c['dt_fraction'][idx], c['relative_error'][idx], sweep.ok[idx]
                amplitude = amplitude_of(sweep, idx)
                d = np.array([difference_at_common_times(history_of(sweep, a), history_of(sweep, b)) / amplitude
                              if oa and ob else np.nan
                              for a, b, oa, ob in zip(idx[:-1], idx[1:], ok[:-1], ok[1:])])
                rows.append(dict(scheme=scheme, shape=shape, transfer=transfer, ks=ks, d=d,
                                 orders=list(successive_orders(ks[:-1], d)), err=err, ok=ok))
    return rows


def temporal_section(out, findings: Findings):
    lines = []
    for amp, title in (('small', 'v0 = 0.1 m/s'), ('large', 'v0 = 0.01 c')):
        path = out / f'temporal_{amp}.h5'
        if not path.exists():
            continue
        sweep = load(path)
        rows = temporal_rows(sweep)
        if not rows:
            continue
        findings.temporal[amp] = rows
        ks = rows[0]['ks']
        elements = int(sweep.cases['elements'][0])
        lines += ['', f'## Temporal convergence, {title}: dt halved at {elements} elements x 4 particles', '',
                  'd(k) = max_t |u_cm(k) - u_cm(k/2)| / amplitude, the change when the step is halved (same mesh, '
                  'compared at the coarse run\'s steps); its observed orders log(d(k)/d(k/2))/log 2; and the error '
                  'against the exact solution at the smallest step, which is then the mesh\'s. nan: a run stopped '
                  '(guard). Blend: flip_fraction 0.99.', '']
        lines += markdown_table(['scheme', 'shape', 'transfer'] + [f'd({k:g})' for k in ks[:-1]]
                                + ['orders', f'error at k = {ks[-1]:g}'],
                                [[r['scheme'], r['shape'], r['transfer']] + [fmt(x) for x in r['d']]
                                 + [', '.join(fo(x) for x in r['orders']), result_cell(r['err'][-1], r['ok'][-1])]
                                 for r in rows])
        # a compact reading of the table: the last observed order per scheme and transfer (range over shapes)
        transfers = sorted({r['transfer'] for r in rows}, key=TRANSFERS.index)
        lines += ['', f'Last observed temporal order (k = {ks[-3]:g} -> {ks[-2]:g} against {ks[-2]:g} -> {ks[-1]:g}), '
                  'range over the five shapes:', '']
        table = []
        for scheme in SCHEMES:
            cells = []
            for transfer in TRANSFERS:
                vals = [r['orders'][-1] for r in rows if r['scheme'] == scheme and r['transfer'] == transfer]
                if not vals:
                    continue
                v = np.array(vals, float)
                v = v[np.isfinite(v)]
                cells.append('nan' if v.size == 0 else f'{v.min():.2f} to {v.max():.2f}')
            table.append([scheme] + cells)
        lines += markdown_table(['scheme'] + transfers, table)
    return lines


# --- Table-2 sweep per shape --------------------------------------------------------------------

def table2_section(out):
    path = out / 'table2.h5'
    if not path.exists():
        return []
    plt = plt_module()
    sweep = load(path)  # the maps mark the stopped cases
    c = sweep.cases
    lines = ['', '## The founding paper\'s Table-2 sweep for every shape (error maps as its Figs. 4 and 7)', '',
             'Vibrating bar, v0 = 0.1 m/s, 2 periods, FLIP; every combination of elements ' +
             ', '.join(str(e) for e in sorted(set(c['elements']))) + ', particles per element ' +
             ', '.join(str(e) for e in sorted(set(c['particles_per_element']))) + ' and dt fractions ' +
             ', '.join(f'{k:g}' for k in sorted(set(c['dt_fraction']))) +
             ' (the paper\'s lists; studies/paper draws the same maps for linear). One colour scale per figure; '
             'a red x: the run stopped (guard).', '']
    elements = sorted(set(c['elements'].tolist()))
    for scheme in ('usf', 'usl'):
        ms = sweep.where(scheme=scheme)
        if not ms.any():
            continue
        norm = pf.shared_log_norm([c['max_error'][ms & sweep.ok]])
        fig, axes = plt.subplots(len(SHAPES), len(elements), figsize=(2.6 * len(elements) + 1.6, 2.35 * len(SHAPES) + 1.0),
                                 squeeze=False)
        fig.subplots_adjust(left=0.06, right=0.88, bottom=0.06, top=0.91, wspace=0.3, hspace=0.45)
        mesh = None
        for r, shape in enumerate(SHAPES):
            for col, e in enumerate(elements):
                ax = axes[r, col]
                grid = pf.case_grid(sweep, sweep.where(scheme=scheme, shape=shape, elements=e), 'max_error')
                mesh = pf.draw_colour_map(ax, grid, norm)
                ax.set_title(f'{shape}, {e} el.', fontsize=9)
                ax.tick_params(labelsize=7)
                if r == len(SHAPES) - 1:
                    ax.set_xlabel(pf.PPE_LABEL, fontsize=8)
                if col == 0:
                    ax.set_ylabel(pf.DT_LABEL, fontsize=8)
        fig.colorbar(mesh, cax=fig.add_axes([0.91, 0.25, 0.015, 0.5]), label=pf.ERROR_LABEL)
        fig.suptitle(f'Table-2 sweep per shape, {scheme.upper()} (the paper\'s Fig. '
                     f'{pf.FIGURE_NUMBERS[scheme][0]} for each shape): maximum u_cm error\n'
                     + pf.problem_text(sweep.config), fontsize=11)
        pf.save_figure(fig, str(out), f'table2_error_maps_{scheme}.png', [sweep])
        lines += [f'![Table-2 error maps, {scheme.upper()}](table2_error_maps_{scheme}.png)', '']
    # per scheme x shape: stopped cases, the smallest error, and how often the shape beats linear on
    # the same (elements, particles, dt) cell
    table = []
    key = lambda i: (c['scheme'][i], int(c['elements'][i]), int(c['particles_per_element'][i]),
                     round(float(c['dt_fraction'][i]), 9))
    linear = {key(i): c['max_error'][i] for i in np.flatnonzero(sweep.where(shape='linear') & sweep.ok)}
    for scheme in ('usf', 'usl'):
        for shape in SHAPES:
            m = sweep.where(scheme=scheme, shape=shape)
            if not m.any():
                continue
            good = m & sweep.ok
            i = np.flatnonzero(good)[np.argmin(c['max_error'][good])] if good.any() else None
            where = (f"{c['max_error'][i]:.2e} ({c['elements'][i]} x {c['particles_per_element'][i]} x "
                     f"{c['dt_fraction'][i]:g})") if i is not None else 'none'
            m50 = good & sweep.where(elements=max(elements))
            med = fmt(float(np.median(c['max_error'][m50]))) if m50.any() else 'nan'
            if shape == 'linear':
                beats = '-'
            else:
                pairs = [(c['max_error'][j], linear[key(j)]) for j in np.flatnonzero(good) if key(j) in linear]
                wins = sum(a < b for a, b in pairs)
                beats = f'{wins} of {len(pairs)} ({100 * wins / max(len(pairs), 1):.0f} %)'
            table.append([scheme, shape, int(m.sum()), int((m & sweep.failed).sum()), where, med, beats])
    lines += markdown_table(['scheme', 'shape', 'runs', 'stopped', 'smallest error (m) and where (el. x ppc x k)',
                             'median error at 50 el. (m)', 'cells where smaller than linear\'s (both completed)'],
                            table)
    return lines


# --- grid crossing: stress snapshots and energy histories ------------------------------------------

def read_single(path):
    """(summary, history, snapshots) of a single-run file; snapshots: list of dicts with time,
    reference_x, x, stress."""
    run = load_run(path)
    summary = dict(run.summary)
    for k in ('status_name', 'message'):
        summary[k] = str(summary[k])
    snaps = [dict(time=snap.time, reference_x=snap.extra['reference_x'], x=snap.x, stress=snap.stress)
             for snap in run.snapshots]
    return summary, run.history, snaps


def bar_exact_stress(X, t, v0):
    """Linear elasticity: u = (v0/omega) sin(beta X) sin(omega t), sigma = E u_X."""
    return BAR_E * BAR_BETA * (v0 / BAR_OMEGA) * np.cos(BAR_BETA * X) * np.sin(BAR_OMEGA * t)


def crossing_section(out):
    runs = {}
    for scheme in SCHEMES:
        for shape in SHAPES:
            path = out / f'crossing_{scheme}_{shape}.h5'
            if path.exists():
                runs[(scheme, shape)] = read_single(path)
    if not runs:
        return []
    plt = plt_module()
    v0 = 0.01 * BAR_C
    any_run = next(iter(runs.values()))
    energy0 = None
    elements = int(any_run[0]['particles'] // 4)
    lines = ['', '## Grid crossing under large motion (v0 = 0.01 c): the stress field and the energy', '',
             f'Single runs, {elements} elements x 4 particles, dt = 0.25 dx/c, FLIP (`crossing_*.nml`). The free end '
             f'moves +-{v0 / BAR_OMEGA:.2f} m, {v0 / BAR_OMEGA / (BAR_L / elements):.1f} cells. Stress noise: RMS over the '
             'particles of sigma_p - sigma_exact(X_p, t) at the snapshot, divided by the largest exact stress '
             '(linear elasticity; the sigma = E ln F model differs from it by about 1 % at this strain).', '']
    # which snapshot: the last one that every completed run holds
    times = sorted({round(s['time'], 12) for r in runs.values() for s in r[2]})
    fig, axes = plt.subplots(len(SCHEMES), len(SHAPES), figsize=(3.3 * len(SHAPES), 2.8 * len(SCHEMES) + 0.8),
                             sharex=True, sharey=True, squeeze=False)
    fig.subplots_adjust(left=0.06, right=0.99, bottom=0.08, top=0.91, wspace=0.08, hspace=0.3)
    t_show = times[-1] if times else None
    noise = {}
    for r, scheme in enumerate(SCHEMES):
        for col, shape in enumerate(SHAPES):
            ax = axes[r, col]
            if (scheme, shape) not in runs:
                ax.set_visible(False)
                continue
            summary, history, snaps = runs[(scheme, shape)]
            snap = [s for s in snaps if t_show is not None and abs(s['time'] - t_show) < 1e-12]
            X = np.linspace(0, BAR_L, 400)
            if t_show is not None:
                ax.plot(X, bar_exact_stress(X, t_show, v0) / 1e6, color='0.3', lw=1.5, label='exact (linear elastic)')
            if snap:
                s = snap[0]
                ax.plot(s['reference_x'], s['stress'] / 1e6, '.', ms=2.5, color=SHAPE_COLOURS[shape], label='particles')
                ex = bar_exact_stress(s['reference_x'], s['time'], v0)
                noise[(scheme, shape)] = float(np.sqrt(np.mean((s['stress'] - ex) ** 2)) / np.max(np.abs(ex)))
            else:
                ax.text(0.5, 0.5, f"stopped at t = {history['time'][-1] / BAR_PERIOD:.2f} T\n({summary['status_name']})",
                        transform=ax.transAxes, ha='center', va='center', fontsize=9, color='red')
            ax.set_title(f'{scheme.upper()}, {shape}' + (f', noise {noise[(scheme, shape)]:.1e}'
                                                          if (scheme, shape) in noise else ''), fontsize=9)
            ax.grid(alpha=0.3)
            if r == len(SCHEMES) - 1:
                ax.set_xlabel('reference position X (m)')
            if col == 0:
                ax.set_ylabel('stress (MPa)')
    axes[0, 0].legend(fontsize=7, loc='lower left')
    peak = BAR_E * v0 / BAR_C / 1e6  # the exact stress amplitude (MPa)
    for ax in axes.flat:
        ax.set_ylim(-1.6 * peak, 1.6 * peak)
    fig.suptitle(f'Grid crossing: particle stress at t = {t_show / BAR_PERIOD:.2f} periods, v0 = 0.01 c = {v0:.1f} m/s, '
                 f'{elements} el. x 4 ppc, k = 0.25, FLIP (axis clipped at 1.6x the exact amplitude)', fontsize=11)
    fig.savefig(out / 'crossing_stress.png', dpi=110)
    plt.close(fig)
    # energy histories
    fig, axes = plt.subplots(1, len(SCHEMES), figsize=(5.0 * len(SCHEMES), 4.0), sharey=True)
    fig.subplots_adjust(left=0.08, right=0.99, bottom=0.13, top=0.91, wspace=0.06)
    table = []
    for ax, scheme in zip(axes, SCHEMES):
        for shape in SHAPES:
            if (scheme, shape) not in runs:
                continue
            summary, h, _ = runs[(scheme, shape)]
            e = h['kinetic_energy'] + h['strain_energy']
            rel = e / e[0] - 1
            ax.plot(h['time'] / BAR_PERIOD, rel, color=SHAPE_COLOURS[shape], lw=1.0, label=shape)
            table.append([scheme, shape, summary['status_name'], f"{h['time'][-1] / BAR_PERIOD:.2f}",
                          f'{np.max(np.abs(rel)):.2e}', f'{rel[-1]:.2e}', fmt(noise.get((scheme, shape), np.nan))])
        ax.set_yscale('symlog', linthresh=1e-4)
        ax.set_title(f'{scheme.upper()}: total energy, v0 = 0.01 c, {elements} el. x 4', fontsize=10)
        ax.set_xlabel('time (periods)')
        ax.grid(alpha=0.3, which='both')
    axes[0].set_ylabel('E(t)/E(0) - 1 (symmetric log, linear below 1e-4)')
    axes[0].legend(fontsize=8)
    fig.savefig(out / 'crossing_energy.png', dpi=110)
    plt.close(fig)
    lines += ['![stress under grid crossing](crossing_stress.png)', '',
              '![energy under grid crossing](crossing_energy.png)', '']
    lines += markdown_table(['scheme', 'shape', 'status', 'completed periods', 'max |E/E0 - 1|', 'E/E0 - 1 at the end',
                             'stress noise'], table)
    return lines


# --- energy over many periods -----------------------------------------------------------------------

def energy_section(out):
    lines = []
    plt = plt_module()
    for amp, title in (('small', 'v0 = 0.1 m/s'), ('large', 'v0 = 0.01 c')):
        path = out / f'energy_{amp}.h5'
        if not path.exists():
            continue
        sweep = load(path)
        cases = sweep.cases
        periods = float(np.max(cases['steps'] * cases['dt'])) / BAR_PERIOD
        def period_mean(h):
            """E averaged over each whole period (the discrete energy swings between kinetic and strain
            energy within a period by about 1 %; the average shows the drift)."""
            e = h['kinetic_energy'] + h['strain_energy']
            n = max(1, int(round(BAR_PERIOD / (h['time'][1] - h['time'][0]))))
            whole = (len(e) - 1) // n
            means = np.array([e[i * n:(i + 1) * n].mean() for i in range(whole)])
            return (np.arange(whole) + 0.5), means, e

        lines += ['', f'## Energy over {periods:.0f} periods, {title}: drift per scheme x shape x transfer', '',
                  'E = kinetic + strain energy of the particles; 20 elements x 4 particles, dt = 0.25 dx/c '
                  '(Bardenhagen 2002 compared USF and USL this way, for linear shapes and FLIP). Drift = E averaged '
                  'over the last whole period / E averaged over the first - 1 (within a period the discrete energy '
                  'swings by about 1 %, so the end value alone would mostly show the phase of that swing). '
                  '"guard (t)": the run stopped at t periods (energy guard: E > 10 E(0)).', '']
        drift, table = {}, []
        for scheme in SCHEMES:
            for shape in SHAPES:
                cells = []
                for transfer in TRANSFERS:
                    m = sweep.rows(scheme=scheme, shape=shape, transfer=transfer)
                    if len(m) == 0:
                        cells.append('')
                        continue
                    i = m[0]
                    h = sweep.histories.get(i)
                    if cases['status'][i] != 0:
                        stop = h['time'][-1] / BAR_PERIOD if h is not None else np.nan
                        cells.append(f'guard ({stop:.1f})')
                        continue
                    _, means, _ = period_mean(h)
                    drift[(scheme, shape, transfer)] = means[-1] / means[0] - 1
                    cells.append(f'{means[-1] / means[0] - 1:+.2e}')
                table.append([scheme, shape] + cells)
        lines += markdown_table(['scheme', 'shape'] + TRANSFERS, table)
        flip = {k[:2]: v for k, v in drift.items() if k[2] == 'flip'}
        if flip:
            worst = max(flip, key=lambda k: abs(flip[k]))
            best = min(flip, key=lambda k: abs(flip[k]))
            lines += ['', f'FLIP: the largest drift is {worst[0].upper()} {worst[1]} ({flip[worst]:+.2e}), the smallest '
                      f'{best[0].upper()} {best[1]} ({flip[best]:+.2e}). PIC loses '
                      f'{-np.median([v for k, v in drift.items() if k[2] == "pic"]):.0%} of the energy (median), '
                      f'the 0.99 blend {-np.median([v for k, v in drift.items() if k[2] == "blend"]):.0%}.']
        fig, axes = plt.subplots(len(SCHEMES), len(TRANSFERS), figsize=(4.2 * len(TRANSFERS), 3.0 * len(SCHEMES) + 0.6),
                                 sharex=True, sharey=True, squeeze=False)
        fig.subplots_adjust(left=0.07, right=0.98, bottom=0.07, top=0.92, wspace=0.08, hspace=0.25)
        for r, scheme in enumerate(SCHEMES):
            for col, transfer in enumerate(TRANSFERS):
                ax = axes[r, col]
                for shape in SHAPES:
                    m = sweep.rows(scheme=scheme, shape=shape, transfer=transfer)
                    if len(m) == 0 or m[0] not in sweep.histories:
                        continue
                    h = sweep.histories[m[0]]
                    tm, means, _ = period_mean(h)
                    if len(means) < 2:
                        continue
                    ax.plot(tm, means / means[0] - 1, color=SHAPE_COLOURS[shape], lw=1.2, label=shape)
                ax.set_yscale('symlog', linthresh=1e-4)
                ax.set_xlabel('time (periods)') if r == len(SCHEMES) - 1 else None
                ax.set_title(f'{scheme.upper()}, {transfer}', fontsize=9)
                ax.grid(alpha=0.3, which='both')
                if r == len(SCHEMES) - 1:
                    ax.set_xlabel('time (periods)')
                if col == 0:
                    ax.set_ylabel('<E>(period) / <E>(first) - 1')
        axes[0, 0].legend(fontsize=7)
        fig.suptitle(f'Total energy averaged per period over {periods:.0f} periods, {title}, 20 el. x 4 ppc, k = 0.25 '
                     '(symmetric log scale, linear below 1e-4; blend: flip_fraction 0.99)', fontsize=11)
        fig.savefig(out / f'energy_{amp}.png', dpi=100)
        plt.close(fig)
        lines += ['', f'![energy over {periods:.0f} periods, {title}](energy_{amp}.png)']
    return lines


# --- error against run time over schemes, shapes and transfers --------------------------------------

def error_against_time(out, small):
    """Points: the FLIP convergence sweep (10-320 elements) and the other transfers' sweep (10-160),
    both timed (one thread); the Pareto front over all of them and the answer table."""
    points = small
    path = out / 'transfers_small.h5'
    if path.exists():
        tr = load(path)
        if np.any(tr.cases['run_time'] > 0):
            points = concatenate_sweeps([small, tr.select(~tr.where(transfer='flip'))])
    pts = points.cases
    ok = points.ok & (pts['run_time'] > 0)
    t, e = pts['run_time'], pts['relative_error']
    label = np.array([f'{s} {h} {tr} {n} el.' for s, h, tr, n in
                      zip(pts['scheme'], pts['shape'], pts['transfer'], pts['elements'])])
    idx = np.flatnonzero(ok)
    front = idx[pareto_front(t[ok], e[ok])]
    stopped = int((~points.ok).sum())
    lines = ['', '## Error against run time over schemes, shapes and transfers (small amplitude, one thread)', '',
             f'{int(ok.sum())} timed runs: every scheme x shape with FLIP at 10-320 elements and every scheme x shape '
             'x PIC, blend (0.99) and APIC at 10-160 elements, 4 particles per element, k = 0.25 (timing pass: each '
             'case repeated until 0.02 s (FLIP) or 0.01 s (the others) are measured, one thread); '
             f'{stopped} runs stopped by a guard have no result and are not shown. The black line in each panel is '
             'that scheme\'s Pareto front; the table below gives the front over all of '
             'them. Every shape with FLIP, and the linear shape with PIC, the blend and APIC, runs on the fused '
             'kernels; the wider shapes with the other transfers run on the generic path (the speed of each path: '
             'Throughput, below).', '', '![error against run time](error_vs_time.png)', '',
             '### For a target relative error, use ...', '']
    targets = (1e-2, 1e-3, 1e-4)
    lines += markdown_table(['target relative error', 'cheapest run reaching it (scheme shape transfer elements)',
                             'run time (s)', 'its error'], cheapest_rows(t, e, label, targets, '.0e', among=ok))
    lines += ['', 'The cheapest run of each shape reaching the target (time relative to the cheapest of all):', '']
    without_shape = [f'{s} {tr} {n} el.' for s, tr, n in zip(pts['scheme'], pts['transfer'], pts['elements'])]
    lines += markdown_table(['target'] + SHAPES, cheapest_by_group_rows(
        t, e, without_shape, targets, [points.where(shape=shape) for shape in SHAPES], '.0e', among=ok))
    lines += ['', 'Pareto front over every scheme (fastest first):', '']
    lines += markdown_table(['run', 'run time (s)', 'relative error'],
                            [[label[i], f'{t[i]:.2e}', f'{e[i]:.2e}'] for i in front])
    try:
        plt = plt_module()
        from matplotlib.lines import Line2D
        fig, axes = plt.subplots(1, 3, figsize=(15, 5.0), sharey=True, sharex=True)
        for ax, scheme in zip(axes, SCHEMES):
            for shape in SHAPES:
                for transfer in TRANSFERS:
                    m = ok & points.where(scheme=scheme, shape=shape, transfer=transfer)
                    if not m.any():
                        continue
                    o = np.argsort(t[m])
                    ax.loglog(t[m][o], e[m][o], marker=TRANSFER_MARKERS[transfer], color=SHAPE_COLOURS[shape],
                              ms=4, lw=0.7, alpha=0.85)
            mine = np.flatnonzero(ok & points.where(scheme=scheme))  # this panel's scheme's front
            if mine.size:
                own = mine[pareto_front(t[mine], e[mine])]
                ax.loglog(t[own], e[own], 'k-', lw=1.6, zorder=5)
            ax.set_title(f'{scheme.upper()}, 4 ppc, k = 0.25, v0 = 0.1 m/s')
            ax.set_xlabel('run time (s, one thread)')
            ax.grid(True, which='both', alpha=0.3)
        axes[0].set_ylabel('relative error of u_cm (max over time / amplitude)')
        handles = [Line2D([], [], color=SHAPE_COLOURS[s], lw=2, label=s) for s in SHAPES]
        handles += [Line2D([], [], color='0.3', marker=TRANSFER_MARKERS[k], ls='none', label=k) for k in TRANSFERS]
        handles += [Line2D([], [], color='k', lw=1.6, label="Pareto front of\nthe panel's scheme")]
        if stopped:
            handles += [Line2D([], [], color='0.55', marker='x', ls='none',
                               label=f'{stopped} runs stopped by a guard: no result, not shown')]
        # beside the panels, not over the data
        fig.legend(handles=handles, fontsize=8, loc='center left', bbox_to_anchor=(0.865, 0.5), frameon=False)
        fig.suptitle('Vibrating bar: error against run time per scheme, shape (colour) and transfer (marker), '
                     '10-320 elements')
        fig.tight_layout(rect=(0, 0, 0.865, 1))
        fig.savefig(out / 'error_vs_time.png', dpi=110)
        plt.close(fig)
    except ImportError:
        lines.append('(matplotlib missing: no figure)')
    return lines


# --- the orders on every scene, and what limits them ---------------------------------------------------

def by_elements(sweep: Sweep, quantity='relative_error', **criteria):
    """{elements: `quantity`} of the cases matching `criteria` (nan for a case without a result)."""
    c = sweep.cases
    return {int(c['elements'][i]): (float(c[quantity][i]) if c['status'][i] == 0 else np.nan)
            for i in sweep.rows(**criteria)}


def profile_errors(out, kind):
    """Per shape: (X, |error|/amplitude) of the particles at the snapshot of the profile run."""
    result = {}
    for shape in SHAPES:
        path = out / f'profile_{kind}_{shape}.h5'
        if not path.exists():
            continue
        summary, _, snaps = read_single(path)
        if not snaps:
            continue
        s = snaps[-1]
        X, u = s['reference_x'], s['x'] - s['reference_x']
        if kind == 'bar':
            v0 = 0.1
            amp = v0 / BAR_OMEGA
            exact = amp * np.sin(BAR_BETA * X) * np.sin(BAR_OMEGA * s['time'])
        else:
            amp, L, c = 1.0e-6, 1.0, (1.0e7 / 1000.0) ** 0.5
            exact = amp * np.sin(2 * np.pi * X / L) * np.sin(np.pi * c * s['time'] / L)
        result[shape] = (X, np.abs(u - exact) / amp)
    return result


def limits_text(rows, column, col_el, findings: Findings):
    """What limits each order, read off the measurements above (every number from the tables)."""
    def rng(values):
        v = np.array([x for x in values if np.isfinite(x)], float)
        return 'nan' if v.size == 0 else (f'{v.min():.2f}' if abs(v.max() - v.min()) < 0.005 else f'{v.min():.2f} to {v.max():.2f}')

    def last_orders(amp, scheme=None, transfer=None, shapes=SHAPES):
        return [r['orders'][-1] for r in findings.temporal.get(amp, [])
                if (scheme is None or r['scheme'] == scheme) and (transfer is None or r['transfer'] == transfer)
                and r['shape'] in shapes]

    def grows(amp, transfer, schemes=SCHEMES, shapes=SHAPES):
        rs = [r for r in findings.temporal.get(amp, []) if r['transfer'] == transfer and r['scheme'] in schemes
              and r['shape'] in shapes]
        return [float(r['d'][-1] / r['d'][0]) for r in rs if r['d'][0] > 0 and np.isfinite(r['d'][-1])]

    o = lambda scene, scheme, shapes: rng([rows.get((scene, scheme, h), np.nan) for h in shapes])
    wide = ['ugimp', 'cpgimp', 'bspline2', 'bspline3']
    out = ['', '### What limits each order', '']
    out.append(f"- **Time step (USF).** USF's spatial order at fixed k is {o('bar small', 'usf', SHAPES)} on the bar and "
               f"{o('manufactured 1e-06', 'usf', SHAPES)} on the manufactured scene for every shape; its temporal order at a "
               f"fixed mesh is {rng(last_orders('small', 'usf', 'flip'))} (FLIP, every shape). Its error is O(dt) = "
               "O(k dx/c): at a fixed dt fraction it falls at first order in dx, whatever the shape. USL and MUSL "
               f"(FLIP) are second order in time at small amplitude ({rng(last_orders('small', 'usl', 'flip') + last_orders('small', 'musl', 'flip'))}) "
               f"and in space ({o('bar small', 'usl', SHAPES)}).")
    if findings.temporal.get('large'):
        out.append(f"- **Time step at large motion.** At v0 = 0.01 c the wide shapes' temporal order falls to "
                   f"{rng(last_orders('large', 'usl', 'flip', wide) + last_orders('large', 'musl', 'flip', wide))} (USL, MUSL; "
                   "the cause is not isolated here): at large motion and a fixed dt fraction the time step, not the "
                   "mesh, sets the error of fine meshes.")
    g_pic, g_blend = grows('small', 'pic'), grows('small', 'blend', ['usl', 'musl'])
    g_apic = grows('small', 'apic', ['usl', 'musl'], ['bspline2', 'bspline3'])
    if g_pic:
        out.append(f"- **Transfer.** PIC and the 0.99 blend do not converge in dt: as k falls from "
                   f"{findings.temporal['small'][0]['ks'][0]:g} to {findings.temporal['small'][0]['ks'][-2]:g} "
                   f"their change d(k) grows {rng(g_pic)}x (PIC) and {rng(g_blend)}x (blend, USL/MUSL): they damp a "
                   "little every step, so more steps damp more, and their error is the damping's (see the energy "
                   "tables). APIC with B-splines shows the same sign, more weakly "
                   f"(d(k) changes {rng(g_apic)}x, USL/MUSL); APIC with linear and GIMP converges at second order in time.")
    out.append(f"- **Grid crossing.** Linear shapes stop converging once particles cross cells: bar at v0 = 0.01 c "
               f"{o('bar large', 'usf', ['linear'])} (USF), {o('bar large', 'musl', ['linear'])} (MUSL), USL stopped; "
               f"manufactured A/L = 1e-3 {o('manufactured 0.001', 'usl', ['linear'])} and A/L = 0.05 "
               f"{o('manufactured 0.05', 'musl', ['linear'])} (MUSL). The wide shapes cure it: bar at v0 = 0.01 c "
               f"{o('bar large', 'usl', wide)} (USL).")
    out.append(f"- **Quadrature at large strain.** The manufactured scene at A/L = 0.05 (strains up to "
               f"{2 * np.pi * 0.05:.0%}) separates "
               f"them: cpGIMP keeps order {o('manufactured 0.05', 'usl', ['cpgimp'])} (USL), while uGIMP "
               f"({o('manufactured 0.05', 'usl', ['ugimp'])}) and the B-splines ({o('manufactured 0.05', 'usl', ['bspline2', 'bspline3'])}) "
               "lose it on the finer meshes, consistent with their integration: the weights stay those of the "
               "undeformed box or point while the particle's domain stretches or shrinks, where cpGIMP's box follows "
               "J (Bardenhagen and Kober 2004). At A/L = 1e-3 uGIMP and cpGIMP reach "
               f"{o('manufactured 0.001', 'usl', ['ugimp', 'cpgimp'])}, the B-splines {o('manufactured 0.001', 'usl', ['bspline2', 'bspline3'])}.")
    prof = findings.profile
    ends = ', '.join(f'{kind} {shape} {ratio:.1f}' for (kind, shape), ratio in prof.items() if shape.startswith('bspline'))
    lin = lambda scene, h: rows.get(('ratio ' + scene, 'usl', h), np.nan)
    out.append(f"- **Boundary treatment.** With the mirror at both fixed ends (x = 0 and, on the manufactured scene, "
               f"x = L) and empty cells past the free end, the B-splines' orders at small strain are "
               f"{o('bar small', 'usl', ['bspline2', 'bspline3'])} on the bar and "
               f"{o('manufactured 1e-06', 'usl', ['bspline2', 'bspline3'])} on the manufactured scene (USL); largest "
               f"particle error near an end (outer tenth) over the interior's, from the profiles above: {ends}. "
               f"They do not beat linear here: at 160 elements their errors are "
               f"{rng([lin('bar small', h) for h in ('bspline2', 'bspline3')])}x linear's on the bar and "
               f"{rng([lin('manufactured 1e-06', h) for h in ('bspline2', 'bspline3')])}x on the manufactured scene (USL).")
    if column and len(col_el) >= 2:
        e = lambda scheme, shape, n: column.get((scheme, shape, n), (np.nan, 0))[0]
        ratio = [e('usl', h, col_el[-1]) / e('usl', 'linear', col_el[-1]) for h in ('bspline2', 'bspline3')]
        out.append(f"- **Body force at a mirrored end (column).** Gravity is not odd about the fixed end (u_xx = "
                   "g/c^2 at x = 0); the image's body force is the mirror of the column's (the scheme reflects the "
                   "external force of the column's own particles onto the ghost as it does the internal force), so "
                   "u_xx jumps at the end. At a fixed dt the B-splines converge under USL at "
                   f"{o('column', 'usl', ['bspline2', 'bspline3'])} ({col_el[0]} to {col_el[-1]} elements) with errors "
                   f"{rng(ratio)}x linear's at {col_el[-1]} elements, under USF and MUSL at "
                   f"{o('column', 'usf', ['bspline2', 'bspline3'])} and {o('column', 'musl', ['bspline2', 'bspline3'])}. "
                   "GIMP matches linear ("
                   f"{o('column', 'usl', ['ugimp', 'cpgimp'])} against {o('column', 'usl', ['linear'])}): at small "
                   "strain its boxes do not reach the ghost node. The manufactured scene's body force vanishes at "
                   "both fixed ends (b is odd about them).")
    return out


def orders_section(out, small, large, findings: Findings):
    lines = ['', '## Observed spatial orders on every scene, and what limits them', '']
    # bar
    rows = {}
    for scheme in SCHEMES:
        for shape in SHAPES:
            errors = by_elements(small, scheme=scheme, shape=shape)
            rows[('bar small', scheme, shape)] = order_between(errors, 40, 160)
            linear = by_elements(small, scheme=scheme, shape='linear')
            rows[('ratio bar small', scheme, shape)] = errors.get(160, np.nan) / linear.get(160, np.nan)
    for scheme, shape, el, err, ok, measure, used, ords in convergence_table(large, True):
        rows[('bar large', scheme, shape)] = order_between(dict(zip(used.tolist(), measure.tolist())), 40, 160)
    man = None
    if (out / 'manufactured.h5').exists():
        man = load(out / 'manufactured.h5')
        for a in sorted(set(man.cases['amplitude'])):
            for scheme in SCHEMES:
                for shape in SHAPES:
                    errors = by_elements(man, scheme=scheme, shape=shape, amplitude=a)
                    rows[(f'manufactured {a:g}', scheme, shape)] = order_between(errors, 40, 160)
                    linear = by_elements(man, scheme=scheme, shape='linear', amplitude=a)
                    rows[(f'ratio manufactured {a:g}', scheme, shape)] = errors.get(160, np.nan) / linear.get(160, np.nan)
    column = {}
    for path in sorted(out.glob('column_e*.h5')):
        cases = load(path).cases
        for i in range(len(cases['scheme'])):
            column[(cases['scheme'][i], cases['shape'][i], int(cases['elements'][i]))] = (
                cases['relative_error'][i] if cases['status'][i] == 0 else np.nan, cases['dt'][i])
    col_el = sorted({k[2] for k in column})
    if len(col_el) >= 2:
        lo, hi = col_el[0], col_el[-1]
        for scheme in SCHEMES:
            for shape in SHAPES:
                e = {n: column.get((scheme, shape, n), (np.nan, 0))[0] for n in col_el}
                rows[('column', scheme, shape)] = order_between(e, lo, hi)
    scenes = [sc for sc in dict.fromkeys(k[0] for k in rows) if not sc.startswith('ratio')]
    heads = {'bar small': 'bar, v0 = 0.1 m/s (vs exact)', 'bar large': 'bar, v0 = 0.01 c (self-convergence d)',
             'column': f'column, fixed dt ({col_el[0] if col_el else ""} -> {col_el[-1] if col_el else ""} el.)'}
    lines += ['Observed order between 40 and 160 elements, log(e(40)/e(160))/log 4 (column: between the two meshes '
              'named), FLIP. Bar: 4 particles per element, k = 0.25, 2 periods. Manufactured (both ends fixed, '
              'A/L given): 2 particles per element, k = 0.1, one period 2L/c, error = max over steps of the '
              'RMS particle displacement error / A. Column (fixed end with body force): 2 particles per element, '
              'the same dt on every mesh (see below). nan: a run stopped or no data.', '']
    lines += markdown_table(['scheme', 'shape'] + [heads.get(sc, sc.replace('manufactured', 'manufactured A/L ='))
                                                   for sc in scenes],
                            [[scheme, shape] + [fo(rows.get((sc, scheme, shape), np.nan)) for sc in scenes]
                             for scheme in SCHEMES for shape in SHAPES])
    if man is not None:
        els = sorted(set(man.cases['elements']))
        key = ('manufactured 0.001', 'usl', 'cpgimp')
        e = by_elements(man, scheme='usl', shape='cpgimp', amplitude=1e-3)
        verdict = 'holds' if rows.get(key, np.nan) >= 1.5 else 'does NOT hold'
        lines += ['', f"Issue 15's check: manufactured A/L = 1e-3, USL, k = 0.1, cpgimp, observed order between 40 and "
                  f"160 elements {fo(rows.get(key, np.nan))} (successive: "
                  f"{fo(order_between(e, 40, 80))}, {fo(order_between(e, 80, 160))}); at least 1.5 {verdict}."]
        for a in sorted(set(man.cases['amplitude'])):
            lines += ['', f'### Manufactured solution, A/L = {a:g}: relative error per elements (successive orders)', '']
            table = []
            for scheme in SCHEMES:
                for shape in SHAPES:
                    m = man.rows('elements', scheme=scheme, shape=shape, amplitude=a)
                    err, st, nm = (man.cases[name][m] for name in ('relative_error', 'status', 'status_name'))
                    cells = [fmt(x) if s == 0 else f'guard ({n})' for x, s, n in zip(err, st, nm)]
                    errors = by_elements(man, scheme=scheme, shape=shape, amplitude=a)
                    ords = successive_orders(els, [errors.get(n, np.nan) for n in els])
                    table.append([scheme, shape] + cells + [', '.join(fo(x) for x in ords)])
            lines += markdown_table(['scheme', 'shape'] + [f'{n} el.' for n in els] + ['orders'], table)
    if column:
        dts = sorted({v[1] for v in column.values()})
        lines += ['', '### Column under gravity (body force at the mirrored fixed end): relative u_cm error per elements',
                  '', f'dt = {dts[0]:.3e} s on every mesh ({len(dts)} distinct value(s)), so that the sudden load\'s '
                  'O(dt) error is the same on every mesh and the change with the elements is the mesh\'s. '
                  'The linear shape has no ghost cell (node 0 held); the wider shapes fold a mirror ghost there.', '']
        table = []
        for scheme in SCHEMES:
            for shape in SHAPES:
                e = [column.get((scheme, shape, n), (np.nan, 0))[0] for n in col_el]
                table.append([scheme, shape] + [fmt(x) for x in e]
                             + [', '.join(fo(x) for x in successive_orders(col_el, e))])
        lines += markdown_table(['scheme', 'shape'] + [f'{n} el.' for n in col_el] + ['orders'], table)
    # where the error sits along the body
    prof = {kind: profile_errors(out, kind) for kind in ('bar', 'manufactured')}
    if any(prof.values()):
        plt = plt_module()
        fig, axes = plt.subplots(1, 2, figsize=(13, 4.4))
        fig.subplots_adjust(left=0.06, right=0.99, bottom=0.12, top=0.86, wspace=0.2)
        table = []
        for ax, (kind, title, ends) in zip(axes, (('bar', 'bar (fixed X = 0 mirrored, free X = L), v0 = 0.1 m/s, '
                                                   '40 el. x 4, t = 1.75 T', 'fixed, free'),
                                                  ('manufactured', 'manufactured, A/L = 1e-6, both ends fixed, 40 el. '
                                                   'x 2, t = L/(2c)', 'fixed, fixed'))):
            for shape, (X, err) in prof[kind].items():
                ax.semilogy(X / X.max(), np.maximum(err, 1e-12), '.-', ms=2, lw=0.6, color=SHAPE_COLOURS[shape],
                            label=shape)
                L = X.max() + X.min()
                a, b, c = err[X < 0.1 * L], err[(X >= 0.1 * L) & (X <= 0.9 * L)], err[X > 0.9 * L]
                worst_end = max(a.max(), c.max())
                table.append([kind, shape, f'{a.max():.2e}', f'{b.max():.2e}', f'{c.max():.2e}',
                              f'{worst_end / b.max():.1f}'])
                findings.profile[(kind, shape)] = worst_end / b.max()
            ax.set_title(f'USL: {title}', fontsize=9)
            ax.set_xlabel('reference position X / L')
            ax.set_ylabel('|u_p - u_exact(X_p)| / amplitude')
            ax.grid(alpha=0.3, which='both')
            ax.legend(fontsize=8)
        fig.suptitle('Where the error sits: particle displacement error along the body, USL, FLIP')
        fig.savefig(out / 'error_profiles.png', dpi=110)
        plt.close(fig)
        lines += ['', '### Where the error sits along the body', '', '![error profiles](error_profiles.png)', '']
        lines += markdown_table(['scene', 'shape', 'max error, X < L/10', 'max error, interior', 'max error, X > 9L/10',
                                 'end / interior'], table)
    return lines + limits_text(rows, column, col_el, findings)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument('folder', type=pathlib.Path)
    args = parser.parse_args(argv)
    out = args.folder
    lines = ['# Shape functions on the vibrating bar', '',
             'Written by `studies/shapes/analyze.py` from the files `studies/shapes/run.sh` wrote in this folder. '
             'Bar: L = 25 m, E = 200 GPa, rho = 7800 kg/m^3, mode 1, 2 periods, 4 particles per element, '
             'dt = 0.25 dx/c, transfer FLIP; error = max over steps of |u_cm - u_cm,exact| / amplitude.', '']

    small = load(out / 'convergence_small.h5')
    lines += ['## Spatial convergence, small amplitude (v0 = 0.1 m/s), against the exact solution', '']
    lines += markdown_table(['scheme', 'shape'] + [f'{e} el.' for e in sorted(set(small.cases['elements']))]
                            + ['observed orders (successive)'],
                            [[scheme, shape] + [result_cell(e, k) for e, k in zip(err, ok)]
                             + [', '.join(fo(o) for o in ords)]
                             for scheme, shape, el, err, ok, measure, used, ords in convergence_table(small, False)])

    large = load(out / 'convergence_large.h5')
    large_elements = sorted(set(large.cases['elements']))
    lines += ['', f'## Large motion, v0 = 0.01 c (the free end moves +-{0.01 * BAR_C / BAR_OMEGA:.2f} m: '
              f'{0.01 * BAR_C / BAR_OMEGA / (BAR_L / 320):.1f} cells at 320 elements)', '',
              'Against the exact solution of linear elasticity (the material is sigma = E ln F, so the error '
              'stops at the model difference, about 0.56 %), and the self-convergence measure '
              'd(E) = max_t |u_cm(E) - u_cm(2E)| / amplitude with its observed orders. "guard": a run stopped.', '']
    lines += markdown_table(['scheme', 'shape', 'error vs exact ' + ' / '.join(str(e) for e in large_elements) + ' el.',
                             'd(E), E = ' + ' / '.join(str(e) for e in large_elements[:-1]), 'orders of d'],
                            [[scheme, shape, ' / '.join(result_cell(e, k) for e, k in zip(err, ok)),
                              ' / '.join(fmt(d) for d in measure), ', '.join(fo(o) for o in ords)]
                             for scheme, shape, el, err, ok, measure, used, ords in convergence_table(large, True)])

    for amp, title in (('small', 'v0 = 0.1 m/s'), ('large', 'v0 = 0.01 c')):
        path = out / f'transfers_{amp}.h5'
        if not path.exists():
            continue
        tr = load(path)
        els = sorted(set(tr.cases['elements']))
        lines += ['', f'## Transfers, USL, {title}: relative error against the exact solution per elements, '
                  'and the observed orders (blend: flip_fraction 0.99)', '']
        table = []
        for shape in SHAPES:
            for transfer in TRANSFERS:
                m = tr.rows('elements', shape=shape, transfer=transfer, scheme='usl')
                err, ok = tr.cases['relative_error'][m], tr.ok[m]
                table.append([shape, transfer] + [result_cell(e, k) for e, k in zip(err, ok)]
                             + [', '.join(fo(x) for x in successive_orders(tr.cases['elements'][m], err))])
        lines += markdown_table(['shape', 'transfer'] + [f'{e} el.' for e in els] + ['orders'], table)

    findings = Findings()
    lines += error_against_time(out, small)
    lines += temporal_section(out, findings)
    lines += table2_section(out)
    lines += crossing_section(out)
    lines += energy_section(out)
    lines += orders_section(out, small, large, findings)

    stab = load(out / 'stability.h5')
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
              'its node is nearly empty.', '']
    table = []
    for scheme in SCHEMES:
        for shape in SHAPES:
            cells = []
            for ppc in (1, 2, 4):
                m = stab.rows(scheme=scheme, shape=shape, particles_per_element=ppc)
                limit = stability_limit(stab.cases['dt_fraction'][m], stab.cases['status'][m])
                if not limit.found:
                    cell = f'> {limit.stable:.2f}'
                elif not np.isfinite(limit.stable):
                    cell = f'< {limit.first_failing:.2f}'
                else:
                    cell = f'{limit.stable:.2f}'
                if (scheme, shape, ppc) in predicted:
                    cell += ' / {:.3f} / {:.3f}'.format(*predicted[(scheme, shape, ppc)])
                cells.append(cell)
            table.append([scheme, shape] + cells)
    lines += markdown_table(['scheme', 'shape', 'ppc = 1', 'ppc = 2', 'ppc = 4'], table)

    with open(out / 'speed.csv') as handle:
        rows = list(csv.DictReader(handle))
    lines += ['', '## Throughput (particle-steps/s, one thread; each run paired with the fused linear run '
              'of the same scheme, size and round, run just before it; median and range of the ratios over the '
              'rounds; on a shared machine the spread is large)', '']
    rates, ratios = {}, {}
    fused = {(int(r['particles']), r['scheme'], r['round']): float(r['particle_steps_per_s'])
             for r in rows if r['path'] == 'fused' and r['shape'] == 'linear'}
    for r in rows:
        key = (int(r['particles']), r['scheme'], r['shape'], r['transfer'], r['path'])
        rate = float(r['particle_steps_per_s'])
        base = fused.get((key[0], key[1], r['round']), fused.get((key[0], 'usl', r['round'])))
        rates.setdefault(key, []).append(rate)
        ratios.setdefault(key, []).append(rate / base)
    order = sorted(rates, key=lambda k: (k[0], SCHEMES.index(k[1]), k[4] != 'fused', SHAPES.index(k[2]), k[3]))
    lines += markdown_table(['particles', 'scheme', 'shape', 'transfer', 'path', 'particle-steps/s (median)',
                             'ratio to fused linear: median (min-max)'],
                            [list(key) + [f'{np.median(rates[key]):.3e}',
                                          f'{np.median(ratios[key]):.2f} ({min(ratios[key]):.2f}-{max(ratios[key]):.2f})']
                             for key in order])
    wall = out / 'wall_time.txt'
    if wall.exists():
        fields = wall.read_text().split() + ['nan', 'nan', 'nan']
        lines += ['', '## Run time of the study', '',
                  f'{float(fields[0]):.0f} s for every run above (`bash studies/shapes/run.sh`, '
                  f'error passes on {os.environ.get("MPM1D_THREADS", "2")} threads, timing passes and '
                  f'throughput on one; including the build check), {fields[3]} of CPU time (user), on {fields[2]} cores whose '
                  f'load average was {fields[1]} when it started (other work on a shared machine slows it and the '
                  'timings).']
    (out / 'summary.md').write_text('\n'.join(lines) + '\n')
    return 0


if __name__ == '__main__':
    raise SystemExit(main())
