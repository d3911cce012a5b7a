"""Summary and figures of the materials study (studies/materials/run.sh): the plastic wave against its
exact small-strain solution (and the finite-strain one, computed here), its convergence, error against
run time, fronts and plateaus, energy balance, stability with plasticity, the bar with both elastic laws,
and the laws' speed and memory.

The exact solutions are written again here, independently of the Fortran scene (mpm_scene_plastic_wave):
small strain (Kolsky 1953, Wang 2007): an elastic precursor at c_e = sqrt(E/rho) carrying sigma_y and
v1 = sigma_y/(rho c_e), a plastic front at c_p = sqrt(E_t/rho), E_t = E H/(E + H), behind which v = V and
|sigma| = sigma_y + rho c_p (V - v1). Finite strain (the code's continuum: Hencky elasticity
sigma = E ln F with linear hardening in the log strain, momentum rho0 v_t = sigma_X in reference
coordinates with unit area): both waves steepen into shocks (sigma'(F) = E/F grows in compression), with
the Rankine-Hugoniot conditions [v] = -U [F], [sigma] = rho0 U^2 [F].

Usage: python studies/materials/analyze.py OUT_FOLDER (the script calls `main`)
"""
from __future__ import annotations

import argparse
import csv
import math
from pathlib import Path
from typing import Dict, List, Optional, Tuple

import numpy as np
import matplotlib

matplotlib.use('Agg')
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402

from ..limits import stability_limit  # noqa: E402
from ..loader import Run, Sweep, load_run, load_sweep  # noqa: E402
from ..orders import fitted_order  # noqa: E402
from ..pareto import cheapest_by_group_rows, cheapest_rows, pareto_front  # noqa: E402
from ..tables import markdown_table, number  # noqa: E402

SCHEMES = ('usf', 'usl', 'musl')
SHAPES = ('linear', 'ugimp', 'cpgimp', 'bspline2', 'bspline3')
TRANSFERS = ('flip', 'pic', 'blend', 'apic')
COLOURS = dict(zip(SHAPES, ('C0', 'C1', 'C2', 'C3', 'C4')))
MARKERS = dict(zip(TRANSFERS, ('o', 's', '^', 'D')))


# --- exact solutions -------------------------------------------------------------------------------

def small_strain(E: float, rho: float, sy: float, H: float, V: float) -> Dict[str, float]:
    """Fronts of the small-strain solution: speeds (m/s, in X) and |stress| behind each (Pa)."""
    ce = math.sqrt(E / rho)
    v1 = sy / (rho * ce)
    if V <= v1:
        return dict(c1=ce, c2=0.0, s1=rho * ce * V, s2=rho * ce * V, v1=V)
    cp = math.sqrt(E * H / (E + H) / rho)
    return dict(c1=ce, c2=cp, s1=sy, s2=sy + rho * cp * (V - v1), v1=v1)


def finite_strain(E: float, rho: float, sy: float, H: float, V: float) -> Dict[str, float]:
    """The same problem for Hencky elasticity with linear hardening in the log strain at finite strain:
    sigma(F) = E ln F to F1 = exp(-sigma_y/E), then -(sigma_y + E_t ln(F1/F)); two shocks (Lagrangian
    speeds U1, U2) from the Rankine-Hugoniot conditions."""
    F1 = math.exp(-sy / E)
    U1 = math.sqrt(sy / (rho * (1.0 - F1)))
    v1 = U1 * (1.0 - F1)
    if V <= v1:  # one elastic shock to F with E ln(1/F) (1 - F) = rho V^2
        lo, hi = 1e-12, 1.0 - 1e-15
        for _ in range(200):
            F = 0.5 * (lo + hi)
            (lo, hi) = (F, hi) if E * math.log(1 / F) * (1 - F) > rho * V * V else (lo, F)
        F = 0.5 * (lo + hi)
        U = V / (1 - F)
        return dict(c1=U, c2=0.0, s1=-E * math.log(F), s2=-E * math.log(F), v1=V)
    Et = E * H / (E + H)
    lo, hi = 1e-12, F1 * (1 - 1e-15)
    for _ in range(200):  # Et ln(F1/F2) (F1 - F2) = rho (V - v1)^2, decreasing in F2
        F2 = 0.5 * (lo + hi)
        (lo, hi) = (F2, hi) if Et * math.log(F1 / F2) * (F1 - F2) > rho * (V - v1) ** 2 else (lo, F2)
    F2 = 0.5 * (lo + hi)
    U2 = (V - v1) / (F1 - F2)
    return dict(c1=U1, c2=U2, s1=sy, s2=sy + Et * math.log(F1 / F2), v1=v1)


