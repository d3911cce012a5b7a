"""The implicit study's computations (mpm1d_post.studies.implicit) on synthetic data with known answers:
the self-convergence in dt and the stiff composite's crossover. The study's pipeline is tested by
studies/implicit/test_implicit_study.py."""
from __future__ import annotations

import numpy as np
import pytest

from mpm1d_post.loader import Sweep
from mpm1d_post.studies.implicit import crossovers, self_convergence


def histories_of_order(order: float, fractions, steps_at_largest: int = 8):
    """u_cm(t) = sin t + k^order cos t on a run of dt fraction k (the coarsest run has `steps_at_largest`
    steps, each halving of k doubles them): the differences of successive runs fall at `order`."""
    histories = {}
    for i, k in enumerate(fractions):
        t = np.linspace(0.0, 1.0, int(round(steps_at_largest * fractions[0] / k)) + 1)
        histories[i] = {'ucm': np.sin(t) + k ** order * np.cos(t)}
    return histories


def test_self_convergence_of_a_second_order_error():
    """With u_k(t) = u(t) + k^2 cos t the difference of runs k and k/2 at t = 0 is 0.75 k^2: orders 2."""
    fractions = [0.1, 0.4, 0.2, 0.05]  # any order in the file
    cases = {'mass': np.array(['lumped'] * 4), 'dt_fraction': np.array(fractions), 'status': np.zeros(4, int)}
    sweep = Sweep(paths=['t.h5'], code_versions=['test'], config={}, sweep=[{}], cases=cases,
                  histories=histories_of_order(2.0, fractions))
    ks, diffs, orders = self_convergence(sweep, mass='lumped')
    assert ks.tolist() == [0.4, 0.2, 0.1, 0.05]
    assert diffs == pytest.approx([0.75 * 0.4 ** 2, 0.75 * 0.2 ** 2, 0.75 * 0.1 ** 2], rel=1e-12)
    assert orders == pytest.approx([2.0, 2.0], abs=1e-12)
    assert self_convergence(sweep, mass='consistent')[0].size == 0


def test_crossover_is_the_smallest_ratio_where_implicit_wins():
    """At 50 elements implicit is slower at r = 10 and faster at 100 with an error within 2x: r = 100, time
    ratio 0.5; at 100 elements it is faster at r = 10 but 3x less accurate, and at 100 within 2x."""
    def run(ratio, n, method, time, ucm):
        return dict(ratio=ratio, n=n, method=method, time=time, ucm=ucm)
    data = [run(10, 50, 'explicit', 1.0, 1e-3), run(10, 50, 'implicit C_soft = 0.5', 2.0, 1e-3),
            run(100, 50, 'explicit', 4.0, 1e-3), run(100, 50, 'implicit C_soft = 0.5', 2.0, 1.5e-3),
            run(10, 100, 'explicit', 2.0, 1e-4), run(10, 100, 'implicit C_soft = 0.5', 1.0, 3e-4),
            run(100, 100, 'explicit', 8.0, 1e-4), run(100, 100, 'implicit C_soft = 0.5', 2.0, 2e-4),
            run(1000, 200, 'explicit', 8.0, 1e-4), run(1000, 200, 'implicit C_soft = 2', 2.0, 1e-4)]
    assert crossovers(data) == {50: (100, 0.5), 100: (100, 0.25)}
