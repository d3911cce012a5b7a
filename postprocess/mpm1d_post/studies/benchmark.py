"""The benchmark (studies/benchmark/run.sh, whose report.py calls `main`): reads the CSV files of OUTDIR,
writes OUTDIR/benchmark.png and OUTDIR/summary.md.  Usage: python studies/benchmark/report.py OUTDIR"""
import argparse
import csv
import os
import subprocess

import matplotlib
matplotlib.use('Agg')
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from ..tables import markdown_table  # noqa: E402

# Bytes each particle moves to or from memory per step in the passes (mpm_transfer), 8 per real,
# 4 per cell index. The kernels write the new cell back unconditionally (a vector store; a masked
# store saved nothing measurable and does not exist without AVX), so a pass that locates counts it.
#   usf : stress pass reads cell, stress, J, writes stress, J (36); move pass reads cell, x, X, v,
#         writes x, v, cell (48)
#   usl : one pass reads cell, x, X, v, stress, J and writes x, v, stress, J, cell (80)
#   musl: remap pass reads cell, x, X, v, writes x, v (44); stress pass reads cell, x, v, stress, J,
#         writes stress, J, cell (56)
BYTES = {'usf': 84, 'usl': 80, 'musl': 100}
# The grid adds about this many bytes per element per step (assembly, momentum solve, clearing and
# writing the element shares; the nodal arrays read by G2P), i.e. this / ppc per particle.
GRID_BYTES_PER_ELEMENT = 200


#: Speed targets of the shapes (ratio to linear on the fused kernels; every shape with FLIP on the fused
#: kernels, the path a run takes).
SHAPE_TARGETS = {'ugimp': 0.5, 'cpgimp': 0.5, 'bspline2': 0.5, 'bspline3': 0.33}
SHAPE_ORDER = ['linear', 'ugimp', 'cpgimp', 'bspline2', 'bspline3']


def shape_table(rows, lines):
    """Section on every shape and transfer (shapes.csv): the median rate, the median over rounds of the
    ratio to the fused linear run of the same scheme, size and round, and (USL) each transfer's cost
    against FLIP with the same shape, path (generic) and round. Returns ({(scheme, shape, n): (ratio to
    fused linear, path)} for FLIP on the fastest path the shape has, {(shape, transfer, n): cost / FLIP's})."""
    if not rows:
        return {}, {}
    def rate(r):
        return float(r['particle_steps_per_s'])
    fused = {(r['scheme'], int(r['particles']), r['round']): rate(r) for r in rows
             if r['path'] == 'fused' and r['shape'] == 'linear'}
    flip = {(r['shape'], int(r['particles']), r['round']): rate(r) for r in rows
            if r['path'] == 'generic' and r['scheme'] == 'usl' and r['transfer'] == 'flip'}
    groups = {}
    for r in rows:
        if not (r['path'] == 'fused' and r['shape'] == 'linear'):
            groups.setdefault((r['scheme'], r['shape'], r['transfer'], int(r['particles']), r['path']), []).append(r)
    ratio, cost = {}, {}
    lines += ['## Shapes and transfers\n',
              'One thread, 4 particles per element; each round runs linear on the fused kernels, then each shape '
              'and transfer on the generic path, and every wide shape with FLIP on the fused kernels (the path a run '
              'takes); ratios are medians over rounds of the paired ratios (range in brackets). One-thread '
              'times are CPU times (a core shared with other work does not count its waiting). Targets: GIMP and '
              'quadratic B-splines >= 0.5 x linear fused, cubic >= 0.33, a transfer <= 1.15 x FLIP (both on the '
              'generic path).\n']
    table = []
    scheme_order = ['usf', 'usl', 'musl']
    transfer_order = ['flip', 'pic', 'blend', 'apic']
    for key in sorted(groups, key=lambda k: (k[3], scheme_order.index(k[0]), SHAPE_ORDER.index(k[1]),
                                             transfer_order.index(k[2]), k[4])):
        s, shape, transfer, n, path = key
        rs = groups[key]
        q = [rate(r) / fused[s, n, r['round']] for r in rs if (s, n, r['round']) in fused]
        cell = f'{np.median(q):.2f} ({min(q):.2f}-{max(q):.2f})' if q else '-'
        if q and transfer == 'flip' and (path == 'fused' or (s, shape, n) not in ratio):
            ratio[s, shape, n] = (float(np.median(q)), path)
        c = '-'
        if s == 'usl' and transfer != 'flip' and path == 'generic':
            cs = [flip[shape, n, r['round']] / rate(r) for r in rs if (shape, n, r['round']) in flip]
            if cs:
                cost[shape, transfer, n] = float(np.median(cs))
                c = f'{np.median(cs):.2f} ({min(cs):.2f}-{max(cs):.2f})'
        table.append([f'{n:.0e}', s, shape, transfer, path, f'{np.median([rate(r) for r in rs]):.3g}', cell, c])
    lines += markdown_table(['particles', 'scheme', 'shape', 'transfer', 'path', 'particle-steps/s', '/ linear fused',
                             'cost / FLIP'], table)
    lines.append('')
    return ratio, cost


