#!/usr/bin/env python3
"""Figures and summary.md of the mpm1d numerical stability study (studies/stability/run.sh).

    mpm1d-stability-figures OUT_DIR -o OUT_DIR     (or .venv/bin/python -m mpm1d_post.studies.stability ...) \\
        --predicted OUT_DIR/predicted/predicted_critical.csv [--timings OUT_DIR/timings.txt]

Reads the files run.sh writes into OUT_DIR (map.h5, coarse.h5, scale_*.h5, large.h5,
long100.h5, long1000.h5, modes.h5, fine_e*.h5, largest.h5) through mpm1d_post.loader, the predicted
critical fractions (CSV of studies/stability/linear_stability.py) and, for growth rates and
linearised energy ratios, linear_stability.py itself. For every case class the summary states
stable or unstable, which guard tripped and when (/cases/trip_step, trip_time), the numbers
behind it, and the checks: every unstable case is caught by a guard with finite outputs, and no
case expected stable trips one. A class whose file is missing is skipped with a note.
Exit status: 0 written (checks may fail: see summary.md), 2 bad or missing input.
"""

from __future__ import annotations

import argparse
import csv
import datetime
import math
import re
import sys
from pathlib import Path
from typing import Dict, List, Optional, Sequence, Tuple

import numpy as np

import matplotlib
matplotlib.use('Agg')
import matplotlib.pyplot as plt  # noqa: E402

from .. import linear_stability as ls  # noqa: E402
from ..figures import duration_text  # noqa: E402
from ..loader import Mpm1dFileError, Sweep, concatenate_sweeps, load_run, load_sweep  # noqa: E402
from ..limits import stability_limit  # noqa: E402
from ..output_files import OutputError, replacing, save_figure_file, with_output_errors  # noqa: E402
from ..tables import markdown_table  # noqa: E402

PROGRAM = 'mpm1d-stability-figures'
SCHEMES = ('usf', 'usl', 'musl')
C_PAPER = math.sqrt(200.0e9 / 7800.0)           # m/s, the paper's steel
RATIO_PAPER = 0.1 / C_PAPER                     # v0/c of the paper
ROUND_OFF_GROWTH = math.log(1.0e16)             # a mode seeded at round-off reaches O(1)
FINITE_COLUMNS = ('max_error', 'relative_error', 'max_energy_ratio', 'final_energy_ratio',
                  'min_volume_ratio', 'max_cell_move')
#: A stopped case has no result (NaN max_error, relative_error): its error up to the stop instead.
STOPPED_FINITE = {'max_error': 'error_before_stop', 'relative_error': 'relative_error_before_stop'}
MESSAGE = re.compile(r'guard\s+(\w+)\s+tripped at step\s*(\d+)\s*of\s*(\d+)\s*\(t\s*=\s*'
                     r'([-+0-9.EeDd]+)\s*s')
#: Finest spacing of the time-step fractions the study runs near its limits.
K_STEP = 0.005

GUARD_COLOURS = {'ok': 'tab:green', 'energy_growth': 'tab:red', 'left_grid': 'tab:purple',
                 'volume_ratio_not_positive': 'tab:orange', 'cell_crossing': 'tab:brown',
                 'non_finite': 'black'}


# --------------------------------------------------------------------------------------------
# Input
# --------------------------------------------------------------------------------------------

def load(path: str) -> Sweep:
    """A sweep as the loader returns it, with trip_step and trip_time as floats (NaN where the case
    completed) and message_ok: whether a stopped case's message has the documented form, names
    its guard and agrees with the trip step stored as a number (a check of the writer, which
    assembles messages after the parallel loop)."""
    sweep = load_sweep(path, cases='all')  # the study is about the stopped cases too
    n = len(sweep)
    for column in ('trip_step', 'trip_time', 'message'):
        if column not in sweep.cases:
            raise Mpm1dFileError(path, f"missing /cases/{column} (written by mpm1d since the trip "
                                       "columns were added; rerun the sweep)")
    stopped = sweep.stopped
    step = np.where(stopped, sweep.cases['trip_step'].astype(float), np.nan)
    time = np.where(stopped, sweep.cases['trip_time'].astype(float), np.nan)
    parsed = np.ones(n, dtype=bool)
    for i in np.flatnonzero(stopped):
        m = MESSAGE.search(str(sweep.cases['message'][i]))
        parsed[i] = bool(m and m.group(1) == sweep.cases['status_name'][i] and int(m.group(2)) == step[i])
    sweep.cases['trip_step'], sweep.cases['trip_time'], sweep.cases['message_ok'] = step, time, parsed
    return sweep


def load_many(paths: Sequence[str]) -> Sweep:
    """The cases of several sweeps side by side (different namelists on purpose: the scale ladder)."""
    return concatenate_sweeps([load(p) for p in paths])


def read_predicted(path: str) -> Dict[Tuple[str, int, int], float]:
    """(scheme, ppc, elements) -> k_crit from linear_stability.py's CSV."""
    with open(path, newline='') as fh:
        return {(r['scheme'], int(r['particles_per_element']), int(r['elements'])): float(r['k_crit'])
                for r in csv.DictReader(fh)}


# --------------------------------------------------------------------------------------------
# Report: text, checks, figures
# --------------------------------------------------------------------------------------------

