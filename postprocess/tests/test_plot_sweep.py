"""mpm1d-plot-sweep on sweeps mpm1d writes: any scheme set (MUSL included), shapes and transfers.
The fitted orders are checked against the orders known for the bar at small amplitude (USL and
MUSL second order, USF first order: Bardenhagen 2002 and studies/shapes), the files it writes, the
selection --at, and a clear refusal (exit 2) of a file that is not a sweep."""
from __future__ import annotations

import csv
import subprocess

import pytest

from mpm1d_post import plot_sweep

SWEEP = ("&discretisation particles_per_element=4, dt_fraction=0.25 /\n&output file='conv.h5' /\n"
         "&sweep scheme='usf','usl','musl', shape='linear','bspline2', transfer='flip', "
         "elements=10,20,40, particles_per_element=2,4, min_time=0.0005 /\n")


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


def test_refuses_shards_of_two_sweeps(mpm1d, sweep_file, tmp_path, capsys):
    """Two different sweeps are not mixed into one fit (as mpm1d merge refuses them)."""
    (tmp_path / 'other.nml').write_text(SWEEP.replace('elements=10,20,40', 'elements=5,10'))
    assert subprocess.run([str(mpm1d), 'other.nml', '-q'], cwd=tmp_path).returncode == 0
    assert plot_sweep.main([str(sweep_file), str(tmp_path / 'conv.h5'), '-o', str(tmp_path / 'out')]) == 2
    err = capsys.readouterr().err
    assert err.startswith('mpm1d-plot-sweep:') and 'is not a shard of the same sweep' in err, err
    assert 'Traceback' not in err and not (tmp_path / 'out').exists()


def test_output_an_existing_file(sweep_file, tmp_path, capsys):
    (tmp_path / 'taken').write_text('keep')
    assert plot_sweep.main([str(sweep_file), '-o', str(tmp_path / 'taken')]) == 2
    err = capsys.readouterr().err
    assert 'is an existing file, not a folder' in err and 'Traceback' not in err, err
    assert (tmp_path / 'taken').read_text() == 'keep'


def test_stopped_cases_apart_and_one_mesh_no_order(mpm1d, tmp_path, capsys):
    """USL at dt = 2.5 dx/c stops on the energy guard on every mesh: drawn as stopped, never fitted; the
    completed series keep their orders from their own cases. A series of one mesh has no order."""
    (tmp_path / 's.nml').write_text("&run periods=2 /\n&output file='s.h5' /\n"
                                    "&sweep elements=10,20,40, dt_fraction=0.1, 2.5, min_time=0 /\n")
    assert subprocess.run([str(mpm1d), 's.nml', '-q'], cwd=tmp_path).returncode == 0
    assert plot_sweep.main([str(tmp_path / 's.h5'), '-o', str(tmp_path / 'out')]) == 0
    rows = {r['series']: r for r in csv.DictReader(open(tmp_path / 'out' / 'orders.csv'))}
    assert rows['USL, linear, flip, dt_fraction=0.1']['points'] == '3'
    assert float(rows['USL, linear, flip, dt_fraction=0.1']['order']) == pytest.approx(2.0, abs=0.2)
    assert rows['USL, linear, flip, dt_fraction=2.5'] == {'series': 'USL, linear, flip, dt_fraction=2.5',
                                                          'points': '0', 'order': '', 'finest_elements': '',
                                                          'finest_error': ''}
    assert plot_sweep.main([str(tmp_path / 's.h5'), '-o', str(tmp_path / 'one'), '--at', 'elements=20']) == 0
    out = capsys.readouterr().out
    assert 'order nan' not in out and 'USL, linear, flip, dt_fraction=0.1: no order (1 mesh with a result' in out
    assert next(csv.DictReader(open(tmp_path / 'one' / 'orders.csv')))['order'] == ''


def test_labels_of_a_scene_and_element_ticks(mpm1d, tmp_path, monkeypatch):
    """The subtitle lists the manufactured scene's own parameters with units (no gravity or
    drive_velocity), '1 period'; the series of one mesh has no order in its label; the element axis
    has plain ticks 10, 20."""
    (tmp_path / 'm.nml').write_text("&scene kind='manufactured', amplitude=1.0e-6 /\n&run periods=1 /\n"
                                    "&output file='m.h5' /\n&sweep elements=10,20, particles_per_element=2,3, "
                                    "scheme='usl','musl', min_time=0 /\n")
    assert subprocess.run([str(mpm1d), 'm.nml', '-q'], cwd=tmp_path).returncode == 0
    shown = {}

    def keep(fig, outdir, name, sources):
        fig.canvas.draw()
        shown[name] = (fig._suptitle.get_text(), [t.get_text() for t in fig.axes[0].get_xticklabels()],
                       fig.axes[0].get_legend_handles_labels()[1])
        return name
    monkeypatch.setattr(plot_sweep.figures, 'save_figure', keep)
    sweep = plot_sweep.load_sweep(tmp_path / 'm.h5', cases='all')
    plot_sweep.error_vs_elements(sweep, tmp_path)
    title, ticks, labels = shown['error_vs_elements.png']
    assert 'manufactured: ' in title and 'amplitude = 1e-06 m' in title and 'density = 7800 kg/m^3' in title
    assert 'gravity' not in title and 'drive_velocity' not in title and 'velocity_amplitude' not in title
    assert title.rstrip().endswith('1 period') and '1 periods' not in title
    assert ticks == ['10', '20'], ticks
    one = plot_sweep.select(sweep, [('elements', '10')])
    plot_sweep.error_vs_elements(one, tmp_path)
    assert not [label for label in shown['error_vs_elements.png'][2] if 'nan' in label]


def test_stopped_cases_counted_never_on_the_error_axis(mpm1d, tmp_path, monkeypatch):
    """The README's sweep: USL at dt = 0.8 dx/c is stopped on every mesh; its errors before the stop
    (down to 3e-9 m) lie below every result. They are counted in the legend, not drawn."""
    (tmp_path / 's.nml').write_text("&output file='s.h5' /\n&sweep scheme='usf','usl', elements=10,20,40,80, "
                                    "particles_per_element=2, dt_fraction=0.2,0.8, min_time=0 /\n")
    assert subprocess.run([str(mpm1d), 's.nml', '-q'], cwd=tmp_path, capture_output=True).returncode == 0
    shown = {}

    def capture(fig, outdir, name, sources):
        ax = fig.axes[0]
        shown[name] = {'y': [y for line in ax.lines for y in line.get_ydata()],
                       'labels': [line.get_label() for line in ax.lines]}
        return name
    monkeypatch.setattr(plot_sweep.figures, 'save_figure', capture)
    sweep = plot_sweep.load_sweep(tmp_path / 's.h5', cases='all')
    plot_sweep.error_vs_elements(sweep, tmp_path)
    drawn = shown['error_vs_elements.png']
    results = sweep.cases['max_error'][sweep.ok]
    assert min(drawn['y']) == pytest.approx(results.min())
    assert not set(sweep.cases['error_before_stop'][sweep.stopped]) & set(drawn['y'])
    assert ('4 cases stopped by a guard (energy_growth 4; at 10, 20, 40, 80 elements): no result, not drawn'
            in drawn['labels'])
