#!/usr/bin/env python3
"""Make every figure of the mpm1d bar study and a summary of its key numbers.

    mpm1d-paper-figures --usf sweep_usf.h5 --usl sweep_usl.h5 \\
        --runs runs/*.h5 -o figures/

Sweeps: ``--usf`` / ``--usl`` take one sweep file each, or the shards of one sweep (merged).
Every case in a ``--usf`` file must be a USF case (likewise USL).
Single runs (``--runs``) are sorted by their ``/config`` attributes: those with a history and the
verification discretisation (20 elements, 1 particle per element, 10 % of the critical step, see
``--verification``) make fig. 3b; those with a snapshot at step 0 make fig. 10 (element counts
of ``--fig10-elements``, or all present when none of those is).

Writes fig3b, fig4-fig9 (per scheme), fig10, error_vs_time (PNG) and summary.md into the output
folder. A figure whose data is not given is skipped and the summary says why. Exit status: 0 on
success, 2 when an input file is missing or is not the expected kind of mpm1d file.
"""

from __future__ import annotations

import argparse
import datetime
from pathlib import Path
import sys

import numpy as np
from typing import Dict, List, Optional, Sequence

from .. import figures
from . import paper_claims as analysis
from ..figures import FigureSkipped
from ..loader import Mpm1dFileError, Run, Sweep, load_run, load_sweep, merge_sweeps
from ..output_files import write_text, with_output_errors
from ..tables import markdown_table

PROGRAM = 'mpm1d-paper-figures'


def parse_args(argv: Optional[Sequence[str]]) -> argparse.Namespace:
    """Command-line options."""
    parser = argparse.ArgumentParser(
        prog=PROGRAM, description='Figures 3b-10 of the MPM bar study, an error-versus-time '
        'plot with its Pareto front, and summary.md, from mpm1d HDF5 files.',
        epilog='Exit status 2 on a missing or wrong input file.')
    parser.add_argument('--usf', nargs='+', metavar='SWEEP.h5', default=[],
                        help='USF sweep file (several: the shards of one sweep)')
    parser.add_argument('--usl', nargs='+', metavar='SWEEP.h5', default=[],
                        help='USL sweep file (several: the shards of one sweep)')
    parser.add_argument('--runs', nargs='+', metavar='RUN.h5', default=[],
                        help='single-run files for fig. 3b and fig. 10 (recognised from their '
                             '/config attributes)')
    parser.add_argument('-o', '--output', required=True, metavar='OUTDIR',
                        help='output folder (created if needed)')
    parser.add_argument('--verification', nargs=3, metavar=('ELEMENTS', 'PPE', 'DT_FRACTION'),
                        default=['20', '1', '0.1'],
                        help='discretisation of the verification case (default: 20 1 0.1)')
    parser.add_argument('--time-elements', type=int, default=3, metavar='N',
                        help='element count of the computation-time figures 5, 6, 8, 9 '
                             '(default: 3)')
    parser.add_argument('--fig10-elements', type=int, nargs='+', default=[1, 3, 7, 10],
                        metavar='N', help='element counts shown in fig. 10 (default: 1 3 7 10)')
    args = parser.parse_args(argv)
    if not (args.usf or args.usl or args.runs):
        parser.error('give at least one of --usf, --usl, --runs')
    try:
        args.verification = (int(args.verification[0]), int(args.verification[1]),
                             float(args.verification[2]))
    except ValueError:
        parser.error('--verification takes ELEMENTS (int) PPE (int) DT_FRACTION (float)')
    return args


def load_scheme_sweep(paths: Sequence[str], scheme: str) -> Sweep:
    """Load and merge the sweep file(s) given for `scheme`, checking that they hold only it."""
    shards = []
    for path in paths:
        sweep = load_sweep(path, cases='all')  # the figures show the stopped cases apart
        others = sorted(set(sweep.schemes) - {scheme})
        if others:
            raise Mpm1dFileError(path, f"given with --{scheme} but holds cases of scheme(s) "
                                       f"{', '.join(repr(s) for s in others)}")
        shards.append(sweep)
    return merge_sweeps(shards)


