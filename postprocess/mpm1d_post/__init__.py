"""mpm1d post-processing: the loader of mpm1d's HDF5 files (``mpm1d_post.loader``, the one place that
knows the file layout), figures, the computations every analysis shares (``orders``, ``pareto``,
``limits``, ``tables``), the studies' analyses (``mpm1d_post.studies.<study>``) and the plotting
commands (console scripts ``mpm1d-plot-sweep``, ``mpm1d-paper-figures``, ``mpm1d-convergence-figures``,
``mpm1d-stability-figures``, ``mpm1d-linear-stability``; each also ``python -m`` its module).

Install: ``studies/setup.sh`` installs it, editable, into the project's venv ``.venv`` (by hand:
``.venv/bin/python -m pip install --no-deps --no-build-isolation -e postprocess``); use ``.venv/bin/python``.
"""

from .loader import (LeftOutCases, Mpm1dFileError, Parameter, Run, Snapshot, Sweep, concatenate_sweeps,
                     load_run, load_sweep, merge_sweeps, parse_parameters)

__all__ = ['LeftOutCases', 'Mpm1dFileError', 'Parameter', 'Run', 'Snapshot', 'Sweep', 'load_run', 'load_sweep',
           'merge_sweeps', 'concatenate_sweeps', 'parse_parameters']
