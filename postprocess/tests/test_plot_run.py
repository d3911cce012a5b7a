"""mpm1d-plot-run and mpm1d-animate on the output of every scene (and a quasi-static run): the figures
of each (titles that name scene, scheme, shape, transfer, law and mesh; the exact profile drawn exactly
where the file has one), the command writing them, one animation frame per snapshot, a stopped run drawn
as no result, and bad input refused with exit 2."""
from __future__ import annotations

import shutil
import warnings

import matplotlib.pyplot as plt
import numpy as np
import pytest
from PIL import Image

import mpm1d_post
from mpm1d_post import animate, figures, load_run, plot_run

#: One small run per scene: its configuration and the snapshot interval giving it 5 snapshots or so.
SCENES = {
    'vibrating_bar': ({'run': {'periods': 1.0}}, 100),
    'column': ({'scene': {'kind': 'column'}, 'run': {'periods': 1.0}}, 100),
    'column_quasi_static': ({'scene': {'kind': 'column', 'gravity': 2.0e5},
                             'discretisation': {'integrator': 'quasi_static', 'load_steps': 4}}, 1),
    'manufactured': ({'scene': {'kind': 'manufactured', 'length': 1.0, 'youngs_modulus': 1e7, 'density': 1000.0,
                                'amplitude': 1e-3}, 'run': {'periods': 1.0}}, 50),
    'composite_bar': ({'scene': {'kind': 'composite_bar', 'lengths': [1.0, 1.0], 'youngs_moduli': [16e6, 1e6],
                                 'densities': [1000.0, 1000.0], 'drive_velocity': 0.01}, 'run': {'end_time': 0.03}}, 40),
    'impact': ({'scene': {'kind': 'impact', 'lengths': [1.0, 0.5], 'youngs_moduli': [200e9, 200e9],
                          'densities': [7800.0, 7800.0], 'velocities': [1.0, -0.5], 'gap': 0.001},
                'run': {'periods': 1.0}}, 80),
    'plastic_wave': ({'scene': {'kind': 'plastic_wave', 'length': 1.0}}, 20),
}
#: The scenes whose snapshots carry exact fields (docs/output.md): all but the impact.
WITHOUT_EXACT = {'impact'}


@pytest.fixture(scope='session')
def runs(mpm1d, tmp_path_factory):
    """The file of each scene's run, by name."""
    folder = tmp_path_factory.mktemp('scenes')
    paths = {}
    for name, (config, every) in SCENES.items():
        config = {**config, 'output': {'snapshot_every': every}}
        config['discretisation'] = {'elements': 20, 'particles_per_element': 2, **config.get('discretisation', {})}
        if 'integrator' not in config['discretisation']:
            config['discretisation']['dt_fraction'] = 0.2
        paths[name] = mpm1d_post.run(config, workdir=folder / name, exe=mpm1d).path
    return paths


@pytest.fixture()
def drawn(monkeypatch):
    """Instead of saving, keep each figure's title and its axes' line labels."""
    shown = {}

    def capture(fig, outdir, name, sources):
        shown[name] = {'title': fig._suptitle.get_text(),
                       'labels': [[line.get_label() for line in ax.lines] for ax in fig.axes],
                       'colours': [line.get_color() for ax in fig.axes for line in ax.lines]}
        plt.close(fig)
        return name
    monkeypatch.setattr(figures, 'save_figure', capture)
    return shown


@pytest.mark.parametrize('scene', ['plastic_wave', 'impact'])
def test_plot_run_writes_its_figures(runs, scene, tmp_path, capsys):
    assert plot_run.main([str(runs[scene]), '-o', str(tmp_path / 'plots')]) == 0
    assert 'wrote ucm.png, energies.png, snapshots.png' in capsys.readouterr().out
    for name in ('ucm.png', 'energies.png', 'snapshots.png'):
        assert (tmp_path / 'plots' / name).stat().st_size > 10000