def stress_profile(front: Dict[str, float], X: np.ndarray, t: float) -> np.ndarray:
    """-|sigma| of a two-front solution at reference positions X and time t."""
    return np.where(X < front['c2'] * t, -front['s2'], np.where(X < front['c1'] * t, -front['s1'], 0.0))


def l1(front: Dict[str, float], X: np.ndarray, stress: np.ndarray, volume: float, t: float) -> float:
    return float(np.sum(np.abs(stress - stress_profile(front, X, t))) * volume)


# --- helpers ---------------------------------------------------------------------------------------

def material(run: Run) -> Tuple[float, float, float, float, float, float]:
    c = run.config
    return (float(c['youngs_modulus']), float(c['density']), float(c['yield_stress']),
            float(c['hardening_modulus']), float(c['drive_velocity']), float(c['length']))


def fmt(x: float, digits: int = 3) -> str:
    return number(x, f'.{digits}g')


def singles(out: Path, prefix: str) -> Dict[int, Run]:
    runs = {}
    for path in sorted(out.glob(f'{prefix}_*.h5')):
        tail = path.stem.rsplit('_', 1)[-1]
        if tail.isdigit():
            runs[int(tail)] = load_run(str(path))
    return dict(sorted(runs.items()))


def crossed(run: Run) -> float:
    """Fraction of the particles in another cell at the end than at the start."""
    s = run.snapshots[-1]
    dx = float(run.config['dx'])
    X = s.extra['reference_x']
    return float(np.mean(np.floor(s.x / dx) != np.floor(X / dx)))


# --- sections --------------------------------------------------------------------------------------

def setup_section(run: Run) -> Tuple[List[str], Dict[str, float], Dict[str, float]]:
    E, rho, sy, H, V, L = material(run)
    ss, fs = small_strain(E, rho, sy, H, V), finite_strain(E, rho, sy, H, V)
    T = float(run.config['final_time'])
    X = (np.arange(200000) + 0.5) / 200000 * L
    diff = np.sum(np.abs(stress_profile(fs, X, T) - stress_profile(ss, X, T))) * L / 200000 / (ss['s2'] * L)
    strain = sy / E + (ss['s2'] - sy) * (E + H) / (E * H)
    table = markdown_table(
        ['front', 'speed, small strain (m/s)', 'speed, finite strain (m/s)', '|stress| behind, small strain (Pa)',
         '|stress| behind, finite strain (Pa)'],
        [['elastic precursor', f'{ss["c1"]:.2f}', f'{fs["c1"]:.2f}', f'{ss["s1"]:.4g}', f'{fs["s1"]:.4g}'],
         ['plastic front', f'{ss["c2"]:.2f}', f'{fs["c2"]:.2f}', f'{ss["s2"]:.4g}', f'{fs["s2"]:.4g}']])
    lines = ['## The problem', '',
             f'A steel bar (E = {E:.3g} Pa, rho = {rho:g} kg/m^3, L = {L:g} m, c_e = {ss["c1"]:.1f} m/s), '
             f'elastoplastic with sigma_y = {sy:.3g} Pa and H = {H:.3g} Pa (E_t = {E * H / (E + H):.4g} Pa), '
             f'its left end driven at V = {V:g} m/s (V/c_e = {V / ss["c1"]:.2e}) for T = {T:.4g} s = 0.8 L/c_e, '
             f'2 particles per element, dt = 0.2 dx/c_e unless said otherwise.', '', *table, '',
             f'Particle velocity between the fronts v1 = {ss["v1"]:.4f} m/s (finite strain {fs["v1"]:.4f}); strain '
             f'behind the plastic front {strain:.2e}. The finite-strain solution of the code\'s own continuum '
             f'(Hencky, hardening in the log strain; both fronts are shocks) differs from the small-strain one '
             f'by {100 * (fs["s2"] / ss["s2"] - 1):+.2f} % in the plastic stress and {100 * (fs["c2"] / ss["c2"] - 1):+.2f} % '
             f'in the plastic front\'s speed; the L1 difference of the two stress profiles at T is '
             f'{diff:.2e} of sigma_p L: the yardstick\'s own error, below which no run can be measured against '
             'the small-strain solution.', '']
    return lines, ss, fs