#: Targets of issue 28: whole runs (set-up included) of each scene and transfer against the fused bar's
#: at the same size and scheme (USL, 2 particles per element, 200 steps).
RUN_TARGETS = {'bar_pic': 0.8, 'bar_blend': 0.8, 'bar_apic': 0.8, 'column': 0.8, 'composite_bar': 0.8,
               'impact_frictionless': 0.7, 'impact_none': 0.7, 'manufactured': 0.5,
               # the cures (docs/theory.md), the same measure: the total-Lagrangian formulation's weights never
               # change, ASFLIP adds a gather, CPDI moves corners, XPIC(2) and FMPM(2) one particle pass more
               'bar_total': 0.9, 'bar_asflip': 0.8, 'bar_cpdi': 0.6, 'bar_xpic2': 0.5, 'bar_fmpm2': 0.5}
RUN_ORDER = ['bar', 'bar_generic', 'bar_pic', 'bar_blend', 'bar_apic', 'column', 'composite_bar', 'manufactured',
             'impact_frictionless', 'impact_none', 'bar_total', 'bar_cpdi', 'bar_xpic2', 'bar_fmpm2', 'bar_asflip',
             'bar_kernel']


def spread(q):
    """median (min-max) of a list of ratios"""
    return f'{np.median(q):.2f} ({min(q):.2f}-{max(q):.2f})'


def ratio_table(rows, lines, targets, counts=()):
    """Section on every scene and transfer against the fused bar (ratios.csv): per size and run the median
    rate, the median over rounds of the paired ratio to the fused bar's whole run, the bytes per particle
    the run holds; the bar's kernel alone (its steps, no set-up) beside them. Appends to `targets`."""
    if not rows:
        return
    def rate(r):
        return float(r['particle_steps_per_s'])
    bar = {(r['size'], r['round']): rate(r) for r in rows if r['run'] == 'bar'}
    lines += ['## Every scene and transfer against the fused bar (issue 28)\n',
              'Whole runs as a user starts them (run_simulation: set-up included, no history, no file), USL, '
              'linear shapes, 2 particles per element, 200 steps, one thread, CPU time; each round runs the fused '
              'bar first, then every other run, then the bar\'s kernel alone (its steps without set-up, as '
              '`throughput` times them). Ratio: median over rounds of rate / the fused bar\'s rate in the same round '
              '(min-max in brackets). bytes/particle: what the run holds per particle (particle arrays, the fused '
              'path\'s forces, the generic path\'s shape cache and scratch).\n']
    table = []
    groups = {}
    for r in rows:
        groups.setdefault((int(r['size']), r['run']), []).append(r)
    for key in sorted(groups, key=lambda k: (k[0], RUN_ORDER.index(k[1]) if k[1] in RUN_ORDER else 99)):
        n, run = key
        rs = groups[key]
        q = [rate(r) / bar[r['size'], r['round']] for r in rs if (r['size'], r['round']) in bar]
        target = RUN_TARGETS.get(run)
        cell = spread(q) if q else '-'
        table.append([f'{n:.0e}', run, rs[0]['path'], f'{float(rs[0]["bytes_per_particle"]):.0f}',
                      f'{np.median([rate(r) for r in rs]):.3g}', cell, target if target else '-'])
        if target and q:
            targets.append((f'{run}, {n:.0e} particles, >= {target} x the fused bar (whole runs)', float(np.median(q)),
                            float(np.median(q)) >= target))
    lines += markdown_table(['particles', 'run', 'path', 'bytes/particle', 'particle-steps/s', '/ fused bar', 'target'],
                            table)
    ir = {r['run']: float(r['instructions']) for r in counts if r['instructions']}
    if 'bar' in ir:
        lines += ['\nInstructions of each whole run at 1e4 particles (valgrind --tool=callgrind, the same runs; '
                  'repeatable on a busy machine, unlike the times above; valgrind counts a `rep stos` of memset by '
                  'its iterations, so clearing arrays weighs more here than in time):\n']
        lines += markdown_table(['run', 'instructions', 'fused bar / run'],
                                [[run, f'{ir[run]:.4g}', f'{ir["bar"] / ir[run]:.3f}'] for run in RUN_ORDER if run in ir])
    lines.append('\nThe kernel row is the bar\'s steps alone: a whole run also places the particles, builds the grid '
                 'and evaluates the exact solution, and each step adds its diagnostics; at 1e4 particles and 200 steps '
                 'that fixed work is a visible part of the run, so a run\'s rate is below the kernel\'s.\n')


