"""mpm1d from Python (mpm1d_post.run, mpm1d_post.sweep): the configuration as a dict or namelist text,
mpm1d's own refusals and guard stops raised with its message, exit code and partial result, and the
tables (pandas DataFrames) equal to the file's datasets."""
from __future__ import annotations

import math
import warnings

import h5py
import numpy as np
import pandas as pd
import pytest

import mpm1d_post
from mpm1d_post import api


@pytest.fixture()
def exe(mpm1d, monkeypatch):
    """The built mpm1d, found as the API finds it: through $MPM1D_EXE."""
    monkeypatch.setenv('MPM1D_EXE', str(mpm1d))
    return mpm1d


def test_namelist_text_of_values():
    text = api.namelist_text({'scene': {'kind': "it's", 'length': 1.5, 'mode': np.int64(3)},
                              'output': {'history': False, 'snapshot_times': [0.0, 1e-05]}})
    assert text == ("&scene kind='it''s', length=1.5, mode=3 /\n"
                    "&output history=.false., snapshot_times=0.0, 1e-05 /\n")
    assert api._value(float('nan')) == 'NaN' and api._value(-math.inf) == '-Infinity'
    with pytest.raises(TypeError, match='no namelist text'):
        api.namelist_text({'scene': {'length': object()}})
    with pytest.raises(TypeError, match="expected a dict of the group's variables"):
        api.namelist_text({'scene': 3})


def test_output_file_of_text():
    assert api._output_file("&output file='a''b.h5', history=.false. /") == "a'b.h5"
    assert api._output_file("! &output file='no.h5' /\n&scene length=1 /") is None
    assert api._output_file('&OUTPUT FILE="x/y.h5" /') == 'x/y.h5'


def test_run_dict_and_text_give_the_same_run(exe, tmp_path):
    as_dict = mpm1d_post.run({'discretisation': {'elements': 10, 'scheme': 'usf'}, 'run': {'periods': 0.5}},
                             workdir=tmp_path / 'dict')
    as_text = mpm1d_post.run("&discretisation elements=10, scheme='usf' /\n&run periods=0.5 /\n",
                             workdir=tmp_path / 'text')
    assert as_dict.path == tmp_path / 'dict' / 'run.h5' and as_dict.path.is_file()
    assert as_dict.ok and as_dict.config['elements'] == 10 and as_dict.config['scheme'] == 'usf'
    assert as_dict.summary['max_error'] == as_text.summary['max_error'] > 0
    assert 'wrote ' + str(as_dict.path) in as_dict.output


def test_a_named_output_file_is_used(exe, tmp_path):
    result = mpm1d_post.run("&output file='mine.h5' /\n&run periods=0.2 /", workdir=tmp_path)
    assert result.path == tmp_path / 'mine.h5'


def test_bad_input_raises_with_mpm1d_message_and_exit_code(exe, tmp_path):
    with pytest.raises(mpm1d_post.Mpm1dError) as caught:
        mpm1d_post.run({'discretisation': {'elemnts': 40}}, workdir=tmp_path)
    error = caught.value
    assert error.exit_code == 2
    assert "run.nml:1: group &discretisation: unknown variable 'elemnts'; did you mean 'elements'?" in error.message
    assert 'exited with code 2' in str(error) and error.result is None
    assert not (tmp_path / 'run.h5').exists()


def test_missing_output_folder_names_the_absolute_path(exe, tmp_path):
    with pytest.raises(mpm1d_post.Mpm1dError) as caught:
        mpm1d_post.run({'output': {'file': 'nowhere/run.h5'}}, workdir=tmp_path)
    assert caught.value.exit_code == 2
    assert f"(looked for {tmp_path}/nowhere, relative to the folder mpm1d runs in)" in caught.value.message


def test_guard_stop_raises_with_the_partial_result(exe, tmp_path):
    with pytest.raises(mpm1d_post.Mpm1dError) as caught, pytest.warns(mpm1d_post.Mpm1dWarning,
                                                                        match='above the linear stability limit'):
        mpm1d_post.run({'discretisation': {'scheme': 'usl', 'dt_fraction': 2.5}}, workdir=tmp_path)
    error = caught.value
    assert error.exit_code == 1 and 'guard energy_growth tripped at step' in error.message
    stopped = error.result
    assert isinstance(stopped, mpm1d_post.RunResult) and not stopped.ok
    assert stopped.summary['status_name'] == 'energy_growth'
    assert math.isnan(stopped.summary['max_error']) and stopped.summary['error_before_stop'] > 0
    # the history up to the stop: t = 0, the completed steps and the step that tripped
    assert len(stopped.history) == stopped.summary['steps_done'] + 2


