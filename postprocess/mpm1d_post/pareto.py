"""Accuracy against cost: the Pareto front of (run time, error) points and the cheapest run that
reaches an error target, written once for every figure and study.

Give only results: completed, timed runs (a stopped run has no error, an untimed one no time).
"""
from __future__ import annotations

from typing import Optional, Sequence

import numpy as np


def pareto_front(times: Sequence[float], errors: Sequence[float]) -> np.ndarray:
    """Indices of the Pareto-optimal points, fastest first: those for which no other point is
    both at least as fast and at least as accurate, and strictly better in one (of identical
    points one is kept)."""
    times, errors = np.asarray(times, float), np.asarray(errors, float)
    order = np.lexsort((errors, times))
    front, best = [], np.inf
    for i in order:
        if errors[i] < best:
            front.append(int(i))
            best = errors[i]
    return np.array(front, dtype=int)


def cheapest_reaching(times: Sequence[float], errors: Sequence[float], target: float,
                      among: Optional[Sequence[bool]] = None) -> Optional[int]:
    """Index of the fastest point whose error is at most `target` (among the points `among` selects,
    every point by default), or None when none reaches it. Of equally fast points the first."""
    times, errors = np.asarray(times, float), np.asarray(errors, float)
    reach = errors <= target
    if among is not None:
        reach &= np.asarray(among, dtype=bool)
    if not reach.any():
        return None
    candidates = np.flatnonzero(reach)
    return int(candidates[np.argmin(times[candidates])])