def convergence_section(out: Path, wave: Sweep, fine: Optional[Sweep]) -> List[str]:
    sources = [s for s in (wave, fine) if s is not None]
    ne_all = sorted({int(n) for s in sources for n in s.cases['elements']})
    rows = []
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.4), sharey=True)
    for ax, scheme in zip(axes, SCHEMES):
        for shape in SHAPES:
            pts = {}
            for src in sources:
                for i in src.rows(scheme=scheme, shape=shape, transfer='flip'):
                    pts[int(src.cases['elements'][i])] = (float(src.cases['relative_error'][i])
                                                          if src.cases['status'][i] == 0 else float('nan'))
            if not pts:
                continue
            n = np.array(sorted(pts), float)
            e = np.array([pts[int(k)] for k in n])
            rows.append([scheme, shape] + [fmt(pts.get(k, float('nan'))) for k in ne_all]
                        + [fmt(fitted_order(n, e), 2), fmt(fitted_order(n[-3:], e[-3:]), 2)])
            ax.loglog(n, e, 'o-', color=COLOURS[shape], ms=3.5, label=shape)
        ref = np.array([50.0, 3200.0])
        ax.loglog(ref, 0.06 * (ref / 50) ** -1.0, 'k:', lw=1, label='order 1')
        ax.loglog(ref, 0.06 * (ref / 50) ** -0.5, 'k--', lw=0.8, label='order 1/2')
        ax.set(xlabel='elements', title=f'{scheme.upper()}, FLIP, 2 ppc, dt = 0.2 dx/c_e')
        ax.grid(alpha=0.3, which='both')
    axes[0].set_ylabel('L1 stress error / (sigma_p L) (-)')
    axes[0].legend(fontsize=8)
    fig.suptitle('Plastic wave: convergence to the small-strain solution')
    fig.tight_layout()
    fig.savefig(out / 'wave_convergence.png', dpi=110)
    plt.close(fig)
    lines = ['## Convergence of the plastic wave', '',
             'Relative L1 stress error at T, sum_p |sigma_p - sigma(X_p, T)| V0_p / (sigma_p L), FLIP '
             '(`wave.h5`, `wave_fine.h5`):', '']
    lines += markdown_table(['scheme', 'shape'] + [f'{n} el.' for n in ne_all] + ['order (all)', 'order (last three)'],
                            rows)
    rows = []
    c = wave.cases
    for scheme in SCHEMES:
        for shape in SHAPES:
            cells = []
            for transfer in TRANSFERS:
                m = wave.rows('elements', scheme=scheme, shape=shape, transfer=transfer)
                e = np.where(wave.ok[m], c['relative_error'][m], np.nan)
                n = c['elements'][m].astype(float)
                stopped = int(np.sum(~wave.ok[m]))
                cells.append(f'{fmt(fitted_order(n, e), 2)} ({fmt(e[-1])})' + (f', {stopped} stopped' if stopped else ''))
            rows.append([scheme, shape] + cells)
    lines += ['', '![convergence](wave_convergence.png)', '',
              'Every transfer (order fitted over all meshes of `wave.h5`):', '']
    lines += markdown_table(['scheme', 'shape'] + list(TRANSFERS), rows)
    lines += ['', 'Cells: order (error at the finest mesh of the sweep).', '']
    return lines


