"""Scenes study report: each scene's error against elements per scheme (figure) and the observed
orders (summary.md), from the sweep files studies/scenes/run.sh writes.

Usage: python report.py OUT_FOLDER SWEEP.h5 [SWEEP.h5 ...] [--fields RUN.h5 ...]

The field pictures compare a single run's last snapshot with exact solutions written here again from
the formulas (an independent check of the Fortran scenes): the column's series, the manufactured
displacement, the composite bar's step waves by characteristics.
"""
from __future__ import annotations

import argparse
from pathlib import Path

import h5py
import matplotlib
import numpy as np

matplotlib.use('Agg')
import matplotlib.pyplot as plt  # noqa: E402


def text(value) -> str:
    return value.decode() if isinstance(value, bytes) else str(value)


def load(path: Path) -> dict:
    """The /cases columns the report needs, and the scene's description from /config."""
    with h5py.File(path, 'r') as h5:
        cases = {name: h5['cases'][name][()] for name in ('scheme', 'elements', 'relative_error', 'status')}
        config = dict(h5['config'].attrs)
    cases['scheme'] = np.array([text(s) for s in cases['scheme']])
    return {'path': path, 'cases': cases, 'kind': text(config['scene_kind']),
            'namelist': text(config['namelist']), 'version': text(h5py.File(path, 'r').attrs['code_version'])}


def orders(elements: np.ndarray, errors: np.ndarray) -> list[float]:
    """Observed order between consecutive resolutions: log(e_i/e_{i+1}) / log(n_{i+1}/n_i)."""
    return [float(np.log(errors[i] / errors[i + 1]) / np.log(elements[i + 1] / elements[i]))
            for i in range(len(errors) - 1)]


def column_displacement(x, t, length, c, g, terms=4000):
    """u(x,t) = u_s(x) + sum_n a_n sin(beta_n x) cos(omega_n t), a_n = 2 g/(c^2 L beta_n^3)."""
    u = -(g / c**2) * (length * x - x**2 / 2)
    for n in range(1, terms + 1):
        beta = (2 * n - 1) * np.pi / (2 * length)
        u += 2 * g / (c**2 * length * beta**3) * np.sin(beta * x) * np.cos(beta * c * t)
    return u


def composite_stress(x, t, lengths, moduli, densities, v):
    """Step waves by characteristics: transmission 2 Zb/(Za+Zb), reflection (Zb-Za)/(Za+Zb), +1 at the
    driven end, -1 at the free end; the stress is the sum of the jumps of the fronts that have passed."""
    speed = np.sqrt(np.asarray(moduli) / np.asarray(densities))
    z = np.asarray(densities) * speed
    left = np.concatenate([[0.0], np.cumsum(lengths)[:-1]])
    right = np.cumsum(lengths)
    fronts, queue = [], [(0, 1, 0.0, -z[0] * v)]
    while queue:
        seg, d, t0, jump = queue.pop()
        if abs(jump) < 1e-15 * z[0] * v:
            continue
        fronts.append((seg, d, t0, jump))
        arrival = t0 + lengths[seg] / speed[seg]
        if arrival >= t:
            continue
        nxt = seg + d
        if nxt < 0:
            queue.append((seg, 1, arrival, jump))
        elif nxt >= len(lengths):
            queue.append((seg, -1, arrival, -jump))
        else:
            za, zb = z[seg], z[nxt]
            queue.append((seg, -d, arrival, (zb - za) / (za + zb) * jump))
            queue.append((nxt, d, arrival, 2 * zb / (za + zb) * jump))
    stress = np.zeros_like(x)
    for seg, d, t0, jump in fronts:
        inside = (x >= left[seg]) & (x < right[seg])
        reach = speed[seg] * (t - t0)
        passed = (x - left[seg] <= reach) if d > 0 else (right[seg] - x <= reach)
        stress += np.where(inside & passed & (reach > 0), jump, 0.0)
    return stress


