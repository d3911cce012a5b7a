"""Figures of one mpm1d run: its centre-of-mass motion against the exact solution with the error over
time, its energies, and its snapshots' particle fields against the scene's exact profiles.

    mpm1d-plot-run RUN.h5 [-o OUTDIR] [--snapshots N]

Writes into OUTDIR (default: plots): `ucm.png` (u_cm and the exact u_cm against time; below,
|u_cm - u_cm,exact|), `energies.png` (kinetic, stored, plastic work where a body is elastoplastic,
and their sum) when the file has a history (``&output history``), and `snapshots.png` (one row per
snapshot, at most N of them evenly chosen (default 6): displacement, velocity and stress of every
particle at its position, the scene's exact profile drawn where the file has it) when it has
snapshots (``&output snapshot_times`` or ``snapshot_every``). Each figure's title names the scene,
scheme, shape, transfer, law, integrator and mesh from the file's ``/config``, and what the run
measured (its error measure and value from ``/summary``); its footer the code version and file. A run
a guard stopped has no result: its figures say so and draw the state up to the stop in grey. A
quasi-static run's "time" is the load factor. Exit status 0 written, 2 bad input, 3 a file could not
be written (a full disk: the message names it; an older file of that name is left as it was).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Dict, List, Optional, Sequence, Tuple

import numpy as np

from . import figures
from .figures import FigureSkipped
import matplotlib.pyplot as plt  # (after figures, which selects the Agg backend)
from .loader import Mpm1dFileError, Run, Snapshot, load_run
from .output_files import with_output_errors

PROGRAM = 'mpm1d-plot-run'
#: The particle fields drawn, with their axis labels and the exact field's dataset.
FIELDS = {'displacement': ('displacement u = x − X (m)', 'exact_displacement'),
          'velocity': ('velocity v (m/s)', 'exact_velocity'),
          'stress': ('stress σ (Pa)', 'exact_stress')}
#: Colours of the particles, per body where the scene has several (the impact's two bars).
BODY_COLOURS = ('C0', 'C1', 'C2', 'C3')
STOPPED_COLOUR = '0.55'


def quasi_static(run: Run) -> bool:
    """Whether the run's "time" is the load factor (integrator quasi_static)."""
    return str(run.config.get('integrator', 'explicit')) == 'quasi_static'


def time_label(run: Run) -> str:
    return 'load factor (the fraction of the load, 0 to 1)' if quasi_static(run) else 'time t (s)'


def moment_text(run: Run, snapshot: Snapshot) -> str:
    """'t = 1.23e-04 s (step 40 of 400)', or the load factor of a quasi-static run."""
    steps = int(run.summary.get('steps', 0))
    if quasi_static(run):
        return f'load factor {snapshot.time:.3g} (step {snapshot.step} of {steps})'
    return f't = {snapshot.time:.4g} s (step {snapshot.step} of {steps})'


def run_title(run: Run) -> str:
    """What ran: 'vibrating bar — USL, linear shape, FLIP, law hencky — 20 elements × 1 particle,
    dt = 0.1 dx/c (400 steps)' (with the integrator when not explicit)."""
    c = run.config
    kind = str(c.get('scene_kind', 'vibrating_bar')).replace('_', ' ')
    transfer = str(c.get('transfer', 'flip'))
    transfer_text = transfer.upper() if transfer != 'blend' else f"blend (FLIP share {c.get('flip_fraction', 0):g})"
    integrator = str(c.get('integrator', 'explicit'))
    method = f"{run.scheme.upper()}" if integrator == 'explicit' else f"{integrator.replace('_', '-')} integrator"
    ppe = run.particles_per_element
    step = (f"{int(c.get('load_steps', run.summary.get('steps', 0)))} load steps" if integrator == 'quasi_static'
            else f"dt = {run.dt_fraction:g} dx/c ({int(run.summary.get('steps', 0))} steps)")
    return (f"{kind} — {method}, {c.get('shape', 'linear')} shape, {transfer_text}, law {c.get('law', 'hencky')} — "
            f"{run.elements} elements × {ppe} particle{'s' if ppe != 1 else ''}, {step}")


def result_text(run: Run) -> str:
    """The run's result as /summary gives it, or why there is none."""
    measure = str(run.summary.get('error_measure', '|u_cm - u_cm,exact| (m)'))
    name, unit = (measure[:measure.rindex(' (')], measure[measure.rindex(' (') + 2:-1]) if measure.endswith(')') \
        else (measure, '')
    if run.ok:
        return (f"error: {name}, its largest value = {float(run.summary['max_error']):.4g} {unit} "
                f"({100 * float(run.summary['relative_error']):.3g} % of the scene's amplitude)")
    return (f"stopped by the {run.summary['status_name']} guard at step {int(run.summary.get('trip_step', 0))} "
            f"(t = {float(run.summary.get('trip_time', 0)):.4g} s): no result; drawn up to the stop in grey")