def plastic_table(rows, counts, lines, targets):
    """Section on the elastoplastic bar against the Hencky bar, shape by shape (plastic.csv,
    plastic_callgrind.csv): per size and shape the median rates and the median over rounds of the paired
    ratio elastoplastic / Hencky (range in brackets). Appends to `targets` (>= 0.8)."""
    if not rows:
        return
    def rate(r):
        return float(r['particle_steps_per_s'])
    hencky = {(r['size'], r['shape'], r['round']): rate(r) for r in rows if r['law'] == 'hencky'}
    hencky_path = {(int(r['size']), r['shape']): r['path'] for r in rows if r['law'] == 'hencky'}
    lines += ['## The elastoplastic bar against the Hencky bar\n',
              'Whole runs (run_simulation, set-up included), USL, FLIP, 2 particles per element, 200 steps, one '
              'thread, CPU time; the yield stress a third of the largest stress the elastic bar reaches in the run, '
              'the hardening modulus E/10 (yielded: the fraction of the particles that yielded by the end). Each '
              'round runs every shape\'s Hencky bar, then the same bar elastoplastic; ratio: median over rounds of '
              'the elastoplastic rate / the Hencky rate of the same shape and round (min-max). Target >= 0.8.\n']
    groups = {}
    for r in rows:
        if r['law'] == 'elastoplastic':
            groups.setdefault((int(r['size']), r['shape']), []).append(r)
    table = []
    for key in sorted(groups, key=lambda k: (k[0], SHAPE_ORDER.index(k[1]) if k[1] in SHAPE_ORDER else 99)):
        n, shape = key
        rs = groups[key]
        q = [rate(r) / hencky[r['size'], shape, r['round']] for r in rs if (r['size'], shape, r['round']) in hencky]
        h = [v for k, v in hencky.items() if int(k[0]) == n and k[1] == shape]
        table.append([f'{n:.0e}', shape, f'{hencky_path.get(key, "-")}, {rs[0]["path"]}',
                      f'{np.median(h) if h else float("nan"):.3g}', f'{np.median([rate(r) for r in rs]):.3g}',
                      f'{float(rs[0]["yielded_fraction"]):.2f}', spread(q) if q else '-'])
        if q:
            targets.append((f'elastoplastic bar, {shape}, {n:.0e} particles, >= 0.8 x the Hencky bar', float(np.median(q)),
                            float(np.median(q)) >= 0.8))
    lines += markdown_table(['particles', 'shape', 'paths (Hencky, elastoplastic)', 'Hencky particle-steps/s',
                             'elastoplastic particle-steps/s', 'yielded', 'elastoplastic / Hencky'], table)
    ir = {(r['shape'], r['law']): float(r['instructions']) for r in counts if r['instructions']}
    if ir:
        lines += ['\nInstructions of each whole run at 1e4 particles (valgrind --tool=callgrind):\n']
        lines += markdown_table(['shape', 'Hencky', 'elastoplastic', 'Hencky / elastoplastic'],
                                [[shape, f'{ir[shape, "hencky"]:.4g}', f'{ir[shape, "elastoplastic"]:.4g}',
                                  f'{ir[shape, "hencky"] / ir[shape, "elastoplastic"]:.3f}'] for shape in SHAPE_ORDER
                                 if (shape, 'hencky') in ir and (shape, 'elastoplastic') in ir])
    lines.append('')


#: Targets of an implicit step: its time per particle-step / an explicit fused one's (lumped mass).
IMPLICIT_TARGETS = {'implicit_linear_lumped': 4.0, 'implicit_hencky_lumped': 6.0}
#: The runs of `mpm1d_bench implicit`, in the order of its table.
IMPLICIT_ORDER = ['explicit_linear', 'explicit_hencky', 'implicit_linear_lumped', 'implicit_hencky_lumped',
                  'implicit_linear_consistent', 'implicit_hencky_consistent']


def implicit_table(rows, counts, lines, targets):
    """Section on an implicit step against an explicit one (implicit.csv, implicit_callgrind.csv): per run the
    median rate, Newton solves per step and the median over rounds of the paired ratio of times per particle-step,
    implicit / explicit of the same law (range in brackets), of the whole runs and, where the file has it, of
    their time loops alone (the steps without the set-up; the targets' measure then). Appends to `targets`."""
    if not rows:
        return
    def rate(r, column='particle_steps_per_s'):
        return float(r[column])
    loops = all(r.get('loop_particle_steps_per_s') for r in rows)
    lines += ['## An implicit step against an explicit one\n',
              'The default bar, 1e5 particles (2 per element), dt = 0.5 dx/c for both; explicit: USL on the fused '
              'kernels, 200 steps; implicit: Newmark\'s trapezoidal rule with Newton, 20 steps; one thread, CPU '
              'time. Each round runs the explicit bars (laws linear and Hencky), then the implicit ones. Ratio: '
              'median over rounds of the implicit time per particle-step / the explicit one of the same law and '
              'round (min-max), of the whole runs and of their time loops alone (the set-up, paid once a run, '
              'weighs ten times more on 20 implicit steps than on 200 explicit ones). Targets (lumped mass, time '
              'per particle-step: the time loops\'): linear <= 4, Hencky <= 6.\n']
    groups = {}
    for r in rows:
        groups.setdefault(r['run'], []).append(r)
    table = []
    for run in sorted(groups, key=lambda k: IMPLICIT_ORDER.index(k) if k in IMPLICIT_ORDER else 99):
        rs = groups[run]
        ratios = {}
        for column in ('particle_steps_per_s', 'loop_particle_steps_per_s') if loops else ('particle_steps_per_s',):
            explicit = {(r['law'], r['round']): rate(r, column) for r in rows if r['run'].startswith('explicit')}
            ratios[column] = [explicit[r['law'], r['round']] / rate(r, column) for r in rs
                              if (r['law'], r['round']) in explicit]
        q = ratios['particle_steps_per_s']
        loop = ratios.get('loop_particle_steps_per_s', [])
        table.append([run, rs[0]['law'], rs[0]['mass'], f'{np.median([rate(r) for r in rs]):.3g}',
                      f'{float(rs[0]["solves_per_step"]):.2f}', spread(q) if q and run.startswith('implicit') else '-',
                      spread(loop) if loop and run.startswith('implicit') else '-'])
        measure = loop or q
        if run in IMPLICIT_TARGETS and measure:
            which = 'time loop' if loop else 'whole run'
            targets.append((f'{run}, time per particle-step ({which}) <= {IMPLICIT_TARGETS[run]} x explicit',
                            float(np.median(measure)), float(np.median(measure)) <= IMPLICIT_TARGETS[run]))
    lines += markdown_table(['run', 'law', 'mass', 'particle-steps/s', 'Newton solves per step',
                             'time / explicit (whole run)', 'time / explicit (time loop)'], table)
    ir = {r['run']: float(r['instructions']) for r in counts if r['instructions']}
    if ir:
        lines += ['\nInstructions per particle-step (valgrind --tool=callgrind; whole runs at 2e4 particles, 100 '
                  'explicit or 10 implicit steps):\n']
        table = []
        for run in IMPLICIT_ORDER:
            if run in ir:
                per = ir[run] / (2e4 * (100 if run.startswith('explicit') else 10))
                ref = ir.get('explicit_' + ('linear' if 'linear' in run else 'hencky'))
                table.append([run, f'{per:.0f}', f'{per / (ref / 2e6):.2f}' if ref else '-'])
        lines += markdown_table(['run', 'instructions per particle-step', '/ explicit'], table)
    lines.append('')


