"""Observed orders of convergence: the one implementation every analysis and study uses.

An error that falls as e ∝ h^p with the size h of a discretisation (an element's length dx, a time
step dt) has the order p. Two runs whose sizes differ by the refinement ratio r = h_coarse / h_fine
give the observed order p = log(e_coarse / e_fine) / log r; several runs give it per successive pair
(`successive_orders`) or as the slope of a least-squares line through log e against log h
(`fitted_order`). A run is given by its size (dt, dt_fraction: smaller is finer) or by its resolution
(elements: larger is finer): r is the larger of the two values over the smaller either way.

Where an error is not a positive finite number (a run stopped by a guard has NaN) there is no order:
NaN. Self-convergence (no exact solution): `difference_at_common_times` is the change of a history
when the step or the mesh is refined, which falls at the same order as the error.
"""
from __future__ import annotations

from typing import Sequence, Union

import numpy as np

Number = Union[float, np.ndarray]


def observed_order(x_coarse: Number, error_coarse: Number, x_fine: Number, error_fine: Number) -> Number:
    """Order p = log(error_coarse / error_fine) / log r between two runs, r = the larger of x_coarse and
    x_fine over the smaller (x: sizes such as dt, or resolutions such as elements). NaN where either
    error is not positive and finite, or the two x are equal. Element-wise on arrays."""
    x1, e1, x2, e2 = (np.asarray(v, dtype=float) for v in (x_coarse, error_coarse, x_fine, error_fine))
    ratio = np.maximum(x1, x2) / np.minimum(x1, x2)
    valid = np.isfinite(e1) & np.isfinite(e2) & (e1 > 0) & (e2 > 0) & (ratio > 1)
    with np.errstate(all='ignore'):
        order = np.log(e1 / e2) / np.log(ratio)
    order = np.where(valid, order, np.nan)
    return float(order) if order.ndim == 0 else order


def successive_orders(x: Sequence[float], errors: Sequence[float]) -> np.ndarray:
    """Observed order between each run and the next, the runs ordered from coarse to fine (elements
    increasing or dt decreasing): one fewer than the runs; NaN next to a run without an error."""
    x, errors = np.asarray(x, dtype=float), np.asarray(errors, dtype=float)
    if x.shape != errors.shape or x.ndim != 1:
        raise ValueError(f'successive_orders: x and errors must be 1-D of one length, got {x.shape} and {errors.shape}')
    return np.atleast_1d(observed_order(x[:-1], errors[:-1], x[1:], errors[1:]))


def log_slope(x: Sequence[float], y: Sequence[float]) -> float:
    """Slope of log(y) against log(x) by least squares over the points with positive x and positive,
    finite y (NaN with fewer than two distinct x among them)."""
    x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
    keep = (x > 0) & (y > 0) & np.isfinite(y)
    if np.unique(x[keep]).size < 2:
        return float('nan')
    return float(np.polyfit(np.log(x[keep]), np.log(y[keep]), 1)[0])


def fitted_order(elements: Sequence[float], errors: Sequence[float]) -> float:
    """Order p of errors ∝ elements^-p: minus the least-squares slope of log(error) against
    log(elements) (`log_slope`; NaN with fewer than two meshes with a positive, finite error)."""
    return -log_slope(elements, errors)


def difference_at_common_times(coarse: Sequence[float], fine: Sequence[float], stride: int = 2) -> float:
    """max_t |coarse(t) - fine(t)| over the coarse history's times, where the fine history has `stride`
    values per coarse step (the step refined by `stride`): the fine history's every stride-th value.
    NaN when either history is missing or the fine one does not reach the coarse one's end."""
    if coarse is None or fine is None:
        return float('nan')
    coarse, fine = np.asarray(coarse, dtype=float), np.asarray(fine, dtype=float)
    end = stride * (len(coarse) - 1) + 1
    if len(coarse) == 0 or len(fine) < end:
        return float('nan')
    return float(np.max(np.abs(coarse - fine[:end:stride])))