def _title(fig: plt.Figure, run: Run, what: str) -> None:
    figures.fitted_title(fig, f'{what}\n{run_title(run)}\n{result_text(run)}', fontsize=9)


def ucm_figure(run: Run, outdir: Path) -> Path:
    """u_cm and u_cm,exact against time; below, |u_cm − u_cm,exact|."""
    if run.history is None:
        raise FigureSkipped(f'{run.path} has no history (run with &output history=.true.): no u_cm figure')
    h = run.history
    colour = 'C0' if run.ok else STOPPED_COLOUR
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(8, 6.4), sharex=True)
    top.plot(h['time'], h['ucm_exact'], color='k', lw=1.2, label='exact')
    top.plot(h['time'], h['ucm'], color=colour, lw=1.0, ls='--' if not run.ok else '-',
             label='mpm1d' + ('' if run.ok else ' (up to the stop: no result)'))
    top.set_ylabel('centre-of-mass displacement u_cm (m)')
    top.legend(fontsize=8)
    error = np.abs(np.asarray(h['ucm']) - np.asarray(h['ucm_exact']))
    shown = error > 0
    if shown.any():
        bottom.semilogy(np.asarray(h['time'])[shown], error[shown], color=colour, lw=1.0)
    else:
        bottom.text(0.5, 0.5, 'u_cm equals the exact u_cm at every step', transform=bottom.transAxes,
                    ha='center', va='center')
    bottom.set_ylabel('|u_cm − u_cm,exact| (m)')
    bottom.set_xlabel(time_label(run))
    for ax in (top, bottom):
        ax.grid(True, alpha=0.3)
    _title(fig, run, 'Centre-of-mass displacement against the exact solution')
    fig.tight_layout(rect=(0, 0.02, 1, 1))
    return Path(figures.save_figure(fig, str(outdir), 'ucm.png', [run]))


def energies_figure(run: Run, outdir: Path) -> Path:
    """Kinetic, stored and plastic energy against time, and their sum."""
    if run.history is None:
        raise FigureSkipped(f'{run.path} has no history (run with &output history=.true.): no energy figure')
    h = run.history
    fig, ax = plt.subplots(figsize=(8, 4.8))
    parts = [('kinetic_energy', 'kinetic'), ('strain_energy', 'stored (the law\'s strain energy)'),
             ('plastic_work', 'plastic work')]
    total = np.zeros_like(np.asarray(h['time'], float))
    for name, label in parts:
        if name in h:
            ax.plot(h['time'], h[name], lw=1.0, label=label)
            total = total + np.asarray(h[name], float)
    ax.plot(h['time'], total, color='k', lw=1.3, label='sum')
    if not run.ok:
        ax.axvline(float(run.summary.get('trip_time', 0)), color='r', lw=0.8, ls=':', label='guard stop')
    ax.set_xlabel(time_label(run))
    ax.set_ylabel('energy per unit cross-section (J/m²)')
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    _title(fig, run, 'Energies (forces that do work, a drive or gravity, change the sum)')
    fig.tight_layout(rect=(0, 0.02, 1, 1))
    return Path(figures.save_figure(fig, str(outdir), 'energies.png', [run]))


def field_values(snapshot: Snapshot, field: str) -> Tuple[np.ndarray, np.ndarray, Optional[Tuple[np.ndarray, np.ndarray]]]:
    """A snapshot's particle positions x, the particles' values of `field` and the exact profile
    (positions X + u_exact(X) in order, values) where the file has it (else None)."""
    reference = snapshot.extra.get('reference_x')
    if field == 'displacement':
        if reference is None:
            raise FigureSkipped('the snapshots lack reference_x: no displacement')
        values = snapshot.x - np.asarray(reference, float)
    else:
        values = getattr(snapshot, field)
    exact = None
    name = FIELDS[field][1]
    if name in snapshot.extra and reference is not None:
        where = np.asarray(reference, float)
        if 'exact_displacement' in snapshot.extra:
            where = where + np.asarray(snapshot.extra['exact_displacement'], float)
        order = np.argsort(where, kind='stable')
        exact = (where[order], np.asarray(snapshot.extra[name], float)[order])
    return snapshot.x, np.asarray(values, float), exact


def chosen_snapshots(snapshots: Sequence[Snapshot], most: int) -> List[int]:
    """Indices of at most `most` snapshots, evenly spread, the first and the last among them."""
    if len(snapshots) <= most:
        return list(range(len(snapshots)))
    return sorted(set(int(round(i)) for i in np.linspace(0, len(snapshots) - 1, most)))


