"""The convergence and stability studies' computations (mpm1d_post.studies.convergence, .stability) on
synthetic sweeps with known answers: a series and its floor, the split of the error into the model
difference and the method's error, and the measured stability limit with its guard. Their pipelines are
tested by studies/convergence/test_convergence_study.py and studies/stability/test_stability_study.py."""
from __future__ import annotations

import numpy as np
import pytest

from mpm1d_post.loader import Sweep
from mpm1d_post.studies import convergence, stability


def sweep_of(cases, histories=None) -> Sweep:
    return Sweep(paths=['c.h5'], code_versions=['test'], config={}, sweep=[{}],
                 cases={k: np.asarray(v) for k, v in cases.items()}, histories=histories or {})


def test_series_of_an_older_file_and_its_floor():
    """A file without shape and law columns (written before them) reads as linear shapes and hencky; errors
    1e-2, 2.5e-3, 1e-3, 9.9e-4 on 100-800 elements: orders 2, 1.32, 0.01, a floor from the third pair on."""
    n = [800, 100, 400, 200]
    errors = {100: 1e-2, 200: 2.5e-3, 400: 1e-3, 800: 9.9e-4}
    s = sweep_of({'scheme': ['usl'] * 4, 'elements': n, 'velocity_amplitude': [0.1] * 4, 'status': [0] * 4,
                  'relative_error': [errors[k] for k in n]})
    ne, rel, idx = convergence.series(s, 'usl', 'linear', 'hencky', 0.1)
    assert ne.tolist() == [100, 200, 400, 800] and rel.tolist() == [1e-2, 2.5e-3, 1e-3, 9.9e-4]
    assert convergence.series(s, 'usl', 'ugimp', 'hencky', 0.1)[2].size == 0
    text, floor = convergence.describe(ne, rel, ratio=1e-2)
    assert floor == 9.9e-4 and text.startswith('order 1.66 to 400 elements, then a floor: 9.90e-04 = 0.10 v0/c')
    assert convergence.floor_start(np.array([2.0, 1.9, 1.8])) is None
    assert convergence.describe(ne[:2], rel[:2], 1e-2) == ('keeps falling (order 2.00; 2.50e-03 at 200)', None)


def test_parts_add_up():
    """Histories e(shape, law) = (u_cm - u_cm,exact) / amplitude with model 0.3 and method -0.5 (times a
    sine): the split returns them, and the hencky run with linear shapes is their sum plus uGIMP's own."""
    t = np.linspace(0.0, 1.0, 9)
    exact = np.sin(2 * np.pi * t)  # its largest |value| 1, first at t = 1/4
    own = 0.01 * np.cos(t)
    e = {('ugimp', 'linear'): own, ('ugimp', 'hencky'): own + 0.3 * exact,
         ('linear', 'linear'): own - 0.5 * exact, ('linear', 'hencky'): own + 0.3 * exact - 0.5 * exact}
    keys = list(e)
    histories = {i: {'time': t, 'ucm_exact': exact, 'ucm': exact + e[k]} for i, k in enumerate(keys)}
    s = sweep_of({'shape': [k[0] for k in keys], 'law': [k[1] for k in keys], 'velocity_amplitude': [0.1] * 4,
                  'status': [0] * 4, 'elements': [400] * 4, 'youngs_modulus': [1e8] * 4, 'density': [1e3] * 4},
                 histories)
    part = convergence.parts(s)[0.1]
    assert convergence.signed_peak(part['model']) == pytest.approx(0.3, rel=1e-12)
    assert convergence.signed_peak(part['method']) == pytest.approx(-0.5, rel=1e-12)
    assert np.max(np.abs(part['residual'])) < 1e-15
    assert part['ratio'] == pytest.approx(0.1 / np.sqrt(1e5))


def test_measured_stability_limit_and_its_guard():
    """USL at 1 ppc over k = 0.6, 0.7, 0.8 with 0.8 stopped by energy_growth at step 120: limit 0.7, the
    first failing case named with its step and time."""
    s = sweep_of({'scheme': ['usl'] * 3 + ['usf'], 'particles_per_element': [1, 1, 1, 1], 'elements': [20] * 4,
                  'dt_fraction': [0.8, 0.6, 0.7, 0.6], 'status': [1, 0, 0, 0],
                  'status_name': ['energy_growth', 'ok', 'ok', 'ok'], 'trip_step': [120.0, np.nan, np.nan, np.nan],
                  'trip_time': [0.012, np.nan, np.nan, np.nan], 'message_ok': [True] * 4})
    measured, first, idx = stability.critical_table(s, 'usl', 1, 20)
    assert measured == 0.7 and first == 0 and idx.tolist() == [1, 2, 0]
    assert stability.trip_text(s.cases, first) == 'energy_growth at step 120 (t = 0.012 s)'
    measured, first, _ = stability.critical_table(s, 'usf', 1, 20)
    assert measured == 0.6 and first is None
    assert stability.critical_table(s, 'musl', 1, 20) is None