class Report:
    def __init__(self, out: str):
        self.out = out
        self.lines: List[str] = []
        self.checks: List[Tuple[str, str, bool, str]] = []
        self.classes: List[Tuple[str, ...]] = []
        self.figures: List[str] = []
        self.versions: set = set()

    def add(self, *lines: str) -> None:
        self.lines.extend(lines)

    def check(self, klass: str, what: str, ok: bool, detail: str = '') -> None:
        self.checks.append((klass, what, bool(ok), detail))

    def footer(self, fig, sources: str) -> None:
        version = ', '.join(sorted(self.versions)) or 'unknown'
        fig.text(0.005, 0.005, f'{version}  |  {sources}  |  '
                 f'{datetime.date.today().isoformat()}', fontsize=6.5, color='0.35')

    def save(self, fig, name: str, sources: str) -> None:
        self.footer(fig, sources)
        save_figure_file(fig, Path(self.out) / name, dpi=130)
        plt.close(fig)
        self.figures.append(name)


def g(x: float, digits: int = 3) -> str:
    if x is None or (isinstance(x, float) and math.isnan(x)):
        return '-'
    return f'{x:.{digits}g}'


def trip_text(c: Dict[str, np.ndarray], i: int) -> str:
    """'guard @ step S (t = T s)' of case i, or 'ok'."""
    if c['status'][i] == 0:
        return 'ok'
    s = c['trip_step'][i]
    where = f" at step {int(s)}" if not math.isnan(s) else ''
    t = c['trip_time'][i]
    when = f" (t = {t:.3g} s)" if not math.isnan(t) else ''
    flag = '' if c['message_ok'][i] else ' [message garbled]'
    return f"{c['status_name'][i]}{where}{when}{flag}"


def class_counts(report: Report, name: str, sweep: Sweep, expected_stable: np.ndarray,
                 unstable_expected: Optional[np.ndarray] = None) -> None:
    """Common checks and the row of the overview table for one case class."""
    c = sweep.cases
    n = len(sweep)
    tripped = sweep.stopped
    guards = {}
    for gname in c['status_name'][tripped]:
        guards[gname] = guards.get(gname, 0) + 1
    finite = np.ones(n, dtype=bool)
    for col in FINITE_COLUMNS:
        if col in c:
            values = np.asarray(c[col], dtype=float)
            if col in STOPPED_FINITE and STOPPED_FINITE[col] in c:  # no result: the error before the stop
                values = np.where(tripped, np.asarray(c[STOPPED_FINITE[col]], dtype=float), values)
            finite &= np.isfinite(values)
    bad_stable = expected_stable & tripped
    garbled = int((~c['message_ok'] & tripped).sum())
    report.check(name, 'all outputs finite (max_error, relative_error, energy ratios, J, cell move; a stopped '
                 'case\'s error before the stop)',
                 finite.all(), f'{int((~finite).sum())} of {n} cases with a non-finite value')
    report.check(name, 'no case expected stable trips a guard', not bad_stable.any(),
                 f'{int(bad_stable.sum())} of {int(expected_stable.sum())} expected-stable cases tripped')
    missed = 0
    if unstable_expected is not None:
        missed = int((unstable_expected & ~tripped).sum())
        report.check(name, 'every case expected unstable is stopped by a guard', missed == 0,
                     f'{missed} of {int(unstable_expected.sum())} expected-unstable cases completed')
    report.classes.append((name, str(n), str(int((~tripped).sum())),
                           ', '.join(f'{k} {v}' for k, v in sorted(guards.items())) or '-',
                           str(int((~finite).sum())), str(int(bad_stable.sum())),
                           '-' if unstable_expected is None else str(missed), str(garbled)))


# --------------------------------------------------------------------------------------------
# 1. time-step stability maps
# --------------------------------------------------------------------------------------------

def critical_table(sweep: Sweep, scheme: str, ppc: int, elements: int):
    """Measured limit of one (scheme, ppc): (measured, first_fail index or None, the cases' indices by
    dt_fraction), or None when the sweep has no such case."""
    idx = sweep.rows('dt_fraction', scheme=scheme, particles_per_element=ppc, elements=elements)
    if idx.size == 0:
        return None
    limit = stability_limit(sweep.cases['dt_fraction'][idx], sweep.cases['status'][idx])
    return limit.stable, (int(idx[limit.first_index]) if limit.found else None), idx


