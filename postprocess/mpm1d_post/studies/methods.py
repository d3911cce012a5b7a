"""The methods study (studies/methods/run.sh, whose analyze.py calls `main`): the cures of docs/theory.md
(total-Lagrangian MPM, CPDI, XPIC, FMPM, ASFLIP) against the updated-Lagrangian methods of before. Reads the
sweep and run files in the output folder and writes summary.md (every number in it is computed here from
those files) and the figures.  Usage: python studies/methods/analyze.py OUTPUT_FOLDER"""
from __future__ import annotations

import argparse
import math
import warnings
from pathlib import Path
from typing import Dict, List, Optional

import numpy as np

from .. import figures as pf
from ..loader import Sweep, concatenate_sweeps, load_run, load_sweep
from ..orders import successive_orders
from ..pareto import cheapest_reaching
from ..tables import markdown_table, number

#: The methods in the order of the tables: name, what it is.
METHODS = [('flip', 'hat, FLIP'), ('pic', 'hat, PIC'), ('apic', 'hat, APIC'), ('cpgimp', 'cpGIMP, FLIP'),
           ('bspline2', 'quadratic B-splines, FLIP'), ('total', 'total Lagrangian, hat, FLIP'),
           ('cpdi', 'CPDI, FLIP'), ('xpic2', 'hat, XPIC(2)'), ('fmpm2', 'hat, FMPM(2)'),
           ('asflip', 'hat, ASFLIP(0.99)')]
#: The cures among them (the others are the updated-Lagrangian methods of before).
CURES = ('total', 'cpdi', 'xpic2', 'fmpm2', 'asflip')
#: The scenes: file prefix, title, what the error measures.
SCENES = [('bar_linear', 'vibrating bar, linear law', 'u_cm over its amplitude'),
          ('bar_hencky', 'vibrating bar, Hencky law', 'u_cm over its amplitude'),
          ('wave', 'plastic wave', 'L1 stress error over the plastic stress times L'),
          ('manufactured', 'manufactured solution, A/L = 0.05', 'RMS displacement error over A')]
TARGETS = (1e-2, 1e-3, 1e-4)
NOISE = ['flip', 'pic', 'blend', 'xpic2', 'xpic4', 'xpic8', 'fmpm2', 'fmpm4', 'fmpm8', 'asflip']
#: A mesh series converges at second order where its last observed order is at least this.
SECOND_ORDER = 1.8


def read_sweep(path: Path) -> Optional[Sweep]:
    """Every case of a sweep file (stopped ones marked by their status), or None when it is not there."""
    if not path.is_file():
        return None
    with warnings.catch_warnings():
        warnings.simplefilter('ignore')
        return load_sweep(path, cases='all')


def series(out: Path, scene: str, method: str) -> Optional[Sweep]:
    """A scene's mesh series of one method: its timed sweep and the untimed finer ones, together."""
    parts = [read_sweep(out / f'{scene}_{method}{suffix}.h5') for suffix in ('', '_more', '_floor')]
    parts = [p for p in parts if p is not None]
    return concatenate_sweeps(parts) if parts else None


def mesh_rows(sweep: Sweep):
    """(elements, relative error or NaN where a guard stopped the case, completed, run time) coarse to fine."""
    index = sweep.rows('elements')
    c = sweep.cases
    return (c['elements'][index].astype(int), np.where(sweep.ok[index], c['relative_error'][index], np.nan),
            sweep.ok[index], c['run_time'][index], c['status_name'][index])


def convergence_section(out: Path, scene: str, title: str, measure: str, findings: Dict) -> List[str]:
    """A scene's table: each method's relative error per mesh and its successive orders."""
    data = {m: series(out, scene, m) for m, _ in METHODS}
    data = {m: s for m, s in data.items() if s is not None}
    if not data:
        return []
    meshes = sorted({int(e) for s in data.values() for e in s.cases['elements']})
    lines = [f'### {title}', '', f'Relative error ({measure}) by elements; `guard`: stopped by a guard (no result); '
             'the orders are those between successive meshes.', '']
    rows = []
    findings[scene] = {}
    for method, label in METHODS:
        if method not in data:
            continue
        elements, errors, ok, times, status = mesh_rows(data[method])
        cells = []
        for mesh in meshes:
            i = np.flatnonzero(elements == mesh)
            cells.append('' if i.size == 0 else (number(errors[i[0]], '.2e') if ok[i[0]] else 'guard'))
        orders = successive_orders(elements[ok], errors[ok]) if ok.sum() > 1 else np.array([])
        findings[scene][method] = dict(elements=elements, errors=errors, ok=ok, times=times, orders=orders)
        rows.append([f'{method} ({label})'] + cells + [', '.join(number(o, '.2f') for o in orders)])
    lines += markdown_table(['method'] + [str(m) for m in meshes] + ['orders'], rows)
    return lines + ['']