class Report:
    """Collects what was made, what was skipped, and the numbers for summary.md."""

    def __init__(self):
        self.written: List[str] = []
        self.skipped: List[str] = []
        self.lines: List[str] = []

    def figure(self, name: str, make):
        """Call `make()`; record its path(s), or the reason it was skipped. Returns its result
        (None if skipped)."""
        try:
            result = make()
        except FigureSkipped as exc:
            self.skipped.append(f'{name}: {exc}')
            return None
        paths = result[0] if isinstance(result, tuple) else result
        paths = list(paths.values()) if isinstance(paths, dict) else [paths]
        self.written += paths
        return result

    def add(self, *lines: str) -> None:
        self.lines.extend(lines)


def _fmt_case(case: Dict) -> str:
    return (f"{case['elements']} el., {case['particles_per_element']} ppe, "
            f"{100 * case['dt_fraction']:g} %")


def _sweep_section(report: Report, sweeps: Dict[str, Sweep], verification) -> None:
    """Verification errors (sweeps), per-scheme error extremes and the sweeps' wall times."""
    rows = []
    for scheme, sweep in sweeps.items():
        for path, attrs, version in zip(sweep.paths, sweep.sweep, sweep.code_versions):
            def get(key, fmt='{}'):
                return fmt.format(attrs[key]) if key in attrs else '—'
            rows.append([scheme.upper(), Path(path).name, get('cases'), get('threads'), get('timing_threads'),
                         f"{get('shard')}/{get('shards')}", get('wall_time', '{:.4g}'),
                         get('error_pass_time', '{:.4g}'), get('timing_pass_time', '{:.4g}'), version])
    report.add('## Sweeps', '', *markdown_table(['scheme', 'file', 'cases', 'threads', 'timing threads', 'shard',
                                                  'wall time (s)', 'error pass (s)', 'timing pass (s)',
                                                  'code version'], rows))
    rows = []
    for scheme, sweep in sweeps.items():
        ext = analysis.error_extremes(sweep, scheme)
        failed = ', '.join(f'{n}: {k}' for n, k in ext['failed'].items()) or '0'
        low, high = ext.get('min'), ext.get('max')
        rows.append([scheme.upper(), ext['cases'], ext['completed'], failed]
                    + ([f"{low['max_error']:.3g}", _fmt_case(low), f"{high['max_error']:.3g}", _fmt_case(high)]
                       if low else ['—'] * 4))
    report.add('', '### Errors per scheme', '', *markdown_table(
        ['scheme', 'cases', 'completed', 'failed', 'min error (m)', 'at', 'max error (m)', 'at'], rows))
    elements, ppe, dt_fraction = verification
    report.add('', f'### Verification case in the sweeps ({elements} el., {ppe} ppe, '
               f'{100 * dt_fraction:g} %)', '')
    for scheme, sweep in sweeps.items():
        case = analysis.verification_case(sweep, scheme, elements, ppe, dt_fraction)
        if not case:
            report.add(f'- {scheme.upper()}: not in the sweep')
        elif case['status_name'] == 'ok':
            report.add(f"- {scheme.upper()}: max error {case['max_error']:.4g} m ({100 * case['relative_error']:.3g} % "
                       f"of the amplitude), status {case['status_name']}")
        else:
            report.add(f"- {scheme.upper()}: no result (status {case['status_name']})")
    report.add('')


