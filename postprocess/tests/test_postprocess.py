#!/usr/bin/env python3
"""Tests of the mpm1d post-processing, on small synthetic HDF5 files laid out as mpm1d writes them.

Run as a plain script (prints ``N passed, M failed`` and exits non-zero on failure):

    .venv/bin/python postprocess/tests/test_postprocess.py

or, as test/run_tests.sh does, ``.venv/bin/python -m pytest postprocess``.

or under pytest, which collects the ``test_*`` functions.

The synthetic files follow the layout the Fortran writer produces: fixed-length, space-padded
byte strings, scalar attributes, scalar ``/summary`` datasets, 1-D ``/cases`` columns. Their
numbers are physically plausible: the exact u_cm of the bar, a grid velocity from a real
lumped-mass particle-to-grid mapping, errors that fall with elements (faster for USL), fall with
the step on fine meshes and not on coarse ones, times proportional to particles / step.
"""

from __future__ import annotations

import contextlib
import io
import os
import shutil
import subprocess
import sys
import tempfile
import traceback
from pathlib import Path

import numpy as np

import h5py

from mpm1d_post import figures
from mpm1d_post.studies import paper as make_paper_figures
from mpm1d_post.studies import paper_claims as analysis
from mpm1d_post.loader import Mpm1dFileError, load_run, load_sweep, parse_parameters

#: The repository's root (this file is postprocess/tests/test_postprocess.py).
ROOT = Path(__file__).resolve().parents[2]

CODE_VERSION = 'mpm1d 0.1.0'
BAR = dict(scene_kind='vibrating_bar', length=25.0, youngs_modulus=200e9, density=7800.0,
           velocity_amplitude=0.1, mode=1)
ELEMENTS = (1, 3, 7, 10, 20, 50)
PPE = tuple(range(1, 11))
DT_FRACTIONS = tuple(round(0.05 * i, 2) for i in range(1, 11))


# --------------------------------------------------------------------------------------------
# Synthetic files in mpm1d's layout
# --------------------------------------------------------------------------------------------

def fortran_string(text: str, length: int = 0) -> np.bytes_:
    """A fixed-length, space-padded byte string, as Fortran writes it."""
    return np.bytes_(text.ljust(max(length, len(text), 1)).encode())


def fortran_strings(texts) -> np.ndarray:
    width = max(len(t) for t in texts) + 2
    return np.array([t.ljust(width).encode() for t in texts], dtype=f'S{width}')


def bar_quantities(elements: int, dt_fraction: float, periods: float = 2.0) -> dict:
    """Resolved quantities of the bar problem, as /config holds them."""
    c = np.sqrt(BAR['youngs_modulus'] / BAR['density'])
    dx = BAR['length'] / elements
    beta = np.pi / (2 * BAR['length'])
    period = 2 * np.pi / (beta * c)
    dt = dt_fraction * dx / c
    steps = int(np.ceil(periods * period / dt))
    return dict(wave_speed=c, dx=dx, dt=dt, period=period, final_time=periods * period,
                steps=steps, beta=beta, omega=beta * c)


def write_config(group: h5py.Group, scheme: str, elements: int, ppe: int, dt_fraction: float):
    """The /config attributes of one case."""
    q = bar_quantities(elements, dt_fraction)
    for key, value in BAR.items():
        group.attrs[key] = fortran_string(value) if isinstance(value, str) else value
    group.attrs['mode'] = np.int32(BAR['mode'])
    group.attrs['scheme'] = fortran_string(scheme)
    group.attrs['elements'] = np.int32(elements)
    group.attrs['particles_per_element'] = np.int32(ppe)
    group.attrs['dt_fraction'] = dt_fraction
    group.attrs['periods'] = 2.0
    for key in ('wave_speed', 'dx', 'dt', 'period', 'final_time'):
        group.attrs[key] = q[key]
    group.attrs['steps'] = np.int32(q['steps'])
    group.attrs['namelist'] = fortran_string(
        f"&discretisation scheme='{scheme}', elements={elements} /")