def table2_table(rows, counts, lines, targets):
    """Section on the Table-2 error pass against an older build (table2.csv, table2_callgrind.csv), per build
    (the study scripts' flags and, when run.sh was given OLD_PORTABLE_MPM1D, the portable one)."""
    if rows:
        lines += ['## Table-2 error pass against an older build\n',
                  'USF and USL sweeps of the founding paper (600 cases each, 2 periods, no timing pass), this build '
                  'and OLD_MPM1D (OLD_PORTABLE_MPM1D for the portable build): on one thread both at once, one on '
                  'each of two cores, swapping cores every round; on two threads alternately. Whole process wall '
                  'time on a shared machine (a second view: the instruction counts below are the repeatable one). '
                  'Speed ratio: median over rounds of old time / new time (min-max).\n']
        table = []
        for build in sorted({r.get('build', '') for r in rows}):
            for scheme in ('usf', 'usl'):
                for t in ('1', '2'):
                    sel = [r for r in rows if r.get('build', '') == build and r['scheme'] == scheme and r['threads'] == t]
                    new = {r['repeat']: float(r['seconds']) for r in sel if r['binary'] == 'new'}
                    old = {r['repeat']: float(r['seconds']) for r in sel if r['binary'] == 'old'}
                    q = [old[k] / new[k] for k in new if k in old]
                    if new:
                        table.append([build or '-', scheme, t, f'{np.median(list(new.values())):.3f}',
                                      f'{np.median(list(old.values())) if old else float("nan"):.3f}',
                                      spread(q) if q else '-'])
                    if q:
                        targets.append((f'Table-2 {scheme}, {build or "this"} build, {t} thread(s), wall time, >= 1.0 x '
                                        'the old build', float(np.median(q)), float(np.median(q)) >= 1.0))
        lines += markdown_table(['build', 'scheme', 'threads', 'new s (median)', 'old s (median)', 'speed new / old'],
                                table)
        lines.append('')
    if counts:
        lines += ['Instruction counts (valgrind --tool=callgrind, one thread; repeatable on a busy machine) and the '
                  'misses of its simulated level-1 instruction and data caches (a step whose code or data do not fit '
                  'in them costs time that the instruction count does not show):\n']
        table = []
        for build in sorted({r.get('build', '') for r in counts}):
            for scheme in ('usf', 'usl'):
                sel = [r for r in counts if r.get('build', '') == build and r['scheme'] == scheme and r['instructions']]
                c = {r['binary']: float(r['instructions']) for r in sel}
                misses = []
                for cache in ('i1_misses', 'd1_misses'):
                    m = {r['binary']: float(r[cache]) for r in sel if r.get(cache)}
                    misses += [f'{m[b]:.3g}' if b in m else '-' for b in ('new', 'old')]
                if 'new' in c and 'old' in c:
                    table.append([build or '-', scheme, f'{c["new"]:.4g}', f'{c["old"]:.4g}', f'{c["old"] / c["new"]:.3f}']
                                 + misses)
                    targets.append((f'Table-2 {scheme}, {build or "this"} build, instructions, old / new >= 1.0',
                                    c['old'] / c['new'], c['old'] / c['new'] >= 1.0))
        lines += markdown_table(['build', 'scheme', 'new', 'old', 'old / new', 'I1 misses new', 'I1 misses old',
                                 'D1 misses new', 'D1 misses old'], table)
        lines.append('')


def optional(d, name):
    path = os.path.join(d, name)
    return read(path) if os.path.exists(path) else []


