"""Figures of any mpm1d sweep: error against elements with the fitted order of each series, error
against run time with the Pareto front, and maps of the error over particles per element × time step.

    mpm1d-plot-sweep SWEEP.h5 [SHARD.h5 ...] -o OUTDIR [--at particles_per_element=4 ...]

Works for any set of schemes (USF, USL, MUSL), shapes, transfers and scenes. A *series* is the
cases that differ only in `elements`: one per combination of the other swept variables (scheme,
shape, transfer, particles per element, dt_fraction, ...); `--at name=value` keeps only the cases
with that value. Each series' order of convergence is the least-squares slope of log(error)
against log(elements), over its completed cases (the order p in error ∝ elements^-p); a series with
fewer than two meshes has no order. A case a guard stopped has no result: it is never drawn on an
error axis (its error before the stop is no result), never fitted, and kept off the Pareto front and
the maps' colour scale; the legends count the stopped cases, the maps mark them. Several files must be
the shards of one sweep (as `mpm1d merge` requires).

Writes into OUTDIR: `error_vs_elements.png`, `error_vs_time.png` (when the sweep has timings),
`error_map_<scheme>_<shape>_<transfer>.png` (one per group, one panel per element count), and
`orders.csv` (series, points, order, error at the finest mesh; empty where there is none). Exit status
0 written, 2 bad input (also: files of two different sweeps, -o naming an existing file).
"""

from __future__ import annotations

import argparse
import csv
import sys
from pathlib import Path
from typing import Dict, List, Optional, Sequence, Tuple

import numpy as np

from . import figures
from .figures import FigureSkipped
import matplotlib.pyplot as plt  # (after figures, which selects the Agg backend)
from .loader import Mpm1dFileError, Sweep, load_sweep, merge_sweeps
from .orders import fitted_order
from .output_files import replacing, with_output_errors
from .pareto import pareto_front

PROGRAM = 'mpm1d-plot-sweep'
#: Columns that name a group (one map figure each); the other swept columns only split series.
GROUP_COLUMNS = ('scheme', 'shape', 'transfer')
#: More series than this in one figure are unreadable: the legend says how to select (--at).
MAX_LEGEND_SERIES = 24
ERROR_LABEL = 'max_error (the scene\'s error measure, m)'


def varied_columns(sweep: Sweep) -> List[str]:
    """The swept columns that take more than one value in `sweep` (registry order), `elements` last
    excluded: they split the cases into series."""
    columns = sweep.parameter_columns or [c for c in ('scheme', 'elements', 'particles_per_element',
                                                      'dt_fraction') if c in sweep.cases]
    return [c for c in columns if c != 'elements' and c in sweep.cases
            and np.unique(sweep.cases[c]).size > 1]


def series_of(sweep: Sweep) -> Dict[Tuple, np.ndarray]:
    """{values of the varied columns: mask of its cases}, in order of first appearance. Scheme,
    shape and transfer always lead the key (constant ones too), so that labels name them."""
    keys = list(dict.fromkeys([c for c in GROUP_COLUMNS if c in sweep.cases] + varied_columns(sweep)))
    result: Dict[Tuple, np.ndarray] = {}
    rows = list(zip(*[sweep.cases[c].tolist() for c in keys])) if keys else [()] * len(sweep)
    for i, row in enumerate(rows):
        result.setdefault(tuple(zip(keys, row)), np.zeros(len(sweep), bool))[i] = True
    return result


def label_of(key: Tuple) -> str:
    """'USL, linear, flip, particles_per_element=4' for a series key."""
    parts = []
    for name, value in key:
        if name in GROUP_COLUMNS:
            parts.append(str(value).upper() if name == 'scheme' else str(value))
        else:
            parts.append(f'{name}={value:g}' if isinstance(value, float) else f'{name}={value}')
    return ', '.join(parts)


def scene_text(sweep: Sweep) -> str:
    """One line naming the scene and its own parameters with units (those the sweep does not vary)."""
    return figures.scene_text(sweep, swept=varied_columns(sweep))