def test_warning_of_a_plastic_wave_that_cannot_yield(exe, tmp_path):
    with pytest.warns(mpm1d_post.Mpm1dWarning, match="the plastic wave cannot yield with law = 'hencky'"):
        result = mpm1d_post.run({'scene': {'kind': 'plastic_wave', 'length': 1.0}, 'material': {'law': 'hencky'}},
                                workdir=tmp_path)
    assert result.summary['yields'] == 0


def test_run_frames_equal_the_file(exe, tmp_path):
    result = mpm1d_post.run({'scene': {'kind': 'plastic_wave', 'length': 1.0},
                             'discretisation': {'elements': 20, 'particles_per_element': 2},
                             'output': {'snapshot_every': 40}}, workdir=tmp_path)
    steps = result.summary['steps']
    with h5py.File(result.path) as f:
        for name in f['history']:
            np.testing.assert_array_equal(result.history[name].to_numpy(), f['history'][name][()])
        groups = sorted(f['snapshots'])
        assert len(groups) == steps // 40 + 1
        assert result.snapshots['snapshot'].nunique() == len(groups)
        for number, group in enumerate(groups, start=1):
            rows = result.snapshots[result.snapshots['snapshot'] == number]
            node_rows = result.grid[result.grid['snapshot'] == number]
            snap = f['snapshots'][group]
            assert (rows['step'] == snap.attrs['step']).all() and (rows['time'] == snap.attrs['time']).all()
            assert list(rows['particle']) == list(range(1, len(rows) + 1))
            for name, data in snap.items():
                where = node_rows if name.startswith('grid_') else rows
                np.testing.assert_array_equal(where[name].to_numpy(), data[()], err_msg=f'{group}/{name}')
    assert {'exact_displacement', 'exact_velocity', 'exact_stress'} <= set(result.snapshots.columns)


def test_sweep_table_equals_the_file_with_statuses_and_nan(exe, tmp_path):
    config = {'discretisation': {'particles_per_element': 2},
              'sweep': {'scheme': ['usf', 'usl'], 'elements': [10, 20], 'dt_fraction': [0.2, 0.8], 'min_time': 0}}
    with pytest.warns(Warning) as said:
        completed = mpm1d_post.sweep(config, workdir=tmp_path / 'completed', threads=1)
    assert any(w.category is mpm1d_post.LeftOutCases and 'left out 2 of 8 cases' in str(w.message) and
               "sweep(..., cases='all') returns every case" in str(w.message) for w in said)
    assert any(w.category is mpm1d_post.Mpm1dWarning and 'above their scheme' in str(w.message) for w in said)
    assert len(completed.to_dataframe()) == 6
    with pytest.warns(mpm1d_post.Mpm1dWarning, match='2 cases ask for a time step above'):
        every = mpm1d_post.sweep(config, workdir=tmp_path / 'all', threads=1, cases='all')
    table = every.to_dataframe()
    assert isinstance(table, pd.DataFrame) and len(table) == 8
    with h5py.File(tmp_path / 'all' / 'sweep.h5') as f:
        assert f['sweep'].attrs['threads'] == 1
        assert set(table.columns) == set(f['cases'])
        for name, data in f['cases'].items():
            values = data[()]
            if values.dtype.kind in 'SO':
                assert list(table[name]) == [v.decode() for v in values], name
            else:
                np.testing.assert_array_equal(table[name].to_numpy(), values, err_msg=name)
    stopped = table[table['status_name'] == 'energy_growth']
    assert len(stopped) == 2 and (stopped['scheme'] == 'usl').all() and (stopped['dt_fraction'] == 0.8).all()
    assert stopped['max_error'].isna().all() and stopped['run_time'].isna().all()
    assert table['max_error'].idxmin() not in stopped.index


def test_sweep_and_run_refuse_each_others_input(exe, tmp_path):
    with pytest.raises(ValueError, match='run it with mpm1d_post.sweep'):
        mpm1d_post.run({'sweep': {'elements': [1, 2]}}, workdir=tmp_path)
    with pytest.raises(ValueError, match='no &sweep group'):
        mpm1d_post.sweep({'discretisation': {'elements': 4}}, workdir=tmp_path)
    with pytest.raises(ValueError, match='threads = 0'):
        mpm1d_post.sweep({'sweep': {'elements': [1, 2]}}, workdir=tmp_path, threads=0)


def test_executable_named_or_refused(tmp_path, mpm1d, monkeypatch):
    monkeypatch.setenv('MPM1D_EXE', str(tmp_path / 'no-such-mpm1d'))
    with pytest.raises(FileNotFoundError, match='no-such-mpm1d'):
        mpm1d_post.run({'run': {'periods': 0.1}}, workdir=tmp_path)
    result = mpm1d_post.run({'run': {'periods': 0.1}}, workdir=tmp_path, exe=mpm1d)
    assert result.ok
