"""Spatial convergence of the bar to fine meshes with both elastic laws: figures and summary from the
sweeps that studies/convergence/run.sh writes (schemes x shapes x laws x elements x amplitudes).

The exact solution is that of linear elasticity. With ``law = 'linear'`` (sigma = E (J - 1)) it is exact
at any amplitude, so the error that remains is the method's; with ``law = 'hencky'`` (sigma = E ln F)
it also contains the model difference between the two continua, of relative order v0/c. For each
scheme, shape, law and amplitude: the u_cm error against elements, the local orders, and the floor
where the error stops falling (relative to the exact u_cm amplitude, and in units of v0/c). From the
histories of one mesh (``--parts``) the error of Hencky with linear shapes is split into the model
difference (hencky - linear law, with uGIMP) and the linear shapes' method error (linear shapes - uGIMP,
with the linear law); the parts add up.

Usage: mpm1d-convergence-figures SWEEP.h5 [SWEEP.h5 ...] [--parts PARTS.h5] --outdir OUTDIR [--wall-time S]
(older form: SWEEP.h5 OUTDIR)
"""
from __future__ import annotations

import argparse
import dataclasses
from pathlib import Path
from typing import Dict, List, Optional, Tuple

import numpy as np
import matplotlib

matplotlib.use('Agg')
import matplotlib.pyplot as plt  # noqa: E402

from ..figures import plain_ticks  # noqa: E402
from ..loader import Sweep, concatenate_sweeps, load_sweep  # noqa: E402
from ..orders import successive_orders  # noqa: E402
from ..output_files import replacing, save_figure_file, with_output_errors  # noqa: E402
from ..tables import markdown_table  # noqa: E402

PROGRAM = 'mpm1d-convergence-figures'

#: The independent reference of issue 26 (sigma = E (J - 1) and Hencky, USL, linear shapes, 2 ppc,
#: v0 = 0.1 m/s): relative u_cm errors at 800, 1600 and 3200 elements.
REFERENCE = {'linear': {800: 1.44e-5, 1600: 1.56e-5, 3200: 1.59e-5},
             'hencky': {800: 6.5e-6, 1600: 4.6e-6, 3200: 4.8e-6}}

SHAPES = ('linear', 'ugimp', 'cpgimp', 'bspline2', 'bspline3')


#: Below this local order the error is taken as no longer falling (a floor).
FLOOR_ORDER = 0.5


def floor_start(orders: np.ndarray) -> Optional[int]:
    """Index of the first mesh pair after which the order stays below FLOOR_ORDER (the error no longer
    falls), or None when it keeps falling."""
    for i in range(len(orders)):
        if np.all(orders[i:] < FLOOR_ORDER):
            return i
    return None


#: Columns that files written before them lack, and the value every case had then.
DEFAULT_COLUMNS = {'shape': 'linear', 'law': 'hencky'}


def with_defaults(sweep: Sweep) -> Sweep:
    """`sweep` with the columns of DEFAULT_COLUMNS that its file lacks (a new Sweep; the same if none)."""
    missing = {name: np.full(len(sweep), value) for name, value in DEFAULT_COLUMNS.items() if name not in sweep.cases}
    return dataclasses.replace(sweep, cases={**sweep.cases, **missing}) if missing else sweep


