"""Scenes study report: each scene's error against elements per scheme (figure) and the observed
orders (summary.md), from the sweep files studies/scenes/run.sh writes.

Usage: python report.py OUT_FOLDER SWEEP.h5 [SWEEP.h5 ...]
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


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('out', type=Path)
    parser.add_argument('sweeps', type=Path, nargs='+')
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
        fig.text(0.01, 0.01, f"mpm1d {data['version']}, {path.name}", fontsize=6)
        fig.tight_layout()
        figure = args.out / f"{path.stem}_error.png"
        fig.savefig(figure, dpi=120)
        plt.close(fig)
        lines += [f'![{data["kind"]}]({figure.name})', '']
    (args.out / 'summary.md').write_text('\n'.join(lines) + '\n', encoding='utf-8')
    print(f"wrote {args.out / 'summary.md'}")
    return 0


if __name__ == '__main__':
    raise SystemExit(main())