def initial_grid(elements: int, ppe: int):
    """Particle positions and the nodal velocity of a lumped-mass P2G of v0·sin(βx) with linear
    shape functions, node 0 fixed (as mpm1d's step-0 snapshot)."""
    length, v0 = BAR['length'], BAR['velocity_amplitude']
    beta = np.pi / (2 * length)
    dx = length / elements
    x_p = (np.arange(elements * ppe) + 0.5) * dx / ppe
    v_p = v0 * np.sin(beta * x_p)
    grid_x = np.linspace(0.0, length, elements + 1)
    cell = np.minimum((x_p // dx).astype(int), elements - 1)
    xi = x_p / dx - cell
    mass, momentum = np.zeros(elements + 1), np.zeros(elements + 1)
    for node, weight in ((cell, 1 - xi), (cell + 1, xi)):
        np.add.at(mass, node, weight)
        np.add.at(momentum, node, weight * v_p)
    grid_v = np.where(mass > 0, momentum / np.where(mass > 0, mass, 1), 0.0)
    grid_v[0] = 0.0
    return x_p, v_p, grid_x, grid_v


def synthetic_error(scheme: str, elements: int, ppe: int, dt_fraction: float) -> float:
    """A plausible max u_cm error (m): spatial error falling with elements (faster for USL),
    a step error on fine meshes, and on coarse meshes an error that grows as the step shrinks."""
    rate = 1.6 if scheme == 'usf' else 2.2
    spatial = 2e-5 * elements ** -rate * (1 + 0.3 / ppe)
    if elements <= 3:
        return spatial * (1 + 0.02 / dt_fraction)
    return spatial * (0.3 + 4 * dt_fraction)


def write_run(path: str, scheme: str, elements: int, ppe: int, dt_fraction: float,
              history: bool = True, snapshot: bool = True):
    """A single-run file."""
    q = bar_quantities(elements, dt_fraction)
    amplitude = BAR['velocity_amplitude'] / (q['omega'] * q['beta'] * BAR['length'])
    error = synthetic_error(scheme, elements, ppe, dt_fraction)
    with h5py.File(path, 'w') as h5:
        h5.attrs['code_version'] = fortran_string(CODE_VERSION)
        h5.attrs['content'] = fortran_string('single run')
        write_config(h5.create_group('config'), scheme, elements, ppe, dt_fraction)
        if history:
            t = np.linspace(0.0, q['final_time'], q['steps'] + 1)
            exact = amplitude * np.sin(q['omega'] * t)
            numerical = exact + error * np.sin(q['omega'] * t) * t / t[-1]
            energy = 0.5 * BAR['density'] * BAR['length'] * BAR['velocity_amplitude'] ** 2 / 2
            for name, values in (('time', t), ('ucm', numerical), ('ucm_exact', exact),
                                 ('kinetic_energy', energy * np.cos(q['omega'] * t) ** 2),
                                 ('strain_energy', energy * np.sin(q['omega'] * t) ** 2)):
                h5[f'history/{name}'] = values
            error = float(np.max(np.abs(numerical - exact)))
        summary = dict(max_error=error, relative_error=error / amplitude,
                       ucm_amplitude=amplitude, steps=np.int32(q['steps']),
                       steps_done=np.int32(q['steps']), particles=np.int32(elements * ppe),
                       dt=q['dt'], run_time=1e-3, status=np.int32(0),
                       status_name=fortran_string('ok'), message=fortran_string('completed'),
                       initial_energy=1.0, final_energy=0.99, max_energy_ratio=1.0,
                       min_volume_ratio=0.999, max_cell_move=0.01, min_node_mass_ratio=0.5)
        for name, value in summary.items():
            h5[f'summary/{name}'] = value
        if snapshot:
            x_p, v_p, grid_x, grid_v = initial_grid(elements, ppe)
            group = h5.create_group('snapshots/0001')
            group.attrs['time'] = 0.0
            group.attrs['step'] = np.int32(0)
            for name, values in (('x', x_p), ('velocity', v_p), ('stress', 0 * x_p),
                                 ('volume_ratio', 1 + 0 * x_p), ('grid_x', grid_x),
                                 ('grid_velocity', grid_v)):
                group[name] = values


def write_sweep(path: str, scheme: str, elements=ELEMENTS, ppe=PPE, dt_fractions=DT_FRACTIONS,
                histories: bool = True, seed: int = 1):
    """A sweep file over elements × particles per element × time step, with a few failures."""
    rng = np.random.default_rng(seed)
    grid = [(e, n, k) for e in elements for n in ppe for k in dt_fractions]
    count = len(grid)
    columns = {name: [] for name in ('elements', 'particles_per_element', 'dt_fraction', 'steps',
                                     'dt', 'max_error', 'relative_error', 'run_time', 'status',
                                     'status_name', 'particles')}
    for e, n, k in grid:
        q = bar_quantities(e, k)
        amplitude = BAR['velocity_amplitude'] / (q['omega'] * q['beta'] * BAR['length'])
        error = synthetic_error(scheme, e, n, k) * (1 + 0.05 * rng.standard_normal())
        failed = (e == 50 and k >= 0.5 and n >= 9) or (scheme == 'usf' and e == 1 and k == 0.5
                                                        and n == 1)
        time = 2e-6 * q['steps'] * e * n * (1 + 0.03 * rng.standard_normal()) + 1e-4
        columns['elements'].append(e)
        columns['particles_per_element'].append(n)
        columns['dt_fraction'].append(k)
        columns['steps'].append(q['steps'])
        columns['dt'].append(q['dt'])
        columns['max_error'].append(1e3 if failed else error)
        columns['relative_error'].append(1e3 / amplitude if failed else error / amplitude)
        columns['run_time'].append(time)
        columns['status'].append(4 if failed else 0)
        columns['status_name'].append('energy_growth' if failed else 'ok')
        columns['particles'].append(e * n)
    with h5py.File(path, 'w') as h5:
        h5.attrs['code_version'] = fortran_string(CODE_VERSION)
        h5.attrs['content'] = fortran_string('sweep')
        write_config(h5.create_group('config'), scheme, 20, 1, 0.1)
        sweep = h5.create_group('sweep')
        sweep.attrs['namelist'] = fortran_string("&sweep elements=1,3,7,10,20,50 /")
        for key, value in (('cases', count), ('threads', 8), ('timing_threads', 1),
                           ('shard', 1), ('shards', 1)):
            sweep.attrs[key] = np.int32(value)
        for key, value in (('min_time', 0.2), ('wall_time', 123.4), ('error_pass_time', 20.5),
                           ('timing_pass_time', 102.9)):
            sweep.attrs[key] = value
        cases = h5.create_group('cases')
        cases['scheme'] = fortran_strings([scheme] * count)
        cases['status_name'] = fortran_strings(columns.pop('status_name'))
        for key in ('elements', 'particles_per_element', 'steps', 'status', 'particles'):
            cases[key] = np.array(columns.pop(key), dtype=np.int32)
        for key, values in columns.items():
            cases[key] = np.array(values, dtype=float)
        cases['mode'] = np.ones(count, np.int32)
        cases['repeats'] = np.full(count, 3, np.int32)
        for key in ('youngs_modulus', 'density', 'velocity_amplitude'):
            cases[key] = np.full(count, BAR[key])
        cases['max_energy_ratio'] = np.ones(count)
        cases['final_energy_ratio'] = np.ones(count)
        if histories:
            t = np.linspace(0, 0.04, 11)
            for name in ('time', 'ucm', 'ucm_exact', 'kinetic_energy', 'strain_energy'):
                h5[f'histories/0001/{name}'] = t


class Files:
    """A temporary folder with a full synthetic input set."""

    def __init__(self):
        self.dir = tempfile.mkdtemp(prefix='mpm1d_post_')
        self.usf = str(Path(self.dir) / 'sweep_usf.h5')
        self.usl = str(Path(self.dir) / 'sweep_usl.h5')
        write_sweep(self.usf, 'usf', seed=1)
        write_sweep(self.usl, 'usl', seed=2)
        self.runs = []
        for scheme in ('usf', 'usl'):
            path = str(Path(self.dir) / f'verify_{scheme}.h5')
            write_run(path, scheme, 20, 1, 0.1, snapshot=True)
            self.runs.append(path)
        for elements in (1, 3, 7, 10):
            path = str(Path(self.dir) / f'initial_{elements}.h5')
            write_run(path, 'usf', elements, 2, 0.1, history=False)
            self.runs.append(path)
        self.out = str(Path(self.dir) / 'figures')

    def cleanup(self):
        shutil.rmtree(self.dir, ignore_errors=True)


_FILES = None


def files() -> Files:
    """The synthetic input set, built once."""
    global _FILES
    if _FILES is None:
        _FILES = Files()
    return _FILES


def run_main(argv):
    """main(argv) with stdout/stderr captured: (status, stdout, stderr)."""
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        status = make_paper_figures.main(argv)
    return status, out.getvalue(), err.getvalue()


# --------------------------------------------------------------------------------------------
# Tests
# --------------------------------------------------------------------------------------------

EXPECTED_FIGURES = ('fig3b_ucm_verification.png', 'fig4_error_map_usf.png',
                    'fig7_error_map_usl.png', 'fig5_time_map_usf.png', 'fig8_time_map_usl.png',
                    'fig6_time_fits_usf.png', 'fig9_time_fits_usl.png',
                    'fig10_initial_velocity.png', 'error_vs_time.png', 'summary.md')


def test_main_writes_every_figure():
    f = files()
    status, out, err = run_main(['--usf', f.usf, '--usl', f.usl, '--runs', *f.runs,
                                 '-o', f.out])
    assert status == 0, f'exit status {status}: {err}'
    for name in EXPECTED_FIGURES:
        path = str(Path(f.out) / name)
        assert Path(path).is_file(), f'{name} not written'
        assert Path(path).stat().st_size > 0, f'{name} is empty'
    with open(Path(f.out) / 'fig4_error_map_usf.png', 'rb') as handle:
        assert handle.read(8) == b'\x89PNG\r\n\x1a\n', 'not a PNG'


def test_summary_contents():
    f = files()
    if not (Path(f.out) / 'summary.md').is_file():
        run_main(['--usf', f.usf, '--usl', f.usl, '--runs', *f.runs, '-o', f.out])
    text = open(Path(f.out) / 'summary.md', encoding='utf-8').read()
    for needle in ('## Findings', 'Pareto', 'R²', '123.4', 'Verification case',
                   'energy_growth', CODE_VERSION):
        assert needle in text, f"summary.md lacks '{needle}'"
    # The synthetic data are built so that claims (a)-(e) hold.
    for key in 'abcde':
        line = next(l for l in text.splitlines() if l.startswith(f'### ({key})'))
        assert line.endswith('**holds**'), f'claim ({key}): {line}'


def test_claims_can_fail():
    """The verdict comes from the data: swap the schemes and claim (d) no longer holds."""
    f = files()
    usf, usl = load_sweep(f.usf), load_sweep(f.usl)
    usf.cases['scheme'][:] = 'usl'
    usl.cases['scheme'][:] = 'usf'
    claim = analysis.claim_usl_faster({'usf': usl, 'usl': usf})
    assert claim.holds is False, claim.details


def test_r_squared_exact_line():
    x = np.arange(1.0, 11.0)
    fit = figures.linear_fit(x, 0.25 * x + 3.0)
    assert abs(fit['r2'] - 1.0) < 1e-12, fit
    assert abs(fit['slope'] - 0.25) < 1e-12 and abs(fit['intercept'] - 3.0) < 1e-10, fit
    k = np.arange(5.0, 55.0, 5.0)
    curve = figures.rational_fit(k, 7.0 / k + 0.5)
    assert abs(curve['r2'] - 1.0) < 1e-12 and abs(curve['a'] - 7.0) < 1e-9, curve
    noisy = figures.linear_fit(x, x + np.array([1, -1] * 5))
    assert noisy['r2'] < 1.0


def test_loader_decodes_strings():
    f = files()
    run = load_run(f.runs[0])
    assert run.code_version == CODE_VERSION and run.scheme == 'usf', run.code_version
    assert run.summary['status_name'] == 'ok' and run.config['scene_kind'] == 'vibrating_bar'
    assert run.snapshot_at(0) is not None and run.history is not None
    sweep = load_sweep(f.usf, cases='all')
    assert sweep.cases['scheme'][0] == 'usf' and sweep.cases['status_name'].dtype.kind == 'U'
    assert len(sweep) == len(ELEMENTS) * len(PPE) * len(DT_FRACTIONS)
    assert sweep.sweep[0]['wall_time'] == 123.4 and 0 in sweep.histories


REGISTRY_HEADER = 'group\tname\tattribute\ttype\tunit\tvalue\tallowed\tsweep_list\thelp'


def test_registry_in_the_file_drives_the_loader():
    """The /config registry says which attributes a file must hold and which /cases columns are swept
    variables; a swept variable's column is there when the sweep's scene uses it (a bar sweep has no
    gap column), so a missing one is not an error: it is not a parameter column."""
    f = files()
    path = str(Path(f.dir) / 'with_registry.h5')
    write_sweep(path, 'usf', elements=(3,), histories=False)
    rows = ['scene\tlength\tlength\treal\tm\t25.0\tfinite real > 0 (m)\t\tlength',
            'scene\tmode\tmode\tinteger\t\t1\tinteger >= 1\tmodes\tthe mode',
            'run\tend_time\tend_time\treal\ts\t\tfinite real > 0 (s)\t\tunset: no attribute']
    with h5py.File(path, 'a') as h5:
        h5['config'].attrs['parameters'] = fortran_string('\n'.join([REGISTRY_HEADER] + rows))
    sweep = load_sweep(path)
    assert sweep.parameter_columns == ['mode'] and sweep.cases['mode'].dtype.kind == 'i'
    assert [p.name for p in sweep.parameters] == ['length', 'mode', 'end_time']
    with h5py.File(path, 'a') as h5:
        del h5['cases/mode']
    assert 'mode' not in load_sweep(path).cases and load_sweep(path).parameter_columns == []
    with h5py.File(path, 'a') as h5:
        h5['cases/mode'] = np.ones(len(sweep), np.int32)
        del h5['config'].attrs['length']
    _expect_load_error(path, "'/config': length")


def _expect_load_error(path, part):
    """load_sweep(path) raises Mpm1dFileError with `part` in its message."""
    try:
        load_sweep(path)
    except Mpm1dFileError as exc:
        assert part in str(exc), str(exc)
    else:
        raise AssertionError(f'{path}: no error naming {part}')


def find_mpm1d():
    """The mpm1d executable built by fpm (None when it cannot be found)."""
    root = ROOT
    try:
        out = subprocess.run(['fpm', 'run', '--profile', 'release', '--target', 'mpm1d', '--runner', 'echo'],
                             cwd=root, capture_output=True, text=True, check=True).stdout.split()
    except (OSError, subprocess.CalledProcessError):
        return None
    exe = str(Path(root) / out[-1]) if out else ''
    return exe if Path(exe).is_file() else None


def test_real_files_carry_the_registry_the_program_lists():
    """A sweep file and a run file written by mpm1d hold its registry (`mpm1d --list-parameters`):
    every variable as a /config attribute and every sweepable one as a /cases column."""
    exe = find_mpm1d()
    if exe is None:
        print('     (mpm1d not built: real-file registry check skipped)')
        return
    listed = parse_parameters(subprocess.run([exe, '--list-parameters'], capture_output=True, text=True,
                                             check=True).stdout)
    assert {p.group for p in listed} >= {'scene', 'discretisation', 'run', 'output', 'guards', 'sweep'}
    f = files()
    with open(Path(f.dir) / 'tiny.nml', 'w') as handle:
        handle.write("&run periods=0.1 /\n&output file='tiny.h5', snapshot_times=0.0 /\n"
                     "&sweep modes=1, 2, elements=3, min_time=0 /\n")
    with open(Path(f.dir) / 'one.nml', 'w') as handle:
        handle.write("&run end_time=1e-3 /\n&output file='one.h5' /\n")
    for name in ('tiny.nml', 'one.nml'):
        subprocess.run([exe, name], cwd=f.dir, capture_output=True, check=True)
    sweep = load_sweep(str(Path(f.dir) / 'tiny.h5'))
    run = load_run(str(Path(f.dir) / 'one.h5'))
    # the bar's entries: a file holds the variables of its scene kind (no kinds: every kind's)
    key = [(p.group, p.name, p.attribute, p.type, p.sweep_list) for p in listed if p.group != 'sweep'
           and (not p.kinds or 'vibrating_bar' in [k.strip() for k in p.kinds.split(',')])]
    for loaded in (sweep, run):
        assert [(p.group, p.name, p.attribute, p.type, p.sweep_list) for p in loaded.parameters] == key
        assert all(p.attribute in loaded.config for p in loaded.parameters if p.written)
    # the swept variables of the bar: every one of another group, and of &scene those its namelist gives
    bar = set(figures._namelist_group(sweep.config['namelist'], 'scene'))
    assert bar >= {'length', 'youngs_modulus', 'velocity_amplitude', 'mode'} and 'gap' not in bar
    # ... but not those of another integrator or law: this explicit Hencky sweep has no column of the
    # implicit integrators' or the elastoplastic law's variables (mpm_sweep_output, scene_columns)
    others = {'mass', 'load_steps', 'newton_tolerance', 'ghost_penalty', 'yield_stress', 'hardening_modulus'}
    assert set(sweep.parameter_columns) == {p.attribute for p in listed if p.sweep_list and p.name not in others
                                            and (p.group != 'scene' or p.name in bar)}
    assert all(c in sweep.cases for c in sweep.parameter_columns)
    assert sweep.cases['mode'].tolist() == [1, 2] and sweep.cases['elements'].tolist() == [3, 3]
    assert run.config['end_time'] == 1e-3 and 'periods' not in run.config
    assert int(run.config['history']) == 1 and len(run.config['snapshot_times']) == 0


def _expect_file_error(argv, name):
    status, _, err = run_main(argv)
    assert status == 2, f'exit status {status} for {name}'
    assert Path(name).name in err, f'message does not name the file: {err!r}'
    return err


def test_bad_files_exit_2():
    f = files()
    out = str(Path(f.dir) / 'bad_out')
    missing = str(Path(f.dir) / 'missing.h5')
    _expect_file_error(['--usf', missing, '-o', out], missing)
    text = str(Path(f.dir) / 'not_hdf5.h5')
    with open(text, 'w') as handle:
        handle.write('not HDF5\n')
    assert 'not an HDF5 file' in _expect_file_error(['--runs', text, '-o', out], text)
    # a single-run file given as a sweep, and a sweep given as a run
    assert 'expected' in _expect_file_error(['--usf', f.runs[0], '-o', out], f.runs[0])
    _expect_file_error(['--runs', f.usl, '-o', out], f.usl)
    # a USL sweep given as USF
    assert "'usl'" in _expect_file_error(['--usf', f.usl, '-o', out], f.usl)
    # an HDF5 file that is not an mpm1d file, and one missing a dataset
    foreign = str(Path(f.dir) / 'foreign.h5')
    with h5py.File(foreign, 'w') as h5:
        h5['data'] = np.arange(3)
    assert 'not an mpm1d file' in _expect_file_error(['--runs', foreign, '-o', out], foreign)
    broken = str(Path(f.dir) / 'broken.h5')
    write_sweep(broken, 'usf', elements=(3,), histories=False)
    with h5py.File(broken, 'a') as h5:
        del h5['cases/max_error']
    assert 'max_error' in _expect_file_error(['--usf', broken, '-o', out], broken)
    try:
        load_run(missing)
    except Mpm1dFileError as exc:
        assert missing in str(exc)
    else:
        raise AssertionError('no Mpm1dFileError for a missing file')


def test_help_and_usage():
    status, out, _ = run_main(['--help'])
    assert status == 0 and '--usf' in out and '--runs' in out
    status, _, err = run_main(['-o', 'x'])
    assert status == 2 and 'at least one' in err


def test_partial_inputs():
    """Only a USF sweep: its figures are made, the others skipped with a reason."""
    f = files()
    out = str(Path(f.dir) / 'usf_only')
    status, _, err = run_main(['--usf', f.usf, '-o', out])
    assert status == 0, err
    assert (Path(out) / 'fig4_error_map_usf.png').is_file()
    assert not (Path(out) / 'fig7_error_map_usl.png').exists()
    text = open(Path(out) / 'summary.md', encoding='utf-8').read()
    assert 'not checked' in text and 'Skipped' in text


def teardown_module(module=None):
    """pytest hook: remove the synthetic files."""
    global _FILES
    if _FILES is not None:
        _FILES.cleanup()
        _FILES = None


# --------------------------------------------------------------------------------------------

def main() -> int:
    """Run every test_* function; print 'N passed, M failed'."""
    tests = [(name, obj) for name, obj in sorted(globals().items())
             if name.startswith('test_') and callable(obj)]
    passed = failed = 0
    try:
        for name, test in tests:
            try:
                test()
            except Exception:  # report every failure, go on with the next test
                failed += 1
                print(f'FAIL {name}')
                traceback.print_exc()
            else:
                passed += 1
                print(f'ok   {name}')
    finally:
        if os.environ.get('MPM1D_KEEP_TEST_FILES') and _FILES is not None:
            print(f'test files kept in {_FILES.dir}')
        else:
            teardown_module()
    print(f'{passed} passed, {failed} failed')
    return 1 if failed else 0


if __name__ == '__main__':
    sys.exit(main())