def time_section(out: Path, wave) -> List[str]:
    c = wave.cases
    ok = wave.ok & (c['run_time'] > 0)
    t, e = c['run_time'], c['relative_error']
    label = np.array([f'{s} {h} {tr} {n} el.' for s, h, tr, n in
                      zip(c['scheme'], c['shape'], c['transfer'], c['elements'])])
    idx = np.flatnonzero(ok)
    lines = ['## Error against run time (one thread)', '']
    if len(idx) == 0:
        return lines + ['No timed runs.', '']
    front = idx[pareto_front(t[ok], e[ok])]
    spread = np.median(c['run_time_spread'][ok]) if 'run_time_spread' in c else float('nan')
    lines += [f'{int(ok.sum())} timed runs (every scheme x shape x transfer, {", ".join(str(n) for n in sorted(set(c["elements"])))} '
              f'elements; timing pass one thread, median spread of the repeats {fmt(spread, 2)}); the black line is '
              'the Pareto front over all of them. Every run of this scene takes the generic path.', '',
              '![error against run time](wave_error_vs_time.png)', '', '### For a target relative L1 error, use ...', '']
    targets = (0.05, 0.02, 0.01)
    lines += markdown_table(['target', 'cheapest run reaching it', 'run time (s)', 'its error'],
                            cheapest_rows(t, e, label, targets, among=ok))
    lines += ['', 'The cheapest run of each shape reaching the target (time relative to the cheapest of all):', '']
    without_shape = [f'{s} {tr} {n} el.' for s, tr, n in zip(c['scheme'], c['transfer'], c['elements'])]
    lines += markdown_table(['target'] + list(SHAPES), cheapest_by_group_rows(
        t, e, without_shape, targets, [wave.where(shape=shape) for shape in SHAPES], among=ok))
    lines += ['', 'Pareto front (fastest first):', '']
    lines += markdown_table(['run', 'run time (s)', 'relative error'],
                            [[label[i], f'{t[i]:.2e}', f'{e[i]:.2e}'] for i in front])
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.8), sharey=True, sharex=True)
    for ax, scheme in zip(axes, SCHEMES):
        for shape in SHAPES:
            for transfer in TRANSFERS:
                m = ok & wave.where(scheme=scheme, shape=shape, transfer=transfer)
                if m.any():
                    o = np.argsort(t[m])
                    ax.loglog(t[m][o], e[m][o], marker=MARKERS[transfer], color=COLOURS[shape], ms=4, lw=0.7,
                              alpha=0.85)
        ax.loglog(t[front], e[front], 'k-', lw=1.6, zorder=5)
        ax.set(title=f'{scheme.upper()}, 2 ppc, dt = 0.2 dx/c_e', xlabel='run time (s, one thread)')
        ax.grid(True, which='both', alpha=0.3)
    axes[0].set_ylabel('L1 stress error / (sigma_p L) (-)')
    handles = [Line2D([], [], color=COLOURS[s], lw=2, label=s) for s in SHAPES]
    handles += [Line2D([], [], color='0.3', marker=MARKERS[k], ls='none', label=k) for k in TRANSFERS]
    handles += [Line2D([], [], color='k', lw=1.6, label='Pareto front (all schemes)')]
    axes[2].legend(handles=handles, fontsize=8, loc='lower left')
    fig.suptitle('Plastic wave: error against run time per scheme, shape (colour) and transfer (marker)')
    fig.tight_layout()
    fig.savefig(out / 'wave_error_vs_time.png', dpi=110)
    plt.close(fig)
    return lines + ['']