def _runs_section(report: Report, verification_runs: List[Run], fig10_runs: List[Run],
                  unused: List[str], deviation: Optional[Dict[int, float]]) -> None:
    """Verification errors from the single-run files and the fig. 10 numbers."""
    report.add('## Single runs', '')
    if verification_runs:
        rows = [[Path(run.path).name, run.scheme.upper(),
                 f"{run.elements} el., {run.particles_per_element} ppe, {100 * run.dt_fraction:g} %"]
                + ([f"{run.summary['max_error']:.4g}", f"{100 * run.summary['relative_error']:.3g} %"] if run.ok
                   else ['— (no result)', '—'])
                + [run.summary['status_name'], run.code_version] for run in verification_runs]
        report.add('Verification case (fig. 3b):', '', *markdown_table(
            ['file', 'scheme', 'discretisation', 'max error (m)', 'relative error', 'status', 'code version'], rows))
        report.add('')
    if deviation:
        report.add('Initial velocity field (fig. 10), largest |v_grid − v0 sin(βx)| over the '
                   'bar, as a fraction of v0: ' + ', '.join(
                       f'{e} el. {100 * d:.1f} %' for e, d in sorted(deviation.items())), '')
    for line in unused:
        report.add(f'- not used: {line}')
    report.add('')


def _fits_section(report: Report, fits: Dict[str, Dict]) -> None:
    """The computation-time fits of figures 6 and 9."""
    if not fits:
        return
    rows = []
    for scheme, fit in fits.items():
        line, curve = fit['particles'], fit['time_step']
        n, k = np.asarray(line['x'], float), np.asarray(curve['x'], float)
        for formula, coefficients, r2, data, spread, fitted, times in (
                ('t = a·n + b (n particles per element)', f"a = {line['slope']:.4g} s, b = {line['intercept']:.4g} s",
                 line['r2'], f"{line['elements']} el., {100 * line['dt_fraction']:g} % of dx/c, {len(line['x'])} points",
                 line.get('spread'), line['slope'] * n + line['intercept'], line['time']),
                ('t = a/k + b (k time step in %)', f"a = {curve['a']:.4g} s·%, b = {curve['b']:.4g} s", curve['r2'],
                 f"{curve['elements']} el., {curve['particles_per_element']} ppe, {len(curve['x'])} points",
                 curve.get('spread'), curve['a'] / k + curve['b'], curve['time'])):
            noisy = figures.timing_noise(spread) or figures.timing_too_small(fitted, times, spread)
            rows.append([scheme.upper(), formula, coefficients, f'{r2:.4f}',
                         data + (f', median spread of the repeats {np.median(spread):.2g}' if spread else ''),
                         noisy or 'repeats steady (the verdict on linearity: Findings (e))'])
    report.add('## Computation-time fits (figures 6 and 9)', '',
               'A fit says something only where the timings are steady: each case was repeated until its '
               'min_time, and the spread of its repeats (interquartile range over median) is the bar in the '
               'figures.', '',
               *markdown_table(['scheme', 'fit', 'coefficients', 'R²', 'data', 'timings'], rows))
    report.add('')


def _pareto_section(report: Report, pareto: Optional[List[Dict]]) -> None:
    """The Pareto-optimal configurations of error against time."""
    if not pareto:
        return
    report.add('## Pareto-optimal configurations (error against time per run)', '',
               'No other case is both faster and more accurate. Fastest first.', '',
               *markdown_table(['scheme', 'elements', 'particles per element', 'time step (%)', 'time per run (s)',
                                'max error (m)'],
                               [[case['scheme'].upper(), case['elements'], case['particles_per_element'],
                                 f"{100 * case['dt_fraction']:g}", f"{case['run_time']:.4g}", f"{case['max_error']:.4g}"]
                                for case in pareto]))
    report.add('')


def _findings_section(report: Report, claims: List[analysis.Claim]) -> None:
    """The paper's claims, each with its verdict from the data and the numbers."""
    report.add('## Findings', '', "Each claim of the paper is checked against mpm1d's numbers "
               '(completed cases only); the verdict follows from the rule stated.', '')
    for claim in claims:
        report.add(f'### ({claim.key}) {claim.statement} — **{claim.verdict}**', '',
                   f'Rule: {claim.rule}.', '')
        report.add(*[f'- {d}' for d in claim.details] or ['- no data'])
        report.add('')


