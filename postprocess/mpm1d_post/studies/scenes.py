"""The scenes study (studies/scenes/run.sh, whose report.py calls `main`): each scene's error against
elements and run time per scheme (figures) and the observed orders (summary.md), its error against dt,
its stability limit next to the bar's, the impact's fields against time, and the benchmark's bytes per
particle and speed per scene, from the files run.sh writes.

Usage: python studies/scenes/report.py OUT_FOLDER SWEEP.h5 [SWEEP.h5 ...] [--fields RUN.h5 ...] [--stability SWEEP.h5 ...]
       [--time SWEEP.h5 ...] [--bench BENCH.csv]

The field pictures compare a single run's last snapshot with exact solutions written here again from
the formulas (an independent check of the Fortran scenes): the column's series, the manufactured
displacement, the composite bar's step waves by characteristics.
"""
from __future__ import annotations

import argparse
from pathlib import Path

import matplotlib
import numpy as np

matplotlib.use('Agg')
import matplotlib.pyplot as plt  # noqa: E402

from ..figures import plain_ticks  # noqa: E402
from ..limits import stability_limit  # noqa: E402
from ..loader import Sweep, load_run, load_sweep  # noqa: E402
from ..orders import successive_orders  # noqa: E402
from ..tables import markdown_table  # noqa: E402

SCHEMES = ('usf', 'usl', 'musl')


def load(path: Path) -> Sweep:
    """Every case of a sweep: the stopped ones are shown apart, never fitted."""
    return load_sweep(path, cases='all')


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
    run = load_run(path)
    config, snap, version = run.config, run.snapshots[-1], run.code_version
    t = snap.time
    x0, x, stress = snap.extra['reference_x'], snap.x, snap.stress
    kind = config['scene_kind']
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
    ax.plot(x0, mpm, 'o', ms=2, label=f"MPM ({config['scheme']}, {config['elements']} elements x "
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


def scene_label(path: Path) -> str:
    """The scene a study file ran: its kind, and the impact's contact."""
    config = load(path).config
    kind = config['scene_kind']
    return f"{kind} ({config['contact']})" if kind == 'impact' else kind


def time_section(paths: list[Path], out: Path) -> list[str]:
    """Error against dt_fraction at a fixed mesh, per scene and scheme, with the observed order in dt."""
    fractions = sorted(set(load(paths[0]).cases['dt_fraction'].tolist()), reverse=True)
    rows = []
    fig, axes = plt.subplots(1, len(paths), figsize=(3.2 * len(paths), 3.4), squeeze=False)
    for ax, path in zip(axes[0], paths):
        sweep = load(path)
        label = scene_label(path)
        for scheme in sweep.schemes:
            pick = sweep.rows('dt_fraction', descending=True, scheme=scheme)
            k, e, ok = (sweep.cases[name][pick] for name in ('dt_fraction', 'relative_error', 'status'))
            cells = [f'{e[i]:.4g}' if ok[i] == 0 else f'guard {ok[i]}' for i in range(len(k))]
            rows.append([label, scheme, ', '.join(cells), ', '.join(f'{x:.2f}' for x in successive_orders(k, e))])
            good = ok == 0
            ax.loglog(k[good], e[good], 'o-', label=scheme)
        ax.set_xlabel('dt / (dx/c)')
        ax.set_ylabel('relative error')
        ax.set_title(label, fontsize=9)
        ax.grid(True, which='both', alpha=0.3)
        ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out / 'time_convergence.png', dpi=110)
    plt.close(fig)
    lines = ['## Convergence in time', '',
             'dt_fraction halved at a fixed mesh (100 elements x 2; the impact 200 x 2): the observed order '
             'in dt = log(e_i/e_i+1)/log 2. Where the spatial error dominates, the error stops falling with dt '
             '(order near 0): the time discretisation is then not what limits the accuracy.', '']
    lines += markdown_table(['scene', 'scheme', 'errors at dt_fraction ' + ', '.join(f'{k:g}' for k in fractions),
                             'orders'], rows)
    return lines + ['', '![error against dt](time_convergence.png)', '']