def stability_section(report: Report, sweep: Sweep, predicted, elements: int, title: str,
                      name: str, figname: str, energy_guard: bool) -> Dict[Tuple[str, int], float]:
    c = sweep.cases
    report.versions.update(sweep.code_versions)
    ppcs = sorted(set(c['particles_per_element'].tolist()))
    schemes = [s for s in SCHEMES if s in set(c['scheme'].tolist())]
    periods = sweep.config.get('periods', float('nan'))
    report.add(f'## {title}', '',
               f'`{Path(sweep.path).name}`: {len(sweep)} cases, {elements} element(s), '
               f'ppc {", ".join(map(str, ppcs))}, k = c dt/dx from {c["dt_fraction"].min():g} to '
               f'{c["dt_fraction"].max():g} ({len(set(c["dt_fraction"].round(6)))} values), '
               f'{duration_text(sweep.config)} of mode 1 (E = 200 GPa, rho = 7800 kg/m^3, v0 = 0.1 m/s). '
               'Measured k_crit = the largest k below the first k that trips a guard; predicted '
               f'k_crit = linear_stability.py ({elements} element(s)). rho(A) is the predicted '
               'amplification per step at the first failing k, and "steps to 1e16" = ln(1e16)/ln rho '
               'the steps a mode seeded at round-off needs to reach the size of the solution.', '')
    header = (['scheme', 'ppc', 'predicted k_crit', 'measured k_crit', 'first failing k', 'guard there',
               'rho(A) there', 'steps to 1e16', 'steps run']
              + (['predicted first failing k (rho > 1 or energy ratio >= guard limit)', 'agrees'] if energy_guard
                 else ['measured <= predicted < first failing']))
    rows = []
    measured_all = {}
    expected_stable = np.zeros(len(sweep), dtype=bool)
    expected_unstable = np.zeros(len(sweep), dtype=bool)
    energy_limited = np.zeros(len(sweep), dtype=bool)
    guard_limit = float(sweep.config.get('energy_growth_limit', 10.0))
    for scheme in schemes:
        for ppc in ppcs:
            result = critical_table(sweep, scheme, ppc, elements)
            if result is None:
                continue
            measured, first, idx = result
            kc = predicted.get((scheme, ppc, elements))
            if kc is None:
                kc = ls.Analyser(elements, ppc).critical_fraction(scheme)[0]
            measured_all[(scheme, ppc)] = measured
            analyser = ls.Analyser(elements, ppc)
            ks = c['dt_fraction'][idx]
            predicted_first = None
            for i, k in zip(idx, ks):
                if k < kc - 1e-9:
                    expected_stable[i] = True
                    if energy_guard:
                        # the energy guard sees the particle energy, not the map's invariant:
                        # a linearly stable run may still exceed the guard's limit (read from the
                        # file, less 1e-4 for the O(v0/c) non-linear terms the linearisation leaves out)
                        emax, _ = ls.energy_ratios(scheme, float(k), ppc, elements, int(c['steps'][i]))
                        if emax >= guard_limit * (1.0 - 1.0e-4):
                            expected_stable[i] = False
                            energy_limited[i] = True
                elif k > kc + 1e-9:
                    rho = analyser.spectral_radius(scheme, float(k))
                    # unstable within the run: a round-off seed grows past O(1) in the steps run
                    if math.log(rho) * c['steps'][i] > ROUND_OFF_GROWTH:
                        expected_unstable[i] = True
                if predicted_first is None and not expected_stable[i]:
                    predicted_first = float(k)
            if first is None:
                rows.append([scheme.upper(), ppc, f'{kc:.4f}', f'>= {measured:g}', 'none', '-', '-', '-', '-']
                            + ['-'] * (2 if energy_guard else 1))
                continue
            kf = float(c['dt_fraction'][first])
            rho = analyser.spectral_radius(scheme, kf)
            need = ROUND_OFF_GROWTH / math.log(rho) if rho > 1 else float('inf')
            if energy_guard:
                # the energy ratio crosses the limit smoothly: the non-linear run may cross it one
                # grid step later than the linearised one
                agree = predicted_first is not None and abs(predicted_first - kf) <= K_STEP + 1e-9
                cell = [g(predicted_first)]
                what = (f'first failing k {kf:g} = predicted {g(predicted_first)} within one step {K_STEP:g} '
                        f'(linear k_crit {kc:.4f})')
            else:
                agree = measured <= kc + 1e-9 < kf
                cell = []
                what = f'measured {measured:g} <= predicted {kc:.4f} < first failing {kf:g}'
            rows.append([scheme.upper(), ppc, f'{kc:.4f}', f'{measured:g}', f'{kf:g}', trip_text(c, first),
                         f'{rho:.4f}', g(need), int(c['steps'][first])] + cell + ['yes' if agree else '**no**'])
            report.check(name, f'{scheme.upper()} ppc {ppc}: {what}', agree)
    report.add(*markdown_table(header, rows))
    report.add('')
    if energy_guard:
        lowest = {}
        for i in np.flatnonzero(energy_limited):
            key = (c['scheme'][i], int(c['particles_per_element'][i]))
            lowest[key] = min(lowest.get(key, 9.0), float(c['dt_fraction'][i]))
        tripped_el = energy_limited & sweep.stopped
        report.add('On one element the **energy_growth guard trips below the linear limit**: the '
                   'particle energy (kinetic + sigma^2 V/2E), which is not the invariant of the '
                   f'discrete map, oscillates beyond the guard limit ({guard_limit:g} x initial) in a linearly stable '
                   'run. `linear_stability.energy_ratios` (the linearised run from the same initial '
                   f'state, as many steps) predicts a maximum energy ratio >= {guard_limit:g} for '
                   f'{int(energy_limited.sum())} cases with k < k_crit, of which {int(tripped_el.sum())} '
                   'tripped energy_growth (USL, 1 particle: the ratio is exactly 1 + k^2). These count as '
                   'expected to trip. Lowest such k per (scheme, ppc): ' +
                   ', '.join(f'{s.upper()} {p}: {k:g}' for (s, p), k in sorted(lowest.items())) + '.', '')
        near = np.array([any(abs(float(c['dt_fraction'][i]) - float(c['dt_fraction'][j])) <= K_STEP + 1e-9
                             for j in np.flatnonzero(~energy_limited & sweep.where(
                                 scheme=c['scheme'][i], particles_per_element=c['particles_per_element'][i])))
                         for i in range(len(c['status']))])
        report.check(name, f'every case with k < k_crit whose linearised energy ratio reaches {guard_limit:g} trips '
                     'energy_growth (but for the first grid step past that limit)',
                     (c['status_name'][energy_limited & ~near] == 'energy_growth').all(),
                     f'{int(tripped_el.sum())} of {int(energy_limited.sum())}')
        expected_unstable |= energy_limited & ~near
    class_counts(report, name, sweep, expected_stable, expected_unstable)
    ok_cases = sweep.ok
    if ok_cases.any():
        j = int(np.argmax(np.where(ok_cases, c['max_energy_ratio'], -1.0)))
        report.add(f'Largest max_energy_ratio of a completed case: {c["max_energy_ratio"][j]:.4f} '
                   f'({c["scheme"][j].upper()}, ppc {c["particles_per_element"][j]}, k = '
                   f'{c["dt_fraction"][j]:g}).', '')
    ok_above = expected_unstable & sweep.ok
    report.add(f'Cases expected stable: {int(expected_stable.sum())}, of which '
               f'{int((expected_stable & sweep.stopped).sum())} tripped a guard. Cases expected '
               f'to trip (above k_crit with predicted growth over the run > 1e16'
               f'{", or energy ratio >= 2" if energy_guard else ""}): {int(expected_unstable.sum())}, of '
               f'which {int(ok_above.sum())} completed. Guards of the failing cases: ' +
               ', '.join(f'{k} {v}' for k, v in sorted(
                   {n: int((c["status_name"] == n).sum()) for n in set(c["status_name"][c["status"] > 0])}.items())) + '.', '')
    plot_map(report, sweep, predicted, elements, figname, zoom=False)
    if elements > 1:
        plot_map(report, sweep, predicted, elements, figname.replace('.png', '_zoom.png'), zoom=True)
    return measured_all


