"""Accuracy against cost: the Pareto front of (run time, error) points, the cheapest run that reaches an
error target and the rows of the studies' tables of them ('for a target error, use ...'), written once
for every figure and study.

Give only results: completed, timed runs (a stopped run has no error, an untimed one no time).
"""
from __future__ import annotations

from typing import List, Optional, Sequence

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


def cheapest_rows(times: Sequence[float], errors: Sequence[float], labels: Sequence[str],
                  targets: Sequence[float], target_spec: str = 'g',
                  among: Optional[Sequence[bool]] = None) -> List[List[str]]:
    """The rows of a table 'for a target error, use ...': per target (written with `target_spec`) the label
    of the cheapest point reaching it, its time and its error (.2e), or 'none of the measured runs'."""
    rows = []
    for target in targets:
        i = cheapest_reaching(times, errors, target, among)
        rows.append([format(target, target_spec)] + (['none of the measured runs', '', ''] if i is None else
                                                      [labels[i], f'{times[i]:.2e}', f'{errors[i]:.2e}']))
    return rows


def cheapest_by_group_rows(times: Sequence[float], errors: Sequence[float], labels: Sequence[str],
                           targets: Sequence[float], groups: Sequence[Sequence[bool]], target_spec: str = 'g',
                           among: Optional[Sequence[bool]] = None) -> List[List[str]]:
    """The rows of a table of the cheapest point of each group (one column each) reaching each target:
    '<label>, <its time over the cheapest of all reaching it>x', or 'not reached'."""
    rows = []
    for target in targets:
        best = cheapest_reaching(times, errors, target, among)
        cells = []
        for group in groups:
            selected = np.asarray(group, dtype=bool) & (True if among is None else np.asarray(among, dtype=bool))
            i = cheapest_reaching(times, errors, target, selected)
            cells.append('not reached' if i is None else f'{labels[i]}, {times[i] / times[best]:.1f}x')
        rows.append([format(target, target_spec)] + cells)
    return rows
