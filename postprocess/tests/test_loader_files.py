"""The loader on files written by mpm1d itself: every /summary dataset and /cases column comes back,
strings as ``str``, a guard's trip step and time as numbers that agree with the message and with
t = step x dt, and a completed case has the same message in a single-run and a sweep file."""
from __future__ import annotations

import re
import subprocess

import h5py
import numpy as np

from mpm1d_post import load_run, load_sweep

#: A stable case and one far above USL's limit (about 0.71 dx/c): a guard stops it.
SWEEP = "&run periods=2 /\n&output file='sweep.h5' /\n&sweep dt_fraction=0.1, 2.5, min_time=0 /\n"


def _run(mpm1d, folder, *args):
    return subprocess.run([str(mpm1d), *args, '--quiet'], cwd=folder, capture_output=True, text=True)


def test_every_column_and_the_trip_as_numbers(mpm1d, tmp_path):
    (tmp_path / 'sweep.nml').write_text(SWEEP)
    assert _run(mpm1d, tmp_path, 'sweep.nml').returncode == 0
    sweep = load_sweep(tmp_path / 'sweep.h5', cases='all')
    with h5py.File(tmp_path / 'sweep.h5', 'r') as h5:
        stored = set(h5['/cases'])
    assert stored <= set(sweep.cases), f'columns the loader drops: {stored - set(sweep.cases)}'
    assert sweep.cases['trip_step'].dtype.kind == 'i' and sweep.cases['trip_time'].dtype.kind == 'f'
    assert all(isinstance(m, str) for m in sweep.cases['message'].tolist())
    assert sweep.cases['status'].tolist()[0] == 0 and sweep.cases['status'].tolist()[1] > 0
    # the stopped case: the numbers agree with the message's text and with t = step x dt
    message = sweep.cases['message'][1]
    step = int(re.search(r'tripped at step (\d+) of', message).group(1))
    assert sweep.cases['trip_step'][1] == step > 0
    assert np.isclose(sweep.cases['trip_time'][1], step * sweep.cases['dt'][1], rtol=1e-12)
    assert sweep.cases['trip_step'][0] == 0 and sweep.cases['trip_time'][0] == 0.0


def test_single_run_and_sweep_say_the_same(mpm1d, tmp_path):
    (tmp_path / 'sweep.nml').write_text(SWEEP)
    assert _run(mpm1d, tmp_path, 'sweep.nml').returncode == 0
    assert _run(mpm1d, tmp_path, 'discretisation.dt_fraction=0.1', 'run.periods=2',
                'output.file=ok.h5').returncode == 0
    assert _run(mpm1d, tmp_path, 'discretisation.dt_fraction=2.5', 'run.periods=2',
                'output.file=stopped.h5').returncode == 1
    sweep = load_sweep(tmp_path / 'sweep.h5', cases='all')
    ok, stopped = load_run(tmp_path / 'ok.h5'), load_run(tmp_path / 'stopped.h5')
    with h5py.File(tmp_path / 'ok.h5', 'r') as h5:
        assert set(h5['/summary']) <= set(ok.summary)
    assert ok.summary['message'] == sweep.cases['message'][0] == 'completed'
    assert ok.summary['max_error'] == sweep.cases['max_error'][0]
    assert stopped.summary['trip_step'] == sweep.cases['trip_step'][1]
    # no result from the stopped run, in either file; the same error before the stop
    assert np.isnan(stopped.summary['max_error']) and np.isnan(sweep.cases['max_error'][1])
    assert stopped.summary['error_before_stop'] == sweep.cases['error_before_stop'][1] > 0
    assert stopped.summary['trip_time'] == sweep.cases['trip_time'][1]
    assert isinstance(stopped.summary['status_name'], str) and stopped.summary['status_name'] == 'energy_growth'


def test_a_scenes_own_snapshot_fields(mpm1d, tmp_path):
    """Every dataset of a snapshot reaches the reader: the impact writes each particle's reference
    position and body index besides the standard fields (at t = 0 the positions are the reference
    positions, and the first half of the particles are bar 1's)."""
    (tmp_path / 'impact.nml').write_text(
        "&scene kind='impact', lengths=1.0, 1.0, youngs_moduli=200.0e9, 200.0e9, densities=7800.0, 7800.0,\n"
        "       velocities=1.0, -1.0, gap=0.0, contact='frictionless' /\n"
        "&discretisation elements=20, particles_per_element=2 /\n&run periods=0.5 /\n"
        "&output file='impact.h5', snapshot_times=0.0 /\n")
    assert _run(mpm1d, tmp_path, 'impact.nml').returncode == 0
    run = load_run(tmp_path / 'impact.h5')
    first = run.snapshots[0]
    with h5py.File(tmp_path / 'impact.h5', 'r') as h5:
        stored = set(h5[f'/snapshots/{sorted(h5["/snapshots"])[0]}'])
    assert stored == set(first.extra) | {'x', 'velocity', 'stress', 'volume_ratio', 'grid_x', 'grid_velocity'}
    assert np.array_equal(first.extra['reference_x'], first.x)
    assert first.extra['body'].tolist() == [1] * 20 + [2] * 20
