"""Figures say what they show and show all of it: no title is cut off at the figure's edges (the
one-panel time maps, Figs. 5 and 8, lost the scheme name), and the time-step axes name the setting
for what it is, a fraction of dx/c, not of the critical step."""
from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
import pytest

from mpm1d_post import figures, load_sweep
from test_postprocess import write_sweep


@pytest.fixture()
def sweeps(tmp_path):
    result = {}
    for scheme in ('usf', 'usl'):
        write_sweep(str(tmp_path / f'{scheme}.h5'), scheme)
        result[scheme] = load_sweep(tmp_path / f'{scheme}.h5', cases='all')
    return result


@pytest.fixture()
def drawn(monkeypatch):
    """Instead of saving, draw each figure and keep its texts' extents in display units."""
    shown = []

    def capture(fig, outdir, name, sources):
        fig.canvas.draw()
        renderer = fig.canvas.get_renderer()
        texts = [fig._suptitle] + [t for ax in fig.axes for t in (ax.title, ax.xaxis.label, ax.yaxis.label)]
        shown.append({'name': name, 'figure': fig.bbox,
                      'texts': [(t.get_text(), t.get_window_extent(renderer)) for t in texts
                                if t is not None and t.get_text()]})
        plt.close(fig)
        return name
    monkeypatch.setattr(figures, 'save_figure', capture)
    return shown


def _inside(box, figure):
    return box.x0 >= figure.x0 - 0.5 and box.x1 <= figure.x1 + 0.5 and box.y1 <= figure.y1 + 0.5


def test_time_map_and_fit_titles_are_whole(sweeps, drawn, tmp_path):
    figures.time_maps(sweeps, str(tmp_path))
    for scheme, sweep in sweeps.items():
        figures.time_fits(sweep, scheme, str(tmp_path))
    figures.error_maps(sweeps, str(tmp_path))
    assert {d['name'] for d in drawn} >= {'fig5_time_map_usf.png', 'fig8_time_map_usl.png',
                                          'fig6_time_fits_usf.png', 'fig9_time_fits_usl.png'}
    for figure in drawn:
        title = figure['texts'][0][0]
        scheme = 'USF' if figure['name'].endswith('usf.png') else 'USL'
        assert scheme in title, f"{figure['name']}: title lacks the scheme: {title!r}"
        for text, box in figure['texts']:
            assert _inside(box, figure['figure']), \
                f"{figure['name']}: {text!r} runs past the figure ({box} outside {figure['figure']})"


def test_time_step_axes_say_fraction_of_dx_over_c(sweeps, drawn, tmp_path):
    figures.time_maps(sweeps, str(tmp_path))
    figures.time_fits(sweeps['usl'], 'usl', str(tmp_path))
    labels = [text for figure in drawn for text, _ in figure['texts']]
    assert not [t for t in labels if 'critical' in t], 'a label still calls dt_fraction "critical"'
    assert any('dx/c' in t for t in labels)


def test_titles_break_between_phrases(sweeps, drawn, tmp_path):
    """Fig. 5's one-panel title broke 'median over repeats' across two lines: lines now end between
    phrases (a phrase is cut only when it alone is longer than a line)."""
    figures.time_maps(sweeps, str(tmp_path))
    title = next(f['texts'][0][0] for f in drawn if f['name'] == 'fig5_time_map_usf.png')
    assert any('Computation time per run (median over repeats)' in line for line in title.split('\n')), title
    # every line the wrapping cut ends between phrases: 'mode 1,' / '2 periods', never 'mode 1, 2' / 'periods'
    lines = title.split('\n')
    assert [line for line in lines[:-1] if not line.endswith((',', '—', ';', 'elements', 'repeats)'))] == [], title
    assert '2 periods' in lines[-1], title
    assert figures.wrap_phrases('Fig. 5 — USF — Computation time per run (median over repeats), 3 elements', 50) == \
        ['Fig. 5 — USF —', 'Computation time per run (median over repeats),', '3 elements']
    assert figures.duration_text({'periods': 1.0}) == '1 period' and figures.duration_text({'periods': 2.5}) == \
        '2.5 periods'


def test_fig10_spans_the_bar(mpm1d, tmp_path):
    """The grid's empty margin cells beyond the free end are not part of the bar: the x-axis is [0, L]."""
    import subprocess
    from mpm1d_post import load_run
    (tmp_path / 'b.nml').write_text("&discretisation elements=3, particles_per_element=2 /\n&run periods=0.1 /\n"
                                    "&output file='b.h5', snapshot_times=0.0 /\n")
    assert subprocess.run([str(mpm1d), 'b.nml', '-q'], cwd=tmp_path).returncode == 0
    run = load_run(tmp_path / 'b.h5')
    assert run.snapshot_at(0).grid_x.max() > run.config['length']  # the grid reaches past the bar
    limits = []
    original = figures.save_figure

    def keep(fig, outdir, name, sources):
        limits.append(fig.axes[0].get_xlim())
        return original(fig, outdir, name, sources)
    figures.save_figure = keep
    try:
        figures.fig10([run], str(tmp_path))
    finally:
        figures.save_figure = original
    assert limits == [(0.0, run.config['length'])]