def fronts_section(out: Path, ss: Dict[str, float], fs: Dict[str, float]) -> Tuple[List[str], Dict]:
    lines = ['## Fronts, plateaus and the non-monotone convergence of linear shapes', '',
             'USL, FLIP, single runs with a snapshot at T (`single_*.h5`; the elastic control `elastic_linear_*.h5`: law '
             'hencky driven at v1, one elastic wave carrying the precursor\'s state sigma_y, v1, without plasticity). '
             'Fronts: the largest X_p whose |sigma_p| reaches half the jump; plateaus: mean |sigma_p| over the middle '
             'half of each zone, relative to the exact value; crossed: fraction of the particles in another cell at '
             'T than at t = 0; end: the driven end\'s travel V T in cells.', '']
    control = singles(out, 'elastic_linear')
    rows = {}
    table = []
    for shape in ('linear', 'ugimp'):
        for n, run in singles(out, f'single_{shape}').items():
            s = run.summary
            if int(s['status']) != 0 or not run.snapshots:
                table.append([shape, n, f'stopped ({s["status_name"]})'] + [''] * 9)
                continue
            T = float(run.snapshots[-1].time)
            end = float(run.config['drive_velocity']) * T / float(run.config['dx'])
            row = dict(error=float(s['relative_error']), end=end, crossed=crossed(run),
                       precursor=float(s['measured_precursor_front']) / float(s['precursor_front']),
                       plastic=float(s['measured_plastic_front']) / float(s['plastic_front']),
                       p1=float(s['measured_precursor_stress']) / float(s['precursor_stress']),
                       p2=float(s['measured_plastic_stress']) / float(s['plastic_stress']),
                       balance=float(s['energy_balance']))
            ctrl = control.get(n) if shape == 'linear' else None
            if ctrl is not None and int(ctrl.summary['status']) == 0:
                row['control'] = float(ctrl.summary['measured_precursor_stress']) / float(ctrl.summary['precursor_stress'])
                row['control_error'] = float(ctrl.summary['relative_error'])
            rows[(shape, n)] = row
            table.append([shape, n, f'{row["error"]:.3e}', f'{end:.2f}', f'{row["crossed"]:.2f}',
                          f'{row["precursor"]:.4f}', f'{row["plastic"]:.4f}', f'{row["p1"]:.4f}', f'{row["p2"]:.4f}',
                          fmt(row.get('control', float('nan')), 4), fmt(row.get('control_error', float('nan'))),
                          f'{row["balance"]:+.2e}'])
    lines += markdown_table(['shape', 'elements', 'rel. L1 error', 'end (cells)', 'crossed', 'precursor front',
                             'plastic front', 'precursor plateau', 'plastic plateau', 'elastic control: plateau',
                             'its error', 'energy balance'], table)
    lines += ['']
    # profiles at two resolutions
    lin, ug = singles(out, 'single_linear'), singles(out, 'single_ugimp')
    pair = [n for n in (100, 800) if n in lin and n in ug] or sorted(set(lin) & set(ug))[:2]
    if pair:
        fig, axes = plt.subplots(2, len(pair), figsize=(7 * len(pair), 7), sharex=True, sharey='row', squeeze=False)
        for col, n in enumerate(pair):
            for row_i, (shape, runs) in enumerate((('linear', lin), ('ugimp', ug))):
                ax = axes[row_i, col]
                run = runs[n]
                s = run.snapshots[-1]
                X = s.extra['reference_x']
                grid = np.linspace(0, float(run.config['length']), 4001)
                ax.plot(X, -s.stress / 1e6, '.', ms=2.5, color=COLOURS[shape], label=f'{shape}, {n} el. (particles)')
                ax.plot(grid, -stress_profile(ss, grid, s.time) / 1e6, 'k-', lw=1.2, label='exact, small strain')
                ax.plot(grid, -stress_profile(fs, grid, s.time) / 1e6, 'k:', lw=1.2, label='exact, finite strain')
                ax.set(title=f'USL, {shape}, {n} elements, t = {s.time * 1e6:.1f} us (rel. L1 error '
                       f'{float(run.summary["relative_error"]):.2e})')
                ax.grid(alpha=0.3)
                if col == 0:
                    ax.set_ylabel('compressive stress -sigma (MPa)')
                if row_i == 1:
                    ax.set_xlabel('reference position X (m)')
                ax.legend(fontsize=7, loc='upper right')
        fig.tight_layout()
        fig.savefig(out / 'wave_profiles.png', dpi=110)
        plt.close(fig)
        lines += ['![stress profiles](wave_profiles.png)', '']
    return lines, rows