def plot_map(report: Report, sweep: Sweep, predicted, elements: int, figname: str, zoom: bool):
    c = sweep.cases
    schemes = [s for s in SCHEMES if s in set(c['scheme'].tolist())]
    ppcs = sorted(set(c['particles_per_element'].tolist()))
    fig, axes = plt.subplots(1, len(schemes), figsize=(4.2 * len(schemes), 4.6), squeeze=False)
    for ax, scheme in zip(axes[0], schemes):
        m = sweep.where(scheme=scheme)
        kcs = [predicted.get((scheme, p, elements)) for p in ppcs]
        kcs = [ls.Analyser(elements, p).critical_fraction(scheme)[0] if k is None else k
               for p, k in zip(ppcs, kcs)]
        for gname, colour in GUARD_COLOURS.items():
            s = m & (c['status_name'] == gname)
            if s.any():
                ax.scatter(c['particles_per_element'][s], c['dt_fraction'][s], s=10 if zoom else 6,
                           marker='o' if gname == 'ok' else 'x', color=colour,
                           label='completed' if gname == 'ok' else f'tripped: {gname}', lw=0.8)
        ax.plot(ppcs, kcs, '-', color='tab:blue', lw=1.5, label='predicted k_crit (linear)')
        meas = []
        for p in ppcs:
            r = critical_table(sweep, scheme, p, elements)
            meas.append(r[0] if r else np.nan)
        ax.plot(ppcs, meas, 's', mfc='none', color='k', ms=7, label='measured k_crit')
        if zoom:
            ax.set_ylim(min(kcs) - 0.06, max(kcs) + 0.06)
        ax.set_xlabel('particles per element')
        ax.set_ylabel('time-step fraction k = c dt / dx  (-)')
        ax.set_title(f'{scheme.upper()}, {elements} element(s)')
        ax.set_xticks(ppcs)
        ax.grid(alpha=0.3)
    axes[0][0].legend(fontsize=7, loc='lower left' if not zoom else 'best')
    fig.suptitle(f'Stability map{" (zoom on the limit)" if zoom else ""}: guard status over '
                 f'(ppc, k); bar L = 25 m, E = 200 GPa, rho = 7800 kg/m^3, v0 = 0.1 m/s, '
                 f'{duration_text(sweep.config)}', fontsize=9)
    fig.tight_layout(rect=(0, 0.03, 1, 0.95))
    report.save(fig, figname, Path(sweep.path).name)
    report.add(f'![{figname}]({figname})', '')


# --------------------------------------------------------------------------------------------
# 2. stiffness and scale
# --------------------------------------------------------------------------------------------

def scale_section(report: Report, sweep: Sweep) -> None:
    c = sweep.cases
    report.versions.update(sweep.code_versions)
    E, rho = c['youngs_modulus'], c['density']
    ratio = c['velocity_amplitude'] / np.sqrt(E / rho)
    report.add('## 2. Stiffness and scale', '',
               f'{len(sweep)} cases: every scheme at E = {", ".join(g(x) for x in sorted(set(E)))} Pa '
               f'x rho = {", ".join(g(x) for x in sorted(set(rho)))} kg/m^3 (wave speeds '
               f'{g(np.sqrt(E / rho).min())} .. {g(np.sqrt(E / rho).max())} m/s), v0/c = '
               f'{RATIO_PAPER:.6g} as in the paper (spread of v0/c over the cases '
               f'{g(float(np.ptp(ratio) / RATIO_PAPER))} relative), 20 elements, 1 ppc, k = 0.1, '
               '2 periods. Deviation = |relative_error / relative_error(paper case) - 1|.', '')
    expected_stable = np.ones(len(sweep), dtype=bool)
    rows = []
    fig, axes = plt.subplots(1, 3, figsize=(13, 4.2))
    for ax, scheme in zip(axes, SCHEMES):
        m = sweep.where(scheme=scheme)
        if not m.any():
            ax.set_visible(False)
            continue
        ref = sweep.where(scheme=scheme, youngs_modulus=200.0e9, density=7800.0)
        if not ref.any():
            rows.append([scheme.upper(), 'no paper case (E = 2e11, rho = 7800) in the sweep'] + ['-'] * 6)
            continue
        r0 = float(c['relative_error'][ref][0])
        dev = np.abs(c['relative_error'] / r0 - 1.0)
        dev[~m] = np.nan
        j = int(np.nanargmax(dev))
        steps = sorted(set(c['steps'][m].tolist()))
        rows.append([scheme.upper(), int(m.sum()), int((m & sweep.ok).sum()), ', '.join(map(str, steps)),
                     f'{r0:.15g}', f'{dev[j]:.2e}', f'({g(E[j])}, {g(rho[j])})',
                     f'{g(np.nanmin(c["max_error"][m]))} .. {g(np.nanmax(c["max_error"][m]))}'])
        report.check('scale', f'{scheme.upper()}: same steps as the paper case in every case', len(steps) == 1,
                     f'steps {steps}')
        report.check('scale', f'{scheme.upper()}: relative_error equals the paper case to 1e-9',
                     dev[j] < 1e-9, f'max deviation {dev[j]:.2e}')
        es, rs = sorted(set(E[m])), sorted(set(rho[m]))
        grid = np.full((len(rs), len(es)), np.nan)
        for i in np.flatnonzero(m):
            grid[rs.index(rho[i]), es.index(E[i])] = max(dev[i], 1e-17)
        im = ax.pcolormesh(np.arange(len(es) + 1), np.arange(len(rs) + 1), np.log10(grid),
                           cmap='viridis', vmin=-17, vmax=-9)
        ax.set_xticks(np.arange(len(es)) + 0.5, [f'{x:.0e}' for x in es], rotation=60, fontsize=7)
        ax.set_yticks(np.arange(len(rs)) + 0.5, [f'{x:.0e}' for x in rs], fontsize=7)
        ax.set_xlabel('Young\'s modulus E (Pa)')
        ax.set_ylabel('density rho (kg/m^3)')
        ax.set_title(f'{scheme.upper()}: log10 |rel. error / paper - 1|', fontsize=9)
        fig.colorbar(im, ax=ax)
    fig.suptitle('Stiffness and scale: relative error against the paper case (E = 200 GPa, '
                 'rho = 7800 kg/m^3); 20 el., 1 ppc, k = 0.1, 2 periods, v0/c = 1.975e-5', fontsize=9)
    fig.tight_layout(rect=(0, 0.03, 1, 0.94))
    report.save(fig, 'scale.png', f'{len(sweep.paths)} files scale_*.h5')
    report.add(*markdown_table(['scheme', 'cases', 'completed', 'steps (all cases)', 'relative_error, paper case',
                                'max deviation', 'at (E, rho)', 'max_error range (m)'], rows))
    report.add('', '![scale.png](scale.png)', '')
    class_counts(report, 'scale', sweep, expected_stable)