def stopped_cases_text(sweep: Sweep) -> str:
    """'4 cases stopped by a guard (energy_growth 4; at 10, 20, 40, 80 elements): no result, not
    drawn' ('' when none stopped)."""
    stopped = sweep.stopped
    if not stopped.any():
        return ''
    names, counts = np.unique(sweep.cases['status_name'][stopped], return_counts=True)
    where = ', '.join(f'{e:g}' for e in np.unique(sweep.cases['elements'][stopped]))
    statuses = ', '.join(f'{n} {c}' for n, c in zip(names, counts))
    count = int(stopped.sum())
    return (f"{count} case{'s' if count != 1 else ''} stopped by a guard ({statuses}; at {where} elements): "
            'no result, not drawn')


def error_vs_elements(sweep: Sweep, outdir: Path) -> Tuple[Path, List[Dict]]:
    """Error against elements (log-log), one line per series with its fitted order. Returns the
    path and the rows of orders.csv."""
    rows, fig = [], plt.figure(figsize=(9.0, 6.2))
    ax = fig.add_subplot(1, 1, 1)
    groups = list(dict.fromkeys(tuple(kv for kv in key if kv[0] in GROUP_COLUMNS)
                                for key in series_of(sweep)))
    colours = {g: plt.get_cmap('tab10')(i % 10) for i, g in enumerate(groups)}
    markers = 'osD^v<>ph*'
    drawn = 0
    for number, (key, mask) in enumerate(series_of(sweep).items()):
        ok = mask & sweep.ok & (sweep.cases['max_error'] > 0)
        if not ok.any():
            rows.append({'series': label_of(key), 'points': 0, 'order': float('nan'),
                         'finest_elements': '', 'finest_error': float('nan')})
            continue
        order_by = np.argsort(sweep.cases['elements'][ok])
        x, y = sweep.cases['elements'][ok][order_by], sweep.cases['max_error'][ok][order_by]
        p = fitted_order(x, y)
        group = tuple(kv for kv in key if kv[0] in GROUP_COLUMNS)
        fitted = f': order {p:.2f}' if np.isfinite(p) else f' ({x.size} mesh: no order)' if x.size == 1 \
            else ': no order'
        ax.loglog(x, y, marker=markers[number % len(markers)], color=colours[group], linewidth=1.1,
                  markersize=4.5, label=f'{label_of(key)}{fitted}' if drawn < MAX_LEGEND_SERIES else None)
        drawn += 1
        rows.append({'series': label_of(key), 'points': int(x.size), 'order': p,
                     'finest_elements': int(x[-1]), 'finest_error': float(y[-1])})
    if drawn == 0:
        plt.close(fig)
        raise FigureSkipped('no completed case with a positive error')
    # a stopped case has no error: it is counted in the legend, never drawn on the error axis (its error
    # before the stop, often below every result, would read as one)
    stopped_label = stopped_cases_text(sweep)
    if stopped_label:
        ax.plot([], [], 'x', color='0.55', label=stopped_label)
    figures.plain_ticks(ax, sweep.cases['elements'][sweep.ok])
    ax.set_xlabel('elements')
    ax.set_ylabel(ERROR_LABEL)
    ax.grid(alpha=0.3, which='both')
    if drawn > MAX_LEGEND_SERIES:
        ax.plot([], [], ' ', label=f'(+{drawn - MAX_LEGEND_SERIES} series: select with --at name=value)')
    ax.legend(fontsize=6.5, loc='best', ncol=1 if drawn <= 12 else 2)
    figures.fitted_title(fig, 'Error against elements, order p of error ∝ elements^-p fitted per series\n'
                         + scene_text(sweep))
    fig.tight_layout(rect=(0, 0.03, 1, 1))
    return Path(figures.save_figure(fig, str(outdir), 'error_vs_elements.png', [sweep])), rows