def make_all(args: argparse.Namespace) -> Report:
    """Load the inputs, make every figure whose data is present, and fill the report.
    Raises Mpm1dFileError on a bad input file."""
    sweeps: Dict[str, Sweep] = {}
    for scheme in ('usf', 'usl'):
        if getattr(args, scheme):
            sweeps[scheme] = load_scheme_sweep(getattr(args, scheme), scheme)
    runs = [load_run(path) for path in args.runs]

    elements, ppe, dt_fraction = args.verification
    order = {'usf': 0, 'usl': 1}
    verification_runs = sorted(
        (r for r in runs if r.history is not None and r.elements == elements
         and r.particles_per_element == ppe and abs(r.dt_fraction - dt_fraction) < 1e-9),
        key=lambda r: order.get(r.scheme, 9))
    initial = [r for r in runs if r.snapshot_at(0) is not None]
    fig10_elements = [e for e in args.fig10_elements if any(r.elements == e for r in initial)]
    fig10_runs = [r for r in initial if not fig10_elements or r.elements in fig10_elements]
    used = {id(r) for r in verification_runs + fig10_runs}
    unused = [f'{Path(r.path).name} ({r.label()}): not the verification case with a '
              'history, and no step-0 snapshot for a fig. 10 element count'
              for r in runs if id(r) not in used]

    report = Report()
    output = args.output
    if verification_runs:
        report.figure('fig3b', lambda: figures.fig3b(verification_runs, output))
    elif runs:
        report.skipped.append('fig3b: no run file with a history and the verification '
                              'discretisation')
    fig10 = report.figure('fig10', lambda: figures.fig10(
        fig10_runs, output, fig10_elements or None)) if runs else None
    if not runs:
        report.skipped.append('fig3b, fig10: no --runs given')

    fits: Dict[str, Dict] = {}
    pareto = None
    if sweeps:
        report.figure('fig4/fig7 error maps', lambda: figures.error_maps(sweeps, output))
        report.figure('fig5/fig8 time maps',
                      lambda: figures.time_maps(sweeps, output, args.time_elements))
        for scheme, sweep in sweeps.items():
            result = report.figure(f'time fits {scheme.upper()}', lambda: figures.time_fits(
                sweep, scheme, output, args.time_elements))
            if result:
                fits[scheme] = result[1]
        result = report.figure('error_vs_time', lambda: figures.error_vs_time(sweeps, output))
        pareto = result[1] if result else None
    else:
        report.skipped.append('fig4-fig9, error_vs_time: no sweep given (--usf/--usl)')

    report.add('# mpm1d bar study — summary', '',
               f"Generated {datetime.datetime.now().isoformat(timespec='seconds')} by "
               f'mpm1d-paper-figures (mpm1d_post.studies.paper).', '')
    if sweeps:
        _sweep_section(report, sweeps, args.verification)
    if runs:
        _runs_section(report, verification_runs, fig10_runs, unused,
                      fig10[1] if fig10 else None)
    _fits_section(report, fits)
    _pareto_section(report, pareto)
    if sweeps:
        _findings_section(report, analysis.check_claims(sweeps, fits))
    report.add('## Figures', '', *[f'- {Path(p).name}' for p in report.written], '')
    if report.skipped:
        report.add('Skipped:', '', *[f'- {s}' for s in report.skipped], '')
    return report


def _main(argv: Optional[Sequence[str]] = None) -> int:
    try:
        args = parse_args(argv)
    except SystemExit as exc:  # --help (0) or a usage error (2): report, do not exit
        return int(exc.code or 0)
    try:
        report = make_all(args)
    except Mpm1dFileError as exc:
        print(f'{PROGRAM}: {exc}', file=sys.stderr)
        return 2
    summary = Path(args.output) / 'summary.md'
    summary.parent.mkdir(parents=True, exist_ok=True)
    write_text(summary, '\n'.join(report.lines).rstrip() + '\n')
    for path in report.written + [summary]:
        print(path)
    for reason in report.skipped:
        print(f'{PROGRAM}: skipped {reason}', file=sys.stderr)
    return 0


def main(argv: Optional[Sequence[str]] = None) -> int:
    """Command-line entry point; returns the exit status (3: a file could not be written)."""
    return with_output_errors(PROGRAM, _main, argv)


if __name__ == '__main__':
    sys.exit(main())