def verdicts(scene: str, findings: Dict) -> List[str]:
    """What the data say of each method on a scene: second order at the finest meshes, or not."""
    result = findings.get(scene, {})
    second, not_second = [], []
    for method, _ in METHODS:
        f = result.get(method)
        if f is None or f['orders'].size == 0:
            continue
        (second if f['orders'][-1] >= SECOND_ORDER else not_second).append(
            f"{method} ({number(f['orders'][-1], '.2f')} up to {f['elements'][f['ok']][-1]} elements)")
    lines = []
    if second:
        lines.append(f"Second order (last observed order >= {SECOND_ORDER}) to the finest mesh: " + ', '.join(second)
                     + '.')
    if not_second:
        lines.append('Not second order at the finest meshes: ' + ', '.join(not_second) + '.')
    return lines + [''] if lines else []


def answer_section(findings: Dict) -> List[str]:
    """Per scene and target, the cheapest timed run that reaches it (run time of the sweep's timing pass)."""
    lines = ['## The answer table', '', 'The cheapest timed run (one thread, median of the timing pass) whose relative '
             'error reaches each target, among every method and mesh of the scene; runs on meshes finer than the timed '
             'ones have no time and do not count.', '']
    rows = []
    for scene, title, _ in SCENES:
        times, errors, labels = [], [], []
        for method, _ in METHODS:
            f = findings.get(scene, {}).get(method)
            if f is None:
                continue
            for e, err, ok, t in zip(f['elements'], f['errors'], f['ok'], f['times']):
                if ok and math.isfinite(t):
                    times.append(t)
                    errors.append(err)
                    labels.append(f'{method}, {e} el')
        for target in TARGETS:
            i = cheapest_reaching(times, errors, target) if times else None
            rows.append([title, format(target, 'g')] + (['none of the timed runs', '', ''] if i is None else
                                                          [labels[i], f'{times[i]:.2e}', f'{errors[i]:.2e}']))
    lines += markdown_table(['scene', 'target', 'cheapest run', 'run time (s)', 'relative error'], rows)
    return lines + ['']


def noise_section(out: Path, noise: Dict) -> List[str]:
    """The bar at v0 = 0.01 c: each transfer's particle velocities at the end against the mode shape. In the linear
    law's exact solution v(X, T) = v0 cos(w T) sin(beta X); the least-squares fit a sin(beta X) of the particles'
    velocities splits them into the mode (a against the exact amplitude: the damping) and the rest (the RMS of the
    residual over v0: the velocity noise). Also the energy at the end over the initial energy, and the u_cm error."""
    rows = []
    for method in NOISE:
        path = out / f'noise_{method}.h5'
        if not path.is_file():
            continue
        run = load_run(str(path))
        s = run.summary
        status = str(s['status_name'])
        if status != 'ok' or not run.snapshots:
            rows.append([method, status, '', '', '', ''])
            continue
        c = run.config
        length, v0 = float(c['length']), float(c['velocity_amplitude'])
        wave_speed = math.sqrt(float(c['youngs_modulus']) / float(c['density']))
        beta = (2 * int(c['mode']) - 1) * math.pi / (2 * length)
        snap = run.snapshots[-1]
        mode = np.sin(beta * snap.extra['reference_x'])
        fitted = float(np.dot(mode, snap.velocity) / np.dot(mode, mode))
        exact = v0 * math.cos(beta * wave_speed * snap.time)
        residual = float(np.sqrt(np.mean((snap.velocity - fitted * mode) ** 2))) / abs(v0)
        ratio = float(s['final_energy']) / float(s['initial_energy'])
        amplitude = fitted / exact if abs(exact) > 0.1 * abs(v0) else math.nan  # (near a node of cos(w T): none)
        noise[method] = dict(noise=residual, mode=amplitude, energy=ratio, error=float(s['relative_error']))
        rows.append([method, 'ok', number(residual, '.2e'), number(amplitude, '.4f'), number(ratio, '.4f'),
                     number(float(s['relative_error']), '.2e')])
    if not rows:
        return []
    lines = ['## Noise against energy', '', "The bar of the linear law (exact at any amplitude) at v0 = 0.01 c, the "
             "particles crossing cells (MUSL, 2 particles per element, dt = 0.1 dx/c), at the end time: the particles' "
             "velocities fitted by the mode a sin(beta X) (least squares over the particles); velocity noise = the "
             "RMS of what the mode leaves over v0, mode amplitude = a over the exact v0 cos(w T) (below 1: damped), "
             "the energy at the end over the initial energy (kinetic + stored), and the u_cm error over its "
             "amplitude.", '']
    lines += markdown_table(['transfer', 'status', 'velocity noise', 'mode amplitude', 'energy ratio', 'u_cm error'],
                            rows)
    return lines + ['']


