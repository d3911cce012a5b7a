"""The computations every analysis shares, against hand-computed values: observed orders
(mpm1d_post.orders), the Pareto front and the cheapest run to a target (mpm1d_post.pareto), the
stability limit of a sweep of time steps (mpm1d_post.limits), markdown tables (mpm1d_post.tables) and
the selection of a sweep's cases (Sweep.where, Sweep.rows)."""
from __future__ import annotations

import math

import numpy as np
import pytest

from mpm1d_post.limits import stability_limit
from mpm1d_post.loader import Sweep
from mpm1d_post.orders import (difference_at_common_times, fitted_order, log_slope, observed_order,
                               successive_orders)
from mpm1d_post.pareto import cheapest_by_group_rows, cheapest_reaching, cheapest_rows, pareto_front
from mpm1d_post.tables import markdown_table, number, table_row


# --- observed orders ------------------------------------------------------------------------------

def test_order_between_two_meshes():
    """e = 1.6e-3 at 40 elements, 1e-4 at 160: e falls 16 times over a ratio of 4, order 2."""
    assert observed_order(40, 1.6e-3, 160, 1e-4) == pytest.approx(2.0, abs=1e-12)
    # the same two runs given by their element lengths (sizes fall as the mesh is refined)
    assert observed_order(1 / 40, 1.6e-3, 1 / 160, 1e-4) == pytest.approx(2.0, abs=1e-12)


def test_order_in_the_time_step():
    """Steps 0.4, 0.2, 0.1 with e = 5 k: order 1 per halving; e = 5 k^2: order 2."""
    ks = np.array([0.4, 0.2, 0.1])
    assert successive_orders(ks, 5 * ks) == pytest.approx([1.0, 1.0], abs=1e-12)
    assert successive_orders(ks, 5 * ks ** 2) == pytest.approx([2.0, 2.0], abs=1e-12)


def test_successive_orders_by_hand():
    """Errors 1, 1/4, 1/16, 1/32 on 10, 20, 40, 80 elements: orders 2, 2, 1; one run with more than
    twice the elements: 30 -> 90 with the error falling 9 times is order 2 again."""
    assert successive_orders([10, 20, 40, 80], [1.0, 0.25, 0.0625, 0.03125]) == pytest.approx([2, 2, 1], abs=1e-12)
    assert successive_orders([30, 90], [9.0, 1.0]) == pytest.approx([2.0], abs=1e-12)
    # an error that rises with refinement has a negative order
    assert successive_orders([10, 20], [1.0, 2.0]) == pytest.approx([-1.0], abs=1e-12)


def test_no_order_without_an_error():
    """NaN beside a run without a result (NaN: stopped by a guard), a zero or negative error, and
    between two runs of the same size."""
    orders = successive_orders([10, 20, 40, 80], [1e-2, float('nan'), 2.5e-4, 6.25e-5])
    assert np.isnan(orders[0]) and np.isnan(orders[1]) and orders[2] == pytest.approx(2.0)
    assert math.isnan(observed_order(10, 0.0, 20, 1e-3))
    assert math.isnan(observed_order(10, 1e-3, 20, 0.0))
    assert math.isnan(observed_order(10, 1e-3, 20, -1e-4))
    assert math.isnan(observed_order(10, 1e-3, 10, 1e-4))
    assert math.isnan(observed_order(10, float('inf'), 20, 1e-4))
    assert successive_orders([10], [1.0]).size == 0
    with pytest.raises(ValueError):
        successive_orders([10, 20, 40], [1.0, 0.5])


def test_fitted_order_of_a_power_law_and_by_hand():
    elements = np.array([10, 20, 40, 80])
    assert fitted_order(elements, 3.0 * elements ** -2.0) == pytest.approx(2.0, abs=1e-12)
    # log x = 0, 1, 2 and log e = 0, -1, -3: least-squares slope -3/2 (Sxy = -3, Sxx = 2)
    x = np.exp([0.0, 1.0, 2.0])
    assert fitted_order(x, np.exp([0.0, -1.0, -3.0])) == pytest.approx(1.5, abs=1e-12)
    assert log_slope(x, np.exp([0.0, -1.0, -3.0])) == pytest.approx(-1.5, abs=1e-12)


