"""mpm1d post-processing: running mpm1d from Python (``mpm1d_post.run``, ``mpm1d_post.sweep``: results
as pandas tables, `mpm1d_post.api`), the loader of mpm1d's HDF5 files (``mpm1d_post.loader``, the one
place that knows the file layout), figures, the computations every analysis shares (``orders``,
``pareto``, ``limits``, ``tables``), the studies' analyses (``mpm1d_post.studies.<study>``) and the
commands (console scripts ``mpm1d-plot-run``, ``mpm1d-animate``, ``mpm1d-plot-sweep``,
``mpm1d-paper-figures``, ``mpm1d-convergence-figures``, ``mpm1d-stability-figures``,
``mpm1d-linear-stability``; each also ``python -m`` its module).

Install: ``studies/setup.sh`` installs it, editable, into the project's venv ``.venv`` (by hand:
``.venv/bin/python -m pip install --no-deps --no-build-isolation -e postprocess``); use ``.venv/bin/python``.
"""

from .loader import (LeftOutCases, Mpm1dFileError, Parameter, Run, Snapshot, Sweep, concatenate_sweeps,
                     load_run, load_sweep, merge_sweeps, parse_parameters)

#: What `mpm1d_post.api` gives at the package's top level, imported when first used (it needs pandas,
#: which the loader and the study scripts do without).
_API = ('run', 'sweep', 'RunResult', 'Mpm1dError', 'Mpm1dWarning')

__all__ = ['LeftOutCases', 'Mpm1dFileError', 'Parameter', 'Run', 'Snapshot', 'Sweep', 'load_run', 'load_sweep',
           'merge_sweeps', 'concatenate_sweeps', 'parse_parameters', *_API]


def __getattr__(name: str):
    if name in _API:
        from . import api
        return getattr(api, name)
    raise AttributeError(f"module 'mpm1d_post' has no attribute '{name}'")