def error_figure(findings: Dict, outdir: Path, sources: List[Sweep], against: str, xlabel: str, title: str,
                 name: str) -> Optional[str]:
    """One panel per scene: each method's relative error of its completed runs against `against` ('elements',
    or 'times': the timed runs only); the cures solid with circles, the methods of before dotted."""
    panels = [(scene, label) for scene, label, _ in SCENES if findings.get(scene)]
    if not panels:
        return None
    fig, axes = pf.plt.subplots(1, len(panels), figsize=(4.2 * len(panels), 4.2), squeeze=False)
    for ax, (scene, label) in zip(axes[0], panels):
        for method, _ in METHODS:
            f = findings[scene].get(method)
            if f is None:
                continue
            shown = f['ok'] & np.isfinite(np.asarray(f[against], dtype=float))
            if shown.any():
                ax.loglog(f[against][shown], f['errors'][shown], marker='o' if method in CURES else '.',
                          linestyle='-' if method in CURES else ':', label=method)
        ax.set_title(label, fontsize=9)
        ax.set_xlabel(xlabel)
        ax.grid(True, which='both', alpha=0.3)
    axes[0][0].set_ylabel('relative error')
    axes[0][-1].legend(fontsize=7)
    pf.fitted_title(fig, title)
    return pf.save_figure(fig, str(outdir), name, sources)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument('out', help='the output folder of studies/methods/run.sh')
    parser.add_argument('--elapsed', type=float, default=math.nan, help='seconds the study took')
    parser.add_argument('--load', default='nan', help='the load average at its start')
    args = parser.parse_args(argv)
    out = Path(args.out)
    findings: Dict = {}
    noise: Dict = {}
    lines = ['# The cures side by side', '',
             'Made by `bash studies/methods/run.sh` (analysis: `mpm1d_post.studies.methods`) in '
             f'{number(args.elapsed, ".0f")} s at a load average of {args.load} at the start. The methods: '
             + '; '.join(f'`{m}` {label}' for m, label in METHODS) + ' (USL, 2 particles per element; the bars and '
             'the manufactured solution at dt = 0.1 dx/c, the plastic wave at its default).', '',
             '## Convergence', '']
    for scene, title, measure in SCENES:
        lines += convergence_section(out, scene, title, measure, findings)
        lines += verdicts(scene, findings)
    lines += answer_section(findings)
    lines += noise_section(out, noise)
    sources = [s for scene, _, _ in SCENES for m, _ in METHODS for s in [series(out, scene, m)] if s is not None]
    figures = [error_figure(findings, out, sources, 'elements', 'elements', 'The cures (solid, circles) against the '
                            'methods of before (dotted): error against elements, USL, 2 particles per element',
                            'methods_convergence.png'),
               error_figure(findings, out, sources, 'times', pf.TIME_LABEL, 'Accuracy against cost: relative error '
                            'against run time (one thread), the timed meshes', 'methods_error_vs_time.png')]
    lines += ['## Figures', ''] + [f'![{Path(f).stem}]({Path(f).name})' for f in figures if f] + ['']
    (out / 'summary.md').write_text('\n'.join(lines), encoding='utf-8')
    print(f'wrote {out / "summary.md"}')
    return 0
