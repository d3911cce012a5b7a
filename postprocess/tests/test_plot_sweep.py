"""mpm1d-plot-sweep on sweeps mpm1d writes: any scheme set (MUSL included), shapes and transfers.
The fitted orders are checked against the orders known for the bar at small amplitude (USL and
MUSL second order, USF first order: Bardenhagen 2002 and studies/shapes), the files it writes, the
selection --at, and a clear refusal (exit 2) of a file that is not a sweep."""
from __future__ import annotations

import csv
import subprocess

import numpy as np
import pytest

from mpm1d_post import plot_sweep

SWEEP = ("&discretisation particles_per_element=4, dt_fraction=0.25 /\n&output file='conv.h5' /\n"
         "&sweep scheme='usf','usl','musl', shape='linear','bspline2', transfer='flip', "
         "elements=10,20,40, particles_per_element=2,4, min_time=0.0005 /\n")


def test_order_of_an_exact_power_law():
    elements = np.array([10, 20, 40, 80])
    assert plot_sweep.convergence_order(elements, 3.0 * elements ** -2.0) == pytest.approx(2.0, abs=1e-12)
    assert np.isnan(plot_sweep.convergence_order([10, 10], [1.0, 2.0]))


@pytest.fixture(scope='module')
def sweep_file(mpm1d, tmp_path_factory):
    folder = tmp_path_factory.mktemp('plot_sweep')
    (folder / 'conv.nml').write_text(SWEEP)
    run = subprocess.run([str(mpm1d), 'conv.nml', '--quiet'], cwd=folder, capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    return folder / 'conv.h5'


def test_every_scheme_and_shape_with_its_order(sweep_file, tmp_path, capsys):
    assert plot_sweep.main([str(sweep_file), '-o', str(tmp_path)]) == 0
    for name in ('error_vs_elements.png', 'error_vs_time.png', 'error_map_musl_bspline2_flip.png',
                 'error_map_usf_linear_flip.png', 'orders.csv'):
        assert (tmp_path / name).stat().st_size > 0, name
    rows = list(csv.DictReader(open(tmp_path / 'orders.csv')))
    assert len(rows) == 3 * 2 * 2            # scheme x shape x particles per element
    for row in rows:
        expected = 1.0 if row['series'].startswith('USF') else 2.0
        assert float(row['order']) == pytest.approx(expected, abs=0.2), row
        assert int(row['points']) == 3


def test_selection(sweep_file, tmp_path):
    assert plot_sweep.main([str(sweep_file), '-o', str(tmp_path), '--at', 'scheme=MUSL',
                            'particles_per_element=4']) == 0
    rows = list(csv.DictReader(open(tmp_path / 'orders.csv')))
    assert [r['series'] for r in rows] == ['MUSL, linear, flip', 'MUSL, bspline2, flip']
    assert plot_sweep.main([str(sweep_file), '-o', str(tmp_path), '--at', 'shape=cubic']) == 2


def test_refuses_what_is_not_a_sweep(tmp_path, capsys):
    (tmp_path / 'x.h5').write_text('not hdf5')
    assert plot_sweep.main([str(tmp_path / 'x.h5'), '-o', str(tmp_path / 'out')]) == 2
    assert 'x.h5' in capsys.readouterr().err