def energy_section(out: Path) -> List[str]:
    path = out / 'energy.h5'
    lines = ['## Energy balance', '']
    if not path.exists():
        return lines + ['(no energy run)', '']
    run = load_run(str(path))
    h = run.history
    if h is None or 'plastic_work' not in h or not run.snapshots:
        return lines + ['(no plastic-work history)', '']
    V = float(run.config['drive_velocity'])
    mass = float(run.config['density']) * float(run.config['length']) / (run.elements * run.particles_per_element)
    rows, ts, parts = [], [], []
    for s in run.snapshots:
        if s.time <= 0:
            continue
        k = int(np.argmin(np.abs(h['time'] - s.time)))
        drive = V * mass * float(np.sum(s.velocity))
        K, U, W = h['kinetic_energy'][k], h['strain_energy'][k], h['plastic_work'][k]
        ts.append(s.time)
        parts.append((K, U, W, drive))
        rows.append([f'{s.time * 1e6:.2f}', f'{K:.4g}', f'{U:.4g}', f'{W:.4g}', f'{drive:.4g}',
                     f'{(K + U + W - drive) / drive:+.2e}'])
    lines += [f'USL, uGIMP, {run.elements} elements (`energy.h5`): kinetic + elastic + plastic work against the '
              'drive\'s work V P(t) (its force is the momentum change at the constant velocity V), J per unit area.', '']
    lines += markdown_table(['t (us)', 'kinetic', 'elastic', 'plastic work', 'drive work', '(K + U + W_p - W)/W'], rows)
    s = run.summary
    others = sorted(out.glob('balance_v*.h5'), key=lambda p: float(p.stem[len('balance_v'):]))
    finest = singles(out, 'single_ugimp')
    if others and finest:
        n = max(finest)
        table = [(float(finest[n].config['drive_velocity']), finest[n])] + \
            [(float(load_run(str(p)).config['drive_velocity']), load_run(str(p))) for p in others]
        lines += ['', f'The balance at T on the finest mesh ({n} elements, uGIMP, USL) against the drive velocity '
                  '(the strain behind the plastic front):', '']
        rows = []
        for v, r in sorted(table, key=lambda x: x[0]):
            E, rho, sy, H, _, _ = material(r)
            front = small_strain(E, rho, sy, H, v)
            strain = sy / E + (front['s2'] - sy) * (E + H) / (E * H)
            rows.append([f'{v:g}', f'{strain:.2e}', f'{float(r.summary["energy_balance"]):+.2e}',
                         f'{float(r.summary["relative_error"]):.2e}'])
        lines += markdown_table(['V (m/s)', 'strain behind the plastic front', '(K + U + W_p - W)/W', 'rel. L1 error'],
                                rows)
    lines += ['', f'At T: plastic work {float(s["plastic_work"]):.4g} J/m^2, of which dissipated (sigma_y alpha) '
              f'{float(s["dissipated_energy"]):.4g} and stored in the hardening (H alpha^2/2) '
              f'{float(s["hardening_energy"]):.4g}; {100 * float(s["yielded_fraction"]):.0f} % of the particles yielded.', '']
    parts_a = np.array(parts)
    fig, ax = plt.subplots(figsize=(7, 4.2))
    ts = np.array(ts) * 1e6
    for j, (name, style) in enumerate((('kinetic', 'C0-'), ('elastic', 'C1-'), ('plastic work', 'C3-'),
                                       ('drive work V P', 'k--'))):
        ax.plot(ts, parts_a[:, j], style, marker='o', ms=3, label=name)
    ax.plot(ts, parts_a[:, :3].sum(axis=1), 'y:', lw=2, label='kinetic + elastic + plastic')
    ax.set(xlabel='t (us)', ylabel='energy (J per m^2 of cross-section)',
           title=f'Plastic wave, USL, uGIMP, {run.elements} elements')
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out / 'wave_energy.png', dpi=110)
    plt.close(fig)
    return lines + ['![energy](wave_energy.png)', '']


def critical(sweep: Sweep, scheme: str, shape: str) -> float:
    """The first dt fraction at which a case of `scheme` and `shape` stopped, nan if none did."""
    m = sweep.rows(scheme=scheme, shape=shape)
    return stability_limit(sweep.cases['dt_fraction'][m], sweep.cases['status'][m]).first_failing