def series(sweep: Sweep, scheme: str, shape: str, law: str, v0: float
           ) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Elements, relative errors and case indices of one series, by elements."""
    sweep = with_defaults(sweep)
    idx = sweep.rows('elements', scheme=scheme, shape=shape, law=law, velocity_amplitude=v0)
    return sweep.cases['elements'][idx].astype(float), sweep.cases['relative_error'][idx], idx


def describe(ne: np.ndarray, rel: np.ndarray, ratio: float) -> Tuple[str, Optional[float]]:
    """What a series does: keeps falling (order of the last pair), or a floor (value, in v0/c)."""
    if len(ne) < 2:
        return 'one mesh', None
    orders = successive_orders(ne, rel)
    start = floor_start(orders)
    if start is None:
        return f'keeps falling (order {np.mean(orders):.2f}; {rel[-1]:.2e} at {int(ne[-1])})', None
    floor = float(rel[-1])
    return (f'order {np.mean(orders[:max(start, 1)]):.2f} to {int(ne[start])} elements, then a floor: '
            f'{floor:.2e} = {floor / ratio:.2f} v0/c at {int(ne[-1])}'), floor


def parts(sweep: Sweep) -> Dict[float, Dict[str, object]]:
    """Per amplitude, the error histories e(t) = u_cm - u_cm,exact of the parts sweep relative to the exact
    amplitude, and their split: model = e(hencky, uGIMP) - e(linear law, uGIMP), method = e(linear law,
    linear) - e(linear law, uGIMP); e(hencky, linear) = e(linear law, uGIMP) + model + method."""
    sweep = with_defaults(sweep)
    c = sweep.cases
    shape, law = c['shape'], c['law']
    found: Dict[float, Dict[str, object]] = {}
    for v0 in sorted(set(c['velocity_amplitude'].tolist()), reverse=True):
        e = {}
        for i in sweep.rows(velocity_amplitude=v0):
            if i not in sweep.histories or c['status'][i] != 0:
                continue
            h = sweep.histories[i]
            e[(str(shape[i]), str(law[i]))] = (h['ucm'] - h['ucm_exact']) / np.max(np.abs(h['ucm_exact']))
            time = h['time']
        needed = [('linear', 'hencky'), ('linear', 'linear'), ('ugimp', 'hencky'), ('ugimp', 'linear')]
        if any(k not in e for k in needed):
            continue
        model = e[('ugimp', 'hencky')] - e[('ugimp', 'linear')]
        method = e[('linear', 'linear')] - e[('ugimp', 'linear')]
        found[v0] = {'time': time, 'errors': e, 'model': model, 'method': method,
                     'residual': e[('linear', 'hencky')] - (e[('ugimp', 'linear')] + model + method),
                     'elements': int(c['elements'][0]),
                     'ratio': v0 / float(np.sqrt(c['youngs_modulus'][0] / c['density'][0]))}
    return found


def signed_peak(x: np.ndarray) -> float:
    return float(x[np.argmax(np.abs(x))])


def _main(argv: Optional[List[str]] = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument('sweeps', nargs='+', help='sweep files (the last one is the output folder in the older form)')
    ap.add_argument('--outdir')
    ap.add_argument('--parts', help='the sweep with histories of one mesh (linear and uGIMP x both laws)')
    ap.add_argument('--wall-time', type=float, default=float('nan'))
    args = ap.parse_args(argv)
    files = list(args.sweeps)
    if args.outdir is None:
        if len(files) < 2:
            ap.error('give --outdir')
        args.outdir = files.pop()
    outdir = Path(args.outdir)
    # every case: the stopped ones are drawn apart and listed, never fitted
    sweep = with_defaults(concatenate_sweeps([load_sweep(f, cases='all') for f in files]))
    c = sweep.cases
    n = len(c['elements'])
    shape_col, law_col = c['shape'], c['law']
    wave = np.sqrt(c['youngs_modulus'] / c['density'])
    amplitudes = sorted(set(c['velocity_amplitude'].tolist()), reverse=True)
    schemes = [s for s in ('usf', 'usl', 'musl') if s in set(c['scheme'])]
    shapes = [s for s in SHAPES if s in set(shape_col)]
    laws = [law for law in ('hencky', 'linear') if law in set(law_col)]
    versions = sorted(set(sweep.code_versions))

    lines = ['# Spatial convergence of the vibrating bar: two elastic laws, every shape', '',
             f'Sweeps {", ".join(f"`{Path(f).name}`" for f in files)}: {n} cases, '
             f'{int(c["particles_per_element"][0])} particles per element, dt = {c["dt_fraction"][0]:g} dx/c, '
             f'half a period; code version {", ".join(versions)}; wall time {args.wall_time:.1f} s '
             '(`bash studies/convergence/run.sh`).', '',
             'u_cm error = max over steps of |u_cm - u_cm,exact| (m), relative to the exact amplitude; order = '
             'local observed order between successive meshes. `hencky`: sigma = E ln F (the code\'s law, '
             'integrated as sigma += E d eps); `linear`: sigma = E (J - 1), for which the exact solution '
             '(linear elasticity) is exact at any amplitude.', '']
    table = []
    panels = [(s, 'linear') for s in schemes if s != 'usl'] + [('usl', shape) for shape in shapes]
    cols = min(3, len(panels))
    rows = -(-len(panels) // cols)
    fig, axes = plt.subplots(rows, cols, figsize=(5.2 * cols, 4.2 * rows), sharey=True, squeeze=False)
    findings: Dict[Tuple[str, str, str, float], Tuple[str, Optional[float]]] = {}
    for k, (scheme, shape) in enumerate(panels):
        ax = axes.flat[k]
        for law, style in zip(laws, ('-', '--')):
            for colour, v0 in zip(('C0', 'C1', 'C2', 'C3'), amplitudes):
                ne, rel, idx = series(sweep, scheme, shape, law, v0)
                if len(idx) == 0:
                    continue
                ratio = v0 / wave[idx[0]]
                ok = sweep.ok[idx]
                # orders between successive completed meshes only (a stopped case has no result)
                orders = dict(zip(ne[ok][1:], successive_orders(ne[ok], rel[ok])))
                for j, i in enumerate(idx):
                    if ok[j]:
                        order = f'{orders[ne[j]]:.2f}' if ne[j] in orders else ''
                        value = f'{rel[j]:.3e}'
                    else:
                        order = ''
                        value = f'no result (before the stop {c["relative_error_before_stop"][i]:.3e})'
                    table.append([scheme, shape, law, f'{v0:g}', f'{ratio:.1e}', int(ne[j]), value, order,
                                  c['status_name'][i]])
                ax.loglog(ne[ok], rel[ok], 'o' + style, color=colour, ms=3.5,
                          label=f'{law} law, v0/c = {ratio:.0e}')
                before = c['relative_error_before_stop'][idx][~ok]
                ax.loglog(ne[~ok], before, 'x', color='0.5', ms=8)
                findings[(scheme, shape, law, v0)] = describe(ne[ok], rel[ok], ratio)
        ref = np.array([100.0, 3200.0])
        ax.loglog(ref, 1e-4 * (ref / 100) ** -2.0, 'k:', lw=1, label='order 2')
        ax.set(xlabel='elements', title=f'{scheme.upper()}, {shape}, {int(c["particles_per_element"][0])} ppc, '
               f'dt = {c["dt_fraction"][0]:g} dx/c')
        plain_ticks(ax, sorted(set(c["elements"].tolist())))
        ax.grid(alpha=0.3, which='both')
        if k % cols == 0:
            ax.set_ylabel('relative u_cm error (-)')
    for ax in axes.flat[len(panels):]:
        ax.axis('off')
    axes.flat[0].legend(fontsize=6.5, title='solid: hencky, dashed: linear law; grey x: stopped by a guard (its error before the stop, no result)', title_fontsize=6.5)
    fig.tight_layout()
    save_figure_file(fig, outdir / 'convergence.png', dpi=110)
    plt.close(fig)

    lines += markdown_table(['scheme', 'shape', 'law', 'v0 (m/s)', 'v0/c', 'elements', 'relative error', 'order',
                             'status'], table)
    lines += ['', '## Findings', '', f'A floor is where every later local order is below {FLOOR_ORDER}.', '']
    for scheme, shape in panels:
        for law in laws:
            for v0 in amplitudes:
                if (scheme, shape, law, v0) in findings:
                    lines.append(f'- {scheme.upper()}, {shape}, {law}, v0 = {v0:g} m/s: '
                                 f'{findings[(scheme, shape, law, v0)][0]}.')
    # The floor, explained from the measurements.
    lines += ['', '## What the floor is made of (USL, v0 = 0.1 m/s)', '']
    top = amplitudes[0]
    ratio = top / float(wave[0])

    def floor_of(shape: str, law: str, v0: float = top) -> Optional[float]:
        return findings.get(('usl', shape, law, v0), ('', None))[1]

    wide = [s for s in shapes if s != 'linear']
    split = parts(load_sweep(args.parts, cases='all')) if args.parts else {}
    model = {v0: signed_peak(p['model']) / p['ratio'] for v0, p in split.items()}
    method = {v0: signed_peak(p['method']) / p['ratio'] for v0, p in split.items()}
    if model:
        lines.append('- Model difference (Hencky\'s continuum against linear elasticity): hencky - linear law with uGIMP '
                     'is ' + ', '.join(f'{m:+.3f}' for m in model.values()) + ' v0/c at v0 = '
                     + ', '.join(f'{v:g}' for v in model) + ' m/s (the split below): proportional to the strain '
                     'amplitude, as ln F = (F - 1) - (F - 1)^2/2 + ... makes it, and no mesh removes it.')
    if wide:
        floors = [floor_of(s, 'hencky') for s in wide]
        lines.append('- With the wide shapes that is the whole floor: Hencky stops at '
                     + ', '.join(f'{s} {m:.2e} ({m / ratio:.2f} v0/c)' if m is not None else f'{s} (no floor yet)'
                                 for s, m in zip(wide, floors))
                     + ' at v0 = ' + f'{top:g} m/s, while the linear law keeps falling: '
                     + '; '.join(f'{s} {findings.get(("usl", s, "linear", top), ("-",))[0]}' for s in wide)
                     + ('. With the linear law no wide shape has a floor at any amplitude.' if all(
                         findings.get(('usl', s, 'linear', v), ('', 0.0))[1] is None for s in wide for v in amplitudes)
                        else '. With the linear law a floor remains for: ' + ', '.join(
                            f'{s} at v0 = {v:g}' for s in wide for v in amplitudes
                            if findings.get(('usl', s, 'linear', v), ('', None))[1] is not None) + '.'))
    lin_floor = floor_of('linear', 'linear')
    if method:
        lines.append('- Method error of linear shapes: linear - uGIMP with the linear law (no model difference) is '
                     + ', '.join(f'{m:+.3f}' for m in method.values()) + ' v0/c at the same amplitudes: also '
                     'proportional to the strain, and it does not fall with the mesh (the linear law with linear '
                     'shapes at v0 = ' + f'{top:g} m/s: '
                     + (f'a floor, {lin_floor:.2e} = {lin_floor / ratio:.2f} v0/c at the finest mesh' if lin_floor is not None
                        else 'no floor')
                     + '). While a particle stays in its cell the hat functions\' quadrature of the cell does not change '
                     '(its mass and internal force come from the particles it holds, sum sigma_p J_p V0_p over them), so '
                     'the cells follow the material moving through the fixed grid only when particles cross: an error '
                     'of the order of the strain, which a finer mesh does not reduce. The wide shapes\' weights move '
                     'with the particles continuously.')
    hen_floor = floor_of('linear', 'hencky')
    if model and method:
        sums = [model[v] + method[v] for v in model]
        opposite = all(model[v] * method[v] < 0 for v in model)
        lines.append('- Hencky with linear shapes carries both' + (', of opposite signs' if opposite else '') + ': '
                     + ', '.join(f'{x:+.3f}' for x in sums)
                     + ' v0/c, which is why its floor'
                     + (f' ({hen_floor:.2e} = {hen_floor / ratio:.2f} v0/c at v0 = {top:g} m/s, finest mesh)' if hen_floor else '')
                     + ' lies below either part. So the floor is not the model difference alone (the explanation the '
                     'study gave before): with linear shapes it is the model difference plus the method\'s own error '
                     'of opposite sign and larger size; with the wide shapes it is the model difference, which the '
                     'linear law removes.')
    if 'linear' in laws and 'hencky' in laws and 'usl' in schemes:
        _, rel_l, _ = series(sweep, 'usl', 'linear', 'linear', top)
        ne_l, rel_h, _ = series(sweep, 'usl', 'linear', 'hencky', top)
        rows_ref = [(int(m), rel_l[list(ne_l).index(m)] if m in ne_l else float('nan'),
                     rel_h[list(ne_l).index(m)] if m in ne_l else float('nan')) for m in (800, 1600, 3200)]
        if any(np.isfinite(r[1]) for r in rows_ref):
            lines += ['', 'Against the independent reference of issue 26 (USL, linear shapes, 2 ppc, v0 = 0.1 m/s):', '']
            lines += markdown_table(
                ['elements', 'linear law, this code', 'linear law, reference', 'hencky, this code', 'hencky, reference'],
                [[m, f'{a:.3e}', f'{REFERENCE["linear"][m]:.2e}', f'{b:.3e}', f'{REFERENCE["hencky"][m]:.1e}']
                 for m, a, b in rows_ref])
    if split:
        first = split[max(split)]
        lines += ['', f'The split, USL, {first["elements"]} elements, from the histories (`parts.h5`, `parts.png`): '
                  'e = (u_cm - u_cm,exact)/amplitude; model = e(hencky, uGIMP) - e(linear law, uGIMP); method = '
                  'e(linear law, linear shapes) - e(linear law, uGIMP); each at its largest |value| over the run, '
                  'and in units of v0/c:', '']
        rows_split = []
        for v0, part in split.items():
            r = part['ratio']
            err = part['errors']
            model_peak, method_peak = signed_peak(part['model']), signed_peak(part['method'])
            rows_split.append([f'{v0:g}', f'{r:.2e}', f'{model_peak:+.2e}', f'{model_peak / r:+.3f}', f'{method_peak:+.2e}',
                               f'{method_peak / r:+.3f}', f'{np.max(np.abs(err[("ugimp", "linear")])):.2e}',
                               f'{np.max(np.abs(err[("linear", "hencky")])):.2e}',
                               f'{np.max(np.abs(part["residual"])):.1e}'])
        lines += markdown_table(['v0 (m/s)', 'v0/c', 'model', 'model/(v0/c)', 'method (linear shapes)', 'method/(v0/c)',
                                 'uGIMP, linear law: its own max error', 'hencky, linear shapes: max error',
                                 'largest |sum - run|'], rows_split)
        fig, axes = plt.subplots(1, len(split), figsize=(5.2 * len(split), 4.2), squeeze=False)
        for ax, (v0, part) in zip(axes.flat, split.items()):
            err = part['errors']
            t = part['time'] / part['time'][-1]
            ax.plot(t, err[('linear', 'hencky')], 'k-', lw=2, label='hencky, linear shapes (the run)')
            ax.plot(t, part['model'], 'C0-', label='model: hencky - linear law (uGIMP)')
            ax.plot(t, part['method'], 'C3-', label='method: linear - uGIMP (linear law)')
            ax.plot(t, err[('ugimp', 'linear')], 'C2-', label='uGIMP, linear law: its own error')
            ax.plot(t, err[('ugimp', 'linear')] + part['model'] + part['method'], 'y:', lw=2, label='sum of the three')
            ax.set(xlabel='t / (half a period)', title=f'USL, {part["elements"]} el., 2 ppc, v0 = {v0:g} m/s')
            ax.grid(alpha=0.3)
        axes.flat[0].set_ylabel('(u_cm - u_cm,exact) / exact amplitude (-)')
        axes.flat[0].legend(fontsize=7)
        fig.tight_layout()
        save_figure_file(fig, outdir / 'parts.png', dpi=110)
        plt.close(fig)
        lines += ['', '![parts.png](parts.png)']
    if 'usf' in schemes:
        _, a, _ = series(sweep, 'usf', 'linear', 'hencky', amplitudes[0])
        _, b, _ = series(sweep, 'usf', 'linear', 'hencky', amplitudes[-1])
        _, d, _ = series(sweep, 'usf', 'linear', 'linear', amplitudes[0])
        if len(a) and len(a) == len(b) == len(d):
            lines += ['', f'- USF is first order in time and space at this dt fraction: its error is the same at '
                      f'every amplitude and for both laws (largest ratio v0 = {amplitudes[0]:g} / {amplitudes[-1]:g}: '
                      f'{np.max(a / b):.3f}; linear law / hencky: {np.max(d / a):.3f}): its own discretisation '
                      'error, far above either floor.']
    lines += ['', '![convergence.png](convergence.png)', '']
    with replacing(outdir / 'summary.md', 'w') as f:
        f.write('\n'.join(lines))
    print(f'wrote {outdir / "summary.md"}, convergence.png' + (', parts.png' if split else ''))
    return 0


def main(argv: Optional[List[str]] = None) -> int:
    """Command-line entry point; returns the exit status (3: a file could not be written)."""
    return with_output_errors(PROGRAM, _main, argv)


if __name__ == '__main__':
    raise SystemExit(main())