@pytest.fixture()
def panels(monkeypatch):
    """Instead of saving, keep each figure's title, its panels (title, colour scale, y label) and the
    labels of its lines and error bars."""
    shown = {}

    def capture(fig, outdir, name, sources):
        found = []
        for ax in fig.axes:
            meshes = [c for c in ax.collections if hasattr(c, 'norm') and c.get_array() is not None]
            found.append({'title': ax.get_title(), 'ylabel': ax.get_ylabel(),
                          'norm': (meshes[0].norm.vmin, meshes[0].norm.vmax) if meshes else None,
                          'labels': [h.get_label() for h in ax.get_legend_handles_labels()[0]],
                          'error_bars': len(ax.containers)})
        shown[name] = {'title': fig._suptitle.get_text(), 'panels': found}
        plt.close(fig)
        return name
    monkeypatch.setattr(figures, 'save_figure', capture)
    return shown


def test_error_maps_one_colour_scale_per_mesh(sweeps, panels, tmp_path):
    """Figs. 4 and 7: on one scale for 1 to 50 elements each panel was almost one colour. Each mesh
    now has its own scale, spanning its completed cases of both schemes (USF and USL compare panel by
    panel); the time-step axis says dx/c once."""
    figures.error_maps(sweeps, str(tmp_path))
    for name in ('fig4_error_map_usf.png', 'fig7_error_map_usl.png'):
        maps = [p for p in panels[name]['panels'] if p['norm'] is not None and p['title']]  # (not the colourbars)
        assert len(maps) == 6, name
        for panel in maps:
            count = int(panel['title'].split()[0])
            errors = np.concatenate([s.cases['max_error'][s.where(scheme=k, elements=count) & s.ok]
                                     for k, s in sweeps.items()])
            assert panel['norm'] == pytest.approx((errors.min(), errors.max())), (name, count)
            assert panel['ylabel'] == 'time step dt (% of dx/c)'
    scales = {p['norm'] for p in panels['fig4_error_map_usf.png']['panels'] if p['norm'] is not None and p['title']}
    assert len(scales) == 6


def test_time_map_title_names_the_mesh_once(sweeps, panels, tmp_path):
    figures.time_maps(sweeps, str(tmp_path))
    figure = panels['fig5_time_map_usf.png']
    text = figure['title'] + ' ' + ' '.join(p['title'] for p in figure['panels'])
    assert text.count('3 elements') == 1, text
    assert len(figure['title'].split('\n')) <= 3, figure['title']


@pytest.mark.parametrize('spread, noisy', [(0.05, False), (0.6, True)])
def test_time_fits_show_the_spread_and_say_when_it_is_too_large(sweeps, panels, tmp_path, spread, noisy):
    """Figs. 6 and 9 fitted lines to timings as if they were exact: each point has its repeats' spread as
    a bar, and a fit over timings whose median spread exceeds 0.2 says it cannot be judged."""
    sweep = sweeps['usl']
    sweep.cases['run_time_spread'] = np.full(len(sweep), spread)
    _, fits = figures.time_fits(sweep, 'usl', str(tmp_path))
    figure = panels['fig9_time_fits_usl.png']
    for panel in figure['panels']:
        assert panel['error_bars'] == 1
        said = any('timings too noisy to judge a fit (median spread of the repeats 0.6 > 0.2)' in ' '.join(label.split())
                   for label in panel['labels'])
        assert said == noisy, panel['labels']
    assert fits['time_step']['spread'] == [spread] * len(fits['time_step']['x'])


@pytest.mark.parametrize('slope, small', [(1e-7, True), (1e-4, False)])
def test_time_fits_say_when_the_timings_are_too_small_to_judge(sweeps, panels, tmp_path, slope, small):
    """Steady repeats (spread 0.05) do not make a fit judgeable when the fitted time changes over the
    measured range by less than that spread of the median time: 1e-7 s per particle over n = 1..10 on
    a 2e-4 s run (a change of 9e-7 s against a spread of 1e-5 s) is noise, 1e-4 s per particle is not.
    The times follow t = 2e-4 s + slope (n + 100 k), k the time-step fraction, so both panels share it."""
    sweep = sweeps['usl']
    cases = sweep.cases
    cases['run_time'] = 2e-4 + slope * (cases['particles_per_element'] + 100 * cases['dt_fraction'])
    cases['run_time_spread'] = np.full(len(sweep), 0.05)
    figures.time_fits(sweep, 'usl', str(tmp_path))
    for panel in panels['fig9_time_fits_usl.png']['panels']:
        said = any('timings too small to judge a fit' in ' '.join(label.split()) for label in panel['labels'])
        assert said == small, panel['labels']
