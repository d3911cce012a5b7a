"""The shapes study's computations (mpm1d_post.studies.shapes) on synthetic sweeps with known answers: the
spatial orders against the exact solution and by self-convergence, the temporal orders, the amplitude the
relative errors divide by, and the bar's exact stress. The study's pipeline is tested by
studies/shapes/test_shapes_study.py."""
from __future__ import annotations

import numpy as np
import pytest

from mpm1d_post.loader import Sweep
from mpm1d_post.studies import shapes


def sweep_of(cases, histories=None) -> Sweep:
    cases = {k: np.asarray(v) for k, v in cases.items()}
    return Sweep(paths=['s.h5'], code_versions=['test'], config={}, sweep=[{}], cases=cases,
                 histories=histories or {})


def test_bar_exact_stress():
    """sigma = E u_X with u = (v0/omega) sin(beta X) sin(omega t): at the fixed end a quarter period in,
    E beta v0 / omega = E v0 / c = rho c v0; zero at the free end."""
    v0 = 0.1
    quarter = shapes.BAR_PERIOD / 4
    assert shapes.bar_exact_stress(0.0, quarter, v0) == pytest.approx(shapes.BAR_RHO * shapes.BAR_C * v0, rel=1e-12)
    assert abs(shapes.bar_exact_stress(shapes.BAR_L, quarter, v0)) < 1e-9 * shapes.BAR_RHO * shapes.BAR_C * v0


def test_amplitude_from_completed_and_stopped_cases():
    """max_error / relative_error, of a completed case or of a stopped one's errors before the stop."""
    nan = float('nan')
    s = sweep_of({'status': [0, 1], 'max_error': [2e-3, nan], 'relative_error': [0.5, nan],
                  'error_before_stop': [nan, 8e-3], 'relative_error_before_stop': [nan, 2.0]})
    assert shapes.amplitude_of(s, np.array([0, 1])) == pytest.approx(4e-3)
    assert shapes.amplitude_of(s, np.array([1])) == pytest.approx(4e-3)


def test_spatial_orders_against_the_exact_solution_and_by_self_convergence():
    """Relative errors 4e-2 h^2 on 10, 20, 40 elements: orders 2; histories u(t) + e(h) cos t compared at the
    coarse times (the step halves with the mesh): differences 0.75 e(h), whose orders are 2 as well. A case
    stopped by a guard leaves NaN beside it."""
    schemes, shapes_col, elements = [], [], []
    for scheme in shapes.SCHEMES:
        for shape in shapes.SHAPES:
            for n in (40, 10, 20):  # any order in the file
                schemes.append(scheme), shapes_col.append(shape), elements.append(n)
    elements = np.array(elements)
    error = 4e-2 * (10.0 / elements) ** 2
    amplitude = 1e-3
    status = np.zeros(len(elements), int)
    status[(np.array(schemes) == 'usf') & (np.array(shapes_col) == 'linear') & (elements == 20)] = 1
    stopped = status > 0
    histories = {}
    for i, n in enumerate(elements):
        t = np.linspace(0.0, 1.0, 8 * n // 10 + 1)
        histories[i] = {'ucm': amplitude * (np.sin(t) + error[i] * np.cos(t))}
    s = sweep_of({'scheme': schemes, 'shape': shapes_col, 'elements': elements, 'status': status,
                  'relative_error': np.where(stopped, np.nan, error), 'max_error': np.where(stopped, np.nan, amplitude * error),
                  'error_before_stop': np.where(stopped, amplitude * error, np.nan),
                  'relative_error_before_stop': np.where(stopped, error, np.nan)}, histories)
    exact = {(r[0], r[1]): r for r in shapes.convergence_table(s, False)}
    scheme, shape, el, err, ok, measure, used, orders = exact[('usl', 'bspline2')]
    assert el.tolist() == [10, 20, 40] and ok.all() and orders == pytest.approx([2.0, 2.0], abs=1e-12)
    assert np.isnan(exact[('usf', 'linear')][7]).all()
    self = {(r[0], r[1]): r for r in shapes.convergence_table(s, True)}
    scheme, shape, el, err, ok, measure, used, orders = self[('musl', 'cpgimp')]
    assert used.tolist() == [10, 20]
    assert measure == pytest.approx([0.75 * 4e-2, 0.75 * 1e-2], rel=1e-9)
    assert orders == pytest.approx([2.0], abs=1e-9)
    assert np.isnan(self[('usf', 'linear')][5]).all()


def test_temporal_orders():
    """u(t) + k cos t at k = 0.4, 0.2, 0.1 (USF-like, first order): the differences 0.5 k, order 1."""
    ks = [0.1, 0.4, 0.2]
    histories = {i: {'ucm': 1e-3 * (np.sin(t) + k * np.cos(t))}
                 for i, k in enumerate(ks) for t in [np.linspace(0.0, 1.0, int(round(4 * 0.4 / k)) + 1)]}
    s = sweep_of({'scheme': ['usf'] * 3, 'shape': ['linear'] * 3, 'transfer': ['flip'] * 3, 'dt_fraction': ks,
                  'status': [0, 0, 0], 'relative_error': [0.1, 0.4, 0.2], 'max_error': [1e-4, 4e-4, 2e-4],
                  'error_before_stop': [np.nan] * 3, 'relative_error_before_stop': [np.nan] * 3}, histories)
    rows = shapes.temporal_rows(s)
    assert len(rows) == 1 and rows[0]['ks'].tolist() == [0.4, 0.2, 0.1]
    assert rows[0]['d'] == pytest.approx([0.2, 0.1], rel=1e-9)
    assert rows[0]['orders'] == pytest.approx([1.0], abs=1e-9)


def test_errors_by_elements_and_the_order_between_two_meshes():
    s = sweep_of({'scheme': ['usl'] * 3 + ['usf'], 'shape': ['linear'] * 4, 'elements': [40, 160, 80, 40],
                  'status': [0, 0, 1, 0], 'relative_error': [1.6e-3, 1e-4, np.nan, 5.0]})
    errors = shapes.by_elements(s, scheme='usl')
    assert errors[40] == 1.6e-3 and errors[160] == 1e-4 and np.isnan(errors[80])
    assert shapes.order_between(errors, 40, 160) == pytest.approx(2.0, abs=1e-12)
    assert np.isnan(shapes.order_between(errors, 40, 80)) and np.isnan(shapes.order_between(errors, 40, 320))
