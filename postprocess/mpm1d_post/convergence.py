"""Spatial convergence of the bar to fine meshes: figure and summary from the sweep that
studies/convergence/run.sh writes (schemes x elements x velocity amplitudes).

For each scheme and amplitude: the u_cm error against elements, the local orders between successive
meshes, and the floor where the error stops falling. The exact solution is that of linear elasticity;
the code integrates sigma = E ln F with the particles really moving, so at finite amplitude the
discrete solution converges to a non-linear continuum solution that differs from the linear one by a
relative amount of the order of the strain amplitude v0/c. The floor is reported relative to the exact
u_cm amplitude next to v0/c.

Usage: mpm1d-convergence-figures SWEEP.h5 OUTDIR [--wall-time SECONDS]
"""
from __future__ import annotations

import argparse
from pathlib import Path
from typing import List, Optional

import numpy as np
import matplotlib

matplotlib.use('Agg')
import matplotlib.pyplot as plt  # noqa: E402

from .figures import plain_ticks  # noqa: E402
from .loader import load_sweep  # noqa: E402


def local_orders(elements: np.ndarray, errors: np.ndarray) -> np.ndarray:
    """Observed order between successive meshes: log(e_i / e_{i+1}) / log(n_{i+1} / n_i)."""
    return np.log(errors[:-1] / errors[1:]) / np.log(elements[1:] / elements[:-1])


#: Below this local order the error is taken as no longer falling (a floor).
FLOOR_ORDER = 0.5


def floor_start(orders: np.ndarray) -> Optional[int]:
    """Index of the first mesh pair after which the order stays below FLOOR_ORDER (the error no longer
    falls), or None when it keeps falling."""
    for i in range(len(orders)):
        if np.all(orders[i:] < FLOOR_ORDER):
            return i
    return None


def main(argv: Optional[List[str]] = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument('sweep')
    ap.add_argument('outdir')
    ap.add_argument('--wall-time', type=float, default=float('nan'))
    args = ap.parse_args(argv)
    sweep = load_sweep(args.sweep, cases='all')  # stopped cases are drawn apart, never fitted
    c = sweep.cases
    wave = np.sqrt(c['youngs_modulus'] / c['density'])
    ratio = c['velocity_amplitude'] / wave
    amplitudes = sorted(set(c['velocity_amplitude'].tolist()), reverse=True)
    lines = ['# Spatial convergence of the vibrating bar to fine meshes', '',
             f'Sweep `{Path(args.sweep).name}`: {len(sweep)} cases, '
             f'{int(c["particles_per_element"][0])} particles per element, dt = '
             f'{c["dt_fraction"][0]:g} dx/c, half a period; code version {", ".join(sweep.code_versions)}; '
             f'wall time {args.wall_time:.1f} s.', '',
             'u_cm error = max over steps of |u_cm - u_cm,exact| (m), relative to the exact amplitude; order = '
             'local observed order between successive meshes.', '',
             '| scheme | v0 (m/s) | v0/c | elements | relative error | order | status |', '|---|---|---|---|---|---|---|']
    fig, axes = plt.subplots(1, len(sweep.schemes), figsize=(5.5 * len(sweep.schemes), 4.3), sharey=True)
    axes = np.atleast_1d(axes)
    findings = []
    stopped_drawn = False
    for ax, scheme in zip(axes, sweep.schemes):
        for colour, v0 in zip(('C0', 'C1', 'C2', 'C3'), amplitudes):
            m = (c['scheme'] == scheme) & np.isclose(c['velocity_amplitude'], v0)
            every = np.flatnonzero(m)[np.argsort(c['elements'][m])]
            stopped = every[c['status'][every] != 0]
            for i in stopped:
                lines.append(f'| {scheme} | {v0:g} | {ratio[i]:.1e} | {int(c["elements"][i])} | no result (before '
                             f'the stop {c["relative_error_before_stop"][i]:.3e}) | | {c["status_name"][i]} |')
            # orders and floors from the completed cases only (a stopped case has no result)
            idx = every[c['status'][every] == 0]
            ne = c['elements'][idx].astype(float)
            rel = c['relative_error'][idx]
            if idx.size == 0:
                findings.append(f'- {scheme.upper()}, v0 = {v0:g} m/s: no case completed.')
                continue
            orders = local_orders(ne, rel)
            for k, i in enumerate(idx):
                order = f'{orders[k - 1]:.2f}' if k > 0 else ''
                lines.append(f'| {scheme} | {v0:g} | {ratio[i]:.1e} | {int(ne[k])} | {rel[k]:.3e} | {order} | '
                             f'{c["status_name"][i]} |')
            ax.loglog(ne, rel, 'o-', color=colour, label=f'v0 = {v0:g} m/s (v0/c = {v0 / wave[idx[0]]:.1e})')
            if stopped.size:
                ax.loglog(c['elements'][stopped], c['relative_error_before_stop'][stopped], 'x', color='0.55', ms=8,
                          label=None if stopped_drawn else 'stopped by a guard: error before the stop, no result')
                stopped_drawn = True
            if orders.size == 0:
                findings.append(f'- {scheme.upper()}, v0/c = {v0 / wave[idx[0]]:.1e}: one completed mesh, no order.')
                continue
            start = floor_start(orders)
            if start is None:
                findings.append(f'- {scheme.upper()}, v0/c = {v0 / wave[idx[0]]:.1e}: the error keeps falling to '
                                f'{int(ne[-1])} elements (last order {orders[-1]:.2f}, mean order '
                                f'{np.mean(orders):.2f}).')
            else:
                findings.append(f'- {scheme.upper()}, v0/c = {v0 / wave[idx[0]]:.1e}: order {np.mean(orders[:max(start, 1)]):.2f} '
                                f'up to {int(ne[start])} elements, then a floor at relative error '
                                f'{rel[start:].min():.2e} ({rel[start:].min() / (v0 / wave[idx[0]]):.2g} x v0/c).')
        if idx.size > 1:
            ref = np.array([ne[0], ne[-1]])
            ax.loglog(ref, rel[0] * 0.5 * (ref / ref[0]) ** -2.0, 'k:', lw=1, label='order 2')
        ax.set(xlabel='elements', title=f'{scheme.upper()}, {int(c["particles_per_element"][0])} ppc, '
               f'dt = {c["dt_fraction"][0]:g} dx/c, 0.5 period')
        ax.grid(alpha=0.3, which='both')
        plain_ticks(ax, c['elements'][c['scheme'] == scheme])
    axes[0].set_ylabel('relative u_cm error (-)')
    axes[0].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(Path(args.outdir) / 'convergence.png', dpi=120)
    lines += ['', '## Findings', '', *findings, '',
              f'A floor is where every later local order is below {FLOOR_ORDER}. '
              'Where the error stops falling, the floor grows with the amplitude: it is the difference '
              'between the code\'s continuum law (sigma = E ln F, particles moving with the material) and '
              'the linear elasticity of the exact solution, of relative order v0/c, not a discretisation '
              'error. A convergence study of the method itself needs an exact solution of the code\'s own '
              'law (the manufactured-solution scene). An error that is the same at every amplitude and falls at '
              'a steady order is the method\'s own discretisation error.', '', '![convergence.png](convergence.png)', '']
    with open(Path(args.outdir) / 'summary.md', 'w') as f:
        f.write('\n'.join(lines))
    print(f'wrote {Path(args.outdir) / "summary.md"} and convergence.png')
    return 0


if __name__ == '__main__':
    raise SystemExit(main())