def error_vs_time(sweep: Sweep, outdir: Path) -> Path:
    """Every completed, timed case as (run time, error), one colour per group, with the Pareto
    front (no other case both faster and more accurate)."""
    timed = sweep.ok & (sweep.cases['run_time'] > 0) & (sweep.cases['max_error'] > 0)
    if not timed.any():
        raise FigureSkipped('no timed cases (the sweep ran without its timing pass: min_time = 0)')
    untimed = int((~sweep.ok).sum())
    fig, ax = plt.subplots(figsize=(8.5, 5.8))
    groups: Dict[Tuple, np.ndarray] = {}
    for key, mask in series_of(sweep).items():
        group = tuple(kv for kv in key if kv[0] in GROUP_COLUMNS)
        groups[group] = groups.get(group, np.zeros(len(sweep), bool)) | mask
    for i, (group, mask) in enumerate(groups.items()):
        sel = mask & timed
        if sel.any():
            ax.scatter(sweep.cases['run_time'][sel], sweep.cases['max_error'][sel], s=14, alpha=0.75,
                       color=plt.get_cmap('tab10')(i % 10), edgecolors='none', label=label_of(group))
    times, errors = sweep.cases['run_time'][timed], sweep.cases['max_error'][timed]
    front = pareto_front(times, errors)
    ax.step(times[front], errors[front], where='post', color='black', linewidth=1.2,
            label='Pareto front (nothing both faster and more accurate)')
    if untimed:
        ax.plot([], [], 'x', color='0.55', label=f"{untimed} case{'s' if untimed != 1 else ''} stopped by a guard or "
                                                   "not run: no result, not shown")
    ax.set_xscale('log')
    ax.set_yscale('log')
    ax.set_xlabel(figures.TIME_LABEL)
    ax.set_ylabel(ERROR_LABEL)
    ax.grid(alpha=0.3, which='both')
    ax.legend(fontsize=7)
    figures.fitted_title(fig, 'Error against run time, every completed case\n' + scene_text(sweep))
    fig.tight_layout(rect=(0, 0.03, 1, 1))
    return Path(figures.save_figure(fig, str(outdir), 'error_vs_time.png', [sweep]))


def error_maps(sweep: Sweep, outdir: Path) -> List[Path]:
    """Per group (scheme, shape, transfer): the error over particles per element × time step, one
    panel per element count, on one log colour scale shared by every group."""
    paths = []
    groups: Dict[Tuple, np.ndarray] = {}
    for key, mask in series_of(sweep).items():
        group = tuple(kv for kv in key if kv[0] in GROUP_COLUMNS)
        groups[group] = groups.get(group, np.zeros(len(sweep), bool)) | mask
    norm = figures.shared_log_norm([sweep.cases['max_error'][sweep.ok & (sweep.cases['max_error'] > 0)]])
    if not (sweep.ok & (sweep.cases['max_error'] > 0)).any():
        raise FigureSkipped('no completed case with a positive error to map')
    for group, mask in groups.items():
        if all(np.unique(sweep.cases[c][mask]).size < 2 for c in ('particles_per_element', 'dt_fraction')
               if c in sweep.cases):
            continue  # one particle count and one step: a map would be one cell per panel
        counts = sorted(set(sweep.cases['elements'][mask].tolist()))
        rows, columns = figures._panel_layout(len(counts))
        fig, axes = plt.subplots(rows, columns, figsize=(4.0 * columns + 1.2, 3.5 * rows + 1.0),
                                 squeeze=False, constrained_layout=True)
        grids, mesh = [], None
        for ax, count in zip(axes.flat, counts):
            grid = figures.case_grid(sweep, mask & sweep.where(elements=count), 'max_error')
            grids.append(grid)
            mesh = figures.draw_colour_map(ax, grid, norm)
            ax.set_title(f'{count} element{"s" if count != 1 else ""}', fontsize=10)
            ax.set_xlabel(figures.PPE_LABEL)
            ax.set_ylabel(figures.DT_LABEL)
        for ax in list(axes.flat)[len(counts):]:
            ax.set_visible(False)
        fig.colorbar(mesh, ax=axes, label=ERROR_LABEL, shrink=0.9)
        figures._status_legend(fig, grids)
        figures.fitted_title(fig, f'{label_of(group)} — error over particles per element × time step\n'
                             + scene_text(sweep))
        fig.get_layout_engine().set(rect=(0, 0.025, 1, 0.975))
        name = 'error_map_' + '_'.join(str(v) for _, v in group) + '.png'
        paths.append(Path(figures.save_figure(fig, str(outdir), name, [sweep])))
    if not paths:
        raise FigureSkipped('maps need more than one particles_per_element or dt_fraction')
    return paths


def _parse_at(items: Sequence[str]) -> List[Tuple[str, str]]:
    selections = []
    for item in items:
        name, sep, value = item.partition('=')
        if not sep or not name or not value:
            raise argparse.ArgumentTypeError(f"--at expects name=value, got {item!r}")
        selections.append((name.strip(), value.strip()))
    return selections