def stability_section(out: Path) -> List[str]:
    files = {'bar, hencky': out / 'stability_bar_hencky.h5', 'bar, elastoplastic': out / 'stability_bar_elastoplastic.h5',
             'plastic wave': out / 'stability_wave.h5'}
    # every case: the critical dt fraction is where cases stop (load_sweep's default keeps the completed ones)
    sweeps = {k: load_sweep(str(p), cases='all') for k, p in files.items() if p.exists()}
    lines = ['## Stability with plasticity', '',
             'Critical dt fraction (the first dt/(dx/c_e) at which a run stops, by a guard; 2 particles per element): '
             'the bar at v0 = 20 m/s, 20 elements, 20 periods, hencky and elastoplastic (sigma_y = 250 MPa: the '
             'initial stress amplitude rho c v0 = 790 MPa yields it), generic path; the plastic wave at '
             f'{int(sweeps["plastic wave"].cases["elements"][0]) if "plastic wave" in sweeps else "?"} elements to 0.8 L/c_e.', '']
    lines += markdown_table(['scheme', 'shape'] + list(sweeps),
                            [[scheme, shape] + [fmt(critical(s, scheme, shape), 3) for s in sweeps.values()]
                             for scheme in SCHEMES for shape in SHAPES])
    if 'bar, elastoplastic' in sweeps:
        c = sweeps['bar, elastoplastic'].cases
        lines += ['', f'(dt fractions tried: {c["dt_fraction"].min():.2f} to {c["dt_fraction"].max():.2f} in steps of '
                  f'{np.diff(np.unique(c["dt_fraction"])).min():.2f}.)']
    return lines + ['']


def bar_section(out: Path) -> List[str]:
    path = out / 'bar.h5'
    if not path.exists():
        return []
    sweep = load_sweep(str(path))
    lines = ['## The bar with both elastic laws (USL, 2 ppc, dt = 0.1 dx/c, half a period, v0 = 0.1 m/s)', '',
             'Relative u_cm error (`bar.h5`; the full study across amplitudes and shapes: studies/convergence):', '']
    ne = sorted(set(sweep.cases['elements'].tolist()))
    rows = []
    fig, ax = plt.subplots(figsize=(7, 4.3))
    for shape in ('linear', 'ugimp', 'bspline2'):
        for law, style in (('hencky', '-'), ('linear', '--')):
            m = sweep.rows('elements', shape=shape, law=law)
            if not m.size:
                continue
            n, e = sweep.cases['elements'][m], sweep.cases['relative_error'][m]
            rows.append([shape, law] + [f'{x:.2e}' for x in e])
            ax.loglog(n, e, 'o' + style, color=COLOURS[shape], ms=3.5, label=f'{shape}, {law}')
    ax.set(xlabel='elements', ylabel='relative u_cm error (-)', title='Bar, USL, v0 = 0.1 m/s (v0/c = 2e-5)')
    ax.grid(alpha=0.3, which='both')
    ax.legend(fontsize=8, title='solid: hencky, dashed: linear law', title_fontsize=7)
    fig.tight_layout()
    fig.savefig(out / 'bar_laws.png', dpi=110)
    plt.close(fig)
    lines += markdown_table(['shape', 'law'] + [f'{n} el.' for n in ne], rows)
    return lines + ['', '![bar, both laws](bar_laws.png)', '']