def read(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument('outdir')
    args = ap.parse_args(argv)
    d = args.outdir
    try:
        version = subprocess.run(['git', 'describe', '--always', '--dirty'], capture_output=True, text=True,
                                 cwd=os.path.dirname(os.path.abspath(__file__))).stdout.strip()
    except OSError:
        version = 'unknown'
    classic = ('bandwidth.csv', 'throughput.csv', 'threads.csv', 'study.csv', 'memory.csv', 'sweep.csv')
    if not all(os.path.exists(os.path.join(d, f)) for f in classic):  # PARTS: only some parts were run
        flags = open(os.path.join(d, 'flags.txt')).read().strip() if os.path.exists(os.path.join(d, 'flags.txt')) else ''
        lines = ['# mpm1d benchmark (some parts)\n', f'Code version {version}. Build: {flags}'.replace('\n', '; ') + '\n']
        targets = []
        ratio_table(optional(d, 'ratios.csv'), lines, targets, optional(d, 'ratios_callgrind.csv'))
        plastic_table(optional(d, 'plastic.csv'), optional(d, 'plastic_callgrind.csv'), lines, targets)
        implicit_table(optional(d, 'implicit.csv'), optional(d, 'implicit_callgrind.csv'), lines, targets)
        table2_table(optional(d, 'table2.csv'), optional(d, 'table2_callgrind.csv'), lines, targets)
        lines += ['## Targets\n'] + [f'- {t}: {v:.3f} -> {"met" if ok else "NOT met"}' for t, v, ok in targets]
        open(os.path.join(d, 'summary.md'), 'w').write('\n'.join(lines) + '\n')
        return 0
    bw = read(os.path.join(d, 'bandwidth.csv'))
    tp = read(os.path.join(d, 'throughput.csv'))
    th = read(os.path.join(d, 'threads.csv'))
    st = read(os.path.join(d, 'study.csv'))
    mem = read(os.path.join(d, 'memory.csv'))
    flags = open(os.path.join(d, 'flags.txt')).read().strip()

    def bandwidth(kernel, threads):
        v = [float(r['bytes_per_s']) for r in bw if r['kernel'] == kernel and int(r['threads']) == threads]
        return np.median(v), min(v), max(v)

    bw1 = bandwidth('update', 1)[0]
    bw2 = bandwidth('update', 2)[0]
    triad1 = bandwidth('triad', 1)[0]
    has_pattern = any(r['kernel'] == 'particles' for r in bw)
    pattern1 = bandwidth('particles', 1)[0] if has_pattern else float('nan')
    pattern2 = bandwidth('particles', 2)[0] if has_pattern else float('nan')
    sweep = read(os.path.join(d, 'sweep.csv'))
    lines = [f'# mpm1d benchmark\n', f'Code version {version}. Build: {flags}'.replace('\n', '; ') + '\n',
             'All rates are medians of the repeats; the spread is min-max. Set-up is not timed; the per-step '
             'diagnostics are. -march=native is for local runs only, not for portable builds.\n',
             '## Memory bandwidth (STREAM-style, arrays of 4e7 doubles)\n']
    table = []
    for k in ('triad', 'update', 'particles'):
        for t in (1, 2):
            if k == 'particles' and not has_pattern:
                continue
            m, lo, hi = bandwidth(k, t)
            table.append([k, t, f'{m/1e9:.1f}', f'{lo/1e9:.1f}-{hi/1e9:.1f}'])
    lines += markdown_table(['kernel', 'threads', 'GB/s median', 'min-max'], table)
    lines.append('\ntriad a = b + s c is counted as STREAM does (24 B, the write-allocate read of a not counted); '
                 'update a = a + s b really moves its 24 B and has the passes\' in-place access pattern, so it sets '
                 'the (strictest) bound. particles moves the 80 B of one USL pass per particle (1e7 particles: read '
                 'x, X, v, stress, J, cell; write x, v, stress, J, cell) with next to no arithmetic: what memory '
                 'allows a pass with 11 streams, the traffic ceiling in the tables below.\n')

    lines += ['## Particle-steps per second, one thread (10 particles per element)\n']
    table = []
    rates = {}
    for s in ('usf', 'usl', 'musl'):
        for n in sorted({int(r['particles']) for r in tp}):
            v = [float(r['particle_steps_per_s']) for r in tp if r['scheme'] == s and int(r['particles']) == n]
            if not v:
                continue
            steps = [r['steps'] for r in tp if r['scheme'] == s and int(r['particles']) == n][0]
            med = np.median(v)
            rates[s, n] = (med, min(v), max(v))
            bound = bw1 / BYTES[s]
            bound_grid = bw1 / (BYTES[s] + GRID_BYTES_PER_ELEMENT / 10)
            table.append([s, f'{n:.0e}', steps, f'{med:.3g}', f'{min(v):.3g}-{max(v):.3g}', BYTES[s], f'{bound:.3g}',
                          f'{100*med/bound:.0f}', f'{100*med/bound_grid:.0f}', f'{100*med*BYTES[s]/triad1:.0f}',
                          f'{100*med*BYTES[s]/pattern1:.0f}'])
    lines += markdown_table(['scheme', 'particles', 'steps', 'rate median', 'min-max', 'bytes/particle-step',
                             'bound (update BW / bytes)', '% of bound', '% of bound incl. grid', '% of triad bound',
                             '% of traffic ceiling'], table)
    lines.append('\nThe bound applies when the particle arrays do not fit in the caches (1e6 particles = 44 MB and '
                 'more; L3 is 32 MB); smaller runs are limited by the arithmetic, not by memory.\n')

    # Roofline at the largest size: the in-cache rate (1e3-1e5 particles, no memory waits) is the
    # arithmetic ceiling of the kernel; a large run cannot beat the smaller of it and the memory bound.
    def in_cache(s):  # the medians of the sizes whose particles fit in the caches
        return [rates[s, n][0] for n in (1000, 10000, 100000) if (s, n) in rates]

    big = max(n for (_, n) in rates)
    ceilings = {}
    lines += [f'## Roofline at {big:.0e} particles (one thread)\n']
    table = []
    for s in ('usf', 'usl', 'musl'):
        cache = in_cache(s)
        if not cache or (s, big) not in rates:
            continue
        ceilings[s] = max(cache)
        r = rates[s, big][0]
        table.append([s, f'{ceilings[s]:.3g}', f'{bw1/BYTES[s]:.3g}', f'{triad1/BYTES[s]:.3g}', f'{pattern1/BYTES[s]:.3g}',
                      f'{r:.3g}', f'{100*r/ceilings[s]:.0f}', f'{100*ceilings[s]*BYTES[s]/bw1:.0f}',
                      f'{100*ceilings[s]*BYTES[s]/triad1:.0f}'])
    lines += markdown_table(['scheme', 'arithmetic ceiling (best in-cache median)', 'update bound', 'triad bound',
                             'traffic ceiling', f'{big:.0e} rate', '% of arithmetic ceiling',
                             'ceiling as % of update bound', 'ceiling as % of triad bound'], table)
    lines.append('\nA large run overlaps memory with arithmetic at best, so its rate cannot exceed the arithmetic '
                 'ceiling. Where the ceiling is below 80 % of a memory bound, that share of the bound is out of '
                 'reach of better streaming or prefetching: it needs fewer instructions per particle.\n')

    lines += ['## OpenMP inside one run\n']
    table = []
    speedups = {}
    for s in ('usf', 'usl', 'musl'):
        for n in sorted({int(r['particles']) for r in th}):
            r1 = [float(r['particle_steps_per_s']) for r in th if r['scheme'] == s and int(r['particles']) == n
                  and r['threads'] == '1']
            r2 = [float(r['particle_steps_per_s']) for r in th if r['scheme'] == s and int(r['particles']) == n
                  and r['threads'] == '2']
            if r1 and r2:
                speedups[s, n] = np.median(r2) / np.median(r1)
                table.append([s, f'{n:.0e}', f'{np.median(r1):.3g}', f'{np.median(r2):.3g}', f'{speedups[s, n]:.2f}',
                              f'{bw2/BYTES[s]:.3g}', f'{pattern2/BYTES[s]:.3g}'])
    lines += markdown_table(['scheme', 'particles', '1 thread', '2 threads', 'speed-up',
                             '2-thread bound (2-thread update BW / bytes)', '2-thread traffic ceiling'], table)
    lines.append('\nResults are bit-for-bit identical with 1 and 2 threads '
                 '(test/unit/scheme/fused/test_fused_threads.f90): the segments '
                 'of a run are fixed by its size, not by the thread count.\n')

    sweep_times = {t: [float(r['seconds']) for r in sweep if int(r['threads']) == t] for t in (1, 2)}
    sweep_cases = int(sweep[0]['cases'])
    sweep_speedup = np.median(sweep_times[1]) / np.median(sweep_times[2])
    lines += ['## Sweep throughput (Table-2 error pass, both schemes)\n',
              f'{sweep_cases} runs (USF and USL; 1, 3, 7, 10, 20, 50 elements; 1-10 particles per element; 5-50 % of '
              'dx/c; 2 periods), one case per thread, no timing pass; whole process wall time, 1 and 2 threads '
              'alternately.\n']
    lines += markdown_table(['threads', 'seconds median', 'min-max', 'runs/s'],
                            [[t, f'{np.median(v):.3f}', f'{min(v):.3f}-{max(v):.3f}', f'{sweep_cases/np.median(v):.0f}']
                             for t, v in sweep_times.items()])
    lines.append(f'\nSpeed-up of 2 threads over 1: **{sweep_speedup:.2f}**.\n')

    # cost model: seconds = C * elements^2 * ppc / dt_fraction, C from the base case
    base = [r for r in st if r['elements'] == '200' and r['ppc'] == '4' and abs(float(r['dt_fraction']) - 0.2) < 1e-9]
    c0 = np.median([float(r['seconds']) for r in base]) / (200**2 * 4 / 0.2)
    cases = sorted({(int(r['elements']), int(r['ppc']), float(r['dt_fraction'])) for r in st})
    lines += ['## Cost of a study run (USL, one period, one thread)\n',
              'Model: seconds = C elements^2 ppc / dt_fraction, C fitted to the 200-element, 4 ppc, 0.2 case.\n']
    table = []
    study_rows = []
    for e, p, k in cases:
        rows = [r for r in st if int(r['elements']) == e and int(r['ppc']) == p and abs(float(r['dt_fraction']) - k) < 1e-9]
        sec = np.median([float(r['seconds']) for r in rows])
        model = c0 * e * e * p / k
        expected_steps = int(base[0]['steps']) * (e / 200) * (0.2 / k)
        if int(rows[0]['steps']) < 0.99 * expected_steps:  # a guard stopped the run (unstable step)
            table.append([e, p, k, f'{rows[0]["steps"]} (stopped by a guard)', f'{sec:.4g}', f'{model:.4g}', '-'])
            continue
        study_rows.append((e, p, k, sec, model))
        table.append([e, p, k, rows[0]['steps'], f'{sec:.4g}', f'{model:.4g}', f'{sec/model:.2f}'])
    lines += markdown_table(['elements', 'ppc', 'dt_fraction', 'steps', 'seconds median', 'model', 'measured/model'],
                            table)
    lines.append('\nAt few particles per element the per-step grid work (proportional to elements^2 / dt_fraction, '
                 'not to ppc) and the fixed cost of a step make the measured cost exceed the model.\n')

    rss = {int(r['particles']): int(r['max_rss_kib']) for r in mem}
    small, big = min(rss), max(rss)
    per_particle = (rss[big] - rss[small]) * 1024 / (big - small)
    lines += ['## Memory\n', f'Max RSS (/usr/bin/time -v) of a {big:.0e}-particle USL run (10 per element) minus that of a '
              f'{small:.0e}-particle run, per particle: **{per_particle:.1f} bytes** (particle arrays 44 B, grid '
              '11 arrays of 8 B per element = 8.8 B per particle at 10 ppc).\n']

    gen = read(os.path.join(d, 'generic.csv')) if os.path.exists(os.path.join(d, 'generic.csv')) else []
    gen_ratio = {}
    if gen:
        lines += ['## Generic path against the fused kernels\n',
                  'Paired runs (fused and generic alternately, one thread, 10 particles per element); ratio of the '
                  'medians, generic / fused particle-steps per second. The generic path (`kernels=\'generic\'`: '
                  'shape cache, per-particle mass and volume, mpm_schemes over mpm_operations) is what new shapes, '
                  'materials and scenes run on.\n']
        table = []
        for s in ('usf', 'usl', 'musl'):
            for n in sorted({int(r['particles']) for r in gen if r['scheme'] == s}):
                f = np.median([float(r['particle_steps_per_s']) for r in gen
                               if r['scheme'] == s and int(r['particles']) == n and r['kernels'] == 'fused'])
                g = np.median([float(r['particle_steps_per_s']) for r in gen
                               if r['scheme'] == s and int(r['particles']) == n and r['kernels'] == 'generic'])
                gen_ratio[s, n] = g / f
                table.append([s, f'{n:.0e}', f'{f:.3g}', f'{g:.3g}', f'{g / f:.2f}'])
        lines += markdown_table(['scheme', 'particles', 'fused (/s)', 'generic (/s)', 'generic / fused'], table)
        lines.append('')
    if os.path.exists(os.path.join(d, 'memory_generic.csv')):
        gm = {int(r['particles']): int(r['max_rss_kib']) for r in read(os.path.join(d, 'memory_generic.csv'))}
        lo, hi = min(gm), max(gm)
        lines.append(f'Memory of the generic path, per particle (RSS difference {lo:.0e} to {hi:.0e} particles): '
                     f'**{(gm[hi] - gm[lo]) * 1024 / (hi - lo):.1f} bytes** (particle arrays 44 B + per-particle '
                     'mass and volume 16 B + shape cache 36 B + three scratch values 24 B (in P2G the per-particle momentum and stress times volume, in G2P the gathered acceleration, velocity and strain rate), and the grid).\n')

    shape_rows = read(os.path.join(d, 'shapes.csv')) if os.path.exists(os.path.join(d, 'shapes.csv')) else []
    shape_ratio, transfer_cost = shape_table(shape_rows, lines)
    run_targets = []
    ratio_table(optional(d, 'ratios.csv'), lines, run_targets, optional(d, 'ratios_callgrind.csv'))
    plastic_table(optional(d, 'plastic.csv'), optional(d, 'plastic_callgrind.csv'), lines, run_targets)
    implicit_table(optional(d, 'implicit.csv'), optional(d, 'implicit_callgrind.csv'), lines, run_targets)
    table2_table(optional(d, 'table2.csv'), optional(d, 'table2_callgrind.csv'), lines, run_targets)

    lines += ['## Targets\n']
    def mark(ok):
        return 'met' if ok else 'NOT met'
    for s in ('usf', 'usl'):
        small_rates = in_cache(s)
        lines.append(f'- {s}, one thread, 1e3-1e5 particles >= 2.5e8/s: {min(small_rates):.3g}-{max(small_rates):.3g} '
                     f'-> {mark(min(small_rates) >= 2.5e8)}')
    for s in ('usf', 'usl', 'musl'):
        if (s, 10**7) in rates:
            r = rates[s, 10**7][0]
            frac = r / (bw1 / BYTES[s])
            lines.append(f'- {s}, 1e7 particles >= 1.5e8/s: {r:.3g}/s -> {mark(r >= 1.5e8)}; >= 80 % of the bound: '
                         f'{100*frac:.0f} % of the update bound, {100*r*BYTES[s]/triad1:.0f} % of the triad bound, '
                         f'{100*r*BYTES[s]/pattern1:.0f} % of the traffic ceiling -> {mark(frac >= 0.8)}'
                         + (f' (arithmetic ceiling {ceilings[s]:.3g}/s = {100*ceilings[s]*BYTES[s]/bw1:.0f} % of the '
                            'update bound)' if s in ceilings else ''))
    for (s, n), v in sorted(speedups.items()):
        lines.append(f'- {s}, {n:.0e} particles, 2 threads speed-up >= 1.7: {v:.2f} -> {mark(v >= 1.7)}')
    lines.append(f'- Table-2 error pass, 2 threads over 1 >= 1.8: {sweep_speedup:.2f} -> {mark(sweep_speedup >= 1.8)}')
    lines.append(f'- memory <= 80 B per particle: {per_particle:.1f} -> {mark(per_particle <= 80)}')
    for (s, n), v in sorted(gen_ratio.items()):
        if n <= 10**5:
            lines.append(f'- {s}, {n:.0e} particles (in cache), generic >= 0.5 x fused: {v:.2f} -> {mark(v >= 0.5)}')
    for (s, shape, n), (v, path) in sorted(shape_ratio.items()):
        if shape in SHAPE_TARGETS:
            lines.append(f'- {s}, {n:.0e} particles, {shape} ({path}) >= {SHAPE_TARGETS[shape]} x linear (fused): '
                         f'{v:.2f} -> {mark(v >= SHAPE_TARGETS[shape])}')
    for (shape, transfer, n), v in sorted(transfer_cost.items()):
        if n <= 10**5:
            lines.append(f'- usl, {n:.0e} particles, {shape}: {transfer} costs <= 1.15 x FLIP: {v:.2f} -> {mark(v <= 1.15)}')
    lines += [f'- {t}: {v:.3f} -> {mark(ok)}' for t, v, ok in run_targets]
    open(os.path.join(d, 'summary.md'), 'w').write('\n'.join(lines) + '\n')

    fig, ax = plt.subplots(2, 2, figsize=(12, 9))
    for s, mk in (('usf', 'o'), ('usl', 's'), ('musl', '^')):
        ns = sorted(n for (ss, n) in rates if ss == s)
        med = np.array([rates[s, n][0] for n in ns])
        err = np.array([[rates[s, n][0] - rates[s, n][1] for n in ns], [rates[s, n][2] - rates[s, n][0] for n in ns]])
        ax[0, 0].errorbar(ns, med, yerr=err, marker=mk, label=f'{s} ({BYTES[s]} B/particle-step)')
        ax[0, 0].axhline(bw1 / BYTES[s], ls=':', color=ax[0, 0].lines[-1].get_color())
    ax[0, 0].axhline(2.5e8, color='k', ls='--', lw=0.8, label='target 2.5e8')
    ax[0, 0].set(xscale='log', xlabel='particles (10 per element)', ylabel='particle-steps / s (1 thread)',
                 title='Throughput; dotted: bandwidth bound (1 thread)')
    ax[0, 0].legend(fontsize=8)
    labels = [f'{s}\n{n:.0e}' for (s, n) in sorted(speedups)]
    ax[0, 1].bar(range(len(labels)), [speedups[k] for k in sorted(speedups)])
    ax[0, 1].axhline(1.7, color='k', ls='--', lw=0.8, label='target 1.7')
    ax[0, 1].axhline(bw2 / bw1, color='r', ls=':', label=f'bandwidth ratio 2/1 threads = {bw2/bw1:.2f}')
    ax[0, 1].set_xticks(range(len(labels)), labels, fontsize=8)
    ax[0, 1].set(ylabel='speed-up, 2 threads vs 1', title='OpenMP inside one run')
    ax[0, 1].legend(fontsize=8)
    sec = np.array([r[3] for r in study_rows])
    model = np.array([r[4] for r in study_rows])
    ax[1, 0].loglog(model, sec, 'o')
    for e, p, k, s_, m_ in study_rows:
        ax[1, 0].annotate(f'{e},{p},{k}', (m_, s_), fontsize=7)
    lim = [min(model.min(), sec.min()) / 2, max(model.max(), sec.max()) * 2]
    ax[1, 0].plot(lim, lim, 'k--', lw=0.8)
    ax[1, 0].set(xlabel='model C elements^2 ppc / dt_fraction (s)', ylabel='measured run time (s)',
                 title='Cost of a study run (USL, one period; labels: elements, ppc, fraction)')
    kinds = [(k, t) for k in ('triad', 'update', 'particles') for t in (1, 2) if k != 'particles' or has_pattern]
    ax[1, 1].bar(range(len(kinds)), [bandwidth(k, t)[0] / 1e9 for k, t in kinds])
    ax[1, 1].set_xticks(range(len(kinds)), [f'{k}\n{t} thread(s)' for k, t in kinds], fontsize=8)
    ax[1, 1].set(ylabel='GB/s', title=f'Memory bandwidth; memory {per_particle:.1f} B/particle')
    fig.suptitle(f'mpm1d benchmark ({version}; {flags.splitlines()[0]})', fontsize=9)
    fig.tight_layout()
    fig.savefig(os.path.join(d, 'benchmark.png'), dpi=110)
    return 0


if __name__ == '__main__':
    raise SystemExit(main())