def select(sweep: Sweep, selections: Sequence[Tuple[str, str]]) -> Sweep:
    """The cases matching every `name=value` (numbers compared as numbers, text case-insensitively)."""
    mask = np.ones(len(sweep), bool)
    for name, value in selections:
        if name not in sweep.cases:
            raise ValueError(f"--at {name}={value}: no column '{name}' (columns: "
                             f"{', '.join(sweep.parameter_columns or sorted(sweep.cases))})")
        column = sweep.cases[name]
        if column.dtype.kind in 'iuf':
            mask &= sweep.where(**{name: float(value)})
        else:  # the column's spellings of the text
            mask &= sweep.where(**{name: {v for v in column.tolist() if str(v).lower() == value.lower()}})
    if not mask.any():
        raise ValueError('no case matches ' + ' '.join(f'{n}={v}' for n, v in selections))
    return sweep.select(mask)


def build_parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog=PROGRAM, description=__doc__.split('\n\n')[0])
    p.add_argument('sweeps', nargs='+', help='sweep file(s): one sweep, or the shards of one')
    p.add_argument('-o', '--outdir', default='plots', help='output folder (default: plots)')
    p.add_argument('--at', nargs='*', default=[], metavar='NAME=VALUE',
                   help='keep only the cases with these values (e.g. particles_per_element=4 dt_fraction=0.25)')
    return p


def _main(argv: Optional[Sequence[str]] = None) -> int:
    args = build_parser().parse_args(argv)
    outdir = Path(args.outdir)
    if outdir.exists() and not outdir.is_dir():
        print(f"{PROGRAM}: -o {args.outdir}: is an existing file, not a folder; allowed: a folder (created "
              "when missing) for the figures", file=sys.stderr)
        return 2
    try:
        # every case: the stopped ones are drawn apart, never fitted
        sweep = merge_sweeps([load_sweep(path, cases='all') for path in args.sweeps])
        sweep = select(sweep, _parse_at(args.at))
    except Mpm1dFileError as exc:
        print(f'{PROGRAM}: {exc}', file=sys.stderr)
        return 2
    except (ValueError, argparse.ArgumentTypeError) as exc:
        print(f'{PROGRAM}: {exc}', file=sys.stderr)
        return 2
    problem = figures.output_folder_problem(outdir, args.outdir)
    if problem:
        print(f'{PROGRAM}: {problem}', file=sys.stderr)
        return 2
    written: List[Path] = []
    rows: List[Dict] = []
    for make in (lambda: error_vs_elements(sweep, outdir), lambda: error_vs_time(sweep, outdir),
                 lambda: error_maps(sweep, outdir)):
        try:
            result = make()
        except FigureSkipped as exc:
            print(f'{PROGRAM}: skipped: {exc}', file=sys.stderr)
            continue
        if isinstance(result, tuple):
            written.append(result[0])
            rows = result[1]
        elif isinstance(result, list):
            written += result
        else:
            written.append(result)
    with replacing(outdir / 'orders.csv', 'w', newline='') as handle:
        writer = csv.DictWriter(handle, ['series', 'points', 'order', 'finest_elements', 'finest_error'])
        writer.writeheader()
        for row in rows:
            # (no order, no error: an empty cell, not 'nan')
            writer.writerow({k: ((f'{v:.4g}' if np.isfinite(v) else '') if isinstance(v, float) else v)
                             for k, v in row.items()})
    written.append(outdir / 'orders.csv')
    for row in rows:
        if np.isfinite(row['order']):
            print(f"{row['series']}: order {row['order']:.2f} over {row['points']} meshes")
        else:
            print(f"{row['series']}: no order ({row['points']} mesh{'' if row['points'] == 1 else 'es'} "
                  "with a result; an order needs two)")
    print(f'{PROGRAM}: wrote ' + ', '.join(p.name for p in written) + f' in {outdir}')
    return 0


def main(argv: Optional[Sequence[str]] = None) -> int:
    """Command-line entry point; returns the exit status (3: a file could not be written)."""
    return with_output_errors(PROGRAM, _main, argv)


if __name__ == '__main__':
    sys.exit(main())