def stability_section(paths: list[Path], out: Path) -> list[str]:
    """The stability limit of each scene per scheme (a sweep of dt_fraction), next to the bar's."""
    limits = {}
    fig, axes = plt.subplots(1, 3, figsize=(12, 3.8))
    for path in paths:
        sweep = load(path)
        label = scene_label(path)
        for ax, scheme in zip(axes, SCHEMES):
            pick = sweep.rows('dt_fraction', scheme=scheme)
            k, ok, ratio = (sweep.cases[name][pick] for name in ('dt_fraction', 'status', 'max_energy_ratio'))
            limits[(label, scheme)] = stability_limit(k, ok).stable
            ax.semilogy(k, np.maximum(ratio, 1e-3), '.-', label=label)
    for ax, scheme in zip(axes, SCHEMES):
        ax.set_xlabel('dt / (dx/c_max)')
        ax.set_ylabel('largest energy / reference energy')
        ax.set_title(f'{scheme}: energy against time step (guard at 10)', fontsize=9)
        ax.grid(True, which='both', alpha=0.3)
    axes[0].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out / 'stability.png', dpi=110)
    plt.close(fig)
    lines = ['## Stability limit', '',
             'Each scene and the bar at 25 elements x 2 particles, dt_fraction from 0.05 to 2.6 in steps of 0.05, '
             'long runs (bar, column, manufactured 20 periods; composite 0.2 s, five crossing times; impact 10 '
             'periods of 2L/c). Limit = the largest dt_fraction below the first one a guard stopped (energy growth '
             'beyond 10x, J <= 0, ...); resolution 0.05. The code\'s table for the bar at 2 particles per element '
             '(mpm_config, stability_limit) says 0.757 for USL and 1.733 for USF and MUSL.', '']
    bar = limits.get(('vibrating_bar', 'usl'), float('nan'))
    rows = []
    for label in dict.fromkeys(key[0] for key in limits):
        row = [limits[(label, scheme)] for scheme in SCHEMES]
        rows.append([label] + [f'{x:.2f}' for x in row] + [f'{row[1] / bar:.2f}'])
    lines += markdown_table(['scene', 'USF limit', 'USL limit', 'MUSL limit', 'USL limit / bar\'s'], rows)
    return lines + ['', '![stability](stability.png)', '']


def bench_section(path: Path) -> list[str]:
    """Bytes per particle and the median particle-steps/s of each scene (mpm1d_bench scenes)."""
    rows = [line.split(',') for line in path.read_text(encoding='utf-8').split('\n') if line.strip()]
    scenes: dict[tuple[str, str], list] = {}
    for scene, route, particles, steps, bytes_, _, seconds, rate in rows:
        scenes.setdefault((scene, route), []).append((float(bytes_), float(rate), int(particles), int(steps)))
    reference = np.median([r[1] for r in scenes[('vibrating_bar', 'generic')]])
    lines = ['## Only what it needs: memory and speed per scene', '',
             f'`mpm1d_bench scenes` (studies/benchmark/bench.f90): each scene\'s whole run (USL, linear, FLIP, '
             f'dt = 0.2 dx/c, one thread, {rows[0][2]} particles, {rows[0][3]} steps; median of '
             f'{len(scenes[("vibrating_bar", "generic")])} runs on a shared machine, so ratios within about 15 % '
             'are noise) and the bytes per particle of the particle arrays its set-up allocates.', '']
    table = []
    for (scene, route), values in scenes.items():
        rate = float(np.median([v[1] for v in values]))
        table.append([scene, route, f'{values[0][0]:.0f}', f'{rate:.3g}', f'{rate / reference:.2f}'])
    lines += markdown_table(['scene', 'path', 'bytes per particle', 'particle-steps/s', 'speed / generic bar'], table)
    return lines + ['']