def draw_field(ax: plt.Axes, run: Run, snapshot: Snapshot, field: str, legend: bool = False) -> None:
    """One snapshot's `field`: the particles (per body) and the exact profile."""
    x, values, exact = field_values(snapshot, field)
    body = snapshot.extra.get('body')
    colour = STOPPED_COLOUR if not run.ok else None
    if body is not None and np.unique(body).size > 1:
        for k, b in enumerate(np.unique(body)):
            mine = np.asarray(body) == b
            ax.plot(x[mine], values[mine], '.', ms=3, color=colour or BODY_COLOURS[k % len(BODY_COLOURS)],
                    label=f'particles of body {int(b)}')
    else:
        ax.plot(x, values, '.', ms=3, color=colour or 'C0', label='particles')
    if exact is not None:
        ax.plot(exact[0], exact[1], '-', color='k', lw=1.0, label='exact')
    if legend:
        ax.legend(fontsize=7, loc='best')


def snapshots_figure(run: Run, outdir: Path, most: int = 6) -> Path:
    """Rows of snapshots (at most `most`), columns displacement, velocity, stress against x."""
    if not run.snapshots:
        raise FigureSkipped(f'{run.path} has no snapshots (run with &output snapshot_times=... or '
                            'snapshot_every=N): no snapshot figure')
    chosen = chosen_snapshots(run.snapshots, most)
    fig, axes = plt.subplots(len(chosen), 3, figsize=(12, 1.9 * len(chosen) + 1.6), sharex=True, squeeze=False)
    for row, index in enumerate(chosen):
        snapshot = run.snapshots[index]
        for col, field in enumerate(FIELDS):
            ax = axes[row, col]
            draw_field(ax, run, snapshot, field, legend=(row == 0 and col == 0))
            ax.grid(True, alpha=0.3)
            if row == 0:
                ax.set_title(FIELDS[field][0], fontsize=9)
            if col == 0:
                ax.set_ylabel(moment_text(run, snapshot).replace(' (', '\n('), fontsize=8)
        for ax in axes[row]:
            ax.ticklabel_format(axis='y', style='sci', scilimits=(-3, 4))
    for ax in axes[-1]:
        ax.set_xlabel('particle position x (m)')
    shown = (f'{len(chosen)} of {len(run.snapshots)} snapshots' if len(chosen) < len(run.snapshots)
             else f'{len(run.snapshots)} snapshot{"s" if len(run.snapshots) != 1 else ""}')
    exact = any(name.startswith('exact_') for name in run.snapshots[0].extra)
    what = (f'Particle fields at {shown}, ' +
            ('the exact profile in black' if exact else 'no exact profile (the scene has none)'))
    _title(fig, run, what)
    fig.tight_layout(rect=(0, 0.02, 1, 1))
    return Path(figures.save_figure(fig, str(outdir), 'snapshots.png', [run]))


def build_parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog=PROGRAM, description=__doc__.split('\n\n')[0])
    p.add_argument('run', help='the HDF5 file of one run (mpm1d RUN.nml)')
    p.add_argument('-o', '--outdir', default='plots', help='output folder (default: plots)')
    p.add_argument('--snapshots', type=int, default=6, metavar='N',
                   help='most snapshots in snapshots.png, evenly chosen (default 6)')
    return p


def plot_run(run: Run, outdir: 'str | Path', most: int = 6) -> Tuple[List[Path], List[str]]:
    """Every figure of `run` into `outdir`: the paths written and why any was skipped."""
    outdir = Path(outdir)
    written, skipped = [], []
    for make in (lambda: ucm_figure(run, outdir), lambda: energies_figure(run, outdir),
                 lambda: snapshots_figure(run, outdir, most)):
        try:
            written.append(make())
        except FigureSkipped as exc:
            skipped.append(str(exc))
    return written, skipped


def _main(argv: Optional[Sequence[str]] = None) -> int:
    args = build_parser().parse_args(argv)
    outdir = Path(args.outdir)
    if args.snapshots < 1:
        print(f'{PROGRAM}: --snapshots {args.snapshots}; allowed: at least 1', file=sys.stderr)
        return 2
    try:
        run = load_run(args.run)
        problem = figures.output_folder_problem(outdir, args.outdir)  # (made once the file reads)
    except Mpm1dFileError as exc:
        problem = str(exc)
    if problem:
        print(f'{PROGRAM}: {problem}', file=sys.stderr)
        return 2
    written, skipped = plot_run(run, outdir, args.snapshots)
    for reason in skipped:
        print(f'{PROGRAM}: skipped: {reason}', file=sys.stderr)
    if not written:
        print(f'{PROGRAM}: nothing to draw in {args.run}', file=sys.stderr)
        return 2
    print(f'{PROGRAM}: wrote ' + ', '.join(p.name for p in written) + f' in {outdir}')
    return 0



def main(argv: Optional[Sequence[str]] = None) -> int:
    """Command-line entry point; returns the exit status (3: a file could not be written)."""
    return with_output_errors(PROGRAM, _main, argv)


if __name__ == '__main__':
    sys.exit(main())