def test_fit_skips_what_has_no_error_and_needs_two_meshes():
    """Points without a positive finite error are left out; fewer than two distinct meshes: NaN."""
    elements = np.array([10, 20, 40, 80])
    errors = 3.0 * elements ** -2.0
    errors[1] = float('nan')
    assert fitted_order(elements, errors) == pytest.approx(2.0, abs=1e-12)
    assert math.isnan(fitted_order([10, 10], [1.0, 2.0]))
    assert math.isnan(fitted_order([10, 20], [1.0, float('nan')]))
    assert math.isnan(log_slope([10, 20, 40], [0.0, -1.0, 1.0]))


def test_difference_of_histories_at_the_coarse_times():
    """The fine history (the step halved) compared at every other value: max |0-0|, |1-1.5|, |2-2|."""
    coarse = np.array([0.0, 1.0, 2.0])
    assert difference_at_common_times(coarse, [0.0, 9.0, 1.5, 9.0, 2.0]) == 0.5
    # the step divided by 4: every fourth value
    assert difference_at_common_times(coarse, [0.0, 7, 7, 7, 0.75, 7, 7, 7, 2.5], stride=4) == 0.5
    # a fine run that stopped before the coarse run's end, and a missing history: no difference
    assert math.isnan(difference_at_common_times(coarse, [0.0, 9.0, 1.5, 9.0]))
    assert math.isnan(difference_at_common_times(None, [0.0]))


# --- Pareto front and the cheapest run to a target -------------------------------------------------

def test_pareto_front():
    times = [1.0, 2.0, 3.0, 1.5, 4.0, 2.5, 1.0]
    errors = [5.0, 3.0, 1.0, 4.0, 1.0, 3.5, 6.0]
    # (1,5) (1.5,4) (2,3) (3,1) optimal; (4,1) slower than (3,1); (2.5,3.5) beaten by (2,3);
    # (1,6) beaten by (1,5).
    assert pareto_front(times, errors).tolist() == [0, 3, 1, 2]
    # of two identical points one is on the front; a single point is its own front
    assert pareto_front([1.0, 1.0], [2.0, 2.0]).tolist() == [0]
    assert pareto_front([3.0], [1.0]).tolist() == [0]
    assert pareto_front([], []).tolist() == []


def test_cheapest_run_reaching_a_target():
    times = [1.0, 2.0, 3.0, 0.5]
    errors = [1e-2, 1e-3, 1e-4, 5e-2]
    assert cheapest_reaching(times, errors, 1e-2) == 0       # 0.5 s misses it, 1 s reaches it
    assert cheapest_reaching(times, errors, 1e-3) == 1
    assert cheapest_reaching(times, errors, 1e-5) is None
    assert cheapest_reaching(times, errors, 1.0) == 3
    # among a selection only (e.g. one shape's runs)
    assert cheapest_reaching(times, errors, 1e-2, among=[False, False, True, True]) == 2
    # a run without an error (NaN) never reaches a target
    assert cheapest_reaching([0.1, 1.0], [float('nan'), 1e-3], 1e-2) == 1


def test_tables_of_the_cheapest_runs():
    times = np.array([1.0, 2.0, 3.0, 0.5, 4.0])
    errors = np.array([1e-2, 1e-3, 1e-4, 5e-2, 2e-3])
    labels = ['a 10 el.', 'a 20 el.', 'b 40 el.', 'b 5 el.', 'b 30 el.']
    assert cheapest_rows(times, errors, labels, (1e-2, 1e-3, 1e-5), '.0e') == [
        ['1e-02', 'a 10 el.', '1.00e+00', '1.00e-02'], ['1e-03', 'a 20 el.', '2.00e+00', '1.00e-03'],
        ['1e-05', 'none of the measured runs', '', '']]
    # per group: b's cheapest to 1e-2 is its 3 s run (its 0.5 s run misses it), 3x the 1 s run of a; to
    # 1e-3 the same 3 s run, 1.5x the 2 s run of a; nothing of a reaches 1e-4
    a, b = np.array([1, 1, 0, 0, 0], bool), np.array([0, 0, 1, 1, 1], bool)
    assert cheapest_by_group_rows(times, errors, labels, (1e-2, 1e-3, 1e-4), [a, b], 'g') == [
        ['0.01', 'a 10 el., 1.0x', 'b 40 el., 3.0x'], ['0.001', 'a 20 el., 1.0x', 'b 40 el., 1.5x'],
        ['0.0001', 'not reached', 'b 40 el., 1.0x']]
    # only the points `among` selects (a stopped or untimed run never counts)
    assert cheapest_rows(times, errors, labels, (1e-2,), among=[False, True, True, True, True])[0][1] == 'a 20 el.'


# --- the stability limit of a sweep of time steps --------------------------------------------------