# --------------------------------------------------------------------------------------------
# 3. large motion
# --------------------------------------------------------------------------------------------

def large_section(report: Report, sweep: Sweep) -> None:
    c = sweep.cases
    report.versions.update(sweep.code_versions)
    ne = int(c['elements'][0])
    c_wave = np.sqrt(c['youngs_modulus'] / c['density'])
    ratio = c['velocity_amplitude'] / c_wave
    ratios = sorted(set(np.round(ratio, 12).tolist()))
    ppcs = sorted(set(c['particles_per_element'].tolist()))
    report.add('## 3. Large motion', '',
               f'{len(sweep)} cases: v0/c = {", ".join(g(r) for r in ratios)}, ppc '
               f'{", ".join(map(str, ppcs))}, every scheme, {ne} elements, k = 0.1, 2 periods. '
               'The grid extends beyond the free end by the end\'s exact displacement amplitude '
               'v0/omega in cells, rounded up, plus 2 (`margin_cells`), so the free end can move out. '
               'Below v0/c = pi/(4 ne ppc) (mode 1) the last particle, at L - dx/(2 ppc), stays in the '
               'bar\'s last cell; above, it crosses into the empty margin cell and the node it enters '
               'gets a tiny mass (the cell-crossing problem of linear shape functions), which USL\'s '
               'strain update does not always survive: it stops with energy_growth, and the '
               'lightest-node mass ratio names the cause. left_grid now means that a particle moved more '
               'than two cells beyond the exact end amplitude: the method itself has failed (errors of '
               'tens of per cent or more at that point). With the grid ending at L (margin_cells = 0, '
               'the code before) every case above the threshold stopped with left_grid.', '')
    rows = []
    threshold = np.array([math.pi * (2 * int(c['mode'][i]) - 1) / (4 * ne * c['particles_per_element'][i])
                          for i in range(len(sweep))])
    expected_stable = ratio < 0.9 * threshold
    expected_unstable = None
    for scheme in SCHEMES:
        rows.append([f'**{scheme.upper()}**'] + [''] * (1 + len(ratios)))
        for ppc in ppcs:
            cells = []
            for r in ratios:
                j = np.flatnonzero(sweep.where(scheme=scheme, particles_per_element=ppc)
                                   & np.isclose(ratio, r, rtol=1e-9))
                if j.size == 0:
                    cells.append('-')
                    continue
                j = int(j[0])
                cells.append(f'ok, rel. err. {c["relative_error"][j]:.3g}' if c['status'][j] == 0
                             else trip_text(c, j))
            rows.append([ppc, f'{math.pi / (4 * ne * ppc):.3g}'] + cells)
    report.add(*markdown_table(['ppc', 'crossing threshold v0/c'] + [f'v0/c = {g(r)}' for r in ratios], rows))
    report.add('')
    energy = c['status_name'] == 'energy_growth'
    report.check('large motion', 'every energy_growth stop met a nearly empty node (lightest node < 0.01 '
                 'of a particle\'s mass)', bool(np.all(c['min_node_mass_ratio'][energy] < 0.01)),
                 f'{int(energy.sum())} energy_growth stops')
    small_motion = ratio <= 0.03  # exact end amplitude 0.03 c/omega = 0.48 m, under one cell
    left = (c['status_name'] == 'left_grid') & small_motion
    report.check('large motion', 'no left_grid while the exact end motion is under one cell (v0/c <= 0.03)',
                 not left.any(), f'{int(left.sum())} such cases left the grid')
    ok = sweep.ok
    if ok.any():
        small = ok & (ratio <= 1.01e-4)
        spread = {}
        for scheme in SCHEMES:
            for ppc in ppcs:
                s = small & sweep.where(scheme=scheme, particles_per_element=ppc)
                if s.sum() > 1:
                    r = c['relative_error'][s]
                    spread[(scheme, ppc)] = float(np.ptp(r) / r.min())
        if spread:
            report.add('Completed cases: for v0/c <= 1e-4 the relative error is independent of the '
                       f'amplitude (spread up to {max(spread.values()):.2e} relative per scheme and ppc); '
                       'it grows with v0/c beyond (non-linear terms: moving particles, J).', '')
    fig, axes = plt.subplots(1, 3, figsize=(13, 4.2), sharey=True)
    for ax, scheme in zip(axes, SCHEMES):
        for n, ppc in enumerate(ppcs):
            colour = f'C{n}'
            s = sweep.where(scheme=scheme, particles_per_element=ppc)
            o = np.argsort(ratio[s])
            r, e, st = ratio[s][o], c['relative_error'][s][o], c['status'][s][o]
            before = c['relative_error_before_stop'][s][o]
            ax.loglog(r[st == 0], e[st == 0], 'o-', color=colour, ms=4, label=f'ppc {ppc}')
            ax.loglog(r[st > 0], before[st > 0], 'x', color=colour, ms=6)  # no result: never joined to the line
            ax.axvline(math.pi / (4 * ne * ppc), color=colour, ls=':', lw=1)
        ax.set_xlabel('v0 / c  (-)')
        ax.set_title(f'{scheme.upper()}, {ne} el., k = 0.1, 2 periods', fontsize=9)
        ax.grid(alpha=0.3, which='both')
    axes[0].set_ylabel('relative error of u_cm (-)')
    axes[0].plot([], [], 'x', color='0.4', label='stopped by a guard: no result\n(error before the stop)')
    axes[0].legend(fontsize=7)
    fig.suptitle('Large motion: relative error against v0/c; dotted: the last particle crosses into the '
                 'empty margin cell above pi/(4 ne ppc)', fontsize=9)
    fig.tight_layout(rect=(0, 0.03, 1, 0.94))
    report.save(fig, 'large_motion.png', Path(sweep.path).name)
    report.add('![large_motion.png](large_motion.png)', '')
    class_counts(report, 'large motion', sweep, expected_stable, expected_unstable)


