"""mpm1d's tables as pandas DataFrames: a sweep's cases, a run's history and its snapshots.

The frames hold the file's numbers as they are (no unit conversion, NaN where the file has NaN, the
status and its name in their columns): the loader (`mpm1d_post.loader`) reads the file, these functions
only rearrange what it read. pandas is Debian's (``python3-pandas``, through the project's venv).
"""

from __future__ import annotations

from typing import Dict, List, Optional

import numpy as np
import pandas as pd

from .loader import Snapshot, Sweep

#: The snapshot datasets with one value per node of the grid (the others have one per particle).
GRID_FIELDS = ('grid_x', 'grid_velocity')


def cases_frame(sweep: Sweep) -> pd.DataFrame:
    """One row per case of `sweep` (those it holds: the completed ones unless it was loaded with
    ``cases='all'``), one column per ``/cases`` dataset, in the file's order."""
    return pd.DataFrame({name: np.asarray(values) for name, values in sweep.cases.items()})


def history_frame(history: Optional[Dict[str, np.ndarray]]) -> pd.DataFrame:
    """One row per recorded step: time, ucm, ucm_exact, the energies (an empty frame without history)."""
    return pd.DataFrame({name: np.asarray(values) for name, values in (history or {}).items()})


def snapshot_frame(snapshots: List[Snapshot]) -> pd.DataFrame:
    """One row per particle per snapshot: ``snapshot`` (1, 2, ... in time order), ``time`` (s),
    ``step``, ``particle`` (1-based), then every particle dataset of the snapshot (``x``,
    ``reference_x``, ``velocity``, ``stress``, ``volume_ratio``, and what the run has of
    ``youngs_modulus``, ``body``, ``plastic_strain``, ``exact_displacement``, ``exact_velocity``,
    ``exact_stress``)."""
    return _long_frame(snapshots, grid=False)


def grid_frame(snapshots: List[Snapshot]) -> pd.DataFrame:
    """One row per grid node per snapshot: ``snapshot``, ``time``, ``step``, ``node`` (0-based, as
    the code numbers them), ``grid_x`` (m), ``grid_velocity`` (m/s)."""
    return _long_frame(snapshots, grid=True)


def _long_frame(snapshots: List[Snapshot], grid: bool) -> pd.DataFrame:
    parts = []
    for number, snapshot in enumerate(snapshots, start=1):
        fields = {'x': snapshot.x, 'reference_x': snapshot.extra.get('reference_x'),
                  'velocity': snapshot.velocity, 'stress': snapshot.stress,
                  'volume_ratio': snapshot.volume_ratio, 'grid_x': snapshot.grid_x,
                  'grid_velocity': snapshot.grid_velocity, **snapshot.extra}
        fields = {name: np.asarray(values) for name, values in fields.items()
                  if values is not None and (name in GRID_FIELDS) == grid}
        count = len(next(iter(fields.values())))
        index = {'node': np.arange(count)} if grid else {'particle': np.arange(1, count + 1)}
        parts.append(pd.DataFrame({'snapshot': number, 'time': snapshot.time, 'step': snapshot.step,
                                   **index, **fields}))
    if not parts:
        columns = ['snapshot', 'time', 'step'] + (['node', *GRID_FIELDS] if grid else ['particle'])
        return pd.DataFrame(columns=columns)
    return pd.concat(parts, ignore_index=True)