@pytest.mark.parametrize('scene', list(SCENES))
def test_titles_and_exact_profiles(runs, scene, drawn, tmp_path):
    run = load_run(runs[scene])
    written, skipped = plot_run.plot_run(run, tmp_path)
    assert not skipped and set(drawn) == {'ucm.png', 'energies.png', 'snapshots.png'}
    kind = scene.replace('_quasi_static', '').replace('_', ' ')
    method = 'quasi-static integrator' if 'quasi_static' in scene else 'USL'
    for name, figure in drawn.items():
        title = figure['title']
        for part in (kind, method, 'linear shape', 'FLIP', f"law {run.config['law']}", '20 elements × 2 particles'):
            assert part in title, f'{scene} {name}: {part!r} not in {title!r}'
        assert "of the scene's amplitude" in title  # its result
    panels = drawn['snapshots.png']['labels']
    with_exact = sum('exact' in labels for labels in panels)
    shown = min(6, len(run.snapshots))
    fields = 2 if 'quasi_static' in scene else 3  # no velocity in a quasi-static run
    assert with_exact == (0 if scene in WITHOUT_EXACT else fields * shown), panels
    if scene == 'impact':  # each bar in its own colour
        assert {'particles of body 1', 'particles of body 2'} <= set(panels[0])


def test_stopped_run_says_no_result_and_is_grey(mpm1d, drawn, tmp_path):
    with pytest.raises(mpm1d_post.Mpm1dError) as caught, warnings.catch_warnings():
        warnings.simplefilter('ignore')
        mpm1d_post.run({'discretisation': {'dt_fraction': 2.5}, 'output': {'snapshot_every': 2}},
                       workdir=tmp_path, exe=mpm1d)
    run = caught.value.result.file
    plot_run.plot_run(run, tmp_path)
    for figure in drawn.values():
        assert 'stopped by the energy_growth guard at step' in figure['title'] and 'no result' in figure['title']
    particles = [c for c in drawn['snapshots.png']['colours'] if c != 'k']
    assert particles and set(particles) == {plot_run.STOPPED_COLOUR}


@pytest.mark.parametrize('scene', list(SCENES))
def test_animation_has_one_frame_per_snapshot(runs, scene, tmp_path, capsys):
    gif = tmp_path / f'{scene}.gif'
    field = 'displacement' if 'quasi_static' in scene else 'velocity' if scene == 'impact' else 'stress'
    assert animate.main([str(runs[scene]), '-o', str(gif), '--field', field]) == 0
    snapshots = len(load_run(runs[scene]).snapshots)
    with Image.open(gif) as image:
        assert image.n_frames == snapshots >= 2
    assert f'{snapshots} frames ({field})' in capsys.readouterr().out


def test_animation_refusals(runs, mpm1d, tmp_path, capsys):
    few = mpm1d_post.run({'run': {'periods': 0.1}, 'output': {'snapshot_times': [0.0]}}, workdir=tmp_path, exe=mpm1d)
    assert animate.main([str(few.path), '-o', str(tmp_path / 'a.gif')]) == 2
    assert 'has 1 snapshot; an animation needs at least 2' in capsys.readouterr().err
    assert animate.main([str(runs['plastic_wave']), '-o', str(tmp_path / 'a.avi')]) == 2
    assert 'allowed: a file name ending in .gif or .mp4' in capsys.readouterr().err
    assert animate.main([str(runs['plastic_wave']), '-o', str(tmp_path / 'a.gif'), '--fps', '0']) == 2
    assert '--fps 0; allowed: > 0' in capsys.readouterr().err
    if shutil.which('ffmpeg') is None:
        assert animate.main([str(runs['plastic_wave']), '-o', str(tmp_path / 'a.mp4')]) == 2
        assert 'writing MP4 needs ffmpeg, which is not installed here' in capsys.readouterr().err
    assert not list(tmp_path.glob('a.*'))


def test_plot_run_refusals(tmp_path, capsys):
    assert plot_run.main([str(tmp_path / 'missing.h5'), '-o', str(tmp_path)]) == 2
    assert 'missing.h5: no such file' in capsys.readouterr().err
    assert plot_run.main([str(tmp_path / 'missing.h5'), '--snapshots', '0']) == 2
    assert '--snapshots 0; allowed: at least 1' in capsys.readouterr().err