def field_figure(path: Path, out: Path) -> str:
    """The last snapshot of a single run against the exact field; returns the summary's lines."""
    with h5py.File(path, 'r') as h5:
        config = dict(h5['config'].attrs)
        snap = h5['snapshots'][sorted(h5['snapshots'])[-1]]
        t = float(snap.attrs['time'])
        x0, x, stress = snap['reference_x'][()], snap['x'][()], snap['stress'][()]
        version = text(h5.attrs['code_version'])
    kind = text(config['scene_kind'])
    fig, ax = plt.subplots(figsize=(5.5, 4))
    if kind == 'column':
        c = np.sqrt(config['youngs_modulus'] / config['density'])
        exact = column_displacement(x0, t, config['length'], c, config['gravity'])
        mpm, label = x - x0, 'displacement u (m)'
    elif kind == 'manufactured':
        c = np.sqrt(config['youngs_modulus'] / config['density'])
        k, w = 2 * np.pi / config['length'], np.pi * c / config['length']
        exact = config['amplitude'] * np.sin(k * x0) * np.sin(w * t)
        mpm, label = x - x0, 'displacement u (m)'
    else:
        n = len(np.atleast_1d(config['lengths']))
        exact = composite_stress(x0, t, np.atleast_1d(config['lengths'])[:n], np.atleast_1d(config['youngs_moduli']),
                                 np.atleast_1d(config['densities']), config['drive_velocity'])
        mpm, label = stress, 'stress (Pa)'
    ax.plot(x0, exact, 'k-', lw=1, label='exact')
    ax.plot(x0, mpm, 'o', ms=2, label=f"MPM ({text(config['scheme'])}, {config['elements']} elements x "
                                         f"{config['particles_per_element']})")
    ax.set_xlabel('reference position X (m)')
    ax.set_ylabel(label)
    ax.set_title(f'{kind} at t = {t:.4g} s', fontsize=10)
    ax.legend(fontsize=8)
    fig.text(0.01, 0.01, f"{version}, {path.name}", fontsize=6)
    fig.tight_layout()
    figure = out / f'{path.stem}.png'
    fig.savefig(figure, dpi=120)
    plt.close(fig)
    deviation = float(np.max(np.abs(mpm - exact)) / np.max(np.abs(exact)))
    return [f'![{kind} field]({figure.name})', '',
            f'{kind}: largest |MPM - exact| / max |exact| of the field above: {deviation:.3g}.', '']


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('out', type=Path)
    parser.add_argument('sweeps', type=Path, nargs='+')
    parser.add_argument('--fields', type=Path, nargs='*', default=[])
    args = parser.parse_args(argv)
    lines = ['# Scenes: observed convergence orders', '',
             'Each scene against its exact solution (README, Scenes); error = `relative_error` of each case '
             '(the scene\'s own measure), observed order between consecutive resolutions = '
             'log(e_i/e_i+1)/log(n_i+1/n_i). Written by `bash studies/scenes/run.sh`.', '']
    for path in args.sweeps:
        data = load(path)
        cases = data['cases']
        fig, ax = plt.subplots(figsize=(5.5, 4))
        lines += [f"## {data['kind']} ({path.name})", '', '```', data['namelist'], '```', '',
                  '| scheme | elements | relative error | order from previous | status |', '|---|---|---|---|---|']
        for scheme in dict.fromkeys(cases['scheme']):
            pick = cases['scheme'] == scheme
            n = cases['elements'][pick]
            e = cases['relative_error'][pick]
            ok = cases['status'][pick]
            sort = np.argsort(n)
            n, e, ok = n[sort], e[sort], ok[sort]
            o = orders(n, e)
            for i in range(len(n)):
                lines.append(f'| {scheme} | {n[i]} | {e[i]:.4g} | {"" if i == 0 else f"{o[i - 1]:.2f}"} | '
                             f'{"ok" if ok[i] == 0 else f"guard {ok[i]}"} |')
            ax.loglog(n, e, 'o-', label=scheme)
        lines.append('')
        ax.set_xlabel('elements across the body')
        ax.set_ylabel('relative error (scene measure)')
        ax.set_title(f"{data['kind']}: error against elements", fontsize=10)
        ax.grid(True, which='both', alpha=0.3)
        ax.legend()
        fig.text(0.01, 0.01, f"{data['version']}, {path.name}", fontsize=6)
        fig.tight_layout()
        figure = args.out / f"{path.stem}_error.png"
        fig.savefig(figure, dpi=120)
        plt.close(fig)
        lines += [f'![{data["kind"]}]({figure.name})', '']
    if args.fields:
        lines += ['## Fields against the exact solutions', '']
        for path in args.fields:
            lines += field_figure(path, args.out)
    (args.out / 'summary.md').write_text('\n'.join(lines) + '\n', encoding='utf-8')
    print(f"wrote {args.out / 'summary.md'}")
    return 0


if __name__ == '__main__':
    raise SystemExit(main())