# --------------------------------------------------------------------------------------------
# 4. long runs
# --------------------------------------------------------------------------------------------

def long_section(report: Report, sweeps: List[Sweep]) -> None:
    report.add('## 4. Long runs: energy drift', '',
               'Every scheme, 20 elements, 100 and 1000 periods of mode 1. final/max energy ratio = '
               'total particle energy at the end / its maximum over the run, relative to the initial one.', '')
    rows = []
    for sweep in sweeps:
        report.versions.update(sweep.code_versions)
        c = sweep.cases
        periods = sweep.config.get('periods', float('nan'))
        order = np.lexsort((c['dt_fraction'], c['particles_per_element'],
                            [SCHEMES.index(s) for s in c['scheme']]))
        rows += [[g(periods), c['scheme'][i].upper(), c['particles_per_element'][i], f'{c["dt_fraction"][i]:g}',
                  c['steps'][i], trip_text(c, i), f'{c["final_energy_ratio"][i]:.6f}',
                  f'{c["max_energy_ratio"][i]:.6f}', g(c['relative_error'][i])] for i in order]
        cons = sweep.where(scheme=('usf', 'musl'))
        drift = np.abs(c['final_energy_ratio'][cons] - 1.0)
        report.check(f'long {g(periods)}', 'USF/MUSL conserve energy: |final ratio - 1| < 0.1 and '
                     'max ratio < 1.1', (drift < 0.1).all() and (c['max_energy_ratio'][cons] < 1.1).all(),
                     f'max |final - 1| = {drift.max():.3g}' if drift.size else '')
        usl = sweep.where(scheme='usl')
        report.check(f'long {g(periods)}', 'USL dissipates: final ratio < 1',
                     (c['final_energy_ratio'][usl] < 1.0).all(),
                     f'final ratios {", ".join(f"{x:.3g}" for x in c["final_energy_ratio"][usl])}')
        class_counts(report, f'long {g(periods)}', sweep, np.ones(len(sweep), dtype=bool))
    report.add(*markdown_table(['periods', 'scheme', 'ppc', 'k', 'steps', 'status', 'final energy ratio',
                                'max energy ratio', 'relative error'], rows))
    report.add('')
    report.add('The relative error of u_cm over 100 and 1000 periods (0.4-0.6 and about 2) is the '
               'accumulated phase error: at 2 the computed oscillation is in opposition to the exact '
               'one; the energy ratios are the measure of stability here.', '')
    hist = [s for s in sweeps if s.histories]
    if hist:
        sweep = hist[0]
        c = sweep.cases
        period = float(sweep.config.get('period', np.nan))
        fig, axes = plt.subplots(1, 3, figsize=(13, 4.0), sharey=True)
        for ax, scheme in zip(axes, SCHEMES):
            for n, i in enumerate(sweep.rows(scheme=scheme)):
                h = sweep.histories.get(int(i))
                if h is None:
                    continue
                e = h['kinetic_energy'] + h['strain_energy']
                step = max(1, e.size // 4000)
                ax.plot(h['time'][::step] / period, e[::step] / e[0], lw=0.8,
                        label=f'ppc {c["particles_per_element"][i]}, k = {c["dt_fraction"][i]:g}')
            ax.set_xlabel('time / period of mode 1  (-)')
            ax.set_title(f'{scheme.upper()}, 20 el.', fontsize=9)
            ax.grid(alpha=0.3)
        axes[0].set_ylabel('total energy / initial energy  (-)')
        axes[0].legend(fontsize=7)
        fig.suptitle('Long runs: energy history over 100 periods (E = 200 GPa, rho = 7800 kg/m^3, '
                     'v0 = 0.1 m/s)', fontsize=9)
        fig.tight_layout(rect=(0, 0.03, 1, 0.94))
        report.save(fig, 'long_energy.png', Path(sweep.path).name)
        report.add('![long_energy.png](long_energy.png)', '')


# --------------------------------------------------------------------------------------------
# 5. high modes
# --------------------------------------------------------------------------------------------

def modes_section(report: Report, sweep: Sweep) -> None:
    c = sweep.cases
    report.versions.update(sweep.code_versions)
    ne = int(c['elements'][0])
    epw = 4.0 * ne / (2 * c['mode'] - 1)
    modes = sorted(set(c['mode'].tolist()))
    ppcs = sorted(set(c['particles_per_element'].tolist()))
    report.add('## 5. High modes', '',
               f'{len(sweep)} cases: modes {modes[0]}..{modes[-1]} on {ne} elements (elements per '
               f'wavelength 4 ne/(2n-1) = {epw.max():g} .. {epw.min():.3g}; 2 is the grid\'s limit), '
               f'ppc {", ".join(map(str, ppcs))}, k = 0.1, 2 periods of the mode. Relative error of u_cm:', '')
    rows = []
    for mode in modes:
        cells = []
        for s in SCHEMES:
            for p in ppcs:
                j = sweep.rows(scheme=s, particles_per_element=p, mode=mode)
                cells.append('-' if j.size == 0 else (f'{c["relative_error"][j[0]]:.3g}' if c['status'][j[0]] == 0
                                                      else trip_text(c, int(j[0]))))
        rows.append([mode, f'{4.0 * ne / (2 * mode - 1):.3g}'] + cells)
    report.add(*markdown_table(['mode', 'el. per wavelength'] + [f'{s.upper()} ppc {p}' for s in SCHEMES for p in ppcs],
                               rows))
    report.add('')
    fig, axes = plt.subplots(1, 3, figsize=(13, 4.0), sharey=True)
    for ax, s in zip(axes, SCHEMES):
        for p in ppcs:
            m = sweep.where(scheme=s, particles_per_element=p) & sweep.ok
            o = np.argsort(epw[m])
            ax.loglog(epw[m][o], c['relative_error'][m][o], 'o-', ms=3, label=f'ppc {p}')
        ax.set_xlabel('elements per wavelength 4 ne/(2n-1)  (-)')
        ax.set_title(f'{s.upper()}, {ne} el., k = 0.1, modes {modes[0]}-{modes[-1]}', fontsize=9)
        ax.grid(alpha=0.3, which='both')
    axes[0].set_ylabel('relative error of u_cm (-)')
    axes[0].legend(fontsize=7)
    fig.suptitle('High modes: error against resolution (E = 200 GPa, rho = 7800 kg/m^3, v0 = 0.1 m/s, '
                 '2 periods of each mode)', fontsize=9)
    fig.tight_layout(rect=(0, 0.03, 1, 0.94))
    report.save(fig, 'modes.png', Path(sweep.path).name)
    report.add('![modes.png](modes.png)', '')
    class_counts(report, 'high modes', sweep, np.ones(len(sweep), dtype=bool))


# --------------------------------------------------------------------------------------------
# 6. very coarse and very fine meshes
# --------------------------------------------------------------------------------------------

def mesh_section(report: Report, coarse: Optional[Sweep], fines: List[Sweep], largest) -> None:
    report.add('## 6. Very coarse and very fine meshes', '')
    if coarse is not None:
        c = coarse.cases
        m = coarse.where(dt_fraction=0.1)
        report.add('One element, k = 0.1, 50 periods (from the one-element map above): relative error '
                   + ', '.join(f'{c["scheme"][i].upper()} ppc {c["particles_per_element"][i]}: '
                               f'{g(c["relative_error"][i])} ({trip_text(c, i)})' for i in np.flatnonzero(m)) + '.', '')
    if fines:
        rows = []
        for sweep in fines:
            report.versions.update(sweep.code_versions)
            c = sweep.cases
            rows += [[c['elements'][i], c['particles'][i], c['scheme'][i].upper(), c['particles_per_element'][i],
                      c['steps'][i], trip_text(c, i), g(c['relative_error'][i]), g(c['max_error'][i])]
                     for i in range(len(sweep))]
            class_counts(report, f'fine {int(c["elements"][0])} el.', sweep, np.ones(len(sweep), dtype=bool))
        report.add(*markdown_table(['elements', 'particles', 'scheme', 'ppc', 'steps', 'status', 'relative error',
                                    'max error (m)'], rows))
        report.add('')
        for sweep in fines:
            c = sweep.cases
            periods = c['steps'][0] * c['dt'][0] / (4.0 * float(sweep.config['length']) /
                                                    math.sqrt(c['youngs_modulus'][0] / c['density'][0]))
            report.add(f'`{Path(sweep.path).name}`: sweep wall time '
                       f'{g(sweep.sweep[0].get("wall_time"))} s on {sweep.sweep[0].get("threads")} threads; '
                       f'{c["steps"][0]} steps are {periods:.2g} periods, so the error (relative to the '
                       'full amplitude) stays tiny: these runs test that large problems run and stay '
                       'finite, not accuracy.', '')
    if largest is not None:
        s = largest.summary
        report.versions.add(largest.code_version)
        report.add(f'**Largest single run**: {largest.elements} elements x {largest.particles_per_element} '
                   f'ppc = {int(s["particles"])} particles, {int(s["steps"])} steps ({largest.scheme.upper()}, '
                   f'k = {largest.dt_fraction:g}), status {s["status_name"]}, run time {s["run_time"]:.3f} s '
                   f'(set-up and time loop), i.e. {1e9 * s["run_time"] / (s["particles"] * s["steps"]):.2f} '
                   f'ns per particle-step; relative error {s["relative_error"]:.3g}.', '')
        report.check('largest run', 'completes with finite error', int(s['status']) == 0 and
                     math.isfinite(s['max_error']), s['status_name'])


# --------------------------------------------------------------------------------------------
# main
# --------------------------------------------------------------------------------------------

def parse_args(argv):
    p = argparse.ArgumentParser(prog=PROGRAM, description='Figures and summary.md of the mpm1d '
                                'stability study from the files of studies/stability/run.sh.')
    p.add_argument('input', help='folder with the study\'s HDF5 files')
    p.add_argument('-o', '--output', required=True, help='output folder (created if needed)')
    p.add_argument('--predicted', required=True, help='predicted_critical.csv of linear_stability.py')
    p.add_argument('--timings', help='timings.txt of run.sh (label seconds per line)')
    return p.parse_args(argv)


def _main(argv=None) -> int:
    args = parse_args(argv)
    Path(args.output).mkdir(parents=True, exist_ok=True)
    report = Report(args.output)
    path = lambda name: str(Path(args.input) / name)  # noqa: E731
    try:
        predicted = read_predicted(args.predicted)
        sections = []
        measured = {}
        if Path(path('map.h5')).exists():
            sweep = load(path('map.h5'))
            ne = int(sweep.cases['elements'][0])
            measured = stability_section(report, sweep, predicted, ne,
                                         f'1. Time-step stability map ({ne} elements)', 'map',
                                         'stability_map.png', energy_guard=False)
        else:
            report.add('## 1. Time-step stability map', '', 'skipped: map.h5 not found', '')
        coarse = None
        if Path(path('coarse.h5')).exists():
            coarse = load(path('coarse.h5'))
            stability_section(report, coarse, predicted, 1, '1b. Time-step stability on one element',
                              'map 1 el.', 'stability_map_1element.png', energy_guard=True)
        scale_files = sorted(str(p) for p in Path(args.input).glob('scale_*.h5'))
        if scale_files:
            scale_section(report, load_many(scale_files))
        else:
            report.add('## 2. Stiffness and scale', '', 'skipped: no scale_*.h5', '')
        if Path(path('large.h5')).exists():
            large_section(report, load(path('large.h5')))
        longs = [load(path(n)) for n in ('long100.h5', 'long1000.h5') if Path(path(n)).exists()]
        if longs:
            long_section(report, longs)
        if Path(path('modes.h5')).exists():
            modes_section(report, load(path('modes.h5')))
        fines = [load(str(p)) for p in sorted(Path(args.input).glob('fine_e*.h5'),
                                              key=lambda p: int(re.sub(r'\D', '', p.name) or 0))]
        largest = load_run(path('largest.h5')) if Path(path('largest.h5')).exists() else None
        mesh_section(report, coarse, fines, largest)
    except OutputError:
        raise
    except (Mpm1dFileError, OSError, KeyError) as exc:
        print(f'{PROGRAM}: {exc}', file=sys.stderr)
        return 2

    failed = [c for c in report.checks if not c[2]]
    head = ['# mpm1d numerical stability study', '',
            f'Code version: {", ".join(sorted(report.versions))}; written '
            f'{datetime.datetime.now().isoformat(timespec="seconds")} by {PROGRAM} (mpm1d_post.studies.stability) from '
            f'`{Path(args.input).resolve()}`.', '']
    if measured:
        ppcs = sorted({p for _, p in measured})
        head += ['## Measured against predicted critical time-step fraction (20 elements)', '']
        head += markdown_table(['ppc'] + [f'{s.upper()} {what}' for s in SCHEMES for what in ('measured', 'predicted')],
                               [[p] + [cell for s in SCHEMES for cell in (f'{measured.get((s, p), float("nan")):g}',
                                                                          f'{predicted.get((s, p, 20), float("nan")):.4f}')]
                                for p in ppcs])
        head.append('')
    head += ['## Overview of the case classes', '']
    head += markdown_table(['class', 'cases', 'completed', 'tripped (guard: count)', 'non-finite outputs',
                            'expected stable but tripped', 'expected unstable but completed', 'garbled messages'],
                           report.classes)
    head += ['', f'## Checks: {len(report.checks) - len(failed)} passed, {len(failed)} failed', '']
    head += [f'- {"PASS" if ok else "**FAIL**"} [{k}] {what}' + (f' ({detail})' if detail else '')
             for k, what, ok, detail in report.checks]
    head.append('')
    garbled = sum(int(r[7]) for r in report.classes)
    if garbled:
        head += [f'Note: {garbled} guard messages in /cases/message do not have the documented form '
                 '("guard NAME tripped at step S of N (t = T s, ...)"): characters are lost or '
                 'duplicated when cases trip on several OpenMP threads at once (the same sweep on '
                 'threads=1 gives none). status/status_name are intact; for those cases the step '
                 'is taken from what can be parsed, the time as step x dt.', '']
    if args.timings and Path(args.timings).exists():
        rows = [line.split() for line in open(args.timings) if line.strip()]
        head += ['## Run time of each step of run.sh (s)', '']
        head += markdown_table(['step', 'wall time (s)'], [r for r in rows if len(r) == 2])
        head.append('')
    with replacing(Path(args.output) / 'summary.md', 'w') as fh:
        fh.write('\n'.join(head + report.lines) + '\n')
    print(f'{PROGRAM}: wrote summary.md and {len(report.figures)} figures ({", ".join(report.figures)}) '
          f'to {args.output}; checks: {len(report.checks) - len(failed)} passed, {len(failed)} failed')
    return 0


def main(argv: Optional[Sequence[str]] = None) -> int:
    """Command-line entry point; returns the exit status (3: a file could not be written)."""
    return with_output_errors(PROGRAM, _main, argv)


if __name__ == '__main__':
    sys.exit(main())
