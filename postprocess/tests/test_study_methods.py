"""The methods study's computations (mpm1d_post.studies.methods) on synthetic sweeps with known answers: a
mesh series with a stopped case, its orders and verdict, and the answer table's cheapest run to each
target. Its pipeline is tested by studies/methods/test_methods_study.py."""
from __future__ import annotations

import math

import numpy as np

from mpm1d_post.loader import Sweep
from mpm1d_post.studies import methods


def sweep_of(cases) -> Sweep:
    return Sweep(paths=['c.h5'], code_versions=['test'], config={}, sweep=[{}],
                 cases={k: np.asarray(v) for k, v in cases.items()}, histories={})


def series_of(errors, status, times):
    """A mesh series on 10, 20, 40, 80 elements given out of order, as a sweep file may hold it."""
    order = [2, 0, 3, 1]
    elements = [10, 20, 40, 80]
    return sweep_of({'elements': [elements[i] for i in order], 'relative_error': [errors[i] for i in order],
                     'status': [status[i] for i in order],
                     'status_name': ['ok' if status[i] == 0 else 'domain_stretched' for i in order],
                     'run_time': [times[i] for i in order]})


def test_convergence_table_orders_and_verdicts(monkeypatch, tmp_path):
    """cpdi: errors 4e-2, 1e-2, 2.5e-3, 6.25e-4 (order 2 throughout); flip: 1e-2, 5e-3, 2.5e-3 and a stopped
    finest case (order 1, the guard's cell says `guard` and its error takes no part in the orders)."""
    data = {'cpdi': series_of([4e-2, 1e-2, 2.5e-3, 6.25e-4], [0] * 4, [1.0, 2.0, 4.0, 8.0]),
            'flip': series_of([1e-2, 5e-3, 2.5e-3, 1.0], [0, 0, 0, 8], [0.1, 0.2, 0.4, 0.8])}
    monkeypatch.setattr(methods, 'series', lambda out, scene, method: data.get(method))
    findings = {}
    lines = methods.convergence_section(tmp_path, 'bar_linear', 'the bar', 'u_cm', findings)
    text = '\n'.join(lines)
    assert '| flip (hat, FLIP) | 1.00e-02 | 5.00e-03 | 2.50e-03 | guard | 1.00, 1.00 |' in text
    assert '| cpdi (CPDI, FLIP) | 4.00e-02 | 1.00e-02 | 2.50e-03 | 6.25e-04 | 2.00, 2.00, 2.00 |' in text
    verdict = '\n'.join(methods.verdicts('bar_linear', findings))
    assert 'Second order (last observed order >= 1.8) to the finest mesh: cpdi (2.00 up to 80 elements).' in verdict
    assert 'Not second order at the finest meshes: flip (1.00 up to 40 elements).' in verdict


def test_answer_table_cheapest_timed_run():
    """Targets 1e-2, 1e-3, 1e-4: the cheapest completed run at or below each; an untimed (NaN) or stopped run
    never counts, and a target nothing reaches says so."""
    ok = np.array([True, True, True, False])
    findings = {'bar_linear': {
        'flip': dict(elements=np.array([10, 20, 40, 80]), errors=np.array([2e-2, 5e-3, 8e-4, 1e-5]), ok=ok,
                     times=np.array([1.0, 2.0, 4.0, 0.5])),
        'cpdi': dict(elements=np.array([10, 20, 40, 80]), errors=np.array([9e-3, 2e-3, 5e-4, 5e-5]),
                     ok=np.array([True] * 4), times=np.array([3.0, 6.0, 12.0, math.nan]))}}
    text = '\n'.join(methods.answer_section(findings))
    assert '| vibrating bar, linear law | 0.01 | flip, 20 el | 2.00e+00 | 5.00e-03 |' in text
    assert '| vibrating bar, linear law | 0.001 | flip, 40 el | 4.00e+00 | 8.00e-04 |' in text
    assert '| vibrating bar, linear law | 0.0001 | none of the timed runs |  |  |' in text