def speed_section(out: Path) -> List[str]:
    lines = ['## Speed and memory of the laws (generic path)', '']
    path = out / 'speed.csv'
    if path.exists():
        with open(path) as f:
            rows = list(csv.DictReader(f))
        by_round: Dict[str, Dict[str, float]] = {}
        for r in rows:
            by_round.setdefault(r['round'], {})[r['law']] = float(r['run_time'])
        laws = ('linear', 'never_yielding', 'yielding')
        lines += [f'The bar at v0 = 20 m/s, {rows[0]["particles"]} particles (4 per element), {rows[0]["steps"]} steps, '
                  'one thread, kernels = \'generic\'; each round runs hencky, linear, elastoplastic never yielding '
                  '(sigma_y = 1e30) and yielding (sigma_y = 1 MPa, H = 1 GPa) one after the other; run time '
                  'ratios to hencky within a round (median, min-max over rounds):', '']
        table = []
        for law in laws:
            ratios = np.array([r[law] / r['hencky'] for r in by_round.values() if law in r and 'hencky' in r])
            if len(ratios):
                table.append([law, f'{np.median(ratios):.3f}', f'{ratios.min():.3f}', f'{ratios.max():.3f}', len(ratios)])
        lines += markdown_table(['law', 'time / hencky (median)', 'min', 'max', 'rounds'], table)
        lines.append('')
    path = out / 'instructions.csv'
    if path.exists():
        with open(path) as f:
            counts = {r['law']: int(r['instructions']) for r in csv.DictReader(f) if r['instructions'].strip().isdigit()}
        if 'hencky' in counts:
            lines += ['Instructions of the same runs at a tenth of the particles and 200 steps (callgrind, the plain '
                      'release build; repeatable under load):', '']
            lines += markdown_table(['law', 'instructions', '/ hencky'],
                                    [[law, f'{n:,}', f'{n / counts["hencky"]:.3f}'] for law, n in counts.items()])
            lines.append('')
    path = out / 'memory.csv'
    if path.exists():
        with open(path) as f:
            rows = [r for r in csv.DictReader(f) if r['max_rss_kib'].strip().isdigit()]
        lines += ['Largest resident memory (`/usr/bin/time -f %M`) of a short generic-path bar run at two sizes: '
                  'bytes per particle from the difference (everything per particle: the particles, the shape cache '
                  'and scratch columns, the law\'s state), and each law against hencky at the larger size:', '']
        table = []
        data: Dict[str, List[Tuple[int, int]]] = {}
        for r in rows:
            data.setdefault(r['law'], []).append((int(r['particles']), int(r['max_rss_kib'])))
        base = max(data.get('hencky', [(1, 0)]))
        for law, pts in data.items():
            pts.sort()
            if len(pts) < 2:
                continue
            slope = (pts[-1][1] - pts[0][1]) * 1024 / (pts[-1][0] - pts[0][0])
            extra = (pts[-1][1] - base[1]) * 1024 / pts[-1][0] if base[0] == pts[-1][0] else float('nan')
            table.append([law, f'{slope:.1f}', f'{extra:+.1f}'])
        lines += markdown_table(['law', 'bytes per particle (slope)', 'extra bytes per particle over hencky'], table)
        lines.append('')
    return lines


def main(argv: Optional[List[str]] = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument('out')
    args = ap.parse_args(argv)
    out = Path(args.out)
    wave = load_sweep(str(out / 'wave.h5'))
    fine = load_sweep(str(out / 'wave_fine.h5')) if (out / 'wave_fine.h5').exists() else None
    reference = next(iter(singles(out, 'single_ugimp').values()))
    wall = (out / 'wall_time.txt').read_text().split() if (out / 'wall_time.txt').exists() else ['nan'] * 3
    lines = ['# Materials: the plastic wave and the elastic laws', '',
             f'`bash studies/materials/run.sh` (code version {reference.code_version}; {wall[0]} s on {wall[2]} cores, '
             f'load average {wall[1]} at the start). Every number below comes from the files in this folder.', '']
    part, ss, fs = setup_section(reference)
    lines += part
    lines += convergence_section(out, wave, fine)
    lines += time_section(out, wave)
    part, rows = fronts_section(out, ss, fs)
    lines += part
    finest = max((n for (shape, n) in rows if shape == 'ugimp'), default=None)
    if finest is not None:
        run = singles(out, 'single_ugimp')[finest]
        s = run.snapshots[-1]
        X = s.extra['reference_x']
        volume = float(run.config['length']) / len(X)
        lines += [f'At {finest} elements (uGIMP) the run\'s L1 error is {l1(ss, X, s.stress, volume, s.time) / (ss["s2"] * float(run.config["length"])):.3e} '
                  f'against the small-strain solution and {l1(fs, X, s.stress, volume, s.time) / (ss["s2"] * float(run.config["length"])):.3e} '
                  'against the finite-strain one (relative to sigma_p L).', '']
    lines += energy_section(out)
    lines += stability_section(out)
    lines += bar_section(out)
    lines += speed_section(out)
    (out / 'summary.md').write_text('\n'.join(lines) + '\n')
    print(f'wrote {out / "summary.md"}')
    return 0


if __name__ == '__main__':
    raise SystemExit(main())
