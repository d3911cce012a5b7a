"""Figures say what they show and show all of it: no title is cut off at the figure's edges (the
one-panel time maps, Figs. 5 and 8, lost the scheme name), and the time-step axes name the setting
for what it is, a fraction of dx/c, not of the critical step."""
from __future__ import annotations

import matplotlib.pyplot as plt
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
    assert [line for line in lines[:-1] if not line.endswith((',', '—', ';', 'elements'))] == [], title
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