def impact_exact(t, v, length, c, stick):
    """Identical bars at +-v, no gap: bar 1's centre-of-mass displacement and the interface stress / (rho c v).
    Frictionless: deceleration c v/L for 2L/c, then parted, free at -v. Stuck ('none'): the deceleration changes
    sign every 2L/c (one free-free bar of length 2L)."""
    period = 2 * length / c
    a = -c * v / length
    u = np.zeros_like(t)
    stress = np.zeros_like(t)
    for i, time in enumerate(t):
        rest, w, wv, sign = time, 0.0, 0.0, 1.0
        if stick:
            stress[i] = -1.0 if int(time // period) % 2 == 0 else 1.0
        else:  # parted at 2L/c: no stress at the interface
            stress[i] = -1.0 if time < period else 0.0
        while rest > 0:
            h = min(rest, period)
            w += wv * h + sign * a * h * h / 2
            wv += sign * a * h
            rest -= h
            if not stick:
                w += wv * rest
                break
            sign = -sign
        u[i] = v * time + w
    return u, stress


def impact_figure(paths: list[Path], out: Path) -> list[str]:
    """Bar 1's centre of mass and the interface stress against time, and the stress along the bars at
    t = L/(2c), for each contact, against the exact solution; and the runs' /summary reports."""
    fig, (ucm_ax, stress_ax, profile_ax) = plt.subplots(1, 3, figsize=(13, 4))
    rows = []
    for path in paths:
        run = load_run(path)
        config, summary, snaps, version = run.config, run.summary, run.snapshots, run.code_version
        times = np.array([snap.time for snap in snaps])
        bar1 = snaps[0].extra['body'] == 1
        ucm = np.array([np.mean(snap.x[bar1] - snap.extra['reference_x'][bar1]) for snap in snaps])
        interface = np.nonzero(bar1)[0][-1]
        stress = np.array([snap.stress[interface] for snap in snaps])
        profile = min(range(len(snaps)), key=lambda i: abs(times[i] - 0.5 / np.sqrt(
            np.atleast_1d(config['youngs_moduli'])[0] / np.atleast_1d(config['densities'])[0])))
        x0_profile, stress_profile = snaps[profile].extra['reference_x'], snaps[profile].stress
        contact = config['contact']
        length = float(np.atleast_1d(config['lengths'])[0])
        rho = float(np.atleast_1d(config['densities'])[0])
        c = float(np.sqrt(np.atleast_1d(config['youngs_moduli'])[0] / rho))
        v = float(np.atleast_1d(config['velocities'])[0])
        fine = np.linspace(0, times[-1], 400)
        exact_u, exact_s = impact_exact(fine, v, length, c, contact == 'none')
        scale_u, scale_s = v * length / c, rho * c * v
        line = ucm_ax.plot(fine * c / length, exact_u / scale_u, '-', lw=1, label=f'exact, {contact}')[0]
        ucm_ax.plot(times * c / length, ucm / scale_u, 'o', ms=3, color=line.get_color(), label=f'MPM, {contact}')
        stress_ax.plot(fine * c / length, exact_s, '-', lw=1, color=line.get_color(), label=f'exact, {contact}')
        stress_ax.plot(times * c / length, stress / scale_s, 'o', ms=3, color=line.get_color(),
                       label=f'MPM, {contact}')
        if contact == 'frictionless':
            t_profile = times[profile]
            exact_profile = np.where(np.abs(x0_profile - length) < c * t_profile, -1.0, 0.0)
            profile_ax.plot(x0_profile, exact_profile, 'k-', lw=1, label='exact')
            profile_ax.plot(x0_profile, stress_profile / scale_s, 'o', ms=2, color=line.get_color(),
                            label=f'MPM, {contact}')
            profile_ax.set_title(f'stress along the bars at t = {t_profile * c / length:.3f} L/c', fontsize=9)
        rows.append([contact, f"{summary['contact_time'] / (2 * length / c):.4f}",
                     f"{summary['max_compressive_stress'] / scale_s:.3f}", f"{summary['final_velocity_1']:.4f}",
                     f"{summary['final_velocity_2']:.4f}", f"{summary['momentum_change']:.2g}",
                     f"{summary['final_energy'] / summary['initial_energy']:.4f}", f"{summary['relative_error']:.4f}"])
    ucm_ax.set_xlabel('time t c / L')
    ucm_ax.set_ylabel('u_cm,1 / (v L/c)')
    ucm_ax.set_title("bar 1's centre of mass", fontsize=9)
    stress_ax.set_xlabel('time t c / L')
    stress_ax.set_ylabel('stress / (rho c v)')
    stress_ax.set_title("stress of bar 1's particle next to the interface", fontsize=9)
    profile_ax.set_xlabel('reference position X (m)')
    profile_ax.set_ylabel('stress / (rho c v)')
    for ax in (ucm_ax, stress_ax, profile_ax):
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=7)
    fig.suptitle(f"impact: steel bars 1 m + 1 m at +-{v:g} m/s, USL, {config['elements']} elements x "
                 f"{config['particles_per_element']}, dt = {config['dt_fraction']:g} dx/c", fontsize=10)
    fig.text(0.01, 0.01, f"{version}, {', '.join(p.name for p in paths)}", fontsize=6)
    fig.tight_layout()
    fig.savefig(out / 'field_impact.png', dpi=110)
    plt.close(fig)
    lines = ['### Impact: two identical steel bars at +-1 m/s', '']
    lines += markdown_table(['contact', 'contact time / (2L/c)', 'largest compressive stress / (rho c v)',
                             'final velocity 1 (m/s)', 'final velocity 2 (m/s)', 'total momentum change / (sum M v)',
                             'final / initial energy', 'max u_cm,1 error / (v L/c)'], rows)
    return lines + ['', 'Exact: frictionless, contact for 2L/c at stress -rho c v, then the velocities exchanged; '
                    "'none' (stuck), the interface stress alternates -+rho c v every 2L/c. The MPM stress "
                    'overshoots at the fronts (Gibbs oscillation of the step wave).', '',
                    '![impact fields](field_impact.png)', '']


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('out', type=Path)
    parser.add_argument('sweeps', type=Path, nargs='+')
    parser.add_argument('--fields', type=Path, nargs='*', default=[])
    parser.add_argument('--stability', type=Path, nargs='*', default=[])
    parser.add_argument('--time', type=Path, nargs='*', default=[])
    parser.add_argument('--bench', type=Path)
    args = parser.parse_args(argv)
    lines = ['# Scenes: observed convergence orders', '',
             'Each scene against its exact solution (README, Scenes); error = `relative_error` of each case '
             '(the scene\'s own measure), observed order between consecutive resolutions = '
             'log(e_i/e_i+1)/log(n_i+1/n_i). Written by `bash studies/scenes/run.sh`.', '']
    for path in args.sweeps:
        sweep = load(path)
        kind = sweep.config['scene_kind']
        fig, (ax, cost) = plt.subplots(1, 2, figsize=(10, 4))
        rows = []
        stopped_shown = False
        for scheme in sweep.schemes:
            pick = sweep.rows('elements', scheme=scheme)
            n, e, ok, seconds, before, name = (sweep.cases[column][pick] for column in (
                'elements', 'relative_error', 'status', 'run_time', 'relative_error_before_stop', 'status_name'))
            o = successive_orders(n, e)
            for i in range(len(n)):
                if ok[i] == 0:
                    rows.append([scheme, n[i], f'{e[i]:.4g}', '' if i == 0 else f'{o[i - 1]:.2f}', f'{seconds[i]:.3g}',
                                 'ok'])
                else:
                    rows.append([scheme, n[i], f'no result ({before[i]:.4g} before the stop)', '', '',
                                 f'guard: {name[i]}'])
            done = ok == 0
            line = ax.loglog(n[done], e[done], 'o-', label=scheme)[0]
            cost.loglog(seconds[done], e[done], 'o-', label=scheme, color=line.get_color())
            if not done.all():
                ax.loglog(n[~done], before[~done], 'x', color='0.55', ms=7,
                          label=None if stopped_shown else 'stopped by a guard: error before the stop, no result')
                stopped_shown = True
        lines += [f"## {kind} ({path.name})", '', '```', sweep.config['namelist'], '```', '']
        lines += markdown_table(['scheme', 'elements', 'relative error', 'order from previous', 'run time (s)',
                                 'status'], rows)
        lines.append('')
        plain_ticks(ax, sweep.cases['elements'])
        ax.set_xlabel('elements across the body')
        ax.set_ylabel('relative error (scene measure)')
        ax.set_title(f"{kind}: error against elements", fontsize=10)
        ax.grid(True, which='both', alpha=0.3)
        ax.legend()
        cost.set_xlabel('run time per case (s; median of the timing pass, one thread)')
        cost.set_ylabel('relative error (scene measure)')
        cost.set_title(f"{kind}: error against run time", fontsize=10)
        cost.grid(True, which='both', alpha=0.3)
        cost.legend()
        fig.text(0.01, 0.01, f"{sweep.code_versions[0]}, {path.name}", fontsize=6)
        fig.tight_layout()
        figure = args.out / f"{path.stem}_error.png"
        fig.savefig(figure, dpi=120)
        plt.close(fig)
        lines += [f'![{kind}]({figure.name})', '']
    if args.time:
        lines += time_section(args.time, args.out)
    if args.stability:
        lines += stability_section(args.stability, args.out)
    if args.bench:
        lines += bench_section(args.bench)
    if args.fields:
        lines += ['## Fields against the exact solutions', '']
        impacts = [path for path in args.fields if path.stem.startswith('field_impact')]
        for path in args.fields:
            if path not in impacts:
                lines += field_figure(path, args.out)
        if impacts:
            lines += impact_figure(impacts, args.out)
    (args.out / 'summary.md').write_text('\n'.join(lines) + '\n', encoding='utf-8')
    print(f"wrote {args.out / 'summary.md'}")
    return 0


if __name__ == '__main__':
    raise SystemExit(main())