def test_stability_limit_between_the_last_completed_and_the_first_stopped():
    # steps in any order; 0.6 stopped (status 1), so did 0.8; 0.7 completed (above the first failure)
    limit = stability_limit([0.8, 0.2, 0.6, 0.4, 0.7], [1, 0, 2, 0, 0])
    assert limit == (0.4, 0.6, 2) and limit.found
    # none stopped: the limit lies beyond the largest step run
    limit = stability_limit([0.1, 0.3, 0.2], [0, 0, 0])
    assert limit.stable == 0.3 and math.isnan(limit.first_failing) and limit.first_index is None and not limit.found
    # the smallest step stopped: no stable step measured
    limit = stability_limit([0.5, 0.3], [1, 1])
    assert math.isnan(limit.stable) and limit.first_failing == 0.3 and limit.first_index == 1
    # a case not run (-1) is neither stable nor stopped
    assert stability_limit([0.1, 0.2, 0.3], [0, -1, 1]) == (0.1, 0.3, 2)
    assert math.isnan(stability_limit([], []).stable)


# --- markdown tables -------------------------------------------------------------------------------

def test_markdown_table_lines():
    assert markdown_table(['scheme', 'elements', 'order'], [['usl', 20, '2.01'], ['usf', 40, '']]) == [
        '| scheme | elements | order |', '|---|---|---|', '| usl | 20 | 2.01 |', '| usf | 40 |  |']
    assert markdown_table(['a']) == ['| a |', '|---|']
    assert table_row([1, 'x']) == '| 1 | x |'


def test_markdown_table_refuses_a_row_of_another_width():
    with pytest.raises(ValueError, match='2 cells under a header of 3'):
        markdown_table(['a', 'b', 'c'], [['1', '2']])


def test_number_or_placeholder():
    assert number(0.012345, '.2e') == '1.23e-02'
    assert number(2.0, '.2f') == '2.00'
    assert number(float('nan'), '.2f') == 'nan'
    assert number(None, '.3g', missing='n/a') == 'n/a'
    assert number(float('inf'), '.3g', missing='-') == '-'
    assert number(np.float64(1234.5), '.3g') == '1.23e+03'


# --- selecting a sweep's cases ---------------------------------------------------------------------

def small_sweep() -> Sweep:
    cases = {'scheme': np.array(['usf', 'usl', 'usl', 'musl', 'usl']),
             'elements': np.array([20, 40, 10, 20, 20]),
             'dt_fraction': np.array([0.1, 0.1, 0.2, 0.1 * (1 + 1e-12), 0.3]),
             'status': np.array([0, 0, 1, 0, 0])}
    return Sweep(paths=['x.h5'], code_versions=['test'], config={}, sweep=[{}], cases=cases)


def test_where_matches_every_criterion():
    s = small_sweep()
    assert s.where(scheme='usl').tolist() == [False, True, True, False, True]
    assert s.where(scheme='usl', elements=20).tolist() == [False, False, False, False, True]
    # a float within 1e-9 relative matches, one value of a list matches
    assert s.where(dt_fraction=0.1).tolist() == [True, True, False, True, False]
    assert s.where(scheme=('usf', 'musl')).tolist() == [True, False, False, True, False]
    assert s.where(dt_fraction=[0.2, 0.3]).tolist() == [False, False, True, False, True]
    assert s.where().all()
    assert not s.where(scheme='apic').any()
    with pytest.raises(KeyError, match="no column 'shape'"):
        s.where(shape='linear')


def test_rows_in_the_order_of_a_column():
    s = small_sweep()
    assert s.rows(scheme='usl').tolist() == [1, 2, 4]
    assert s.rows('elements', scheme='usl').tolist() == [2, 4, 1]
    assert s.rows('dt_fraction', descending=True, scheme='usl').tolist() == [4, 2, 1]
    # ties keep the file's order
    assert s.rows('elements').tolist() == [2, 0, 3, 4, 1]
    assert s.rows('elements', descending=True).tolist() == [1, 0, 3, 4, 2]
    many = Sweep(paths=['y.h5'], code_versions=['test'], config={}, sweep=[{}],
                 cases={'status': np.zeros(60, int), 'elements': np.array([20, 10, 30] * 20)})
    assert many.rows('elements').tolist() == list(range(1, 60, 3)) + list(range(0, 60, 3)) + list(range(2, 60, 3))
    # a sweep without a scheme column (the implicit integrator's): 60 cases all the same
    assert len(many) == 60 and many.where(elements=10).sum() == 20
