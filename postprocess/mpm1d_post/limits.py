"""The stability limit measured by a sweep of time steps, written once for every study: the largest
step below the first one at which a guard stopped the run.

A run stopped by a guard has a status above 0; a completed run 0; a case not run (-1) is neither and
is left out.
"""
from __future__ import annotations

from typing import NamedTuple, Optional, Sequence

import numpy as np


class StabilityLimit(NamedTuple):
    """What a sweep of time steps says about the limit."""
    #: The largest step below the first one that failed (NaN when the smallest step failed; the
    #: largest step run when none failed: the limit lies beyond it).
    stable: float
    #: The smallest step at which a guard stopped the run (NaN when none did).
    first_failing: float
    #: Position of that run in the arrays given (None when none failed).
    first_index: Optional[int]

    @property
    def found(self) -> bool:
        """Whether a run failed, so that the limit lies between `stable` and `first_failing`."""
        return self.first_index is not None


def stability_limit(steps: Sequence[float], statuses: Sequence[int]) -> StabilityLimit:
    """The limit from runs at the time steps `steps` (any order) with their `statuses`."""
    steps, statuses = np.asarray(steps, dtype=float), np.asarray(statuses)
    ran = np.flatnonzero(statuses >= 0)
    if ran.size == 0:
        return StabilityLimit(float('nan'), float('nan'), None)
    ran = ran[np.argsort(steps[ran], kind='stable')]
    failed = ran[statuses[ran] > 0]
    if failed.size == 0:
        return StabilityLimit(float(steps[ran[-1]]), float('nan'), None)
    first = int(failed[0])
    below = ran[steps[ran] < steps[first]]
    return StabilityLimit(float(steps[below[-1]]) if below.size else float('nan'), float(steps[first]), first)
